//! The triangle coverage rule stated once, exactly and independently of the block, so
//! that the tests (`tests/raster_tri.rs`) and `fpgfx stress` check [`super::tri`] against
//! the same reference instead of each against its own.
//!
//! It shares nothing with the block's edge functions: doubled sub-pixel units in `i128`
//! (no width to overflow), the interior side from the signed area, and the top-left rule
//! read off the outward normal of each edge. Slow (three 128-bit edge evaluations per
//! pixel) and meant for small frames or sampled rows.

use protocol::raster::{Cull, Point};

/// Whether the centre of pixel (`px`, `py`) is covered by the triangle `v` (vertices in
/// sub-pixel units with `subpixel_bits` fractional bits), under the top-left rule (docs/requirements.md §0): a centre
/// strictly inside is covered; one exactly on an edge only if that edge is a *left* edge
/// (its outward normal points to −x: the interior lies to its right) or a *top* edge
/// (horizontal, outward normal to −y, i.e. up on a y-down screen: the interior below).
/// Zero-area triangles cover nothing; `cull` discards clockwise or counter-clockwise
/// triangles on a y-down screen (a positive signed area is clockwise there).
pub fn covers(v: &[Point; 3], subpixel_bits: u8, cull: Cull, px: i64, py: i64) -> bool {
    let p: [(i128, i128); 3] = core::array::from_fn(|k| (2 * v[k].x as i128, 2 * v[k].y as i128));
    let area2 = (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0);
    if area2 == 0 {
        return false;
    }
    // y down: a positive signed area is clockwise on screen.
    match (cull, area2 > 0) {
        (Cull::Clockwise, true) | (Cull::CounterClockwise, false) => return false,
        _ => {}
    }
    let s: i128 = area2.signum();
    let h = 1i128 << subpixel_bits;
    let (cx, cy) = ((2 * px as i128 + 1) * h, (2 * py as i128 + 1) * h);
    for k in 0..3 {
        let (a, b) = (p[k], p[(k + 1) % 3]);
        // Inward normal n = s·(−(by − ay), bx − ax); E = n·(c − a).
        let nx = -s * (b.1 - a.1);
        let ny = s * (b.0 - a.0);
        let e = nx * (cx - a.0) + ny * (cy - a.1);
        if e < 0 {
            return false;
        }
        if e == 0 {
            // outward = −n
            let top_left = -nx < 0 || (nx == 0 && -ny < 0);
            if !top_left {
                return false;
            }
        }
    }
    true
}
