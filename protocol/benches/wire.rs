//! Encode + decode throughput and wire overhead of a raster command stream, against the
//! targets of docs/requirements.md §7.1 (overhead ≤ 10 %, codec ≥ 50 MB/s on one core).
//!
//! `cargo bench -p protocol --bench wire` prints the overhead table first (it is a count,
//! not a timing), then criterion measures, per stream:
//! - `codec`: batching + postcard + link framing (header, CRC-32, COBS, delimiter) and
//!   the way back (split at 0x00, COBS decode, CRC check, postcard decode);
//! - `link`: the same bytes through two `Link` state machines, ACKs included.
//!
//! Throughput is reported in payload bytes (the postcard encoding of the commands alone).
//! Targets: overhead ≤ 10 % for a triangle stream, ≥ 50 MB/s encode + decode on one core.

use criterion::{black_box, criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use protocol::frame::{encode, raster_commands, RasterBatch, RasterBatcher};
use protocol::link::{decode_frame, encode_frame, Event, Header, Kind, Link, MAX_FRAME};
use protocol::raster::{Line, LineAlgo, Point, RasterCmd, Rgb, Shade, Triangle};
use protocol::MAX_PAYLOAD;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const COMMANDS: usize = 10_000;

fn point(rng: &mut SmallRng) -> Point {
    // A 1920 × 1080 viewport with 8 sub-pixel bits.
    Point {
        x: rng.gen_range(0..1920 << 8),
        y: rng.gen_range(0..1080 << 8),
    }
}

fn color(rng: &mut SmallRng) -> Rgb {
    Rgb::new(rng.gen(), rng.gen(), rng.gen())
}

fn triangles(gouraud: bool, z: bool) -> Vec<RasterCmd> {
    let mut rng = SmallRng::seed_from_u64(4);
    (0..COMMANDS)
        .map(|_| {
            RasterCmd::Triangle(Triangle {
                v: [point(&mut rng), point(&mut rng), point(&mut rng)],
                shade: if gouraud {
                    Shade::Gouraud([color(&mut rng), color(&mut rng), color(&mut rng)])
                } else {
                    Shade::Flat(color(&mut rng))
                },
                z: z.then(|| [rng.gen_range(0..1 << 24); 3]),
                w: None,
                tex: None,
            })
        })
        .collect()
}

fn lines() -> Vec<RasterCmd> {
    let mut rng = SmallRng::seed_from_u64(5);
    (0..COMMANDS)
        .map(|_| {
            RasterCmd::Line(Line {
                from: point(&mut rng),
                to: point(&mut rng),
                color: color(&mut rng),
                color_to: None,
                width: 256,
                aa: false,
                algo: LineAlgo::Bresenham,
            })
        })
        .collect()
}

fn payload_bytes(cmds: &[RasterCmd]) -> usize {
    let mut buf = [0u8; MAX_PAYLOAD];
    cmds.iter()
        .map(|c| encode(c, &mut buf).map(|b| b.len()).unwrap_or(0))
        .sum()
}

/// Batches, encodes and frames a command stream; returns the wire bytes.
fn encode_stream(cmds: &[RasterCmd]) -> Vec<u8> {
    let mut wire = Vec::with_capacity(cmds.len() * 32);
    let mut batcher = RasterBatcher::new();
    let mut frame = [0u8; MAX_FRAME];
    let mut seq = 0u16;
    let mut emit = |batch: RasterBatch, wire: &mut Vec<u8>| {
        let bytes = batch.as_bytes();
        let header = Header {
            kind: Kind::Data,
            epoch: 0,
            seq,
            ack: 0,
            credit: 8,
        };
        seq = seq.wrapping_add(1);
        let n = encode_frame(&header, bytes, &mut frame).expect("frame buffer is MAX_FRAME");
        wire.extend_from_slice(&frame[..n]);
    };
    for cmd in cmds {
        if let Some(msg) = batcher.push(cmd).expect("commands fit a frame") {
            emit(msg, &mut wire);
        }
    }
    if let Some(msg) = batcher.finish() {
        emit(msg, &mut wire);
    }
    wire
}

/// Splits, checks and decodes a framed stream; returns the number of commands.
fn decode_stream(wire: &mut [u8]) -> usize {
    let mut count = 0;
    for chunk in wire.split_mut(|&b| b == 0).filter(|c| !c.is_empty()) {
        let (_, payload) = decode_frame(chunk).expect("intact frame");
        for cmd in raster_commands(payload).expect("a raster batch") {
            black_box(cmd.expect("valid command"));
            count += 1;
        }
    }
    count
}

/// Sends the stream through two links in memory, both directions pumped.
fn through_links(cmds: &[RasterCmd]) -> usize {
    let mut host: Link = Link::new(Default::default());
    let mut dev: Link = Link::new(Default::default());
    let mut batcher = RasterBatcher::new();
    let mut msgs: Vec<RasterBatch> = Vec::new();
    for c in cmds {
        if let Some(m) = batcher.push(c).expect("fits") {
            msgs.push(m);
        }
    }
    msgs.extend(batcher.finish());
    let mut frame = [0u8; MAX_FRAME];
    let mut delivered = 0;
    let mut next = 0;
    let now = 0;
    while delivered < cmds.len() {
        while next < msgs.len() {
            if host.send(now, msgs[next].as_bytes()).is_err() {
                break;
            }
            next += 1;
        }
        while let Some(n) = host.poll_transmit(now, &mut frame) {
            let mut input = &frame[..n];
            loop {
                let (used, ev) = dev.handle_input(now, input);
                input = &input[used..];
                match ev {
                    Some(Event::Data(p)) => {
                        for c in raster_commands(p).expect("a raster batch") {
                            black_box(c.expect("valid command"));
                            delivered += 1;
                        }
                    }
                    Some(_) => {}
                    None if input.is_empty() => break,
                    None => {}
                }
            }
        }
        while let Some(n) = dev.poll_transmit(now, &mut frame) {
            let mut input = &frame[..n];
            loop {
                let (used, ev) = host.handle_input(now, input);
                input = &input[used..];
                if ev.is_none() && input.is_empty() {
                    break;
                }
            }
        }
    }
    delivered
}

fn bench(c: &mut Criterion) {
    let streams = [
        ("triangles-flat", triangles(false, false)),
        ("triangles-gouraud-z", triangles(true, true)),
        ("lines", lines()),
    ];
    println!("\nwire overhead (bytes on the wire / payload bytes, {COMMANDS} commands)");
    println!("| stream | payload B | wire B | overhead |");
    println!("|---|---:|---:|---:|");
    for (name, cmds) in &streams {
        let payload = payload_bytes(cmds);
        let wire = encode_stream(cmds).len();
        println!(
            "| {name} | {payload} | {wire} | {:.1} % |",
            100.0 * (wire as f64 / payload as f64 - 1.0)
        );
    }
    let mut group = c.benchmark_group("wire");
    for (name, cmds) in &streams {
        let payload = payload_bytes(cmds) as u64;
        group.throughput(Throughput::Bytes(payload));
        group.bench_function(format!("codec/{name}"), |b| {
            b.iter_batched(
                || (),
                |()| {
                    let mut wire = encode_stream(black_box(cmds));
                    black_box(decode_stream(&mut wire))
                },
                BatchSize::LargeInput,
            )
        });
        group.bench_function(format!("link/{name}"), |b| {
            b.iter(|| black_box(through_links(black_box(cmds))))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
