//! The planned (monomorphised) kernels must render exactly what the general kernel renders
//! — RGB, depth and normal AOVs bit for bit — on the gallery, the reference scene and every
//! feature subset of them, in f32 and Q16.16 (and with the seed's approximations); and the
//! register image the plan sends must render the same image as the full one.

use jobs::scene::{planned_scene, scene_wire_cost, to_regs};
use sim_target::num::SqrtKind;
use sim_target::rt::{self, Kernel, Math, Numeric, RenderOptions, Scene, Subset};
use sim_target::scene_regs::from_regs;

use crate::common;
use common::assert_same_frame;

use common::GALLERY as SCENES;

fn scenes() -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    for (name, text) in SCENES {
        let scene = jobs::scene::parse(text, name).expect("gallery scene parses");
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
                assert_same_frame(
                    &p,
                    &g,
                    &format!("{name} {numeric:?} {math:?} planned/general"),
                );
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
    let scene = jobs::scene::parse(text, "reference").expect("parses");
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
    let scene = jobs::scene::parse(SCENES[1].1, "fresnel").expect("parses");
    let (f, p) = scene_wire_cost(&Subset::Depth1.apply(&scene)).expect("fits");
    assert!(p.changed < f.changed && p.bytes < f.bytes, "{f:?} {p:?}");
}

/// Scenes that probe the culling's edges: the eye inside a bound, objects behind the
/// camera, a tiny far sphere, a huge close one, rotated and anisotropic shapes, a cube
/// seen edge-on, everything reflecting (secondary rays from every surface).
fn cull_edge_scenes() -> Vec<(String, Scene)> {
    let base = jobs::scene::parse(SCENES[2].1, "shapes").expect("parses");
    let mut out = Vec::new();
    // eye inside the bound of the first bounded object
    let mut s = base.clone();
    if let Some(o) = s.objects.iter_mut().find(|o| o.shape != rt::Shape::Plane) {
        o.translate = s.camera.position;
        o.scale = [3.0, 3.0, 3.0];
    }
    out.push(("eye-inside-bound".to_string(), s));
    // everything but the first object behind the camera, along the view axis
    let mut s = base.clone();
    let (c, l) = (s.camera.position, s.camera.look_at);
    let back = [c[0] - l[0], c[1] - l[1], c[2] - l[2]];
    for (k, o) in s.objects.iter_mut().enumerate().skip(1) {
        let f = 0.3 * k as f64;
        o.translate = [c[0] + back[0] * f, c[1] + back[1] * f, c[2] + back[2] * f];
    }
    out.push(("behind-camera".to_string(), s));
    // tiny far, huge near, anisotropic rotated
    let mut s = base.clone();
    for (k, o) in s.objects.iter_mut().enumerate() {
        match k % 3 {
            0 => o.scale = [0.01, 0.01, 0.01],
            1 => o.scale = [4.0, 0.1, 1.5],
            _ => {}
        }
        o.rotate = [17.0 * k as f64, 29.0, -41.0 * k as f64];
    }
    out.push(("tiny-anisotropic-rotated".to_string(), s));
    // every material a mirror: reflected rays start on every surface
    let mut s = base;
    for m in &mut s.materials {
        m.reflection = rt::Reflection::Constant(0.6);
    }
    s.depth = 3;
    out.push(("all-mirrors".to_string(), s));
    out
}

#[test]
fn culling_is_bit_identical_in_every_admitted_format() {
    let mut list: Vec<(String, Scene)> = SCENES
        .iter()
        .map(|(n, t)| (n.to_string(), jobs::scene::parse(t, n).expect("parses")))
        .collect();
    list.extend(cull_edge_scenes());
    for (name, scene) in &list {
        for numeric in [
            Numeric::F64,
            Numeric::F32,
            Numeric::Q16_16,
            Numeric::Q8_24,
            Numeric::Q32_32,
        ] {
            let opts = |cull| RenderOptions {
                numeric,
                aovs: true,
                size: Some((96, 54)),
                cull,
                ..Default::default()
            };
            let (Ok(c), Ok(n)) = (
                rt::render(scene, &opts(true)),
                rt::render(scene, &opts(false)),
            ) else {
                panic!("{name} {numeric:?} does not render");
            };
            assert_same_frame(&c, &n, &format!("{name} {numeric:?} culled/unculled"));
        }
    }
}

#[test]
fn culling_removes_work_where_it_is_admitted() {
    let scene = jobs::scene::parse(SCENES[0].1, "reference").expect("parses");
    let n = scene.objects.len() as f64;
    let d = Math::default();
    // 8 objects, of which the wall plane is unbounded and the floor square wide: a tile
    // of primary rays tests fewer than half of them on average
    let f32_mean = rt::primary_candidates::<f32>(&scene, 1920, 1080, &d);
    assert!(f32_mean < 0.5 * n, "f32: {f32_mean} of {n}");
    // Q16.16's 2⁻¹⁶ step admits every bounded object from the camera's distance under
    // the Stable model (the old shape-blind model left out the cylinder, cone and cube:
    // 5.14), so its tiles list exactly what f32's do
    let q_mean = rt::primary_candidates::<sim_target::num::Q16_16>(&scene, 1920, 1080, &d);
    assert_eq!(q_mean, f32_mean, "Q16.16: {q_mean} of {n}");
    // the seed's textbook quadratic keeps the old model: fewer objects admitted
    let textbook = Math {
        quadratic: sim_target::rt::shapes::Quadratic::Textbook,
        ..d
    };
    let q_tb = rt::primary_candidates::<sim_target::num::Q16_16>(&scene, 1920, 1080, &textbook);
    assert!(q_tb > q_mean && q_tb < n, "Q16.16 textbook: {q_tb} of {n}");
    // Q8.24's ±128 cannot hold |o′|² from the camera's distance: nothing culled
    assert_eq!(
        rt::primary_candidates::<sim_target::num::Q8_24>(&scene, 1920, 1080, &d),
        n
    );
    // f16 and Q24.8 are too coarse: every object is tested
    assert_eq!(
        rt::primary_candidates::<half::f16>(&scene, 1920, 1080, &d),
        n
    );
    assert_eq!(
        rt::primary_candidates::<sim_target::num::Q24_8>(&scene, 1920, 1080, &d),
        n
    );
    // the seed's √ (PRE_S + 2 NR, ≈ 10 %) can put a root of an object behind the ray in
    // front of it: no culling; 5 NR steps (bound 4.7e-6), 3 seamless or the 16-entry table
    // with 2 are accurate enough
    let seed = Math::SEED;
    assert_eq!(rt::primary_candidates::<f32>(&scene, 1920, 1080, &seed), n);
    for (sqrt, culls) in [
        (SqrtKind::PreS { iters: 2 }, false),
        (SqrtKind::PreS { iters: 3 }, false),
        (SqrtKind::PreS { iters: 4 }, false),
        (SqrtKind::PreS { iters: 5 }, true),
        (SqrtKind::Seamless { iters: 3 }, true),
        (SqrtKind::Lut16 { iters: 2 }, true),
        (SqrtKind::Exact, true),
    ] {
        let m = Math { sqrt, ..d };
        let mean = rt::primary_candidates::<f32>(&scene, 1920, 1080, &m);
        assert_eq!(mean < n, culls, "{sqrt:?}: {mean}");
    }
    // the spheres-only subset leaves most tiles empty
    let spheres = Subset::SpheresFlat.apply(&scene);
    let m = rt::primary_candidates::<f32>(&spheres, 1920, 1080, &d);
    assert!(m < 0.5, "spheres only: {m}");
}
