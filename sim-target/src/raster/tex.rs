//! Texture sampling (seed 001): UV in Q16.16, repeat/clamp, nearest, bilinear with
//! 8-bit weights, trilinear between MIP levels stored after the base level.

use super::{tri::TriSetup, RasterError};
use protocol::raster::{Filter, Rgb, TexRef, Wrap};

/// Texels of the whole MIP chain (or just the base level when not trilinear).
pub fn footprint(t: &TexRef) -> u64 {
    let levels = if t.filter == Filter::Trilinear {
        max_level(t) + 1
    } else {
        1
    };
    (0..levels)
        .map(|l| level_size(t, l).0 as u64 * level_size(t, l).1 as u64)
        .sum()
}

/// Largest MIP level (1 × 1 in the longer direction).
pub(crate) fn max_level(t: &TexRef) -> u32 {
    t.width_log2.max(t.height_log2) as u32
}

fn level_size(t: &TexRef, l: u32) -> (u32, u32) {
    (
        1 << (t.width_log2 as u32).saturating_sub(l),
        1 << (t.height_log2 as u32).saturating_sub(l),
    )
}

fn level_base(t: &TexRef, l: u32) -> u64 {
    t.base as u64
        + (0..l)
            .map(|k| level_size(t, k).0 as u64 * level_size(t, k).1 as u64)
            .sum::<u64>()
}

/// Refuses textures that reach past memory (or have absurd sizes).
pub(crate) fn check(t: &TexRef, words: usize) -> Result<(), RasterError> {
    let err = RasterError::Texture {
        base: t.base,
        w: 1u32.checked_shl(t.width_log2 as u32).unwrap_or(0),
        h: 1u32.checked_shl(t.height_log2 as u32).unwrap_or(0),
        words,
    };
    if t.width_log2 > 15 || t.height_log2 > 15 {
        return Err(err);
    }
    if t.base as u64 + footprint(t) > words as u64 {
        return Err(err);
    }
    Ok(())
}

/// Level of detail in Q8 (8 fractional bits), one per triangle from the affine UV
/// gradient: log2 of the longer texel-space step of one pixel, clamped to the chain.
pub fn lod(t: &TexRef, s: &TriSetup) -> u32 {
    if t.filter != Filter::Trilinear || s.area == 0 {
        return 0;
    }
    let area = s.area as f64;
    let grad = |k: usize, scale: f64| {
        let dx: f64 = (0..3)
            .map(|v| t.uv[v][k] as f64 * s.edges[v].a as f64)
            .sum::<f64>()
            / area;
        let dy: f64 = (0..3)
            .map(|v| t.uv[v][k] as f64 * s.edges[v].b as f64)
            .sum::<f64>()
            / area;
        (dx * scale / 65536.0, dy * scale / 65536.0)
    };
    let (dudx, dudy) = grad(0, (1u32 << t.width_log2) as f64);
    let (dvdx, dvdy) = grad(1, (1u32 << t.height_log2) as f64);
    let rho = dudx.hypot(dvdx).max(dudy.hypot(dvdy));
    if rho <= 1.0 {
        return 0;
    }
    let l = (rho.log2() * 256.0).round();
    (l as u32).min(max_level(t) * 256)
}

fn wrap(i: i64, n: u32, w: Wrap) -> u32 {
    match w {
        Wrap::Repeat => (i & (n as i64 - 1)) as u32,
        Wrap::Clamp => i.clamp(0, n as i64 - 1) as u32,
    }
}

fn texel(mem: &[u32], t: &TexRef, l: u32, x: i64, y: i64) -> u32 {
    let (w, h) = level_size(t, l);
    let (x, y) = (wrap(x, w, t.wrap), wrap(y, h, t.wrap));
    let idx = level_base(t, l) + y as u64 * w as u64 + x as u64;
    mem.get(idx as usize).copied().unwrap_or(0)
}

fn unpack(c: u32) -> [u32; 3] {
    [c >> 16 & 255, c >> 8 & 255, c & 255]
}

/// Nearest texel of level `l` at (u, v) in Q16.16.
pub(crate) fn nearest(mem: &[u32], t: &TexRef, l: u32, u: i64, v: i64) -> [u32; 3] {
    let (w, h) = level_size(t, l);
    let x = (u * w as i64) >> 16;
    let y = (v * h as i64) >> 16;
    unpack(texel(mem, t, l, x, y))
}

/// Bilinear sample of level `l` at (u, v) in Q16.16, 8-bit weights, channels ×256
/// (8 fractional bits kept for the trilinear blend).
pub fn bilinear_q8(mem: &[u32], t: &TexRef, l: u32, u: i64, v: i64) -> [u32; 3] {
    let (w, h) = level_size(t, l);
    // Texel centres sit at +0.5: shift by half a texel before splitting.
    let pu = ((u * w as i64) >> 8) - 128;
    let pv = ((v * h as i64) >> 8) - 128;
    let (x, fx) = (pu >> 8, (pu & 255) as u32);
    let (y, fy) = (pv >> 8, (pv & 255) as u32);
    let t00 = unpack(texel(mem, t, l, x, y));
    let t10 = unpack(texel(mem, t, l, x + 1, y));
    let t01 = unpack(texel(mem, t, l, x, y + 1));
    let t11 = unpack(texel(mem, t, l, x + 1, y + 1));
    core::array::from_fn(|c| {
        let s = (256 - fx) * (256 - fy) * t00[c]
            + fx * (256 - fy) * t10[c]
            + (256 - fx) * fy * t01[c]
            + fx * fy * t11[c];
        (s + 128) >> 8
    })
}

/// The filtered colour at (u, v) in Q16.16 with level of detail `lod` (Q8).
pub fn sample(mem: &[u32], t: &TexRef, u: i64, v: i64, lod: u32) -> Rgb {
    let c = match t.filter {
        Filter::Nearest => nearest(mem, t, 0, u, v).map(|c| c << 8),
        Filter::Bilinear => bilinear_q8(mem, t, 0, u, v),
        Filter::Trilinear => {
            let l0 = (lod >> 8).min(max_level(t));
            let l1 = (l0 + 1).min(max_level(t));
            let f = lod & 255;
            let a = bilinear_q8(mem, t, l0, u, v);
            let b = bilinear_q8(mem, t, l1, u, v);
            core::array::from_fn(|k| (a[k] * (256 - f) + b[k] * f + 128) >> 8)
        }
    };
    let r = c.map(|v| ((v + 128) >> 8).min(255) as u8);
    Rgb::new(r[0], r[1], r[2])
}
