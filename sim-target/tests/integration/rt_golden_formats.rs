//! Golden images per number format: the gallery rendered small in every format and with
//! both math presets must reproduce stored FNV-1a hashes of its RGB888 bytes and of its
//! depth/normal AOVs exactly (metric: bit-identical output). `rt_golden` pins f64 only;
//! this file pins the formats whose arithmetic the speed work touches (fixed-point
//! multiply/divide, literal folding, dispatch), so an optimisation that changes one bit of
//! f32 or Q16.16 output fails here instead of slipping through the PSNR thresholds. After
//! an intended change, run with `RT_GOLDEN_PRINT=1 cargo test -p sim-target --test
//! integration rt_golden_formats:: -- --nocapture`, paste, and say why in docs/rt.md.

use sim_target::rt::{self, Math, Numeric, RenderOptions};

use crate::common;

use common::GALLERY as SCENES;

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
    ("reference", "F16", false, 0xc176d33f9ddf989a),
    ("reference", "F16", true, 0x1a8e5378276a29e1),
    ("reference", "Q16_16", false, 0x8998d6217ce56463),
    ("reference", "Q16_16", true, 0x7776fb08586e84db),
    ("reference", "Q8_24", false, 0x0152c452937b5609),
    ("reference", "Q8_24", true, 0x34a9ebc20b430103),
    ("reference", "Q24_8", false, 0x3340c4f851b7add8),
    ("reference", "Q24_8", true, 0xc7eab4ab4bcf7305),
    ("reference", "Q32_32", false, 0x351504d17eee9e6e),
    ("reference", "Q32_32", true, 0x7ebc609f2751c284),
    ("fresnel", "F32", false, 0x8c2390b2eacb277f),
    ("fresnel", "F32", true, 0x43df321f0c6ccee6),
    ("fresnel", "F16", false, 0xa64288b9428a7411),
    ("fresnel", "F16", true, 0x99d2d608b13045be),
    ("fresnel", "Q16_16", false, 0x3755b7178fa48a9c),
    ("fresnel", "Q16_16", true, 0x7ff9a0a08a201ee1),
    ("fresnel", "Q8_24", false, 0xfc2f16d9e4ad8b77),
    ("fresnel", "Q8_24", true, 0x3cfe49f02a1a12c9),
    ("fresnel", "Q24_8", false, 0x58ae2ab9c9d90998),
    ("fresnel", "Q24_8", true, 0x99d1a998dc76c819),
    ("fresnel", "Q32_32", false, 0x84c77afa7ef63593),
    ("fresnel", "Q32_32", true, 0xaaf197aca65d2540),
    ("shapes", "F32", false, 0xda186ba37224c4e1),
    ("shapes", "F32", true, 0xb63c2703d824953a),
    ("shapes", "F16", false, 0x002b9a07721137ff),
    ("shapes", "F16", true, 0x9cff556c45c670c3),
    ("shapes", "Q16_16", false, 0x5d75eade3aa6e1d2),
    ("shapes", "Q16_16", true, 0x472349743f6ddcc6),
    ("shapes", "Q8_24", false, 0x2cd590d9c1717af6),
    ("shapes", "Q8_24", true, 0x09f28d18d9fff3e5),
    ("shapes", "Q24_8", false, 0xc6c6228589290706),
    ("shapes", "Q24_8", true, 0x17ba80aea9b408bc),
    ("shapes", "Q32_32", false, 0xa93dfd5cfec137dc),
    ("shapes", "Q32_32", true, 0xfd113044c44c1d02),
    ("textures", "F32", false, 0x1c5aa1ce6bb12250),
    ("textures", "F32", true, 0xd8b4d299e7a98f93),
    ("textures", "F16", false, 0xffc4f93285d594d0),
    ("textures", "F16", true, 0xf2193de6a1a53472),
    ("textures", "Q16_16", false, 0x3c21b8e1f56c7786),
    ("textures", "Q16_16", true, 0x37f6d183e7f39cb2),
    ("textures", "Q8_24", false, 0x1c8c1a9ca2c95775),
    ("textures", "Q8_24", true, 0x330fd828f6f3ad75),
    ("textures", "Q24_8", false, 0x06dfa78a55cbf47b),
    ("textures", "Q24_8", true, 0x15b1afb77ccc2bf0),
    ("textures", "Q32_32", false, 0x80204313e57b6da3),
    ("textures", "Q32_32", true, 0x8f7f56637c01f542),
    ("brdf", "F32", false, 0xaf09484be023c230),
    ("brdf", "F32", true, 0x4723a362047e0b5b),
    ("brdf", "F16", false, 0x9124cafc267e2b87),
    ("brdf", "F16", true, 0xdfeaca63171d7c99),
    ("brdf", "Q16_16", false, 0x55e82f7d0850b21b),
    ("brdf", "Q16_16", true, 0x3f4b34c0286dd609),
    ("brdf", "Q8_24", false, 0x97be536b4b21938e),
    ("brdf", "Q8_24", true, 0xb1d9130d013c94bf),
    ("brdf", "Q24_8", false, 0x3fa7e1b601e871db),
    ("brdf", "Q24_8", true, 0x114a6fb2c1d179ef),
    ("brdf", "Q32_32", false, 0xcd7dfa7231eee6a0),
    ("brdf", "Q32_32", true, 0x61bf604010d437d1),
];

fn hash_of(name: &str, text: &str, numeric: Numeric, seed_math: bool) -> u64 {
    let scene = jobs::scene::parse(text, name).expect("parses");
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
    common::frame_hash(&f)
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
