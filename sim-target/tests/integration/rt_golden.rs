//! Golden images: every example scene rendered small in f64 must reproduce a stored
//! FNV-1a hash of its RGB888 bytes exactly (metric: bit-identical output). f64 arithmetic
//! is deterministic here (no fused operations, row order does not matter; sin/cos/tan come
//! from the platform's libm, so the hashes are for x86-64 Linux like CI), so any change
//! of the kernel's results shows up. After an intended change, run with
//! `RT_GOLDEN_PRINT=1 cargo test -p sim-target --test integration rt_golden:: -- --nocapture`
//! and paste.

use sim_target::rt::{self, Numeric, RenderOptions};

use crate::common;

const GOLDEN: &[(&str, &str, u64)] = &[
    (
        "reference",
        include_str!("../../../examples/reference.toml"),
        0x6401_f915_375f_787d,
    ),
    (
        "fresnel",
        include_str!("../../../examples/rt/fresnel.toml"),
        0x8b03_772d_4003_6aa4,
    ),
    (
        "shapes",
        include_str!("../../../examples/rt/shapes.toml"),
        0xd1fd_77a2_0091_0d71,
    ),
    (
        "textures",
        include_str!("../../../examples/rt/textures.toml"),
        0x8812_bf84_0389_4bd6,
    ),
    (
        "brdf",
        include_str!("../../../examples/rt/brdf.toml"),
        0x4b35_2506_bdf2_6721,
    ),
];

#[test]
fn gallery_matches_golden_hashes() {
    let print = std::env::var("RT_GOLDEN_PRINT").is_ok();
    for (name, text, want) in GOLDEN {
        let scene = jobs::scene::parse(text, name).expect("parses");
        let opts = RenderOptions {
            numeric: Numeric::F64,
            size: Some((96, 54)),
            ..Default::default()
        };
        let f = rt::render(&scene, &opts).expect("renders");
        let got = common::fnv1a(f.rgb8.iter().copied());
        if let Ok(dir) = std::env::var("RT_DUMP") {
            let full = rt::render(
                &scene,
                &RenderOptions {
                    numeric: Numeric::F64,
                    ..Default::default()
                },
            )
            .expect("renders");
            let mut out = format!("P6\n{} {}\n255\n", full.width, full.height).into_bytes();
            out.extend_from_slice(&full.rgb8);
            let _ = std::fs::write(format!("{dir}/{name}.ppm"), out);
        }
        if print {
            eprintln!("(\"{name}\", …, {got:#018x}),");
        } else {
            assert_eq!(got, *want, "{name}: golden hash changed ({got:#018x})");
        }
    }
}
