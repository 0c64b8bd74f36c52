//! Seed fill (span-based, explicit bounded stack) and scanline polygon fill.

use super::{fb::Framebuffer, RasterError};
use protocol::raster::{Connectivity, FillRule, Polygon, SeedFill};

/// Spans the seed fill may hold at once: the block's stack RAM. Span seeding needs at
/// most a few entries per row boundary of the region, so mazes at the largest viewport
/// fit; a pathological region that does not is an error, never a crash.
pub const FILL_STACK: usize = 1 << 16;

/// Fills the region of the seed's colour connected to the seed; returns busy cycles
/// (pixels read). Never recursive: spans go through a bounded explicit stack.
pub fn seed_fill(fb: &mut Framebuffer, f: &SeedFill) -> Result<u64, RasterError> {
    let (w, h) = (fb.width() as i64, fb.height() as i64);
    let (sx, sy) = (f.seed.x as i64, f.seed.y as i64);
    let Some(target) = fb.pixel(f.seed.x as u32, f.seed.y as u32) else {
        return Err(RasterError::SeedOutside {
            x: f.seed.x,
            y: f.seed.y,
        });
    };
    if target == f.color {
        return Ok(1);
    }
    let diag = if f.connectivity == Connectivity::Eight {
        1
    } else {
        0
    };
    let is_t = |fb: &Framebuffer, x: i64, y: i64| fb.pixel(x as u32, y as u32) == Some(target);
    let mut stack: Vec<(i64, i64)> = Vec::with_capacity(256);
    stack.push((sx, sy));
    let mut reads = 0u64;
    while let Some((x, y)) = stack.pop() {
        reads += 1;
        if !is_t(fb, x, y) {
            continue;
        }
        let mut l = x;
        while l > 0 && is_t(fb, l - 1, y) {
            l -= 1;
        }
        let mut r = x;
        while r + 1 < w && is_t(fb, r + 1, y) {
            r += 1;
        }
        reads += (r - l + 1) as u64;
        fb.fill_span(y as u32, l as u32, r as u32 + 1, f.color);
        for ny in [y - 1, y + 1] {
            if !(0..h).contains(&ny) {
                continue;
            }
            let mut i = (l - diag).max(0);
            let end = (r + diag).min(w - 1);
            while i <= end {
                reads += 1;
                if is_t(fb, i, ny) {
                    if stack.len() >= FILL_STACK {
                        return Err(RasterError::FillStack(FILL_STACK));
                    }
                    stack.push((i, ny));
                    while i <= end && is_t(fb, i, ny) {
                        i += 1;
                    }
                } else {
                    i += 1;
                }
            }
        }
    }
    Ok(reads)
}

/// Scanline polygon fill with the even-odd or non-zero rule. A pixel is inside when its
/// centre is; crossings are exact rationals reduced to "first pixel centre at or right
/// of the crossing", and edges are half-open in y so shared vertices count once.
pub fn polygon(fb: &mut Framebuffer, p: &Polygon, bits: u8) -> u64 {
    let n = p.points.len();
    if n < 3 {
        return 0;
    }
    let hh = 1i128 << bits;
    let pts: Vec<(i128, i128)> = p
        .points
        .iter()
        .map(|q| (2 * q.x as i128, 2 * q.y as i128))
        .collect();
    let miny = pts.iter().map(|q| q.1).min().unwrap_or(0);
    let maxy = pts.iter().map(|q| q.1).max().unwrap_or(0);
    let (w, h) = (fb.width() as i64, fb.height() as i64);
    let j0 = ((miny - hh).div_euclid(2 * hh) as i64).max(0);
    let j1 = ((maxy - hh).div_euclid(2 * hh) as i64 + 1).min(h);
    let mut xs: Vec<(i64, i32)> = Vec::with_capacity(n);
    let mut busy = 0u64;
    for j in j0..j1 {
        let yc = (2 * j as i128 + 1) * hh;
        xs.clear();
        for k in 0..n {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            if a.1 == b.1 {
                continue;
            }
            let (lo, hi, dir) = if a.1 < b.1 { (a, b, 1) } else { (b, a, -1) };
            if !(lo.1 <= yc && yc < hi.1) {
                continue;
            }
            // x = lo.x + (yc − lo.y)(hi.x − lo.x)/(hi.y − lo.y) = num/den, den > 0.
            let den = hi.1 - lo.1;
            let num = lo.0 * den + (yc - lo.1) * (hi.0 - lo.0);
            // First i with (2i + 1)·hh ≥ num/den.
            let t = num - den * hh;
            let d = 2 * hh * den;
            let i = -((-t).div_euclid(d));
            xs.push((i.clamp(-1, w as i128 + 1) as i64, dir));
        }
        xs.sort_unstable();
        busy += 1 + xs.len() as u64;
        let mut wind = 0i32;
        let mut count = 0u32;
        for k in 0..xs.len() {
            wind += xs[k].1;
            count += 1;
            let inside = match p.rule {
                FillRule::EvenOdd => count % 2 == 1,
                FillRule::NonZero => wind != 0,
            };
            if inside && k + 1 < xs.len() {
                let x0 = xs[k].0.clamp(0, w);
                let x1 = xs[k + 1].0.clamp(0, w);
                if x0 < x1 {
                    busy += (x1 - x0) as u64;
                    fb.fill_span(j as u32, x0 as u32, x1 as u32, p.color);
                }
            }
        }
    }
    busy
}
