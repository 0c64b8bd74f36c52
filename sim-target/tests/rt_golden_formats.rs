//! Golden images per number format: the gallery rendered small in every format and with
//! both math presets must reproduce stored FNV-1a hashes of its RGB888 bytes and of its
//! depth/normal AOVs exactly (metric: bit-identical output). `rt_golden` pins f64 only;
//! this file pins the formats whose arithmetic the speed work touches (fixed-point
//! multiply/divide, literal folding, dispatch), so an optimisation that changes one bit of
//! f32 or Q16.16 output fails here instead of slipping through the PSNR thresholds. After
//! an intended change, run with `RT_GOLDEN_PRINT=1 cargo test -p sim-target --test
//! rt_golden_formats -- --nocapture`, paste, and say why in docs/rt.md.

use sim_target::rt::{self, scene_file, Math, Numeric, RenderOptions};

fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

const SCENES: &[(&str, &str)] = &[
    ("reference", include_str!("../../examples/reference.toml")),
    ("fresnel", include_str!("../../examples/rt/fresnel.toml")),
    ("shapes", include_str!("../../examples/rt/shapes.toml")),
    ("textures", include_str!("../../examples/rt/textures.toml")),
    ("brdf", include_str!("../../examples/rt/brdf.toml")),
];

const FORMATS: &[Numeric] = &[
    Numeric::F32,
    Numeric::F16,
    Numeric::Q16_16,
    Numeric::Q8_24,
    Numeric::Q24_8,
    Numeric::Q32_32,
];

/// (scene, format, seed math?, hash of rgb8 ‖ depth ‖ normal).
const GOLDEN: &[(&str, &str, bool, u64)] = &[
    ("reference", "F32", false, 0x55b165513723c6b4),
    ("reference", "F32", true, 0x96ddeb9d48d5a86c),
    ("reference", "F16", false, 0xc6b7eac27f733fd6),
    ("reference", "F16", true, 0x1a8e5378276a29e1),
    ("reference", "Q16_16", false, 0x92ba1d3f9e127103),
    ("reference", "Q16_16", true, 0xcda690f14c2ed232),
    ("reference", "Q8_24", false, 0x753c2bcebd1908bf),
    ("reference", "Q8_24", true, 0x26a3555ad57e5ec9),
    ("reference", "Q24_8", false, 0x17a0dc623017d85d),
    ("reference", "Q24_8", true, 0x24903b24c9e7966b),
    ("reference", "Q32_32", false, 0x2f7a1e2b82cbd38b),
    ("reference", "Q32_32", true, 0x398b60cb41571a29),
    ("fresnel", "F32", false, 0x333e834d485c97bf),
    ("fresnel", "F32", true, 0x43df321f0c6ccee6),
    ("fresnel", "F16", false, 0xdb1d4a80e5f2e1a9),
    ("fresnel", "F16", true, 0x99d2d608b13045be),
    ("fresnel", "Q16_16", false, 0x585733a4b502e465),
    ("fresnel", "Q16_16", true, 0xcc065ef4a3b0a8fa),
    ("fresnel", "Q8_24", false, 0x501066feb4c044d8),
    ("fresnel", "Q8_24", true, 0x43168dd0c50f998d),
    ("fresnel", "Q24_8", false, 0x702a5d272787d1d8),
    ("fresnel", "Q24_8", true, 0xd6106c83cdb1641f),
    ("fresnel", "Q32_32", false, 0x2dd502f2d377d7a6),
    ("fresnel", "Q32_32", true, 0x882fc45e5656e050),
    ("shapes", "F32", false, 0x52901ba7726156e3),
    ("shapes", "F32", true, 0xb63c2703d824953a),
    ("shapes", "F16", false, 0x1c961d9586654d83),
    ("shapes", "F16", true, 0x9cff556c45c670c3),
    ("shapes", "Q16_16", false, 0x9c207a64e5634479),
    ("shapes", "Q16_16", true, 0xe3a56d8dd0eb02a4),
    ("shapes", "Q8_24", false, 0x478db4e58b5f3beb),
    ("shapes", "Q8_24", true, 0x526d74b702d09ab3),
    ("shapes", "Q24_8", false, 0x3330861c993f0815),
    ("shapes", "Q24_8", true, 0xed7142cc54c067cd),
    ("shapes", "Q32_32", false, 0xfaccb2d3043f31c9),
    ("shapes", "Q32_32", true, 0x1698e84cce854ac4),
    ("textures", "F32", false, 0x8aa4407047e7b99a),
    ("textures", "F32", true, 0xd8b4d299e7a98f93),
    ("textures", "F16", false, 0x960f457bc15b8949),
    ("textures", "F16", true, 0xf2193de6a1a53472),
    ("textures", "Q16_16", false, 0xdf601ffe229238b0),
    ("textures", "Q16_16", true, 0x73b859bdc32b846e),
    ("textures", "Q8_24", false, 0xc0dcdafd64a8a77f),
    ("textures", "Q8_24", true, 0xeb187560639d8eba),
    ("textures", "Q24_8", false, 0xc265ee292f95054f),
    ("textures", "Q24_8", true, 0x7ac702ffb1855465),
    ("textures", "Q32_32", false, 0x833f306d2a470bc1),
    ("textures", "Q32_32", true, 0xb73e997a7387d649),
    ("brdf", "F32", false, 0x41d4a61f694cc11c),
    ("brdf", "F32", true, 0x4723a362047e0b5b),
    ("brdf", "F16", false, 0xacc1f1561cd2be5a),
    ("brdf", "F16", true, 0xdfeaca63171d7c99),
    ("brdf", "Q16_16", false, 0x7362358e4aa321c5),
    ("brdf", "Q16_16", true, 0x70cb276418f8786f),
    ("brdf", "Q8_24", false, 0x3f8d0a8461976c48),
    ("brdf", "Q8_24", true, 0x6db6844f680b1cfe),
    ("brdf", "Q24_8", false, 0xb5b14ec64af5eb84),
    ("brdf", "Q24_8", true, 0xf53a1647cb60a515),
    ("brdf", "Q32_32", false, 0xcfc13678ddc99503),
    ("brdf", "Q32_32", true, 0x5fc30d7afabba588),
];

fn hash_of(name: &str, text: &str, numeric: Numeric, seed_math: bool) -> u64 {
    let scene = scene_file::parse(text, name).expect("parses");
    let opts = RenderOptions {
        numeric,
        size: Some((64, 36)),
        aovs: true,
        math: if seed_math {
            Math::SEED
        } else {
            Math::default()
        },
        ..Default::default()
    };
    let f = rt::render(&scene, &opts).expect("renders");
    let depth = f.depth.unwrap_or_default();
    let normal = f.normal.unwrap_or_default();
    fnv1a(
        f.rgb8
            .iter()
            .copied()
            .chain(depth.iter().flat_map(|v| v.to_le_bytes()))
            .chain(normal.iter().flat_map(|v| v.to_le_bytes())),
    )
}

#[test]
fn every_format_matches_golden_hashes() {
    let print = std::env::var("RT_GOLDEN_PRINT").is_ok();
    let mut n = 0;
    for (name, text) in SCENES {
        for numeric in FORMATS {
            for seed_math in [false, true] {
                let fmt = format!("{numeric:?}");
                let got = hash_of(name, text, *numeric, seed_math);
                if print {
                    eprintln!("    (\"{name}\", \"{fmt}\", {seed_math}, {got:#018x}),");
                    continue;
                }
                let want = GOLDEN
                    .iter()
                    .find(|g| g.0 == *name && g.1 == fmt && g.2 == seed_math)
                    .map(|g| g.3);
                assert_eq!(
                    Some(got),
                    want,
                    "{name} {fmt} seed_math={seed_math}: golden hash changed ({got:#018x})"
                );
                n += 1;
            }
        }
    }
    assert!(print || n == SCENES.len() * FORMATS.len() * 2);
}
