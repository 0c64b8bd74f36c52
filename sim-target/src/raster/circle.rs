//! Midpoint circles (seed 000): D₀ = 1 − r; D < 0 ⇒ D += 2x + 3, else D += 2(x − y) + 5
//! and y −= 1; eight-way symmetry; filled circles as one span per row.

use super::fb::Framebuffer;
use protocol::raster::Circle;

/// The first-octant points (x, y), x ≤ y, of a midpoint circle of integer radius `r`.
pub fn octant(r: i64) -> Vec<(i64, i64)> {
    let (mut x, mut y, mut d) = (0i64, r, 1 - r);
    let mut pts = Vec::new();
    while x <= y {
        pts.push((x, y));
        if d < 0 {
            d += 2 * x + 3;
        } else {
            d += 2 * (x - y) + 5;
            y -= 1;
        }
        x += 1;
    }
    pts
}

/// The eight points symmetric to (x, y) about the axes and diagonals.
fn eight_way(x: i64, y: i64) -> [(i64, i64); 8] {
    [
        (x, y),
        (y, x),
        (-x, y),
        (-y, x),
        (x, -y),
        (y, -x),
        (-x, -y),
        (-y, -x),
    ]
}

/// All distinct outline offsets, eight-way symmetric.
pub fn outline(r: i64) -> Vec<(i64, i64)> {
    let mut v: Vec<(i64, i64)> = octant(r)
        .into_iter()
        .flat_map(|(x, y)| eight_way(x, y))
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// Draws a circle around the pixel nearest the centre with the radius rounded to whole
/// pixels; returns busy cycles (one per octant step, or per filled pixel).
pub(crate) fn draw(fb: &mut Framebuffer, c: &Circle, bits: u8) -> u64 {
    let half = if bits == 0 { 0 } else { 1i64 << (bits - 1) };
    let cx = (c.center.x as i64 + half) >> bits;
    let cy = (c.center.y as i64 + half) >> bits;
    let r = (c.radius as i64 + half) >> bits;
    let (w, h) = (fb.width() as i64, fb.height() as i64);
    let oct = octant(r);
    if c.fill {
        // Half-width of each row offset dy: the largest |x| of an outline point on it.
        let mut half_w = vec![-1i64; r as usize + 1];
        for &(x, y) in &oct {
            for (a, b) in [(x, y), (y, x)] {
                let slot = &mut half_w[b as usize];
                *slot = (*slot).max(a);
            }
        }
        let mut n = 0u64;
        for (dy, &hw) in half_w.iter().enumerate() {
            if hw < 0 {
                continue;
            }
            let rows: &[i64] = if dy == 0 { &[0] } else { &[-1, 1] };
            for s in rows {
                let y = cy + s * dy as i64;
                if !(0..h).contains(&y) {
                    continue;
                }
                let x0 = (cx - hw).max(0);
                let x1 = (cx + hw + 1).min(w);
                if x0 < x1 {
                    n += (x1 - x0) as u64;
                    fb.fill_span(y as u32, x0 as u32, x1 as u32, c.color);
                }
            }
        }
        n + oct.len() as u64
    } else {
        // Each symmetric point once: the axes and the diagonal have only four images.
        let mut plot = |dx: i64, dy: i64| {
            let (x, y) = (cx + dx, cy + dy);
            if (0..w).contains(&x) && (0..h).contains(&y) {
                fb.put(x as u32, y as u32, c.color);
            }
        };
        for &(x, y) in &oct {
            if y == 0 {
                plot(0, 0);
            } else if x == 0 {
                for (dx, dy) in [(0, y), (0, -y), (y, 0), (-y, 0)] {
                    plot(dx, dy);
                }
            } else if x == y {
                for (dx, dy) in [(x, x), (-x, x), (x, -x), (-x, -x)] {
                    plot(dx, dy);
                }
            } else {
                for (dx, dy) in eight_way(x, y) {
                    plot(dx, dy);
                }
            }
        }
        oct.len() as u64
    }
}
