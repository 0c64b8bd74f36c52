//! The planned (monomorphised) kernels must render exactly what the general kernel renders
//! — RGB, depth and normal AOVs bit for bit — on the gallery, the reference scene and every
//! feature subset of them, in f32 and Q16.16 (and with the seed's approximations); and the
//! register image the plan sends must render the same image as the full one.

use sim_target::rt::{
    self, scene_file,
    subset::Subset,
    wire::{planned_scene, scene_wire_cost},
    Kernel, Math, Numeric, RenderOptions, Scene,
};
use sim_target::scene_regs::{from_regs, to_regs};

const SCENES: &[(&str, &str)] = &[
    ("reference", include_str!("../../examples/reference.toml")),
    ("fresnel", include_str!("../../examples/rt/fresnel.toml")),
    ("shapes", include_str!("../../examples/rt/shapes.toml")),
    ("textures", include_str!("../../examples/rt/textures.toml")),
    ("brdf", include_str!("../../examples/rt/brdf.toml")),
];

fn scenes() -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    for (name, text) in SCENES {
        let scene = scene_file::parse(text, name).expect("gallery scene parses");
        for sub in Subset::ALL {
            out.push((format!("{name}/{}", sub.label()), sub.apply(&scene)));
        }
    }
    out
}

fn frame(scene: &Scene, numeric: Numeric, math: Math, kernel: Kernel) -> rt::Frame {
    rt::render(
        scene,
        &RenderOptions {
            numeric,
            math,
            aovs: true,
            size: Some((48, 27)),
            kernel,
            ..Default::default()
        },
    )
    .expect("renders")
}

#[test]
fn planned_kernels_are_bit_identical_to_the_general_one() {
    let mut kernels = std::collections::BTreeSet::new();
    for (name, scene) in scenes() {
        kernels.insert(rt::plan(&scene).features().to_string());
        for numeric in [Numeric::F32, Numeric::Q16_16] {
            for math in [Math::default(), Math::SEED] {
                let p = frame(&scene, numeric, math, Kernel::Planned);
                let g = frame(&scene, numeric, math, Kernel::General);
                assert_eq!(p.rgb8, g.rgb8, "{name} {numeric:?} rgb");
                let bits = |v: &Option<Vec<f32>>| {
                    v.iter().flatten().map(|x| x.to_bits()).collect::<Vec<_>>()
                };
                assert_eq!(bits(&p.depth), bits(&g.depth), "{name} {numeric:?} depth");
                assert_eq!(
                    bits(&p.normal),
                    bits(&g.normal),
                    "{name} {numeric:?} normal"
                );
                assert_eq!(p.stats.rays(), g.stats.rays(), "{name} ray count");
            }
        }
    }
    // the subsets really exercise different kernels (not all the general one)
    assert!(kernels.len() >= 6, "{kernels:?}");
    assert!(kernels.contains("sh0-tx0-sp1-rf0-so1"), "{kernels:?}");
}

#[test]
fn plan_features_follow_the_scene() {
    let text = SCENES[0].1;
    let scene = scene_file::parse(text, "reference").expect("parses");
    let full = rt::plan(&scene).features();
    assert!(full.shadows && full.textures && full.reflect && !full.spheres_only);
    let flat = rt::plan(&Subset::SpheresFlat.apply(&scene)).features();
    assert!(!flat.shadows && !flat.textures && !flat.reflect && flat.spheres_only);
    assert!(
        !rt::plan(&Subset::NoShadows.apply(&scene))
            .features()
            .shadows
    );
    assert!(
        !rt::plan(&Subset::NoTextures.apply(&scene))
            .features()
            .textures
    );
    assert!(!rt::plan(&Subset::Depth1.apply(&scene)).features().reflect);
}

#[test]
fn planned_register_image_renders_the_same_and_sends_no_more() {
    for (name, scene) in scenes() {
        let plan = rt::plan(&scene);
        let full = from_regs(&to_regs(&scene).expect("fits")).expect("decodes");
        let planned =
            from_regs(&to_regs(&planned_scene(&scene, &plan)).expect("fits")).expect("decodes");
        for numeric in [Numeric::F32, Numeric::Q16_16] {
            let a = frame(&full, numeric, Math::default(), Kernel::Planned);
            let b = frame(&planned, numeric, Math::default(), Kernel::Planned);
            assert_eq!(a.rgb8, b.rgb8, "{name} {numeric:?}");
        }
        let (f, p) = scene_wire_cost(&scene).expect("fits");
        assert!(
            p.changed <= f.changed && p.bytes <= f.bytes,
            "{name}: {f:?} {p:?}"
        );
    }
}

#[test]
fn depth1_plan_stops_sending_reflection_words() {
    let scene = scene_file::parse(SCENES[1].1, "fresnel").expect("parses");
    let (f, p) = scene_wire_cost(&Subset::Depth1.apply(&scene)).expect("fits");
    assert!(p.changed < f.changed && p.bytes < f.bytes, "{f:?} {p:?}");
}
