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
    ("reference", "F32", false, 0x1ccdca5eebbfe04a),
    ("reference", "F32", true, 0x96ddeb9d48d5a86c),
    ("reference", "F16", false, 0x20a20185a7043b4d),
    ("reference", "F16", true, 0x1a8e5378276a29e1),
    ("reference", "Q16_16", false, 0xb18d14073d2e6110),
    ("reference", "Q16_16", true, 0x255553b548cdecf1),
    ("reference", "Q8_24", false, 0x745f674aeddf3065),
    ("reference", "Q8_24", true, 0xa8c95599d44b5d18),
    ("reference", "Q24_8", false, 0xbebb10ebe4e859d6),
    ("reference", "Q24_8", true, 0x2c786cbd8a2f56f2),
    ("reference", "Q32_32", false, 0xf5fbf2086f8d3c6e),
    ("reference", "Q32_32", true, 0x3ddb0f5687e11576),
    ("fresnel", "F32", false, 0xfd37138560232713),
    ("fresnel", "F32", true, 0x43df321f0c6ccee6),
    ("fresnel", "F16", false, 0x5c1ea23800a55169),
    ("fresnel", "F16", true, 0x99d2d608b13045be),
    ("fresnel", "Q16_16", false, 0xe544a6317b845619),
    ("fresnel", "Q16_16", true, 0x7ff9a0a08a201ee1),
    ("fresnel", "Q8_24", false, 0x30013351b9d4cdcd),
    ("fresnel", "Q8_24", true, 0x3cfe49f02a1a12c9),
    ("fresnel", "Q24_8", false, 0x39576c31bf16ba83),
    ("fresnel", "Q24_8", true, 0x0bdc7927acf5f663),
    ("fresnel", "Q32_32", false, 0x543d34dd346bcf9f),
    ("fresnel", "Q32_32", true, 0xaaf197aca65d2540),
    ("shapes", "F32", false, 0x32713c7b238ea345),
    ("shapes", "F32", true, 0xb63c2703d824953a),
    ("shapes", "F16", false, 0x3d1b7f76beb7e32e),
    ("shapes", "F16", true, 0x9cff556c45c670c3),
    ("shapes", "Q16_16", false, 0x094a745b02568ee3),
    ("shapes", "Q16_16", true, 0x21b7b5dc7e8e9e93),
    ("shapes", "Q8_24", false, 0x2cb1bd4216de43f9),
    ("shapes", "Q8_24", true, 0xba233da4a4861f05),
    ("shapes", "Q24_8", false, 0x7dabbee1fe1bbe1a),
    ("shapes", "Q24_8", true, 0x1b396c351f6850cd),
    ("shapes", "Q32_32", false, 0x7e4de15ca28a44f6),
    ("shapes", "Q32_32", true, 0x608cfcaab860dde9),
    ("textures", "F32", false, 0x53b7a83c6f453eb7),
    ("textures", "F32", true, 0xd8b4d299e7a98f93),
    ("textures", "F16", false, 0xdbbd78e5af5e45cc),
    ("textures", "F16", true, 0xf2193de6a1a53472),
    ("textures", "Q16_16", false, 0xf850181b1159adbc),
    ("textures", "Q16_16", true, 0x291dbd3a6b3fcac3),
    ("textures", "Q8_24", false, 0xe4aa0f8d18342b34),
    ("textures", "Q8_24", true, 0xab19349fa328412c),
    ("textures", "Q24_8", false, 0xfdf7dd3bc6dddd08),
    ("textures", "Q24_8", true, 0x678e3781c354f5e1),
    ("textures", "Q32_32", false, 0x6916954747135027),
    ("textures", "Q32_32", true, 0x97409a3736b0afea),
    ("brdf", "F32", false, 0xfad774773c8a7708),
    ("brdf", "F32", true, 0x4723a362047e0b5b),
    ("brdf", "F16", false, 0xfbc1760293e20196),
    ("brdf", "F16", true, 0xdfeaca63171d7c99),
    ("brdf", "Q16_16", false, 0xe5dde063cbf7523e),
    ("brdf", "Q16_16", true, 0x2185942479d880cd),
    ("brdf", "Q8_24", false, 0x47f673554f7d5aba),
    ("brdf", "Q8_24", true, 0xb1d9130d013c94bf),
    ("brdf", "Q24_8", false, 0xa95bf0471fd66da7),
    ("brdf", "Q24_8", true, 0x114a6fb2c1d179ef),
    ("brdf", "Q32_32", false, 0x515c00af0fcb8874),
    ("brdf", "Q32_32", true, 0x61bf604010d437d1),
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
