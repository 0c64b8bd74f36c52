//! Fill rate of the raster golden model per traversal against embedded-graphics drawing
//! the same triangles into a comparable RGB888 framebuffer, against tiny-skia on the
//! workloads the traversal-independence requirement names, and line pixel rate.
//!
//! `cargo bench -p sim-target --bench raster -- --warm-up-time 1 --measurement-time 2`;
//! `RASTER_RATIO=sliver cargo bench -p sim-target --bench raster` for the tiny-skia
//! ratios paired round by round ([`ratio_mode`]), `RASTER_CG=…` for callgrind.

use std::convert::Infallible;

use criterion::{criterion_group, BenchmarkId, Criterion, Throughput};
use embedded_graphics::{
    pixelcolor::Rgb888,
    prelude::{DrawTarget, OriginDimensions, Point as EgPoint, Primitive, RgbColor, Size},
    primitives::{PrimitiveStyle, Rectangle, Triangle as EgTriangle},
    Drawable, Pixel as EgPixel,
};
use protocol::raster::*;
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

/// Deterministic generator for the tiny-skia workloads (an LCG, so that both sides and
/// both runs of a before/after comparison draw the same triangles).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) as u32
    }

    /// Uniform in `lo..=hi`.
    fn range(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo + 1) as u32) as i32
    }
}

/// Twice the signed area of a triangle in whole pixels.
fn area2(t: &Tri) -> i64 {
    let [(x0, y0), (x1, y1), (x2, y2)] = t.map(|(x, y)| (x as i64, y as i64));
    (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)
}

/// `n` triangles with integer vertices inside the viewport whose area lies in `area`,
/// each drawn as `offsets` from a random anchor (rejection-sampled, fixed seed).
fn random_tris(
    seed: u64,
    n: usize,
    area: core::ops::RangeInclusive<i64>,
    mut shape: impl FnMut(&mut Lcg) -> [(i32, i32); 2],
) -> Vec<Tri> {
    let mut r = Lcg(seed);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let p = (r.range(0, W as i32 - 1), r.range(0, H as i32 - 1));
        let [u, v] = shape(&mut r);
        let t = [p, (p.0 + u.0, p.1 + u.1), (p.0 + v.0, p.1 + v.1)];
        let inside = t
            .iter()
            .all(|&(x, y)| (0..W as i32).contains(&x) && (0..H as i32).contains(&y));
        if inside && area.contains(&(area2(&t).abs() / 2)) {
            out.push(t);
        }
    }
    out
}

/// The requirement's three workloads: 10 000 triangles of ~100 px, 1 000 of ~10 000 px
/// and 10 000 slivers (100–250 px long, 1–3 px wide), both orientations.
fn skia_workloads() -> Vec<(&'static str, Vec<Tri>)> {
    let corners = |m: i32| {
        move |r: &mut Lcg| {
            [
                (r.range(-m, m), r.range(-m, m)),
                (r.range(-m, m), r.range(-m, m)),
            ]
        }
    };
    let sliver = |r: &mut Lcg| {
        let (dx, dy) = (r.range(-250, 250), r.range(-250, 250));
        let (ox, oy) = (r.range(-3, 3), r.range(-3, 3));
        [(dx, dy), (dx + ox, dy + oy)]
    };
    vec![
        ("100px", random_tris(1, 10_000, 90..=110, corners(20))),
        (
            "10000px",
            random_tris(2, 1_000, 9_000..=11_000, corners(200)),
        ),
        (
            "sliver",
            random_tris(3, 10_000, 50..=400, |r| loop {
                let s = sliver(r);
                let len2 = s[0].0 * s[0].0 + s[0].1 * s[0].1;
                if (100 * 100..=250 * 250).contains(&len2) {
                    return s;
                }
            }),
        ),
    ]
}

/// tiny-skia's side of the comparison: the triangles as paths, a 512 × 512 pixmap and an
/// opaque solid paint without anti-aliasing.
struct Skia {
    paths: Vec<tiny_skia::Path>,
    pixmap: tiny_skia::Pixmap,
    paint: tiny_skia::Paint<'static>,
}

impl Skia {
    fn new(tris: &[Tri]) -> Self {
        let paths: Vec<tiny_skia::Path> = tris
            .iter()
            .filter_map(|t| {
                let mut pb = tiny_skia::PathBuilder::new();
                pb.move_to(t[0].0 as f32, t[0].1 as f32);
                pb.line_to(t[1].0 as f32, t[1].1 as f32);
                pb.line_to(t[2].0 as f32, t[2].1 as f32);
                pb.close();
                pb.finish()
            })
            .collect();
        assert_eq!(paths.len(), tris.len(), "every triangle is a valid path");
        let mut paint = tiny_skia::Paint::default();
        paint.set_color_rgba8(255, 128, 0, 255);
        paint.anti_alias = false;
        Self {
            paths,
            pixmap: tiny_skia::Pixmap::new(W, H).expect("pixmap"),
            paint,
        }
    }

    fn fill(&mut self) {
        for p in &self.paths {
            self.pixmap.fill_path(
                p,
                &self.paint,
                tiny_skia::FillRule::Winding,
                tiny_skia::Transform::identity(),
                None,
            );
        }
    }
}

/// The model (every traversal, and the protocol's default) against tiny-skia 0.11 filling
/// the same integer-vertex triangles into a 512 × 512 RGBA8888 pixmap, anti-aliasing off,
/// one solid opaque colour (its fastest path: a span fill). Throughput is in the model's
/// fragments for every entry, so the time ratio is the fill-rate ratio.
fn vs_tiny_skia(c: &mut Criterion) {
    for (name, tris) in skia_workloads() {
        let cmds = cmds(&tris);
        let mut probe = Raster::new(W, H, &setup(Traversal::Scanline)).expect("setup");
        for cmd in &cmds {
            probe.draw(cmd).expect("draw");
        }
        let mut g = c.benchmark_group(format!("vs-tiny-skia/{name}"));
        g.throughput(Throughput::Elements(probe.stats().fragments));
        g.sample_size(10);
        let travs = [
            ("default", Traversal::default()),
            ("BoundingBox", Traversal::BoundingBox),
            ("Scanline", Traversal::Scanline),
            ("Zigzag", Traversal::Zigzag),
            ("Tiles", Traversal::Tiles),
            ("Simd8", Traversal::Simd8),
        ];
        for (id, t) in travs {
            let mut r = Raster::new(W, H, &setup(t)).expect("setup");
            g.bench_function(BenchmarkId::from_parameter(id), |b| {
                b.iter(|| {
                    for cmd in &cmds {
                        r.draw(cmd).expect("draw");
                    }
                })
            });
        }
        let mut sk = Skia::new(&tris);
        g.bench_function(BenchmarkId::from_parameter("tiny-skia"), |b| {
            b.iter(|| sk.fill())
        });
        g.finish();
    }
}

criterion_group!(benches, triangles, vs_tiny_skia, lines);

/// Instruction-count mode for `valgrind --tool=callgrind` on a shared machine, where
/// wall-clock medians are noisy: `RASTER_CG=100px:Scanline` (or `line:Bresenham`, or
/// `ts:sliver:Tiles` for a tiny-skia workload, `ts:sliver:tiny-skia` for tiny-skia) draws
/// that workload `RASTER_CG_ITERS` times (default 100) and exits without criterion.
fn callgrind_mode(spec: &str) {
    let iters: usize = std::env::var("RASTER_CG_ITERS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100);
    let (shape, trav) = spec.rsplit_once(':').unwrap_or((spec, "Scanline"));
    let cmds = if shape == "line" {
        let algo = if trav == "Dda" {
            LineAlgo::Dda
        } else {
            LineAlgo::Bresenham
        };
        line_cmds(algo)
    } else {
        // `ts:100px` names a tiny-skia workload.
        let tris = match shape.strip_prefix("ts:") {
            Some(ts) => skia_workloads().into_iter().find(|(n, _)| *n == ts),
            None => shapes().into_iter().find(|(n, _)| *n == shape),
        }
        .map(|(_, t)| t)
        .unwrap_or_default();
        if trav == "tiny-skia" {
            // tiny-skia itself, for cycle counts of both sides of the comparison.
            let mut sk = Skia::new(&tris);
            for _ in 0..iters {
                sk.fill();
            }
            println!("{spec}: {} triangles drawn {iters} times", tris.len());
            return;
        }
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

/// Paired mode for the tiny-skia ratios on a noisy shared machine, where two criterion
/// runs a minute apart differ by more than the effect measured:
/// `RASTER_RATIO=100px` draws that `vs-tiny-skia` workload with the default, every
/// traversal and tiny-skia in turn, round after round (`RASTER_RATIO_ROUNDS`, default
/// 40), and prints each one's fastest round and its ratio to tiny-skia's fastest. The
/// interleaving exposes every contender to the same drifts in the machine's speed, and
/// the fastest round is the one least disturbed.
fn ratio_mode(workload: &str) {
    use std::time::{Duration, Instant};
    let rounds: usize = std::env::var("RASTER_RATIO_ROUNDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(40);
    let Some((_, tris)) = skia_workloads().into_iter().find(|(n, _)| *n == workload) else {
        eprintln!("RASTER_RATIO: no workload {workload:?} (100px, 10000px, sliver)");
        std::process::exit(2);
    };
    let cmds = cmds(&tris);
    let mut models: Vec<(String, Raster)> =
        std::iter::once(("default".to_string(), Traversal::default()))
            .chain(Traversal::ALL.into_iter().map(|t| (format!("{t:?}"), t)))
            .map(|(name, t)| (name, Raster::new(W, H, &setup(t)).expect("setup")))
            .collect();
    let mut sk = Skia::new(&tris);
    let mut best = vec![Duration::MAX; models.len() + 1];
    for _ in 0..rounds {
        for (k, (_, r)) in models.iter_mut().enumerate() {
            let t = Instant::now();
            for cmd in &cmds {
                r.draw(std::hint::black_box(cmd)).expect("draw");
            }
            best[k] = best[k].min(t.elapsed());
        }
        let t = Instant::now();
        sk.fill();
        best[models.len()] = best[models.len()].min(t.elapsed());
    }
    let ts = best[models.len()];
    println!("{workload}: fastest of {rounds} interleaved rounds, ms (× tiny-skia)");
    for (k, (name, _)) in models.iter().enumerate() {
        let ms = best[k].as_secs_f64() * 1e3;
        let x = ts.as_secs_f64() / best[k].as_secs_f64();
        println!("  {name:<12} {ms:8.3} ({x:.2}×)");
    }
    println!("  {:<12} {:8.3}", "tiny-skia", ts.as_secs_f64() * 1e3);
}

fn main() {
    if let Ok(spec) = std::env::var("RASTER_CG") {
        callgrind_mode(&spec);
        return;
    }
    if let Ok(w) = std::env::var("RASTER_RATIO") {
        ratio_mode(&w);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
