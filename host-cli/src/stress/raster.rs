//! The raster category: closed meshes whose shared edges must cover every pixel exactly
//! once, single adversarial triangles checked against the top-left oracle, and every
//! other primitive with extreme values.

use protocol::raster::{
    Aa, AaPattern, Bezier, BezierPatch, Circle, Connectivity, Cull, FillRule, Filter, Line,
    LineAlgo, Pixel, Point, Polygon, RasterCmd, RasterSetup, Rgb, SeedFill, Shade, TexRef,
    Traversal, Triangle, Wrap, MAX_SUBPIXEL_BITS,
};
use rand::rngs::SmallRng;
use rand::Rng;
use sim_target::raster::{oracle, Raster, COORD_LIMIT};

use super::report::CaseResult;

fn rgb(rng: &mut SmallRng) -> Rgb {
    Rgb::new(rng.gen(), rng.gen(), rng.gen())
}

/// A coordinate in sub-pixel units: mostly near the viewport, sometimes at the guard
/// band's limit or just beyond it (which must be refused).
fn coord(rng: &mut SmallRng, bits: u8, side: u32) -> i32 {
    let unit = 1i64 << bits;
    let v: i64 = match rng.gen_range(0..10) {
        0 => COORD_LIMIT as i64 * if rng.gen() { 1 } else { -1 },
        1 => (COORD_LIMIT as i64 - rng.gen_range(0..4)) * if rng.gen() { 1 } else { -1 },
        2 => (COORD_LIMIT as i64 + rng.gen_range(1..4)) * if rng.gen() { 1 } else { -1 },
        3 => rng.gen_range(-(COORD_LIMIT as i64)..=COORD_LIMIT as i64),
        _ => rng.gen_range(-2 * unit..(side as i64 + 2) * unit),
    };
    v as i32
}

fn rand_point(rng: &mut SmallRng, bits: u8, side: u32) -> Point {
    Point {
        x: coord(rng, bits, side),
        y: coord(rng, bits, side),
    }
}

/// Where a point lies with respect to a simple closed polygon, exactly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Inside,
    Boundary,
    Outside,
}

fn polygon_side(poly: &[(i128, i128)], q: (i128, i128)) -> Side {
    let mut wn = 0i32;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let cross = (b.0 - a.0) * (q.1 - a.1) - (b.1 - a.1) * (q.0 - a.0);
        if cross == 0
            && q.0 >= a.0.min(b.0)
            && q.0 <= a.0.max(b.0)
            && q.1 >= a.1.min(b.1)
            && q.1 <= a.1.max(b.1)
        {
            return Side::Boundary;
        }
        if a.1 <= q.1 {
            if b.1 > q.1 && cross > 0 {
                wn += 1;
            }
        } else if b.1 <= q.1 && cross < 0 {
            wn -= 1;
        }
    }
    if wn != 0 {
        Side::Inside
    } else {
        Side::Outside
    }
}

fn cross(o: Point, a: Point, b: Point) -> i128 {
    (a.x as i128 - o.x as i128) * (b.y as i128 - o.y as i128)
        - (a.y as i128 - o.y as i128) * (b.x as i128 - o.x as i128)
}

/// A closed mesh: triangles, and the outline of their union when the mesh is known to
/// tile it (then every pixel strictly inside must be written exactly once).
struct Mesh {
    tris: Vec<[Point; 3]>,
    outline: Option<Vec<Point>>,
}

fn pt(x: i64, y: i64) -> Point {
    Point {
        x: x.clamp(-(COORD_LIMIT as i64), COORD_LIMIT as i64) as i32,
        y: y.clamp(-(COORD_LIMIT as i64), COORD_LIMIT as i64) as i32,
    }
}

/// A fan around a centre: boundary points at sorted angles with gaps below π, so that the
/// union is the star-shaped outline. Sometimes a boundary point is split exactly on its
/// edge (a collinear vertex: zero-area neighbours in the outline) or repeated.
fn fan(rng: &mut SmallRng, bits: u8, side: u32) -> Mesh {
    let unit = 1i64 << bits;
    let huge = rng.gen_ratio(1, 4);
    let c = (
        rng.gen_range(0..=side as i64 * unit),
        rng.gen_range(0..=side as i64 * unit),
    );
    let n = rng.gen_range(3..=10);
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.gen_range(0.0..std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    let max_r = if huge {
        COORD_LIMIT as f64
    } else {
        side as f64 * unit as f64
    };
    let mut pts: Vec<Point> = angles
        .iter()
        .map(|a| {
            let r = rng.gen_range(1.0..max_r.max(2.0));
            pt(
                c.0 + (r * a.cos()).round() as i64,
                c.1 + (r * a.sin()).round() as i64,
            )
        })
        .collect();
    if rng.gen_ratio(1, 3) {
        let k = rng.gen_range(0..pts.len());
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        if (a.x + b.x) % 2 == 0 && (a.y + b.y) % 2 == 0 {
            pts.insert(
                k + 1,
                pt((a.x as i64 + b.x as i64) / 2, (a.y as i64 + b.y as i64) / 2),
            );
        }
    }
    let cp = pt(c.0, c.1);
    let mut tris = Vec::new();
    let mut valid = true;
    for k in 0..pts.len() {
        let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
        // Consistent winding (angles increase); a reflex gap breaks the star.
        if cross(cp, a, b) < 0 {
            valid = false;
        }
        let mut t = [cp, a, b];
        if rng.gen() {
            t.swap(1, 2);
        }
        tris.push(t);
    }
    // The outline must turn by the sum of the fan angles, i.e. once: check with exact
    // orientation that every boundary point is strictly around the centre.
    let total: f64 = (0..pts.len())
        .map(|k| {
            let (a, b) = (pts[k], pts[(k + 1) % pts.len()]);
            let a0 = (a.y as f64 - cp.y as f64).atan2(a.x as f64 - cp.x as f64);
            let b0 = (b.y as f64 - cp.y as f64).atan2(b.x as f64 - cp.x as f64);
            (b0 - a0).rem_euclid(std::f64::consts::TAU)
        })
        .sum();
    if (total - std::f64::consts::TAU).abs() > 1e-6 || pts.contains(&cp) {
        valid = false;
    }
    Mesh {
        tris,
        outline: valid.then_some(pts),
    }
}

/// A jittered grid of convex quads, each split along a random diagonal; one row is a
/// strip. Jitter below a quarter of a cell keeps every quad convex (checked exactly).
fn grid(rng: &mut SmallRng, bits: u8, side: u32) -> Mesh {
    let unit = 1i64 << bits;
    let (nx, ny) = (rng.gen_range(1..=5usize), rng.gen_range(1..=5usize));
    let huge = rng.gen_ratio(1, 5);
    let span = if huge {
        (COORD_LIMIT as i64) / 3
    } else {
        side as i64 * unit
    };
    let cw = rng.gen_range(4..=(span / nx as i64).max(5));
    let ch = rng.gen_range(4..=(span / ny as i64).max(5));
    let j = (cw.min(ch) - 1) / 4;
    let ox = rng.gen_range(-2 * unit..=side as i64 * unit) - if huge { span / 2 } else { 0 };
    let oy = rng.gen_range(-2 * unit..=side as i64 * unit) - if huge { span / 2 } else { 0 };
    let mut v = vec![vec![Point { x: 0, y: 0 }; nx + 1]; ny + 1];
    for (r, row) in v.iter_mut().enumerate() {
        for (c, p) in row.iter_mut().enumerate() {
            let jx = if j > 0 { rng.gen_range(-j..=j) } else { 0 };
            let jy = if j > 0 { rng.gen_range(-j..=j) } else { 0 };
            *p = pt(ox + c as i64 * cw + jx, oy + r as i64 * ch + jy);
        }
    }
    let mut tris = Vec::new();
    let mut valid = true;
    for r in 0..ny {
        for c in 0..nx {
            let q = [v[r][c], v[r][c + 1], v[r + 1][c + 1], v[r + 1][c]];
            let s: Vec<i128> = (0..4)
                .map(|k| cross(q[k], q[(k + 1) % 4], q[(k + 2) % 4]))
                .collect();
            if !(s.iter().all(|&x| x > 0) || s.iter().all(|&x| x < 0)) {
                valid = false;
            }
            let (a, b) = if rng.gen() {
                ([q[0], q[1], q[2]], [q[0], q[2], q[3]])
            } else {
                ([q[0], q[1], q[3]], [q[1], q[2], q[3]])
            };
            for mut t in [a, b] {
                if rng.gen() {
                    t.swap(0, 1);
                }
                tris.push(t);
            }
        }
    }
    let mut outline = Vec::new();
    outline.extend((0..=nx).map(|c| v[0][c]));
    outline.extend((1..=ny).map(|r| v[r][nx]));
    outline.extend((0..nx).rev().map(|c| v[ny][c]));
    outline.extend((1..ny).rev().map(|r| v[r][0]));
    // Clamping at the guard band can fold the outline: only then is it not a tiling.
    if v.iter().flatten().any(|p| {
        p.x.unsigned_abs() >= COORD_LIMIT as u32 || p.y.unsigned_abs() >= COORD_LIMIT as u32
    }) {
        valid = false;
    }
    Mesh {
        tris,
        outline: valid.then_some(outline),
    }
}

fn setup(rng: &mut SmallRng, w: u32, h: u32, bits: u8) -> RasterSetup {
    RasterSetup {
        width: w as u16,
        height: h as u16,
        subpixel_bits: bits,
        background: Rgb::new(0, 0, 0),
        aa: Aa::default(),
        cull: Cull::None,
        traversal: Traversal::ALL[rng.gen_range(0..Traversal::ALL.len())],
    }
}

pub(super) fn raster_case(rng: &mut SmallRng) -> CaseResult {
    let mut r = CaseResult::default();
    let (w, h) = (rng.gen_range(1..=16u32), rng.gen_range(1..=16u32));
    let bits = rng.gen_range(0..=MAX_SUBPIXEL_BITS);
    match rng.gen_range(0..10) {
        0..=3 => raster_mesh(rng, w, h, bits, &mut r),
        4..=7 => raster_triangle(rng, w, h, bits, &mut r),
        _ => raster_prims(rng, w, h, bits, &mut r),
    }
    r
}

fn raster_mesh(rng: &mut SmallRng, w: u32, h: u32, bits: u8, r: &mut CaseResult) {
    let side = w.max(h);
    let mesh = if rng.gen() {
        fan(rng, bits, side)
    } else {
        grid(rng, bits, side)
    };
    let s = setup(rng, w, h, bits);
    let Ok(mut block) = Raster::new(w, h, &s) else {
        r.counts.rejected += 1;
        return;
    };
    block.framebuffer_mut().track_writes(true);
    let color = rgb(rng);
    for t in &mesh.tris {
        let cmd = RasterCmd::Triangle(Triangle {
            v: *t,
            shade: Shade::Flat(color),
            z: None,
            w: None,
            tex: None,
        });
        if block.draw(&cmd).is_err() {
            r.counts.rejected += 1;
        }
    }
    let Some(counts) = block.framebuffer().write_counts() else {
        return;
    };
    let outline: Option<Vec<(i128, i128)>> = mesh.outline.as_ref().map(|o| {
        o.iter()
            .map(|p| (2 * p.x as i128, 2 * p.y as i128))
            .collect()
    });
    let hh = 1i128 << bits;
    for y in 0..h {
        for x in 0..w {
            let got = counts[(y * w + x) as usize] as u64;
            let want = mesh
                .tris
                .iter()
                .filter(|t| oracle::covers(t, bits, Cull::None, x as i64, y as i64))
                .count() as u64;
            if got != want {
                r.counts.coverage += 1;
            }
            if let Some(o) = &outline {
                if got > 1 {
                    r.counts.double_writes += 1;
                }
                let c = ((2 * x as i128 + 1) * hh, (2 * y as i128 + 1) * hh);
                if got == 0 && polygon_side(o, c) == Side::Inside {
                    r.counts.cracks += 1;
                }
            }
        }
    }
    if r.counts.coverage + r.counts.cracks + r.counts.double_writes > 0 {
        r.failure = Some(format!(
            "mesh ({} triangles, {}x{}, {bits} bits, {:?}): {} cracks, {} double writes, {} coverage mismatches; triangles {:?}",
            mesh.tris.len(),
            w,
            h,
            s.traversal,
            r.counts.cracks,
            r.counts.double_writes,
            r.counts.coverage,
            mesh.tris
        ));
    }
}

/// A triangle that is degenerate, a sliver, at the coordinate limits, or random, with
/// random shading, depth, perspective, texture and AA.
fn adversarial_triangle(rng: &mut SmallRng, bits: u8, side: u32) -> [Point; 3] {
    let (a, b) = (rand_point(rng, bits, side), rand_point(rng, bits, side));
    let third = rand_point(rng, bits, side);
    match rng.gen_range(0..6) {
        // collinear: a + k(b − a) for small rational k
        0 => {
            let k = rng.gen_range(-2i64..=3);
            [
                a,
                b,
                pt(
                    a.x as i64 + k * (b.x as i64 - a.x as i64),
                    a.y as i64 + k * (b.y as i64 - a.y as i64),
                ),
            ]
        }
        // coincident vertices
        1 => [a, a, if rng.gen() { a } else { b }],
        // sliver: the midpoint nudged by one sub-pixel unit
        2 => {
            let m = pt(
                (a.x as i64 + b.x as i64) / 2 + rng.gen_range(-1..=1),
                (a.y as i64 + b.y as i64) / 2 + rng.gen_range(-1..=1),
            );
            [a, m, b]
        }
        // axis-aligned edges (exercise the top/left distinction exactly on centres)
        3 => {
            let u = 1i64 << bits;
            let q = |v: i64| (v.div_euclid(u) * u + u / 2) as i32;
            let (x0, y0, x1, y1) = (q(a.x as i64), q(a.y as i64), q(b.x as i64), q(b.y as i64));
            [
                Point { x: x0, y: y0 },
                Point { x: x1, y: y0 },
                Point {
                    x: if rng.gen() { x0 } else { x1 },
                    y: y1,
                },
            ]
        }
        _ => [a, b, third],
    }
}

fn raster_triangle(rng: &mut SmallRng, w: u32, h: u32, bits: u8, r: &mut CaseResult) {
    let side = w.max(h);
    let v = adversarial_triangle(rng, bits, side);
    let mut s = setup(rng, w, h, bits);
    s.cull = [Cull::None, Cull::Clockwise, Cull::CounterClockwise][rng.gen_range(0..3)];
    let aa = rng.gen_ratio(1, 5);
    if aa {
        s.aa = Aa {
            pattern: [
                AaPattern::Regular,
                AaPattern::Jitter,
                AaPattern::Rotated,
                AaPattern::Poisson,
                AaPattern::Coverage,
            ][rng.gen_range(0..5)],
            samples: if rng.gen_ratio(1, 4) {
                rng.gen()
            } else {
                rng.gen_range(1..=16)
            },
        };
    }
    let shade = if rng.gen() {
        Shade::Flat(rgb(rng))
    } else {
        Shade::Gouraud([rgb(rng), rgb(rng), rgb(rng)])
    };
    let extreme_u32 = |rng: &mut SmallRng| match rng.gen_range(0..4) {
        0 => 0,
        1 => u32::MAX,
        2 => 1,
        _ => rng.gen(),
    };
    let z = rng
        .gen_ratio(1, 4)
        .then(|| [0; 3].map(|_: u32| extreme_u32(rng) & 0xff_ffff));
    let wv = rng
        .gen_ratio(1, 4)
        .then(|| [0; 3].map(|_: u32| extreme_u32(rng)));
    let tex = rng.gen_ratio(1, 4).then(|| {
        let e = |rng: &mut SmallRng| match rng.gen_range(0..4) {
            0 => i32::MAX,
            1 => i32::MIN,
            _ => rng.gen_range(-(1 << 20)..(1 << 20)),
        };
        TexRef {
            base: if rng.gen_ratio(1, 8) { rng.gen() } else { 0 },
            width_log2: rng.gen_range(0..=12),
            height_log2: rng.gen_range(0..=12),
            uv: [[e(rng), e(rng)], [e(rng), e(rng)], [e(rng), e(rng)]],
            wrap: if rng.gen() { Wrap::Repeat } else { Wrap::Clamp },
            filter: [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][rng.gen_range(0..3)],
        }
    });
    let Ok(mut block) = Raster::new(w, h, &s) else {
        r.counts.rejected += 1;
        return;
    };
    block.framebuffer_mut().track_writes(true);
    let t = Triangle {
        v,
        shade,
        z,
        w: wv,
        tex,
    };
    if block.draw(&RasterCmd::Triangle(t)).is_err() {
        r.counts.rejected += 1;
        return;
    }
    // Coverage is exact only where every covered pixel is written: no AA (which blends
    // partial pixels) and no depth test.
    if aa || z.is_some() {
        return;
    }
    let Some(counts) = block.framebuffer().write_counts() else {
        return;
    };
    for y in 0..h {
        for x in 0..w {
            let got = counts[(y * w + x) as usize];
            let want = oracle::covers(&v, bits, s.cull, x as i64, y as i64) as u8;
            if got > 1 {
                r.counts.double_writes += 1;
            }
            if got != want {
                r.counts.coverage += 1;
            }
        }
    }
    if r.counts.coverage + r.counts.double_writes > 0 {
        r.failure = Some(format!(
            "triangle {v:?} ({w}x{h}, {bits} bits, {:?}, {:?}): {} coverage mismatches",
            s.traversal, s.cull, r.counts.coverage
        ));
    }
}

fn raster_prims(rng: &mut SmallRng, w: u32, h: u32, bits: u8, r: &mut CaseResult) {
    // Set-ups at and beyond their limits too.
    let (w, h, bits) = match rng.gen_range(0..12) {
        0 => (0, h, bits),
        1 => (w, 5000, bits),
        2 => (w, h, MAX_SUBPIXEL_BITS + rng.gen_range(1..4)),
        _ => (w, h, bits),
    };
    let s = setup(rng, w.max(1), h.max(1), bits);
    let Ok(mut block) = Raster::new(w, h, &s) else {
        r.counts.rejected += 1;
        return;
    };
    let side = w.max(h);
    for _ in 0..rng.gen_range(1..4) {
        let p = |rng: &mut SmallRng| rand_point(rng, bits, side);
        let cmd = match rng.gen_range(0..7) {
            0 => RasterCmd::Line(Line {
                from: p(rng),
                to: p(rng),
                color: Rgb::new(255, 255, 255),
                color_to: None,
                width: 0,
                aa: false,
                algo: LineAlgo::Bresenham,
            }),
            1 => {
                let (from, to) = (p(rng), p(rng));
                RasterCmd::Line(Line {
                    from,
                    to,
                    color: rgb(rng),
                    color_to: rng.gen::<bool>().then(|| rgb(rng)),
                    width: match rng.gen_range(0..4) {
                        0 => u32::MAX,
                        1 => rng.gen_range(0..(64 << bits)),
                        _ => 0,
                    },
                    aa: rng.gen(),
                    algo: if rng.gen() {
                        LineAlgo::Dda
                    } else {
                        LineAlgo::Bresenham
                    },
                })
            }
            2 => RasterCmd::Circle(Circle {
                center: p(rng),
                radius: match rng.gen_range(0..4) {
                    0 => u32::MAX,
                    1 => 0,
                    2 => COORD_LIMIT as u32,
                    _ => rng.gen_range(0..(64 << bits)),
                },
                color: rgb(rng),
                fill: rng.gen(),
            }),
            3 => {
                let mut points = heapless::Vec::new();
                for _ in 0..rng.gen_range(0..=protocol::raster::MAX_POLYGON) {
                    let _ = points.push(p(rng));
                }
                RasterCmd::Polygon(Polygon {
                    points,
                    rule: if rng.gen() {
                        FillRule::EvenOdd
                    } else {
                        FillRule::NonZero
                    },
                    color: rgb(rng),
                })
            }
            4 => {
                let mut points = heapless::Vec::new();
                for _ in 0..rng.gen_range(0..=4) {
                    let _ = points.push(p(rng));
                }
                RasterCmd::Bezier(Bezier {
                    points,
                    color: rgb(rng),
                    tolerance: match rng.gen_range(0..3) {
                        0 => 0,
                        1 => u32::MAX,
                        _ => rng.gen_range(1..1000),
                    },
                })
            }
            5 => {
                let points = core::array::from_fn(|_| p(rng));
                RasterCmd::Patch(BezierPatch {
                    points,
                    steps: if rng.gen_ratio(1, 8) {
                        rng.gen()
                    } else {
                        rng.gen_range(0..6)
                    },
                    color: rgb(rng),
                })
            }
            _ => RasterCmd::Fill(SeedFill {
                seed: Pixel {
                    x: rng.gen_range(0..=side as u16 + 2),
                    y: rng.gen_range(0..=side as u16 + 2),
                },
                color: rgb(rng),
                connectivity: if rng.gen() {
                    Connectivity::Four
                } else {
                    Connectivity::Eight
                },
            }),
        };
        if block.draw(&cmd).is_err() {
            r.counts.rejected += 1;
        }
    }
}
