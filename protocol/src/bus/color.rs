//! Colours on the bus: RGB888 as is, RGB332 by bit replication, never silently rounded.

use crate::raster::Rgb;

pub(super) fn rgb24(c: Rgb) -> u32 {
    (u32::from(c.r) << 16) | (u32::from(c.g) << 8) | u32::from(c.b)
}

/// The RGB332 byte of a colour that is exactly representable, or `None`.
pub fn rgb332_encode(c: Rgb) -> Option<u8> {
    let q = (c.r >> 5) << 5 | (c.g >> 5) << 2 | c.b >> 6;
    (rgb332_decode(q) == c).then_some(q)
}

/// Expands an RGB332 byte by bit replication (3-bit 7 and 2-bit 3 become 255).
pub fn rgb332_decode(q: u8) -> Rgb {
    let r3 = q >> 5;
    let g3 = (q >> 2) & 7;
    let b2 = q & 3;
    let e3 = |v: u8| (v << 5) | (v << 2) | (v >> 1);
    Rgb::new(e3(r3), e3(g3), b2 * 0x55)
}

/// The nearest RGB332 colour (per channel, by value): the explicit, lossy step a caller
/// takes before packing for an 8-bit layout.
pub fn quantize_rgb332(c: Rgb) -> Rgb {
    // Nearest of the levels bit replication actually produces (ties go to the darker).
    let nearest = |v: u8, levels: u8, expand: fn(u8) -> u8| {
        (0..levels)
            .min_by_key(|&k| (i16::from(expand(k)) - i16::from(v)).abs())
            .unwrap_or(0)
    };
    let e3 = |k: u8| (k << 5) | (k << 2) | (k >> 1);
    let e2 = |k: u8| k * 0x55;
    rgb332_decode(nearest(c.r, 8, e3) << 5 | nearest(c.g, 8, e3) << 2 | nearest(c.b, 4, e2))
}
