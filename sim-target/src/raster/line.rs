//! Lines: Bresenham (p₁ = 2Δy − Δx) and DDA for thin lines, the implicit form for thick
//! lines, distance coverage for anti-aliased ones, colours interpolated along the line.
//!
//! Thin lines run between the pixels containing the end points (seed 000 draws between
//! integer pixels). Both end points are drawn. Symmetry (A→B draws what B→A draws) comes
//! from canonicalising the direction before stepping: the walk always starts at the end
//! with the smaller major coordinate, so the tie-breaks of the decision variable are the
//! same either way.

use super::fb::Framebuffer;
use protocol::raster::{Line, LineAlgo, Rgb};

fn lerp(c0: Rgb, c1: Rgb, k: i64, n: i64) -> Rgb {
    if n == 0 {
        return c0;
    }
    let m = |a: u8, b: u8| ((a as i64 * (n - k) + b as i64 * k + n / 2) / n) as u8;
    Rgb::new(m(c0.r, c1.r), m(c0.g, c1.g), m(c0.b, c1.b))
}

/// Pixels of a thin line from pixel `a` to pixel `b`, in walk order, canonicalised.
/// `plot(x, y, k, n)` gets the step index `k` of `n` measured from `a`.
pub fn thin_pixels<F: FnMut(i64, i64, i64, i64)>(
    a: (i64, i64),
    b: (i64, i64),
    algo: LineAlgo,
    plot: &mut F,
) {
    let (dx, dy) = ((b.0 - a.0).abs(), (b.1 - a.1).abs());
    let x_major = dx >= dy;
    let key = |p: (i64, i64)| if x_major { (p.0, p.1) } else { (p.1, p.0) };
    let swapped = key(b) < key(a);
    let (s, e) = if swapped { (b, a) } else { (a, b) };
    // Work in (major, minor) coordinates.
    let (m0, n0, m1, n1) = if x_major {
        (s.0, s.1, e.0, e.1)
    } else {
        (s.1, s.0, e.1, e.0)
    };
    let dm = m1 - m0;
    let dn = (n1 - n0).abs();
    let sn = if n1 >= n0 { 1 } else { -1 };
    let mut out = |m: i64, n: i64, k: i64| {
        let kk = if swapped { dm - k } else { k };
        if x_major {
            plot(m, n, kk, dm)
        } else {
            plot(n, m, kk, dm)
        }
    };
    match algo {
        LineAlgo::Bresenham => {
            let mut p = 2 * dn - dm;
            let mut n = n0;
            for k in 0..=dm {
                out(m0 + k, n, k);
                if p < 0 {
                    p += 2 * dn;
                } else {
                    n += sn;
                    p += 2 * dn - 2 * dm;
                }
            }
        }
        LineAlgo::Dda => {
            // Minor coordinate in Q32 with rounding folded into the start value.
            let slope = if dm == 0 { 0 } else { ((n1 - n0) << 32) / dm };
            let mut acc = (n0 << 32) + (1 << 31);
            for k in 0..=dm {
                let n = if k == dm { n1 } else { acc >> 32 };
                out(m0 + k, n, k);
                acc += slope;
            }
        }
    }
}

/// Draws a line; returns busy cycles (one per pixel visited).
pub(crate) fn draw(fb: &mut Framebuffer, l: &Line, bits: u8) -> u64 {
    draw_skip_first(fb, l, bits, false)
}

/// Draws a line, optionally without the pixel of `from` (polyline joints).
pub(crate) fn draw_skip_first(fb: &mut Framebuffer, l: &Line, bits: u8, skip_first: bool) -> u64 {
    let c1 = l.color_to.unwrap_or(l.color);
    if l.aa {
        return aa_line(fb, l, bits);
    }
    if l.width > (1u32 << bits) {
        return thick(fb, l, bits);
    }
    let a = ((l.from.x >> bits) as i64, (l.from.y >> bits) as i64);
    let b = ((l.to.x >> bits) as i64, (l.to.y >> bits) as i64);
    let (w, h) = (fb.width() as i64, fb.height() as i64);
    let inside = |p: (i64, i64)| (0..w).contains(&p.0) && (0..h).contains(&p.1);
    if l.color_to.is_none() && !skip_first && !fb.tracking() && inside(a) && inside(b) {
        if l.algo == LineAlgo::Bresenham {
            return fast_bresenham(fb, a, b, l.color);
        }
        // In-bounds DDA: the same walk, writing straight into the buffer.
        let c = l.color;
        let rgb = fb.raw_rgb_mut();
        let mut n = 0u64;
        thin_pixels(a, b, l.algo, &mut |x, y, _, _| {
            let k = 3 * (y * w + x) as usize;
            rgb[k..k + 3].copy_from_slice(&[c.r, c.g, c.b]);
            n += 1;
        });
        fb.add_fragments(n);
        return n;
    }
    let mut n = 0u64;
    let flat = l.color_to.is_none();
    thin_pixels(a, b, l.algo, &mut |x, y, k, len| {
        n += 1;
        if skip_first && (x, y) == a {
            return;
        }
        if (0..w).contains(&x) && (0..h).contains(&y) {
            let c = if flat {
                l.color
            } else {
                lerp(l.color, c1, k, len)
            };
            fb.put(x as u32, y as u32, c);
        }
    });
    n
}

/// The same walk as [`thin_pixels`] (canonical direction, p₁ = 2Δy − Δx) stepping a
/// byte offset, for flat lines that lie inside the framebuffer: no per-pixel clipping.
fn fast_bresenham(fb: &mut Framebuffer, a: (i64, i64), b: (i64, i64), c: Rgb) -> u64 {
    let width = fb.width() as i64;
    let (dx, dy) = ((b.0 - a.0).abs(), (b.1 - a.1).abs());
    let x_major = dx >= dy;
    let key = |p: (i64, i64)| if x_major { (p.0, p.1) } else { (p.1, p.0) };
    let (s, e) = if key(b) < key(a) { (b, a) } else { (a, b) };
    let (dm, dn) = if x_major {
        (e.0 - s.0, dy)
    } else {
        (e.1 - s.1, dx)
    };
    let (step_m, step_n) = if x_major {
        (3, if e.1 >= s.1 { 3 * width } else { -3 * width })
    } else {
        (3 * width, if e.0 >= s.0 { 3 } else { -3 })
    };
    let rgb = fb.raw_rgb_mut();
    let mut o = 3 * (s.1 * width + s.0);
    let mut p = 2 * dn - dm;
    for _ in 0..=dm {
        let k = o as usize;
        rgb[k..k + 3].copy_from_slice(&[c.r, c.g, c.b]);
        o += step_m;
        if p < 0 {
            p += 2 * dn;
        } else {
            o += step_n;
            p += 2 * dn - 2 * dm;
        }
    }
    fb.add_fragments(dm as u64 + 1);
    dm as u64 + 1
}

/// Thick line: pixel centres with |a·x + b·y + c| ≤ h·√(a² + b²)/2 (docs/requirements.md §3), squared to
/// stay in integers, and between the perpendiculars through the end points (butt caps).
fn thick(fb: &mut Framebuffer, l: &Line, bits: u8) -> u64 {
    let c1 = l.color_to.unwrap_or(l.color);
    let hh = 1i128 << bits;
    let (x0, y0) = (2 * l.from.x as i128, 2 * l.from.y as i128);
    let (x1, y1) = (2 * l.to.x as i128, 2 * l.to.y as i128);
    let (a, b) = (y1 - y0, -(x1 - x0));
    let len2 = a * a + b * b;
    let wd = 2 * l.width as i128;
    let pad = wd / 2 + 2 * hh;
    let px = |v: i128| (v.div_euclid(2 * hh)) as i64;
    let (w, h) = (fb.width() as i64, fb.height() as i64);
    let xs = px(x0.min(x1) - pad).max(0)..=px(x0.max(x1) + pad).min(w - 1);
    let ys = px(y0.min(y1) - pad).max(0)..=px(y0.max(y1) + pad).min(h - 1);
    let mut n = 0;
    for j in ys {
        for i in xs.clone() {
            n += 1;
            let cx = (2 * i as i128 + 1) * hh;
            let cy = (2 * j as i128 + 1) * hh;
            let d = a * (cx - x0) + b * (cy - y0);
            let t = (cx - x0) * (x1 - x0) + (cy - y0) * (y1 - y0);
            if 4 * d * d <= wd * wd * len2 && t >= 0 && t <= len2 {
                let k = if len2 == 0 {
                    0
                } else {
                    (t * 1024 / len2) as i64
                };
                fb.put(i as u32, j as u32, lerp(l.color, c1, k, 1024));
            }
        }
    }
    n
}

/// Anti-aliased line: coverage from the distance of the pixel centre to the segment,
/// `clamp(w/2 + 1/2 − d, 0, 1)` across and the same along past the end points.
fn aa_line(fb: &mut Framebuffer, l: &Line, bits: u8) -> u64 {
    let c1 = l.color_to.unwrap_or(l.color);
    let s = (1u64 << bits) as f64;
    let (x0, y0) = (l.from.x as f64 / s, l.from.y as f64 / s);
    let (x1, y1) = (l.to.x as f64 / s, l.to.y as f64 / s);
    let half = (l.width as f64 / s).max(1.0) / 2.0;
    let (dx, dy) = (x1 - x0, y1 - y0);
    let len = dx.hypot(dy);
    let (w, h) = (fb.width() as i64, fb.height() as i64);
    let pad = half + 1.0;
    let xs =
        ((x0.min(x1) - pad).floor() as i64).max(0)..=((x0.max(x1) + pad).ceil() as i64).min(w - 1);
    let ys =
        ((y0.min(y1) - pad).floor() as i64).max(0)..=((y0.max(y1) + pad).ceil() as i64).min(h - 1);
    let mut n = 0;
    for j in ys {
        for i in xs.clone() {
            n += 1;
            let (px, py) = (i as f64 + 0.5 - x0, j as f64 + 0.5 - y0);
            let (t, d) = if len > 0.0 {
                ((px * dx + py * dy) / len, (px * dy - py * dx).abs() / len)
            } else {
                (0.0, px.hypot(py))
            };
            let across = (half + 0.5 - d).clamp(0.0, 1.0);
            let along = (t + 0.5).min(len + 0.5 - t).clamp(0.0, 1.0);
            let cov = (across * along * 255.0).round() as u32;
            if cov > 0 {
                let k = if len > 0.0 {
                    ((t / len).clamp(0.0, 1.0) * 1024.0) as i64
                } else {
                    0
                };
                fb.blend(i as u32, j as u32, lerp(l.color, c1, k, 1024), cov, 255);
            }
        }
    }
    n
}
