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
    ("reference", "F32", false, 0x04a50d085fac53c8),
    ("reference", "F32", true, 0x96ddeb9d48d5a86c),
    ("reference", "F16", false, 0x3c0a0b1f1b3f17bf),
    ("reference", "F16", true, 0x1a8e5378276a29e1),
    ("reference", "Q16_16", false, 0x98a5b340adaa1957),
    ("reference", "Q16_16", true, 0x255553b548cdecf1),
    ("reference", "Q8_24", false, 0x06491d1a4ba82727),
    ("reference", "Q8_24", true, 0xa8c95599d44b5d18),
    ("reference", "Q24_8", false, 0x28162db55f279f9f),
    ("reference", "Q24_8", true, 0x2c786cbd8a2f56f2),
    ("reference", "Q32_32", false, 0x6712961fb3c10cfa),
    ("reference", "Q32_32", true, 0x3ddb0f5687e11576),
    ("fresnel", "F32", false, 0x8c2390b2eacb277f),
    ("fresnel", "F32", true, 0x43df321f0c6ccee6),
    ("fresnel", "F16", false, 0xa64288b9428a7411),
    ("fresnel", "F16", true, 0x99d2d608b13045be),
    ("fresnel", "Q16_16", false, 0xa1ab457aa082cb44),
    ("fresnel", "Q16_16", true, 0x7ff9a0a08a201ee1),
    ("fresnel", "Q8_24", false, 0xfc2f16d9e4ad8b77),
    ("fresnel", "Q8_24", true, 0x3cfe49f02a1a12c9),
    ("fresnel", "Q24_8", false, 0xaa9f37966046c8e6),
    ("fresnel", "Q24_8", true, 0x0bdc7927acf5f663),
    ("fresnel", "Q32_32", false, 0x84c77afa7ef63593),
    ("fresnel", "Q32_32", true, 0xaaf197aca65d2540),
    ("shapes", "F32", false, 0xda186ba37224c4e1),
    ("shapes", "F32", true, 0xb63c2703d824953a),
    ("shapes", "F16", false, 0x002b9a07721137ff),
    ("shapes", "F16", true, 0x9cff556c45c670c3),
    ("shapes", "Q16_16", false, 0x17747943a50c013a),
    ("shapes", "Q16_16", true, 0x21b7b5dc7e8e9e93),
    ("shapes", "Q8_24", false, 0xbf5e1de8ca7ce5fd),
    ("shapes", "Q8_24", true, 0xba233da4a4861f05),
    ("shapes", "Q24_8", false, 0xa9b9e81b9da434e8),
    ("shapes", "Q24_8", true, 0x1b396c351f6850cd),
    ("shapes", "Q32_32", false, 0x111c38240ecce3a5),
    ("shapes", "Q32_32", true, 0x608cfcaab860dde9),
    ("textures", "F32", false, 0x1c5aa1ce6bb12250),
    ("textures", "F32", true, 0xd8b4d299e7a98f93),
    ("textures", "F16", false, 0xd201719a28610826),
    ("textures", "F16", true, 0xf2193de6a1a53472),
    ("textures", "Q16_16", false, 0x74290ef1da109e3e),
    ("textures", "Q16_16", true, 0x291dbd3a6b3fcac3),
    ("textures", "Q8_24", false, 0x08f8bddd124e9bc2),
    ("textures", "Q8_24", true, 0xab19349fa328412c),
    ("textures", "Q24_8", false, 0x43cff0f440fe6d9b),
    ("textures", "Q24_8", true, 0x678e3781c354f5e1),
    ("textures", "Q32_32", false, 0x5ff49f24213d9b5e),
    ("textures", "Q32_32", true, 0x97409a3736b0afea),
    ("brdf", "F32", false, 0xaf09484be023c230),
    ("brdf", "F32", true, 0x4723a362047e0b5b),
    ("brdf", "F16", false, 0x9124cafc267e2b87),
    ("brdf", "F16", true, 0xdfeaca63171d7c99),
    ("brdf", "Q16_16", false, 0x458716c92b496587),
    ("brdf", "Q16_16", true, 0x2185942479d880cd),
    ("brdf", "Q8_24", false, 0x97be536b4b21938e),
    ("brdf", "Q8_24", true, 0xb1d9130d013c94bf),
    ("brdf", "Q24_8", false, 0x3fa7e1b601e871db),
    ("brdf", "Q24_8", true, 0x114a6fb2c1d179ef),
    ("brdf", "Q32_32", false, 0xcd7dfa7231eee6a0),
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
