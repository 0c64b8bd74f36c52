//! A read-back from the built-in target, whose controller has a link of bulk frames, to
//! hosts of either size: the chunks are sized for the smaller of the two ends, so a host
//! with a board-sized link (an older `fpgfx`, or another tool) still gets chunks it can
//! take, each of them a whole `DeviceFrame`, and a bulk host gets 16 KiB ones.

use std::time::Duration;

use protocol::frame::{
    chunk_view, decode, encode, read_chunk_len, Caps, DeviceFrame, Hello, HostFrame, PixelFormat,
    Plane, ReadRequest, Rect, READ_CHUNK,
};
use protocol::link::{encoded_len, Bulk, Capacity, Event, Link, Small, BULK_PAYLOAD, CRC32};
use protocol::raster::{Aa, Cull, RasterSetup, Rgb, Traversal};
use protocol::MAX_PAYLOAD;

const W: u16 = 320;
const H: u16 = 240;
const BACKGROUND: [u8; 3] = [0x10, 0x20, 0x30];

/// What the host saw of a read-back: each chunk's length, the bytes, and whether every
/// chunk also decoded as a whole `DeviceFrame` (what a host without `chunk_view` does).
struct Seen {
    chunks: Vec<usize>,
    data: Vec<u8>,
    crc_ok: bool,
    all_decode: bool,
}

/// Shakes hands with the built-in target over a host link of capacity `C`, saying it
/// accepts `link_payload`, clears a frame and reads it back.
fn read_back<C: Capacity>(link_payload: u32) -> Seen {
    let mut target = sim_board::in_process::sim_target();
    let mut host: Box<Link<8, C>> = Box::new(Link::new(Default::default()));
    let mut out = vec![0u8; encoded_len(C::PAYLOAD) + 1];
    let mut input = vec![0u8; 1 << 16];
    let caps = Caps {
        link_payload,
        ..Caps::default()
    };
    let setup = RasterSetup {
        width: W,
        height: H,
        subpixel_bits: 4,
        background: Rgb::new(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]),
        aa: Aa::default(),
        cull: Cull::default(),
        traversal: Traversal::default(),
    };
    let req = ReadRequest {
        plane: Plane::Color,
        rect: Rect {
            x: 0,
            y: 0,
            w: W,
            h: H,
        },
        format: PixelFormat::Rgb888,
    };
    let mut queue: Vec<HostFrame> = vec![
        HostFrame::Hello(Hello::new(caps, "read-back test")),
        HostFrame::RasterSetup(setup),
        HostFrame::Read(req),
    ];
    queue.reverse();
    let mut seen = Seen {
        chunks: Vec::new(),
        data: Vec::new(),
        crc_ok: false,
        all_decode: true,
    };
    for now in 0..10_000u64 {
        if let Some(frame) = queue.last() {
            let mut buf = [0u8; MAX_PAYLOAD];
            let bytes = encode(frame, &mut buf).expect("a request fits");
            if host.send(now, bytes).is_ok() {
                queue.pop();
            }
        }
        while let Some(n) = host.poll_transmit(now, &mut out) {
            target.write_all(&out[..n]).expect("the pipe takes bytes");
        }
        let n = target
            .read(&mut input, Duration::from_millis(1))
            .expect("the model runs");
        let mut at = 0;
        loop {
            let (used, event) = host.handle_input(now, &input[at..n]);
            at += used;
            match event {
                Some(Event::Data(payload)) => {
                    if let Some(chunk) = chunk_view(payload) {
                        let (offset, bytes) = chunk.expect("a chunk decodes");
                        assert_eq!(offset as usize, seen.data.len(), "chunks in order");
                        seen.chunks.push(bytes.len());
                        seen.data.extend_from_slice(bytes);
                        seen.all_decode &= decode::<DeviceFrame>(payload).is_ok();
                    } else if let DeviceFrame::ReadDone(done) =
                        decode::<DeviceFrame>(payload).expect("an answer decodes")
                    {
                        assert_eq!(done.len as usize, seen.data.len());
                        seen.crc_ok = done.crc32 == CRC32.checksum(&seen.data);
                        return seen;
                    }
                }
                Some(_) => {}
                None if at == n => break,
                None => {}
            }
        }
    }
    panic!(
        "no end of the read-back; {} bytes in {} chunks",
        seen.data.len(),
        seen.chunks.len()
    );
}

fn check(seen: &Seen, chunk: usize) {
    let bytes = usize::from(W) * usize::from(H) * 3;
    assert_eq!(seen.data.len(), bytes);
    assert!(seen.crc_ok, "the read-back's CRC matches");
    assert!(
        seen.data.chunks(3).all(|p| p == BACKGROUND),
        "the cleared frame"
    );
    // Every chunk but the last is full.
    let (last, full) = seen.chunks.split_last().expect("chunks");
    assert!(full.iter().all(|&n| n == chunk), "{:?}", &seen.chunks[..4]);
    assert!(*last <= chunk && *last > 0);
    assert_eq!(seen.chunks.len(), bytes.div_ceil(chunk));
}

#[test]
fn a_host_that_states_no_payload_gets_board_sized_chunks_it_can_decode() {
    let seen = read_back::<Small>(0);
    check(&seen, READ_CHUNK);
    assert!(seen.all_decode, "each chunk is a whole DeviceFrame");
}

#[test]
fn a_bulk_host_gets_chunks_of_a_bulk_frame() {
    let seen = read_back::<Bulk>(BULK_PAYLOAD as u32);
    check(&seen, read_chunk_len(BULK_PAYLOAD));
    assert_eq!(read_chunk_len(BULK_PAYLOAD), 16_352);
}

#[test]
fn a_host_between_the_two_gets_chunks_of_its_own_size() {
    let seen = read_back::<Bulk>(1000);
    check(&seen, read_chunk_len(1000));
}
