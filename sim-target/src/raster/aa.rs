//! Anti-aliasing (seed 001): supersampling with regular, jittered, rotated-grid and
//! Poisson-disc patterns, and analytic coverage. Samples are tested with the same edge
//! functions and top-left rule as the aliased path, in `i128` at 1/256-pixel sample
//! offsets; the pixel gets `colour·k/n + old·(n−k)/n`.

use super::fb::Framebuffer;
use super::tri;
use protocol::raster::{Aa, AaPattern, Cull, Point, Shade, Triangle};

/// Sample offsets inside the pixel in 1/256 px, deterministic for a pattern and count.
/// Grid-based patterns round the count to a square `m²` (m ≥ 1).
pub fn pattern(p: AaPattern, samples: u8) -> Vec<(u32, u32)> {
    let n = samples.max(1) as u32;
    let m = ((n as f64).sqrt().round() as u32).max(1);
    let cell = |a: u32, k: u32| (2 * a + 1) * 128 / k;
    let mut rng = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        // xorshift64*: fixed seed, so "random" patterns are reproducible golden data.
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        (rng.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 32) as u32
    };
    match p {
        AaPattern::None | AaPattern::Coverage => vec![(128, 128)],
        AaPattern::Regular => (0..m * m)
            .map(|k| (cell(k % m, m), cell(k / m, m)))
            .collect(),
        AaPattern::Jitter => (0..m * m)
            .map(|k| {
                let (a, b) = (k % m, k / m);
                (
                    a * 256 / m + next() % (256 / m).max(1),
                    b * 256 / m + next() % (256 / m).max(1),
                )
            })
            .collect(),
        AaPattern::Rotated => {
            // n-rooks on an m² × m² grid: (a, b) → x = a·m + b, y = b·m + (m − 1 − a).
            // For m = 2 this is the classic RGSS pattern.
            let k2 = m * m;
            (0..k2)
                .map(|k| {
                    let (a, b) = (k / m, k % m);
                    (cell(a * m + b, k2), cell(b * m + (m - 1 - a), k2))
                })
                .collect()
        }
        AaPattern::Poisson => {
            // Dart throwing with a shrinking radius until n samples fit.
            let mut r = 0.75 * 256.0 / (n as f64).sqrt();
            let mut pts: Vec<(u32, u32)> = Vec::new();
            let mut tries = 0;
            while pts.len() < n as usize {
                let c = (next() % 256, next() % 256);
                let ok = pts.iter().all(|q| {
                    let dx = q.0 as f64 - c.0 as f64;
                    let dy = q.1 as f64 - c.1 as f64;
                    dx.hypot(dy) >= r
                });
                if ok {
                    pts.push(c);
                }
                tries += 1;
                if tries % 200 == 0 {
                    r *= 0.9;
                }
            }
            pts
        }
    }
}

/// Samples of pixel (i, j) inside the triangle, out of `offs.len()`.
pub fn covered(v: &[Point; 3], bits: u8, offs: &[(u32, u32)], i: i64, j: i64) -> u32 {
    let Some(cw) = tri::is_clockwise(v) else {
        return 0;
    };
    let o = if cw { [0, 2, 1] } else { [0, 1, 2] };
    let p: [(i128, i128); 3] =
        core::array::from_fn(|k| ((v[o[k]].x as i128) << 8, (v[o[k]].y as i128) << 8));
    let edges: [(i128, i128, i128, i128, bool); 3] = core::array::from_fn(|k| {
        let (a, b) = (p[(k + 1) % 3], p[(k + 2) % 3]);
        let (ea, eb) = (b.1 - a.1, -(b.0 - a.0));
        (ea, eb, a.0, a.1, ea > 0 || (ea == 0 && eb > 0))
    });
    let mut k = 0;
    for &(ox, oy) in offs {
        let sx = ((i as i128) * 256 + ox as i128) << bits;
        let sy = ((j as i128) * 256 + oy as i128) << bits;
        let inside = edges.iter().all(|&(ea, eb, x0, y0, tl)| {
            let e = ea * (sx - x0) + eb * (sy - y0);
            e > 0 || (e == 0 && tl)
        });
        k += inside as u32;
    }
    k
}

/// Exact area of triangle ∩ pixel (i, j) in pixels (Sutherland–Hodgman in f64).
pub fn exact_coverage(v: &[Point; 3], bits: u8, i: i64, j: i64) -> f64 {
    let s = (1u64 << bits) as f64;
    let mut poly: Vec<(f64, f64)> = v
        .iter()
        .map(|p| (p.x as f64 / s - i as f64, p.y as f64 / s - j as f64))
        .collect();
    // Clip against 0 ≤ x ≤ 1, 0 ≤ y ≤ 1.
    type Side = fn((f64, f64)) -> f64;
    let sides: [Side; 4] = [|p| p.0, |p| 1.0 - p.0, |p| p.1, |p| 1.0 - p.1];
    for side in sides {
        let mut out = Vec::with_capacity(poly.len() + 2);
        for k in 0..poly.len() {
            let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
            let (da, db) = (side(a), side(b));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let t = da / (da - db);
                out.push((a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t));
            }
        }
        poly = out;
        if poly.is_empty() {
            return 0.0;
        }
    }
    let mut a2 = 0.0;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        a2 += a.0 * b.1 - a.1 * b.0;
    }
    (a2 / 2.0).abs()
}

/// Pixel bounding box (inclusive) of the triangle's closure, clipped to the viewport.
fn bbox(v: &[Point; 3], bits: u8, w: u32, h: u32) -> Option<(i64, i64, i64, i64)> {
    let x0 = v.iter().map(|p| p.x).min()? as i64 >> bits;
    let x1 = v.iter().map(|p| p.x).max()? as i64 >> bits;
    let y0 = v.iter().map(|p| p.y).min()? as i64 >> bits;
    let y1 = v.iter().map(|p| p.y).max()? as i64 >> bits;
    let r = (
        x0.max(0),
        y0.max(0),
        x1.min(w as i64 - 1),
        y1.min(h as i64 - 1),
    );
    (r.0 <= r.2 && r.1 <= r.3).then_some(r)
}

/// Draws an anti-aliased triangle (flat colour; Gouraud uses the pixel-centre colour);
/// returns pixels visited. `shade(fb, x, y, colour)` is asked for every pixel with
/// coverage: it may run the depth test and substitute a texture colour, and returns the
/// colour to blend or `None` to leave the pixel (depth test failed).
pub(crate) fn draw_triangle(
    fb: &mut Framebuffer,
    t: &Triangle,
    bits: u8,
    cull: Cull,
    aa: Aa,
    shade: &mut dyn FnMut(
        &mut Framebuffer,
        u32,
        u32,
        protocol::raster::Rgb,
    ) -> Option<protocol::raster::Rgb>,
) -> u64 {
    let Some(cw) = tri::is_clockwise(&t.v) else {
        return 0;
    };
    if matches!(
        (cull, cw),
        (Cull::Clockwise, true) | (Cull::CounterClockwise, false)
    ) {
        return 0;
    }
    let Some((x0, y0, x1, y1)) = bbox(&t.v, bits, fb.width(), fb.height()) else {
        return 0;
    };
    let offs = pattern(aa.pattern, aa.samples);
    let levels = if aa.samples == 0 {
        256
    } else {
        aa.samples as u32
    };
    let mut n = 0;
    for j in y0..=y1 {
        for i in x0..=x1 {
            n += 1;
            let (k, of) = if aa.pattern == AaPattern::Coverage {
                (
                    (exact_coverage(&t.v, bits, i, j) * levels as f64).round() as u32,
                    levels,
                )
            } else {
                (covered(&t.v, bits, &offs, i, j), offs.len() as u32)
            };
            if k > 0 {
                let c = match t.shade {
                    Shade::Flat(c) => c,
                    Shade::Gouraud(c) => gouraud_at(&t.v, bits, &c, i, j),
                };
                if let Some(c) = shade(fb, i as u32, j as u32, c) {
                    fb.blend(i as u32, j as u32, c, k, of);
                }
            }
        }
    }
    n
}

fn gouraud_at(
    v: &[Point; 3],
    bits: u8,
    c: &[protocol::raster::Rgb; 3],
    i: i64,
    j: i64,
) -> protocol::raster::Rgb {
    let s = (1u64 << bits) as f64;
    let p: Vec<(f64, f64)> = v.iter().map(|q| (q.x as f64 / s, q.y as f64 / s)).collect();
    let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
    let e = |a: (f64, f64), b: (f64, f64)| (x - a.0) * (b.1 - a.1) - (y - a.1) * (b.0 - a.0);
    let area = e(p[0], p[1]) + e(p[1], p[2]) + e(p[2], p[0]);
    let l = [
        e(p[1], p[2]) / area,
        e(p[2], p[0]) / area,
        e(p[0], p[1]) / area,
    ]
    .map(|w| w.clamp(0.0, 1.0));
    let sum: f64 = l.iter().sum();
    let ch = |f: fn(&protocol::raster::Rgb) -> u8| -> u8 {
        let v: f64 = (0..3).map(|k| f(&c[k]) as f64 * l[k]).sum::<f64>() / sum.max(1e-12);
        v.round().clamp(0.0, 255.0) as u8
    };
    protocol::raster::Rgb::new(ch(|c| c.r), ch(|c| c.g), ch(|c| c.b))
}
