//! The built-in target's read-back: a 1920 × 1080 RGB888 frame (6.2 MB) through the
//! controller, the link (COBS, CRC-32, ACKs, both ends' state machines) and the
//! end-to-end CRC, as `fpgfx render` and `fpgfx raster` read every frame. Target: ≥ 1 GB/s
//! (docs/bench.md).
//!
//! `cargo bench -p host-cli --bench readback` reports the throughput in pixel bytes.
//! The frame is drawn once (Gouraud triangles over a dark background, few zero bytes:
//! zeros cost COBS a block each, so a black frame would measure COBS, not the link).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use host_cli::session::Session;
use protocol::frame::{PixelFormat, Plane, ReadRequest, Rect};

/// Two triangles covering the frame, shaded across it.
const JOB: &str = r##"
size = [1920, 1080]
background = "#101018"
subpixel_bits = 8

[[cmd]]
op = "triangle"
v = [[0.0, 0.0], [1920.0, 0.0], [0.0, 1080.0]]
colors = ["#ff4020", "#20ff40", "#4020ff"]

[[cmd]]
op = "triangle"
v = [[1920.0, 0.0], [1920.0, 1080.0], [0.0, 1080.0]]
colors = ["#80c0ff", "#ffc080", "#c0ff80"]
"##;

fn readback(c: &mut Criterion) {
    let job = jobs::raster::parse(JOB, "readback.toml").expect("the bench's job parses");
    let mut session = Session::new(sim_board::in_process::sim_target());
    session
        .handshake()
        .expect("the built-in target shakes hands");
    host_cli::run::raster::run(&mut session, &job, "readback.toml").expect("the job draws");
    let req = ReadRequest {
        plane: Plane::Color,
        rect: Rect {
            x: 0,
            y: 0,
            w: 1920,
            h: 1080,
        },
        format: PixelFormat::Rgb888,
    };
    let bytes = 1920 * 1080 * 3;
    let mut g = c.benchmark_group("readback");
    g.throughput(Throughput::Bytes(bytes));
    g.sample_size(30);
    g.bench_function("builtin_1080p_rgb888", |b| {
        b.iter(|| {
            let data = session.read_back(req).expect("the read-back succeeds");
            assert_eq!(data.len() as u64, bytes);
            data
        })
    });
    g.finish();
}

criterion_group!(benches, readback);
criterion_main!(benches);
