//! f32's packet kernel (primary rays searched eight at a time, `Kernel::Planned`) against
//! the scalar kernel it must equal (`Kernel::Scalar`, one ray at a time): RGB, depth,
//! normal and object AOVs and every ray count bit for bit, on the gallery and its feature
//! subsets, at sizes that leave partial packets and tiles, with several samples per pixel,
//! culled and unculled; and on random scenes of every shape, turned, stretched and seen
//! from inside, where the lanes' selects meet every branch of the intersectors (parallel
//! rays, Δ′ < 0, roots behind the eye, a = 0).

use sim_target::rt::{self, Kernel, Numeric, RenderOptions, Scene, Shape, Subset, ToneMap};

use crate::common;
use common::{assert_same_frame, Rng};

/// The gallery and the Mitsuba comparison's Lambert scene.
fn scenes() -> impl Iterator<Item = (&'static str, &'static str)> {
    common::GALLERY.iter().copied().chain([(
        "lambert",
        include_str!("../../../bench/mitsuba/lambert.toml"),
    )])
}

fn options(size: (u32, u32), spp: u32, cull: bool) -> RenderOptions {
    RenderOptions {
        numeric: Numeric::F32,
        aovs: true,
        size: Some(size),
        spp: Some(spp),
        cull,
        ..Default::default()
    }
}

fn assert_packets_equal(scene: &Scene, size: (u32, u32), spp: u32, cull: bool, what: &str) {
    assert_packets_equal_with(scene, &options(size, spp, cull), what);
}

/// The packet kernel's frame, AOVs (when `opts` asks for them) and ray counts are the
/// scalar kernel's.
fn assert_packets_equal_with(scene: &Scene, opts: &RenderOptions, what: &str) {
    let frame = |kernel| {
        let o = RenderOptions { kernel, ..*opts };
        rt::render(scene, &o).expect("renders")
    };
    let p = frame(Kernel::Planned);
    let s = frame(Kernel::Scalar);
    assert_same_frame(&p, &s, what);
    assert_eq!(p.object, s.object, "{what}: object AOV");
    assert_eq!(
        (
            p.stats.primary_rays,
            p.stats.shadow_rays,
            p.stats.reflected_rays,
            p.stats.refracted_rays
        ),
        (
            s.stats.primary_rays,
            s.stats.shadow_rays,
            s.stats.reflected_rays,
            s.stats.refracted_rays
        ),
        "{what}: ray counts"
    );
}

#[test]
fn packets_equal_the_scalar_kernel_on_the_gallery() {
    for (name, text) in scenes() {
        let scene = jobs::scene::parse(text, name).expect("gallery scene parses");
        for sub in Subset::ALL {
            let s = sub.apply(&scene);
            let what = format!("{name}/{}", sub.label());
            // 53 columns: six whole packets and a partial one, tiles cut at 48
            assert_packets_equal(&s, (53, 31), 1, true, &what);
        }
        assert_packets_equal(&scene, (37, 20), 4, true, &format!("{name} spp 4"));
        assert_packets_equal(&scene, (40, 22), 1, false, &format!("{name} unculled"));
    }
}

/// A random object: any shape, anywhere near the origin, turned and stretched.
fn object(rng: &mut Rng, material: usize) -> rt::Object {
    let shapes = Shape::ALL;
    let shape = shapes[(rng.next() * shapes.len() as f64) as usize % shapes.len()];
    // a third of the objects keep the axes (the diagonal transform), and some sit at
    // right angles so that rays run parallel to their faces and axes
    let rotate = match (rng.next() * 3.0) as u32 {
        0 => [0.0; 3],
        1 => [90.0 * (rng.next() * 4.0).floor(), 0.0, 90.0],
        _ => [
            rng.range(-180.0, 180.0),
            rng.range(-180.0, 180.0),
            rng.range(-180.0, 180.0),
        ],
    };
    let s = rng.range(0.3, 1.5);
    let scale = if rng.next() < 0.5 {
        [s; 3]
    } else {
        [s, s * rng.range(0.2, 3.0), s * rng.range(0.2, 3.0)]
    };
    rt::Object {
        shape,
        translate: [
            rng.range(-3.0, 3.0),
            rng.range(-2.0, 2.0),
            rng.range(-3.0, 3.0),
        ],
        scale,
        rotate,
        material,
    }
}

/// A camera on a sphere about the origin, looking near it: every fourth (`n`) among the
/// objects (inside some of them), the others outside.
fn place_camera(scene: &mut Scene, rng: &mut Rng, n: usize) {
    let r = if n.is_multiple_of(4) { 1.5 } else { 9.0 };
    let (th, ph) = (rng.range(0.0, std::f64::consts::TAU), rng.range(-1.2, 1.2));
    scene.camera.position = [
        r * th.cos() * ph.cos(),
        r * ph.sin(),
        r * th.sin() * ph.cos(),
    ];
    scene.camera.look_at = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0];
    scene.camera.up = [0.0, 1.0, 0.0];
}

#[test]
fn packets_equal_the_scalar_kernel_on_random_scenes() {
    let base = jobs::scene::parse(
        include_str!("../../../examples/reference.toml"),
        "reference",
    )
    .expect("parses");
    let materials = base.materials.len();
    let mut rng = Rng(0x9ac7);
    for n in 0..40 {
        let mut scene = base.clone();
        let count = 1 + (rng.next() * 9.0) as usize;
        scene.objects = (0..count)
            .map(|k| object(&mut rng, k % materials))
            .collect();
        place_camera(&mut scene, &mut rng, n);
        assert_packets_equal(&scene, (45, 26), 1, true, &format!("random scene {n}"));
    }
}

/// Scenes the packet lanes shade (`rt/packet/shade.rs`): the Lambert scene's
/// materials, half of them with an ambient term, one or two point lights (sometimes
/// among the objects), shadows on and off, and random objects of every shape, turned,
/// stretched and around the camera. Half the materials have a Blinn–Phong highlight of
/// any exponent (0, 1, even, odd, the largest); a third of the scenes give one material
/// a Torrance–Sparrow term instead, which leaves its lanes to `trace` inside the same
/// packets; a third add a spot light aimed near the objects (its cone's edge across the
/// frame). Some also at four samples per pixel and some unculled.
#[test]
fn packet_shading_equals_the_scalar_kernel_on_random_scenes() {
    let base = jobs::scene::parse(
        include_str!("../../../bench/mitsuba/lambert.toml"),
        "lambert",
    )
    .expect("parses");
    let reference = jobs::scene::parse(
        include_str!("../../../examples/reference.toml"),
        "reference",
    )
    .expect("parses");
    let torrance_sparrow = reference
        .materials
        .iter()
        .filter_map(|m| m.specular.clone())
        .find(|s| matches!(s.model, rt::SpecularModel::TorranceSparrow { .. }))
        .expect("the reference scene has a Torrance–Sparrow material");
    let mut rng = Rng(0x5ade);
    for n in 0..48 {
        let mut scene = base.clone();
        scene.ambient = [0.3, 0.25, 0.2];
        for m in scene.materials.iter_mut().step_by(2) {
            m.ambient = Some(rt::Term {
                k: rng.range(0.1, 1.0),
                color: [rng.next(), rng.next(), rng.next()],
            });
        }
        // Blinn–Phong highlights (shaded in lanes) of every kind of exponent, and now
        // and then a Torrance–Sparrow one (left to `trace`)
        for m in scene.materials.iter_mut().skip(1).step_by(2) {
            let exponent = [0, 1, 2, 7, 64, 255, 1023][(rng.next() * 7.0) as usize % 7];
            m.specular = Some(rt::Specular {
                k: rng.range(0.1, 1.0),
                color: [rng.next(), rng.next(), rng.next()],
                model: rt::SpecularModel::BlinnPhong,
                exponent,
            });
        }
        if n % 3 == 1 {
            scene.materials[2].specular = Some(torrance_sparrow.clone());
        }
        let materials = scene.materials.len();
        let count = 1 + (rng.next() * 9.0) as usize;
        scene.objects = (0..count)
            .map(|k| object(&mut rng, k % materials))
            .collect();
        let mut light = scene.lights[0].clone();
        light.position = [
            rng.range(-3.0, 3.0),
            rng.range(-2.0, 4.0),
            rng.range(-3.0, 3.0),
        ];
        if n % 2 == 0 {
            scene.lights.push(light.clone());
        }
        if n % 3 == 2 {
            let position = [
                rng.range(-4.0, 4.0),
                rng.range(1.0, 5.0),
                rng.range(-4.0, 4.0),
            ];
            let cos_outer = rng.range(0.5, 0.95);
            scene.lights.push(rt::Light {
                position,
                color: [40.0, 35.0, 30.0],
                spot: Some(rt::Spot {
                    direction: [
                        rng.range(-1.0, 1.0) - position[0],
                        -position[1],
                        rng.range(-1.0, 1.0) - position[2],
                    ],
                    cos_outer,
                    // a hard edge (inner = outer) now and then
                    cos_inner: if n % 9 == 2 {
                        cos_outer
                    } else {
                        rng.range(cos_outer, 1.0)
                    },
                }),
            });
        }
        scene.shadows = n % 4 != 3;
        place_camera(&mut scene, &mut rng, n);
        assert_packets_equal(&scene, (45, 26), 1, true, &format!("plain scene {n}"));
        match n % 6 {
            0 => assert_packets_equal(&scene, (37, 20), 4, true, &format!("plain {n} spp 4")),
            3 => assert_packets_equal(&scene, (40, 22), 1, false, &format!("plain {n} unculled")),
            // the colour bytes quantised in lanes without AOVs (the row builds no hit),
            // and through the other tone map, with one sample and with several
            1 | 4 => {
                let spp = if n % 6 == 1 { 1 } else { 4 };
                let mut o = options((43, 21), spp, true);
                o.aovs = false;
                assert_packets_equal_with(&scene, &o, &format!("plain {n} no AOVs"));
                o.tone_map = ToneMap::Reinhard;
                assert_packets_equal_with(&scene, &o, &format!("plain {n} Reinhard"));
            }
            _ => {}
        }
    }
}
