//! Procedural textures in the block's 256×256-word texture memory, (u, v) mappings and
//! filtering. Generation runs once per scene in f64 (the seed fills the memory from the
//! MicroBlaze); only mapping and sampling run in the target format.

use super::scene::{Filter, Mapping, Scene, TextureKind};
use super::vec::V3;
use super::Math;
use crate::num::{self, Scalar};
use core::f64::consts::PI;
use std::sync::{Arc, Mutex};

/// TEXT_PAGE_SIZE: words of texture memory shared by all textures.
pub const TEXTURE_WORDS: usize = 256 * 256;

/// Side of each texture when `n` textures share the memory: the largest power of two with
/// n·side² ≤ 65 536 (256 for one texture, 128 for up to four, 64 for up to sixteen).
pub fn side_for(n: usize) -> usize {
    let mut side = 256;
    while side > 1 && n.max(1) * side * side > TEXTURE_WORDS {
        side /= 2;
    }
    side
}

/// Word index of texture slot `slot`'s first texel when every slot is `side`² words.
pub fn slot_base(slot: usize, side: usize) -> usize {
    slot * side * side
}

/// The texture memory the block samples for `scene`: each textured material's texture in
/// its slot, in material order, the rest zero. The kernel renders from this, and it is
/// public because it is an input of the hardware block (the seed's MicroBlaze fills it
/// before a frame): test vectors carry it so that a testbench can load it into its DUT.
pub fn memory(scene: &Scene) -> Vec<u32> {
    let side = super::plan(scene).texture_side;
    let mut mem = vec![0u32; TEXTURE_WORDS];
    let textures = scene.materials.iter().filter_map(|m| m.texture.as_ref());
    for (slot, t) in textures.enumerate() {
        let dst = mem.get_mut(slot_base(slot, side)..).unwrap_or_default();
        for (w, &texel) in dst.iter_mut().zip(texels(t.kind, side).iter()) {
            *w = texel;
        }
    }
    mem
}

/// How many generated textures [`texels`] keeps.
const KEPT_TEXTURES: usize = 16;

/// One texture's `side`² texels, row by row, generated once per process for each
/// (kind, side) among the last sixteen made: marble and wood cost f64 value noise per
/// texel (65 536 texels at side 256), which dominated small frames rendered again and
/// again from one scene (an animation's frames, a testbench's loop, a preview, the C
/// library checking a caller's texture memory before it renders). The values are
/// [`texel`]'s whatever the cache holds.
pub fn texels(kind: TextureKind, side: usize) -> Arc<[u32]> {
    type Kept = Vec<((TextureKind, usize), Arc<[u32]>)>;
    static KEPT: Mutex<Kept> = Mutex::new(Vec::new());
    let key = (kind, side);
    // A poisoned lock (a panic elsewhere while it was held) only costs the cache.
    if let Some(t) = KEPT
        .lock()
        .ok()
        .and_then(|kept| kept.iter().find(|(k, _)| *k == key).map(|(_, t)| t.clone()))
    {
        return t;
    }
    let t: Arc<[u32]> = (0..side * side)
        .map(|i| texel(kind, i % side, i / side, side))
        .collect();
    if let Ok(mut kept) = KEPT.lock() {
        if kept.len() >= KEPT_TEXTURES {
            kept.remove(0);
        }
        kept.push((key, t.clone()));
    }
    t
}

/// Whether a texture's texels are a grey mix factor (true) or a colour (false).
pub fn is_grey(kind: TextureKind) -> bool {
    !matches!(kind, TextureKind::RgbDots)
}

fn hash(seed: u32, x: i64, y: i64) -> f64 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (seed as u64).wrapping_mul(0x1656_67B1_9E37_79F9);
    h ^= h >> 33;
    h = h.wrapping_mul(0xFF51_AFD7_ED55_8CCD);
    h ^= h >> 33;
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// Smooth value noise in [0, 1] on a unit lattice.
pub fn value_noise(seed: u32, x: f64, y: f64) -> f64 {
    // `floor_f64`: `f64::floor` bit for bit without its libm call (texture generation runs
    // per scene; at small frame sizes it showed in the profile)
    let (xf, yf) = (num::floor_f64(x), num::floor_f64(y));
    let (fx, fy) = (x - xf, y - yf);
    let (xi, yi) = (xf as i64, yf as i64);
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sy) = (s(fx), s(fy));
    let a = hash(seed, xi, yi);
    let b = hash(seed, xi + 1, yi);
    let c = hash(seed, xi, yi + 1);
    let d = hash(seed, xi + 1, yi + 1);
    let top = a + (b - a) * sx;
    let bot = c + (d - c) * sx;
    top + (bot - top) * sy
}

/// Turbulence: Σ noise(2^o·p)/2^o over five octaves, in [0, ~2).
pub fn turbulence(seed: u32, x: f64, y: f64) -> f64 {
    let mut sum = 0.0;
    let mut f = 1.0;
    for _ in 0..5 {
        sum += value_noise(seed, x * f, y * f) / f;
        f *= 2.0;
    }
    sum
}

/// One texel (0x00RRGGBB; grey textures repeat the mix byte in all three).
pub fn texel(kind: TextureKind, x: usize, y: usize, side: usize) -> u32 {
    let grey = |g: u32| (g << 16) | (g << 8) | g;
    match kind {
        TextureKind::Xor => {
            let g = ((x * 256 / side) ^ (y * 256 / side)) as u32 & 255;
            grey(g)
        }
        TextureKind::Checkerboard { cell } => {
            let cell = (cell.max(1)) as usize;
            grey(if (x / cell + y / cell).is_multiple_of(2) {
                255
            } else {
                0
            })
        }
        TextureKind::RgbDots => match (y * side + x) % 3 {
            0 => 0xFF_0000,
            1 => 0x00_FF00,
            _ => 0x00_00FF,
        },
        TextureKind::Marble { seed } => {
            let (u, v) = (x as f64 / side as f64, y as f64 / side as f64);
            let t = turbulence(seed, u * 8.0, v * 8.0);
            let m = 0.5 * (1.0 + (2.0 * PI * 4.0 * u + 5.0 * t).sin());
            grey((m * 255.0).floor().clamp(0.0, 255.0) as u32)
        }
        TextureKind::Wood { seed } => {
            let (u, v) = (x as f64 / side as f64 - 0.5, y as f64 / side as f64 - 0.5);
            let r = (u * u + v * v).sqrt();
            let t = turbulence(seed, u * 6.0 + 10.0, v * 6.0 + 10.0);
            let w = (12.0 * r + 0.3 * t).fract();
            grey((w * 255.0).floor().clamp(0.0, 255.0) as u32)
        }
    }
}

/// (u, v) ∈ [0, 1)² of an object-space point by a mapping.
pub fn map_uv<S: Scalar>(mapping: Mapping, p: V3<S>, m: &Math) -> (S, S) {
    let one = S::one();
    let around = || {
        let a = num::atan2(p.x, p.z, m.atan).mul_rn(S::from_f64(1.0 / (2.0 * PI)));
        if a < S::zero() {
            a + one
        } else {
            a
        }
    };
    match mapping {
        Mapping::Planar => ((p.x + one).half_rn(), (p.z + one).half_rn()),
        Mapping::Cylindrical => (around(), (p.y + one).half_rn()),
        Mapping::Spherical => (
            around(),
            one - num::acos(p.y, m.acos).mul_rn(S::from_f64(1.0 / PI)),
        ),
    }
}

/// A texture's slot in memory, in the target format.
///
/// Built once per scene ([`TexSlot::new`]): everything a sample needs that does not depend
/// on (u, v) — the byte→level table, the side in the format, the wrap mask — is computed
/// here instead of per sample (the hardware has them as constants in its address unit).
#[derive(Debug, Clone)]
pub struct TexSlot<S> {
    /// Index of the texture's first word in the ray tracer's texture memory.
    pub base: usize,
    /// Side in texels.
    pub side: usize,
    /// How a hit point becomes (u, v), as the material's texture says.
    pub mapping: Mapping,
    /// Nearest or bilinear lookup, as the material's texture says.
    pub filter: Filter,
    /// (u, v) scale.
    pub scale: (S, S),
    /// (u, v) offset.
    pub offset: (S, S),
    /// Grey mix texture?
    pub grey: bool,
    /// Channel byte b → b/255 in the format ([`levels`]), so that a fetch indexes instead
    /// of converting three f64 values per texel (four texels per bilinear sample).
    pub levels: [S; 256],
    /// `side` in the format (the texel-space scale of u and v).
    sidef: S,
    /// `side − 1` when `side` is a power of two (always, by [`side_for`]): the repeat wrap
    /// is then a mask, as in hardware; `None` falls back to a Euclidean remainder.
    mask: Option<i64>,
}

impl<S: Scalar> TexSlot<S> {
    /// A slot of `side`² words from `base` with its per-scene constants.
    pub fn new(
        base: usize,
        side: usize,
        mapping: Mapping,
        filter: Filter,
        scale: (S, S),
        offset: (S, S),
        grey: bool,
    ) -> Self {
        let s = side as i64;
        Self {
            base,
            side,
            mapping,
            filter,
            scale,
            offset,
            grey,
            levels: levels(),
            sidef: S::from_f64(side as f64),
            mask: (s > 0 && s & (s - 1) == 0).then_some(s - 1),
        }
    }

    /// Word address of texel (x, y) after the repeat wrap.
    #[inline(always)]
    fn addr(&self, x: i64, y: i64) -> usize {
        let (x, y) = match self.mask {
            Some(m) => ((x & m) as usize, (y & m) as usize),
            // a side of 0 never comes from `side_for`; max(1) keeps it from dividing by 0
            None => {
                let s = (self.side as i64).max(1);
                (x.rem_euclid(s) as usize, y.rem_euclid(s) as usize)
            }
        };
        self.base + y * self.side + x
    }

    /// (u, v) after the slot's scale, offset and repeat, in texels.
    #[inline(always)]
    fn texel_uv(&self, u: S, v: S) -> (S, S) {
        let u = (u.mul_rn(self.scale.0) + self.offset.0).fract();
        let v = (v.mul_rn(self.scale.1) + self.offset.1).fract();
        (u * self.sidef, v * self.sidef)
    }
}

/// The value of each channel byte, b/255, exactly as converted per fetch before.
pub fn levels<S: Scalar>() -> [S; 256] {
    let k = 1.0 / 255.0;
    core::array::from_fn(|b| S::from_f64(b as f64 * k))
}

#[inline(always)]
fn unpack<S: Scalar>(w: u32, levels: &[S; 256]) -> V3<S> {
    V3::new(
        levels[((w >> 16) & 255) as usize],
        levels[((w >> 8) & 255) as usize],
        levels[(w & 255) as usize],
    )
}

/// Bilinear footprint of texel-space (fx, fy): the top-left texel and the weights.
#[inline(always)]
fn footprint<S: Scalar>(fx: S, fy: S) -> ((i64, i64), (S, S)) {
    let half = S::from_f64(0.5);
    let (fx, fy) = (fx - half, fy - half);
    let (x0, y0) = (fx.floor(), fy.floor());
    ((x0.int_to_i64(), y0.int_to_i64()), (fx - x0, fy - y0))
}

/// What a filter interpolates: a colour or a grey texture's mix factor, each channel
/// scaled by the format's rounded product (`V3::scale` is `mul_rn` per channel, so both
/// filter the same way bit for bit).
trait Texel<S>: Copy + core::ops::Add<Output = Self> {
    fn times(self, k: S) -> Self;
}

impl<S: Scalar> Texel<S> for S {
    #[inline(always)]
    fn times(self, k: S) -> S {
        self.mul_rn(k)
    }
}

impl<S: Scalar> Texel<S> for V3<S> {
    #[inline(always)]
    fn times(self, k: S) -> V3<S> {
        self.scale(k)
    }
}

/// The slot's filter at (u, v) over texels read by `fetch` (repeat wrap).
#[inline(always)]
fn filtered<S: Scalar, T: Texel<S>>(
    slot: &TexSlot<S>,
    u: S,
    v: S,
    fetch: impl Fn(i64, i64) -> T,
) -> T {
    let (fu, fv) = slot.texel_uv(u, v);
    match slot.filter {
        Filter::Nearest => fetch(fu.floor_i64(), fv.floor_i64()),
        Filter::Bilinear => {
            let one = S::one();
            let ((xi, yi), (ax, ay)) = footprint(fu, fv);
            let c00 = fetch(xi, yi);
            let c10 = fetch(xi + 1, yi);
            let c01 = fetch(xi, yi + 1);
            let c11 = fetch(xi + 1, yi + 1);
            let top = c00.times(one - ax) + c10.times(ax);
            let bot = c01.times(one - ax) + c11.times(ax);
            top.times(one - ay) + bot.times(ay)
        }
    }
}

/// Sample a slot at (u, v) after its transform, repeat wrap. Returns the texel value as a
/// colour (for grey textures every channel is the mix factor).
#[inline]
pub fn sample<S: Scalar>(mem: &[u32], slot: &TexSlot<S>, u: S, v: S) -> V3<S> {
    filtered(slot, u, v, |x, y| {
        unpack(mem.get(slot.addr(x, y)).copied().unwrap_or(0), &slot.levels)
    })
}

/// [`sample`]'s first channel alone, bit for bit: a grey texture's mix factor. Grey texels
/// repeat one byte in all three channels and the kernel reads only the first, so one
/// lookup per texel and one interpolation chain give the same value as three
/// (tests/rt_texture_fast.rs compares the two for every format).
#[inline]
pub fn sample_grey<S: Scalar>(mem: &[u32], slot: &TexSlot<S>, u: S, v: S) -> S {
    filtered(slot, u, v, |x, y| {
        let w = mem.get(slot.addr(x, y)).copied().unwrap_or(0);
        slot.levels[((w >> 16) & 255) as usize]
    })
}
