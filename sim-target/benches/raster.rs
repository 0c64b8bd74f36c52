//! Fill rate of the raster golden model per traversal against embedded-graphics drawing
//! the same triangles into a comparable RGB888 framebuffer, and line pixel rate.
//!
//! `cargo bench -p sim-target --bench raster -- --warm-up-time 1 --measurement-time 2`

use std::convert::Infallible;

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use embedded_graphics::{
    pixelcolor::Rgb888,
    prelude::{DrawTarget, OriginDimensions, Point as EgPoint, Primitive, RgbColor, Size},
    primitives::{PrimitiveStyle, Rectangle, Triangle as EgTriangle},
    Drawable, Pixel as EgPixel,
};
use protocol::frame::*;
use sim_target::raster::Raster;

const W: u32 = 512;
const H: u32 = 512;
const BITS: u8 = 8;

/// RGB888, row-major, like the model's framebuffer.
struct EgFb {
    buf: Vec<u8>,
}

impl OriginDimensions for EgFb {
    fn size(&self) -> Size {
        Size::new(W, H)
    }
}

impl DrawTarget for EgFb {
    type Color = Rgb888;
    type Error = Infallible;

    fn draw_iter<I: IntoIterator<Item = EgPixel<Rgb888>>>(
        &mut self,
        pixels: I,
    ) -> Result<(), Infallible> {
        for EgPixel(p, c) in pixels {
            if p.x >= 0 && p.y >= 0 && (p.x as u32) < W && (p.y as u32) < H {
                let o = (p.y as usize * W as usize + p.x as usize) * 3;
                self.buf[o] = c.r();
                self.buf[o + 1] = c.g();
                self.buf[o + 2] = c.b();
            }
        }
        Ok(())
    }

    // A fair opponent: solid rectangles (triangle scanlines) as row-slice writes.
    fn fill_solid(&mut self, area: &Rectangle, c: Rgb888) -> Result<(), Infallible> {
        let a = area.intersection(&Rectangle::new(EgPoint::zero(), Size::new(W, H)));
        let (x0, y0) = (a.top_left.x as usize, a.top_left.y as usize);
        for y in y0..y0 + a.size.height as usize {
            let row = &mut self.buf
                [(y * W as usize + x0) * 3..(y * W as usize + x0 + a.size.width as usize) * 3];
            for px in row.chunks_exact_mut(3) {
                px[0] = c.r();
                px[1] = c.g();
                px[2] = c.b();
            }
        }
        Ok(())
    }
}

/// Triangles in pixel units, several positions per shape so that no one alignment wins.
/// A triangle in whole pixels.
type Tri = [(i32, i32); 3];

fn shapes() -> Vec<(&'static str, Vec<Tri>)> {
    let place = |t: [(i32, i32); 3], n: i32| -> Vec<[(i32, i32); 3]> {
        (0..n)
            .map(|k| t.map(|(x, y)| (x + (k * 37) % 300, y + (k * 53) % 300)))
            .collect()
    };
    vec![
        ("10px", place([(0, 0), (5, 1), (1, 5)], 64)),
        ("100px", place([(0, 0), (15, 2), (3, 14)], 64)),
        ("10000px", place([(0, 0), (141, 5), (8, 146)], 8)),
        ("thin", place([(0, 0), (200, 190), (203, 190)], 16)),
    ]
}

fn setup(t: Traversal) -> RasterSetup {
    RasterSetup {
        width: W as u16,
        height: H as u16,
        subpixel_bits: BITS,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: t,
    }
}

fn cmds(tris: &[[(i32, i32); 3]]) -> Vec<RasterCmd> {
    tris.iter()
        .map(|t| {
            RasterCmd::Triangle(Triangle {
                v: t.map(|(x, y)| Point {
                    x: x << BITS,
                    y: y << BITS,
                }),
                shade: Shade::Flat(Rgb::new(255, 128, 0)),
                z: None,
                w: None,
                tex: None,
            })
        })
        .collect()
}

fn triangles(c: &mut Criterion) {
    for (name, tris) in shapes() {
        let cmds = cmds(&tris);
        let mut probe = Raster::new(W, H, &setup(Traversal::Scanline)).expect("setup");
        for cmd in &cmds {
            probe.draw(cmd).expect("draw");
        }
        let frags = probe.stats().fragments;
        let mut g = c.benchmark_group(format!("triangle/{name}"));
        g.throughput(Throughput::Elements(frags));
        for t in [
            Traversal::BoundingBox,
            Traversal::Scanline,
            Traversal::Zigzag,
            Traversal::Tiles,
            Traversal::Simd8,
        ] {
            let mut r = Raster::new(W, H, &setup(t)).expect("setup");
            g.bench_function(BenchmarkId::from_parameter(format!("{t:?}")), |b| {
                b.iter(|| {
                    for cmd in &cmds {
                        r.draw(cmd).expect("draw");
                    }
                })
            });
        }
        let mut fb = EgFb {
            buf: vec![0; (W * H * 3) as usize],
        };
        let style = PrimitiveStyle::with_fill(Rgb888::new(255, 128, 0));
        let eg: Vec<EgTriangle> = tris
            .iter()
            .map(|t| {
                EgTriangle::new(
                    EgPoint::new(t[0].0, t[0].1),
                    EgPoint::new(t[1].0, t[1].1),
                    EgPoint::new(t[2].0, t[2].1),
                )
            })
            .collect();
        g.bench_function(BenchmarkId::from_parameter("embedded-graphics"), |b| {
            b.iter(|| {
                for t in &eg {
                    let _ = t.into_styled(style).draw(&mut fb);
                }
            })
        });
        g.finish();
    }
}

/// 256 random full-window lines (fixed seed) drawn with `algo`.
fn line_cmds(algo: LineAlgo) -> Vec<RasterCmd> {
    let mut s = 99u64;
    let mut rnd = move |m: u32| {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 33) as u32 % m) as i32
    };
    (0..256)
        .map(|_| {
            RasterCmd::Line(Line {
                from: Point {
                    x: rnd(W) << BITS,
                    y: rnd(H) << BITS,
                },
                to: Point {
                    x: rnd(W) << BITS,
                    y: rnd(H) << BITS,
                },
                color: Rgb::new(255, 255, 255),
                color_to: None,
                width: 0,
                aa: false,
                algo,
            })
        })
        .collect()
}

fn lines(c: &mut Criterion) {
    let mut g = c.benchmark_group("line");
    for algo in [LineAlgo::Bresenham, LineAlgo::Dda] {
        let ls = line_cmds(algo);
        let mut probe = Raster::new(W, H, &setup(Traversal::Tiles)).expect("setup");
        for l in &ls {
            probe.draw(l).expect("draw");
        }
        g.throughput(Throughput::Elements(probe.stats().fragments));
        let mut r = Raster::new(W, H, &setup(Traversal::Tiles)).expect("setup");
        g.bench_function(BenchmarkId::from_parameter(format!("{algo:?}")), |b| {
            b.iter(|| {
                for l in &ls {
                    r.draw(l).expect("draw");
                }
            })
        });
    }
    g.finish();
}

criterion_group!(benches, triangles, lines);

/// Instruction-count mode for `valgrind --tool=callgrind` on a shared machine, where
/// wall-clock medians are noisy: `RASTER_CG=100px:Scanline` (or `line:Bresenham`) draws
/// that workload `RASTER_CG_ITERS` times (default 100) and exits without criterion.
fn callgrind_mode(spec: &str) {
    let iters: usize = std::env::var("RASTER_CG_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let (shape, trav) = spec.split_once(':').unwrap_or((spec, "Scanline"));
    let cmds = if shape == "line" {
        let algo = if trav == "Dda" {
            LineAlgo::Dda
        } else {
            LineAlgo::Bresenham
        };
        line_cmds(algo)
    } else {
        let tris = shapes()
            .into_iter()
            .find(|(n, _)| *n == shape)
            .map(|(_, t)| t)
            .unwrap_or_default();
        cmds(&tris)
    };
    let t = [
        Traversal::BoundingBox,
        Traversal::Scanline,
        Traversal::Zigzag,
        Traversal::Tiles,
        Traversal::Simd8,
    ]
    .into_iter()
    .find(|t| format!("{t:?}") == trav)
    .unwrap_or(Traversal::Scanline);
    let mut r = Raster::new(W, H, &setup(t)).expect("setup");
    for _ in 0..iters {
        for cmd in &cmds {
            r.draw(std::hint::black_box(cmd)).expect("draw");
        }
    }
    println!("{spec}: {} fragments", r.stats().fragments);
}

fn main() {
    if let Ok(spec) = std::env::var("RASTER_CG") {
        callgrind_mode(&spec);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
