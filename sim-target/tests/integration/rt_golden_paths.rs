//! Golden hashes for the kernel paths the gallery (`rt_golden_formats`) does not reach:
//! several samples per pixel (the sub-pixel grid), Reinhard tone mapping, a glass object
//! whose refracted rays recurse, and the general kernel and the unculled planned kernel on
//! the same scene. Metric: bit-identical RGB888 + depth + normal AOVs. The hashes were
//! recorded on 82b93aa, before the session-6 restructuring of the kernel (rows as the
//! monomorphised unit, `trace` inlined, refraction out of line), so they pin that it
//! changed no bit. After an intended change: `RT_GOLDEN_PRINT=1 cargo test -p sim-target
//! --test integration rt_golden_paths:: -- --nocapture`, paste, and say why in docs/rt.md.

use sim_target::rt::{self, Kernel, Numeric, RenderOptions, ToneMap};

use crate::common;

/// A glass sphere in front of a mirror and a textured floor, lit by a point light: every
/// ray kind (primary, shadow, reflected, refracted) at depth 4.
const SCENE: &str = r#"
[render]
size = [48, 32]
depth = 4
background = [0.2, 0.3, 0.5]
[camera]
position = [0.0, 1.0, 6.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_y = 45.0
[ambient]
color = [0.1, 0.1, 0.1]
[[light]]
position = [3.0, 5.0, 4.0]
color = [40.0, 40.0, 40.0]
[material.glass]
diffuse = { k = 0.05, color = [0.9, 0.9, 1.0] }
specular = { k = 0.5, model = "blinn-phong", exponent = 64 }
reflection = { mode = "fresnel", eta = 1.5, transmit = true }
[material.mirror]
diffuse = { k = 0.1, color = [0.8, 0.8, 0.8] }
reflection = { mode = "constant", k = 0.8 }
[material.floor]
diffuse = { k = 0.8, color = [0.9, 0.8, 0.7] }
ambient = { k = 0.5, color = [1.0, 1.0, 1.0] }
texture = { kind = "checkerboard", mapping = "planar", scale = [2.0, 2.0], color2 = [0.1, 0.1, 0.1], filter = "bilinear", cell = 32 }
[[object]]
shape = "sphere"
translate = [0.0, 0.0, 0.0]
material = "glass"
[[object]]
shape = "square"
translate = [0.0, -1.0, 0.0]
scale = [5.0, 1.0, 5.0]
material = "floor"
[[object]]
shape = "plane"
translate = [0.0, 0.0, -3.0]
rotate = [90.0, 0.0, 0.0]
material = "mirror"
"#;

/// (label, format, hash of rgb8 ‖ depth ‖ normal).
const GOLDEN: &[(&str, &str, u64)] = &[
    ("planned", "F64", 0xbe9e998dfdcfba35),
    ("planned", "F32", 0x26b5add4c9dbf141),
    ("planned", "Q16_16", 0x9b7908b0445838f8),
    ("planned", "Q32_32", 0x20e75ec131421fa9),
    ("spp4-reinhard", "F64", 0x03759b73921c6cfb),
    ("spp4-reinhard", "F32", 0x0e259c07c68f5ef4),
    ("spp4-reinhard", "Q16_16", 0xe40bbb75b87cf9f3),
    ("spp4-reinhard", "Q32_32", 0xa139ff7945a96fec),
    ("general", "F64", 0xbe9e998dfdcfba35),
    ("general", "F32", 0x26b5add4c9dbf141),
    ("general", "Q16_16", 0x9b7908b0445838f8),
    ("general", "Q32_32", 0x20e75ec131421fa9),
    ("nocull", "F64", 0xbe9e998dfdcfba35),
    ("nocull", "F32", 0x26b5add4c9dbf141),
    ("nocull", "Q16_16", 0x9b7908b0445838f8),
    ("nocull", "Q32_32", 0x20e75ec131421fa9),
];

fn hash(numeric: Numeric, label: &str) -> u64 {
    let scene = jobs::scene::parse(SCENE, "paths.toml").expect("parses");
    let mut opts = RenderOptions {
        numeric,
        aovs: true,
        ..Default::default()
    };
    match label {
        "spp4-reinhard" => {
            opts.spp = Some(4);
            opts.tone_map = ToneMap::Reinhard;
        }
        "general" => opts.kernel = Kernel::General,
        "nocull" => opts.cull = false,
        _ => {}
    }
    let f = rt::render(&scene, &opts).expect("renders");
    assert!(f.stats.refracted_rays > 0, "the glass refracts");
    let levels: std::collections::BTreeSet<u8> = f.rgb8.iter().copied().collect();
    assert!(
        levels.len() > 40,
        "a real image: {} grey levels",
        levels.len()
    );
    common::frame_hash(&f)
}

#[test]
fn kernel_paths_match_golden_hashes() {
    let print = std::env::var("RT_GOLDEN_PRINT").is_ok();
    let mut n = 0;
    for label in ["planned", "spp4-reinhard", "general", "nocull"] {
        for numeric in [Numeric::F64, Numeric::F32, Numeric::Q16_16, Numeric::Q32_32] {
            let fmt = format!("{numeric:?}");
            let got = hash(numeric, label);
            if print {
                eprintln!("    (\"{label}\", \"{fmt}\", {got:#018x}),");
                continue;
            }
            let want = GOLDEN
                .iter()
                .find(|g| g.0 == label && g.1 == fmt)
                .map(|g| g.2);
            assert_eq!(Some(got), want, "{label} {fmt}: {got:#018x}");
            n += 1;
        }
    }
    assert!(print || n == 16);
}
