//! Seeded generators of FITkit commands: whole-pixel coordinates in 0..512, RGB332.

use protocol::bus::rgb332_decode;
use protocol::raster::{Line, LineAlgo, Point, RasterCmd, Rgb, Shade, Triangle};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// Largest FITkit coordinate (9 bits).
pub const MAX_COORD: i32 = 511;

/// The generator of one test, so a failing case replays from its seed.
pub fn rng(seed: u64) -> SmallRng {
    SmallRng::seed_from_u64(seed)
}

/// Any RGB332 colour.
pub fn color(rng: &mut SmallRng) -> Rgb {
    rgb332_decode(rng.gen())
}

/// An RGB332 colour other than `not` (so a write is visible on that background).
pub fn color_except(rng: &mut SmallRng, not: Rgb) -> Rgb {
    loop {
        let c = color(rng);
        if c != not {
            return c;
        }
    }
}

pub fn line(a: (i32, i32), b: (i32, i32), color: Rgb) -> RasterCmd {
    RasterCmd::Line(Line {
        from: Point { x: a.0, y: a.1 },
        to: Point { x: b.0, y: b.1 },
        color,
        color_to: None,
        width: 1,
        aa: false,
        algo: LineAlgo::Bresenham,
    })
}

pub fn triangle(v: [(i32, i32); 3], color: Rgb) -> RasterCmd {
    RasterCmd::Triangle(Triangle {
        v: v.map(|(x, y)| Point { x, y }),
        shade: Shade::Flat(color),
        z: None,
        w: None,
        tex: None,
    })
}

/// A point in `0..=max_x × 0..=max_y`.
pub fn point(rng: &mut SmallRng, max_x: i32, max_y: i32) -> (i32, i32) {
    (rng.gen_range(0..=max_x), rng.gen_range(0..=max_y))
}

/// A coordinate that is the viewport's limit 0 or 511 two times in three, else anywhere.
pub fn limit_coord(rng: &mut SmallRng) -> i32 {
    match rng.gen_range(0..3) {
        0 => 0,
        1 => MAX_COORD,
        _ => rng.gen_range(0..=MAX_COORD),
    }
}

/// A point within `r` of `c`, clamped to the coordinate range.
pub fn near(rng: &mut SmallRng, c: (i32, i32), r: i32) -> (i32, i32) {
    let k = |v: i32, rng: &mut SmallRng| (v + rng.gen_range(-r..=r)).clamp(0, MAX_COORD);
    (k(c.0, rng), k(c.1, rng))
}

/// A sliver: two vertices far apart, the third within one pixel of the line through
/// them (or on it: a degenerate triangle).
pub fn sliver(rng: &mut SmallRng, max_x: i32, max_y: i32) -> [(i32, i32); 3] {
    let a = point(rng, max_x, max_y);
    let b = point(rng, max_x, max_y);
    let t = rng.gen_range(0..=16);
    let m = (a.0 + (b.0 - a.0) * t / 16, a.1 + (b.1 - a.1) * t / 16);
    [a, b, near(rng, m, 1)]
}

/// A triangle whose edges have odd x and y extents, so each passes through the centre of
/// a pixel (its midpoint is at half-integers): the fill rule decides those pixels.
pub fn through_centres(rng: &mut SmallRng, max: i32) -> [(i32, i32); 3] {
    loop {
        let a = point(rng, max, max);
        let odd = |rng: &mut SmallRng| 2 * rng.gen_range(-20..=20) + 1;
        let b = (a.0 + odd(rng), a.1 + odd(rng));
        // The third vertex differs from a by even steps, so b→c is odd-odd too; a→c is
        // even-even, which passes through pixel centres when halving it once more is odd.
        let even = |rng: &mut SmallRng| 2 * (2 * rng.gen_range(-10..=10) + 1);
        let c = (a.0 + even(rng), a.1 + even(rng));
        let ok = |p: (i32, i32)| (0..=max).contains(&p.0) && (0..=max).contains(&p.1);
        if ok(b) && ok(c) {
            return [a, b, c];
        }
    }
}
