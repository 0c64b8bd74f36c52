//! The texture sampler's fast paths against the sampler they replaced, bit for bit, in
//! every number format: `sample` (per-scene constants moved into `TexSlot`, the fixed
//! formats' mask `fract` and shift `floor_i64`) and `sample_grey` (one channel, one
//! interpolation chain) must give exactly what the old three-channel `sample` gave — the
//! golden images depend on it, and these tests reach inputs the gallery does not
//! (negative, huge and out-of-range coordinates, odd offsets, both filters, NaN).

use proptest::prelude::*;
use sim_target::num::{Scalar, Q16_16, Q24_8, Q32_32, Q8_24};
use sim_target::rt::texture::{
    sample, sample_grey, side_for, slot_base, texel, texels, TexSlot, TEXTURE_WORDS,
};
use sim_target::rt::V3;
use sim_target::rt::{Filter, Mapping, TextureKind};

/// The sampler as it was before session 5 (verbatim but for taking the slot's public
/// fields): the reference the fast paths must reproduce.
fn sample_ref<S: Scalar>(mem: &[u32], slot: &TexSlot<S>, u: S, v: S) -> V3<S> {
    let unpack = |w: u32, levels: &[S; 256]| {
        V3::new(
            levels[((w >> 16) & 255) as usize],
            levels[((w >> 8) & 255) as usize],
            levels[(w & 255) as usize],
        )
    };
    let u = (u.mul_rn(slot.scale.0) + slot.offset.0).fract();
    let v = (v.mul_rn(slot.scale.1) + slot.offset.1).fract();
    let side = slot.side as i64;
    let sidef = S::from_f64(slot.side as f64);
    let pow2 = side > 0 && side & (side - 1) == 0;
    let fetch = |x: i64, y: i64| -> V3<S> {
        let (x, y) = if pow2 {
            ((x & (side - 1)) as usize, (y & (side - 1)) as usize)
        } else {
            (x.rem_euclid(side) as usize, y.rem_euclid(side) as usize)
        };
        unpack(
            mem.get(slot.base + y * slot.side + x).copied().unwrap_or(0),
            &slot.levels,
        )
    };
    match slot.filter {
        Filter::Nearest => {
            let x = (u * sidef).floor().to_f64() as i64;
            let y = (v * sidef).floor().to_f64() as i64;
            fetch(x, y)
        }
        Filter::Bilinear => {
            let half = S::from_f64(0.5);
            let fx = u * sidef - half;
            let fy = v * sidef - half;
            let x0 = fx.floor();
            let y0 = fy.floor();
            let (ax, ay) = (fx - x0, fy - y0);
            let (xi, yi) = (x0.to_f64() as i64, y0.to_f64() as i64);
            let one = S::one();
            let c00 = fetch(xi, yi);
            let c10 = fetch(xi + 1, yi);
            let c01 = fetch(xi, yi + 1);
            let c11 = fetch(xi + 1, yi + 1);
            let top = c00.scale(one - ax) + c10.scale(ax);
            let bot = c01.scale(one - ax) + c11.scale(ax);
            top.scale(one - ay) + bot.scale(ay)
        }
    }
}

/// Same bits (NaN equals NaN: the floats may carry one through).
fn same<S: Scalar>(a: S, b: S) -> bool {
    let (a, b) = (a.to_f64(), b.to_f64());
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

/// Texture memory of `n` slots of `side`² words: grey words (one byte repeated) or any
/// colour, from a seed (an LCG: the content only has to vary).
fn memory(words: usize, seed: u64, grey: bool) -> Vec<u32> {
    let mut s = seed | 1;
    (0..words)
        .map(|_| {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let w = (s >> 40) as u32 & 0x00FF_FFFF;
            if grey {
                let g = w & 255;
                (g << 16) | (g << 8) | g
            } else {
                w
            }
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn check<S: Scalar>(
    side: usize,
    slots: usize,
    slot_i: usize,
    filter: Filter,
    scale: (f64, f64),
    offset: (f64, f64),
    uv: &[(f64, f64)],
    seed: u64,
) -> Result<(), TestCaseError> {
    for grey in [true, false] {
        let mem = memory(slots * side * side, seed, grey);
        let slot = TexSlot::<S>::new(
            slot_i * side * side,
            side,
            Mapping::Planar,
            filter,
            (S::from_f64(scale.0), S::from_f64(scale.1)),
            (S::from_f64(offset.0), S::from_f64(offset.1)),
            grey,
        );
        for &(u, v) in uv {
            let (u, v) = (S::from_f64(u), S::from_f64(v));
            let want = sample_ref(&mem, &slot, u, v);
            let got = sample(&mem, &slot, u, v);
            prop_assert!(
                same(got.x, want.x) && same(got.y, want.y) && same(got.z, want.z),
                "{} rgb {filter:?} side {side} ({u:?}, {v:?}): {got:?} vs {want:?}",
                S::NAME
            );
            let g = sample_grey(&mem, &slot, u, v);
            prop_assert!(
                same(g, want.x),
                "{} grey {filter:?} side {side} ({u:?}, {v:?}): {g:?} vs {:?}",
                S::NAME,
                want.x
            );
        }
    }
    Ok(())
}

fn coords() -> impl Strategy<Value = Vec<(f64, f64)>> {
    let c = prop_oneof![
        4 => -1.5f64..2.5,
        2 => -40_000.0f64..40_000.0,
        1 => Just(0.0),
        1 => Just(1.0),
        1 => Just(-0.0),
        1 => (0u32..=256).prop_map(|i| i as f64 / 256.0),
        1 => -1e-6f64..1e-6,
    ];
    prop::collection::vec((c.clone(), c), 24)
}

fn filters() -> impl Strategy<Value = Filter> {
    prop_oneof![Just(Filter::Nearest), Just(Filter::Bilinear)]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn fast_sampler_matches_reference_in_every_format(
        n in 1usize..=16,
        pick in 0usize..16,
        odd_side in any::<bool>(),
        filter in filters(),
        scale in (-8.0f64..8.0, -8.0f64..8.0),
        offset in (-3.0f64..3.0, -3.0f64..3.0),
        uv in coords(),
        seed in any::<u64>(),
    ) {
        // the kernel's sides are powers of two; 48 exercises the remainder fallback
        let side = if odd_side { 48 } else { side_for(n) };
        let slots = n.min(65_536 / (side * side)).max(1);
        let i = pick % slots;
        check::<f32>(side, slots, i, filter, scale, offset, &uv, seed)?;
        check::<f64>(side, slots, i, filter, scale, offset, &uv, seed)?;
        check::<half::f16>(side, slots, i, filter, scale, offset, &uv, seed)?;
        check::<Q16_16>(side, slots, i, filter, scale, offset, &uv, seed)?;
        check::<Q8_24>(side, slots, i, filter, scale, offset, &uv, seed)?;
        check::<Q24_8>(side, slots, i, filter, scale, offset, &uv, seed)?;
        check::<Q32_32>(side, slots, i, filter, scale, offset, &uv, seed)?;
    }
}

#[test]
fn non_finite_and_extreme_coordinates() {
    let side = side_for(5);
    for filter in [Filter::Nearest, Filter::Bilinear] {
        let uv = [
            (f64::NAN, 0.3),
            (0.3, f64::NAN),
            (f64::INFINITY, -0.2),
            (f64::NEG_INFINITY, 0.7),
            (f64::MAX, f64::MIN),
            (1e30, -1e30),
            (-0.5 / side as f64, 1.0 - 1e-9),
        ];
        for (scale, offset) in [((1.0, 1.0), (0.0, 0.0)), ((4.0, 3.0), (0.25, -0.5))] {
            check::<f32>(side, 5, 2, filter, scale, offset, &uv, 7).unwrap();
            check::<f64>(side, 5, 2, filter, scale, offset, &uv, 7).unwrap();
            check::<Q16_16>(side, 5, 2, filter, scale, offset, &uv, 7).unwrap();
            check::<Q32_32>(side, 5, 4, filter, scale, offset, &uv, 7).unwrap();
        }
    }
}

/// The test can fail: a sampler that reads the second channel instead of the first is
/// caught on colour texels.
#[test]
fn reference_distinguishes_channels() {
    let side = 4;
    let mem: Vec<u32> = (0..16).map(|i| (i << 16) | ((255 - i) << 8)).collect();
    let slot = TexSlot::<f32>::new(
        0,
        side,
        Mapping::Planar,
        Filter::Nearest,
        (1.0, 1.0),
        (0.0, 0.0),
        false,
    );
    let c = sample_ref(&mem, &slot, 0.6, 0.3);
    assert_ne!(c.x, c.y);
    assert_eq!(sample_grey(&mem, &slot, 0.6, 0.3), c.x);
}

/// Texture memory holds each material's texture in its slot, in material order, and
/// nothing after the last.
#[test]
fn memory_holds_each_texture_in_its_slot_in_material_order() {
    let text = include_str!("../../../examples/rt/textures.toml");
    let scene = jobs::scene::parse(text, "textures.toml").unwrap();
    let kinds: Vec<TextureKind> = scene
        .materials
        .iter()
        .filter_map(|m| m.texture.as_ref().map(|t| t.kind))
        .collect();
    assert_eq!(kinds.len(), 5);
    let side = side_for(kinds.len());
    assert_eq!(side, 64);
    let mem = sim_target::rt::texture::memory(&scene);
    assert_eq!(mem.len(), TEXTURE_WORDS);
    for (slot, &kind) in kinds.iter().enumerate() {
        let base = slot_base(slot, side);
        for y in 0..side {
            for x in 0..side {
                assert_eq!(
                    mem[base + y * side + x],
                    texel(kind, x, y, side),
                    "{kind:?}"
                );
            }
        }
    }
    assert!(mem[slot_base(kinds.len(), side)..].iter().all(|&w| w == 0));
    // Again, now from the generated textures kept for the process.
    assert!(sim_target::rt::texture::memory(&scene) == mem);
}

/// The kept textures are `texel`'s values however the cache turns over: more kinds and
/// sides than it keeps, then the first again.
#[test]
fn kept_textures_are_the_texels() {
    let kinds = (0..20)
        .map(|seed| TextureKind::Marble { seed })
        .chain([TextureKind::Xor, TextureKind::RgbDots])
        .chain((1..4).map(|cell| TextureKind::Checkerboard { cell }))
        .chain([
            TextureKind::Wood { seed: 3 },
            TextureKind::Marble { seed: 0 },
        ]);
    for (i, kind) in kinds.enumerate() {
        let side = [64, 128, 16][i % 3];
        let t = texels(kind, side);
        assert_eq!(t.len(), side * side);
        for (j, &w) in t.iter().enumerate() {
            assert_eq!(
                w,
                texel(kind, j % side, j / side, side),
                "{kind:?} at {side}"
            );
        }
    }
}
