//! The frame core `rt_cast` against the golden model rendering the same register image in
//! Q16.16 with its AOV planes: for every pixel the same colour, the same hit or miss, the
//! same object, the same depth and the same normal, bit for bit, and the frame's cycle
//! count by the model's formula for the core (`sim_target::rt::core`). Materials: Lambert
//! with or without an ambient term and a Blinn-Phong highlight (exponents 0 to 1023), one
//! point light or none, lights bright enough to clip, backgrounds beyond [0, 1], hard
//! shadows on in most scenes.
//!
//! Scenes: random cameras (position, aim, up, field of view) and one to eight objects of
//! every shape, rotated or not, scaled per axis, in front of, around and behind the
//! camera; mixed in: duplicated objects (coincident surfaces: the later one must win the
//! tie, as the model's t <= best does), touching spheres, a max_distance that cuts
//! through the scene, a zero bias, far scenes whose values come near the edge of
//! Q16.16's range, scenes without objects, and a light in a plane (its shadow rays end
//! on the plane).

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use rt_core_rtl_sim::{Cast, CastFrame};
use sim_target::rt::core::CoreFrame;
use sim_target::rt::{
    self, Camera, DiffuseModel, Light, Material, Numeric, Object, Reflection, RenderOptions, Scene,
    Shape, Specular, SpecularModel, Term, NO_OBJECT,
};
use sim_target::scene_regs::from_regs;

/// A Lambert material, with or without an ambient term and a Blinn-Phong highlight.
fn material(rng: &mut SmallRng) -> Material {
    let colour = |rng: &mut SmallRng| [0, 1, 2].map(|_| rng.gen_range(0.0..1.0));
    Material {
        name: "m".into(),
        ambient: rng.gen_bool(0.7).then(|| Term {
            k: rng.gen_range(0.05..1.0),
            color: colour(rng),
        }),
        diffuse: Term {
            k: rng.gen_range(0.0..1.0),
            color: colour(rng),
        },
        diffuse_model: DiffuseModel::Lambert,
        specular: rng.gen_bool(0.6).then(|| Specular {
            k: rng.gen_range(0.05..1.0),
            color: colour(rng),
            model: SpecularModel::BlinnPhong,
            exponent: match rng.gen_range(0..4) {
                0 => rng.gen_range(0..4),
                1 => rng.gen_range(0..=1023),
                _ => rng.gen_range(4..200),
            },
        }),
        reflection: Reflection::None,
        texture: None,
    }
}

fn v3(rng: &mut SmallRng, s: f64) -> [f64; 3] {
    [0, 1, 2].map(|_| rng.gen_range(-s..=s))
}

/// A random scene of class `class` (see the module doc).
fn scene(rng: &mut SmallRng, class: u32) -> Scene {
    let far = class == 5;
    let unit = if far { 400.0 } else { 1.0 };
    let width = rng.gen_range(4..=28);
    let height = rng.gen_range(3..=20);
    let position = loop {
        let p = v3(rng, 12.0 * unit);
        if p.iter().map(|x| x * x).sum::<f64>() > (2.0 * unit) * (2.0 * unit) {
            break p;
        }
    };
    let look_at = v3(rng, 2.0 * unit);
    let up = if rng.gen_bool(0.7) {
        [0.0, 1.0, 0.0]
    } else {
        v3(rng, 1.0)
    };
    let count = match class {
        4 => 0,
        _ => rng.gen_range(1..=8),
    };
    let mut objects: Vec<Object> = (0..count)
        .map(|_| {
            let uniform = rng.gen_range(0.3..3.0) * unit;
            Object {
                // planes are infinite and would take most pixels: half as often
                shape: loop {
                    let s = Shape::ALL[rng.gen_range(0..Shape::ALL.len())];
                    if s != Shape::Plane || rng.gen_bool(0.5) {
                        break s;
                    }
                },
                translate: v3(rng, 5.0 * unit),
                scale: if rng.gen_bool(0.5) {
                    [uniform; 3]
                } else {
                    [0, 1, 2].map(|_| rng.gen_range(0.2..3.0) * unit)
                },
                rotate: if rng.gen_bool(0.5) {
                    [0.0; 3]
                } else {
                    v3(rng, 180.0)
                },
                material: 0,
            }
        })
        .collect();
    let mut materials = Vec::new();
    match class {
        // coincident: a copy of an object later in the list
        1 if !objects.is_empty() => {
            let k = rng.gen_range(0..objects.len());
            let copy = objects[k].clone();
            let at = rng.gen_range(k..objects.len());
            objects.insert(at + 1, copy);
            objects.truncate(8);
        }
        // touching spheres along x
        2 => {
            objects.truncate(6);
            let r = rng.gen_range(0.5..1.5);
            let c = v3(rng, 2.0);
            for s in [-1.0, 1.0] {
                objects.push(Object {
                    shape: Shape::Sphere,
                    translate: [c[0] + s * r, c[1], c[2]],
                    scale: [r; 3],
                    rotate: [0.0; 3],
                    material: 0,
                });
            }
        }
        // objects behind the camera: mirrored through it
        3 => {
            for o in objects.iter_mut().step_by(2) {
                for (t, p) in o.translate.iter_mut().zip(position) {
                    *t = 2.0 * p - *t;
                }
            }
        }
        _ => {}
    }
    for (i, o) in objects.iter_mut().enumerate() {
        o.material = i;
        materials.push(material(rng));
    }
    if materials.is_empty() {
        materials.push(material(rng));
    }
    // none or one point light (the core's default build has one lane), sometimes bright
    // enough to clip
    let mut lights = if rng.gen_bool(0.85) {
        // half the time above an object, which then casts its shadow on what lies below
        let position = match objects.len() {
            n if n > 0 && rng.gen_bool(0.5) => {
                let o = objects[rng.gen_range(0..n)].translate;
                let j = v3(rng, 1.5 * unit);
                [
                    o[0] + j[0],
                    o[1] + rng.gen_range(3.0..9.0) * unit,
                    o[2] + j[2],
                ]
            }
            _ => v3(rng, 10.0 * unit),
        };
        vec![Light {
            position,
            color: [0, 1, 2].map(|_| rng.gen_range(0.0..60.0) * unit.min(400.0)),
            spot: None,
        }]
    } else {
        Vec::new()
    };
    // a light in a plane: every shadow ray towards it ends on the plane (its origin stays
    // on the surface: bias 0), where the range test's last bits decide
    if class == 7 {
        if let Some(l) = lights.first_mut() {
            objects.truncate(7);
            let mut plane = Object {
                shape: Shape::Plane,
                translate: v3(rng, 3.0),
                scale: [1.0; 3],
                rotate: [0.0; 3],
                material: objects.len(),
            };
            plane.translate[1] = l.position[1];
            objects.push(plane);
            materials.push(material(rng));
        }
    }
    let dist = (0..3)
        .map(|a| (position[a] - look_at[a]).powi(2))
        .sum::<f64>()
        .sqrt();
    Scene {
        width,
        height,
        depth: 1,
        bias: match if class == 7 { 0 } else { rng.gen_range(0..4) } {
            0 => 0.0,
            1 => 1.0 / 65536.0,
            _ => rng.gen_range(0.0005..0.01),
        },
        max_distance: if class == 6 {
            rng.gen_range(0.5..1.2) * dist
        } else {
            1e6
        },
        background: [0, 1, 2].map(|_| rng.gen_range(-0.2..1.2)),
        spp: 1,
        shadows: rng.gen_bool(0.7),
        camera: Camera {
            position,
            look_at,
            up,
            fov_y: rng.gen_range(15.0..120.0),
        },
        ambient: [0, 1, 2].map(|_| rng.gen_range(0.0..0.5)),
        lights,
        materials,
        objects,
    }
}

/// Clock edges of a frame by the model's formula for the core.
fn expected_cycles(s: &Scene) -> u64 {
    CoreFrame::of(s).cycles()
}

/// The model's frame of `scene`, through the register image the core reads.
fn model(scene: &Scene) -> (Vec<u32>, rt::Frame) {
    let regs = jobs::scene::to_regs(scene).expect("scene fits the registers");
    let words: Vec<u32> = regs.words().collect();
    let held = from_regs(&regs).expect("image reads back");
    let opts = RenderOptions {
        numeric: Numeric::Q16_16,
        aovs: true,
        ..Default::default()
    };
    (words, rt::render(&held, &opts).expect("model renders"))
}

fn f(bits: i32) -> f32 {
    (f64::from(bits) / 65536.0) as f32
}

/// Every pixel of the core's frame against the model's planes; the first difference.
fn compare(rtl: &CastFrame, m: &rt::Frame) -> Result<(), String> {
    let (w, h) = (m.width as usize, m.height as usize);
    if rtl.pixels.len() != w * h {
        return Err(format!("{} pixels, model {}", rtl.pixels.len(), w * h));
    }
    let (Some(depth), Some(normal), Some(object)) = (&m.depth, &m.normal, &m.object) else {
        return Err("model has no AOV planes".into());
    };
    let kcu116 = rt::pack_kcu116(&m.rgb8, m.width);
    for (i, p) in rtl.pixels.iter().enumerate() {
        let (x, y) = (i % w, i / w);
        if (usize::from(p.x), usize::from(p.y)) != (x, y) {
            return Err(format!("pixel {i} came as ({}, {})", p.x, p.y));
        }
        let obj = if p.hit { u16::from(p.obj) } else { NO_OBJECT };
        let d = if p.hit { f(p.t) } else { f32::INFINITY };
        let n = p.n.map(f);
        let mn = [normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]];
        let mrgb = [m.rgb8[3 * i], m.rgb8[3 * i + 1], m.rgb8[3 * i + 2]];
        if p.kcu116 != kcu116[i] {
            return Err(format!(
                "pixel ({x}, {y}): RTL KCU116 word {:#06x}, model {:#06x}",
                p.kcu116, kcu116[i]
            ));
        }
        if p.rgb != mrgb {
            return Err(format!(
                "pixel ({x}, {y}): RTL colour {:?}, model {mrgb:?} (object {obj}, depth {d})",
                p.rgb
            ));
        }
        if obj != object[i]
            || d.to_bits() != depth[i].to_bits()
            || n.map(f32::to_bits) != mn.map(f32::to_bits)
        {
            return Err(format!(
                "pixel ({x}, {y}): RTL object {obj} depth {d} normal {n:?}, \
                 model object {} depth {} normal {mn:?}",
                object[i], depth[i]
            ));
        }
    }
    Ok(())
}

#[test]
fn generated_scenes_give_the_models_aov_planes() {
    let mut rng = SmallRng::seed_from_u64(0x7274_6361);
    let mut core = Cast::new().expect("Verilated rt_cast");
    let (mut pixels, mut hits, mut mid, mut shadowed) = (0usize, 0usize, 0usize, 0usize);
    let mut shapes_hit = [0usize; 7];
    let mut slots = std::collections::BTreeSet::new();
    for k in 0..300u32 {
        let s = scene(&mut rng, k % 8);
        let (words, m) = model(&s);
        if s.shadows {
            // pixels a shadow changed: the model's frame without shadows differs there
            let (_, lit) = model(&Scene {
                shadows: false,
                ..s.clone()
            });
            shadowed += m
                .rgb8
                .chunks(3)
                .zip(lit.rgb8.chunks(3))
                .filter(|(a, b)| a != b)
                .count();
            slots.insert(CoreFrame::of(&s).slot());
        }
        core.load(&words).expect("image fits");
        let frame = core.render(1 << 22, |_| false).expect("frame completes");
        assert_eq!(frame.err, 0, "scene {k}: the core refused it");
        if let Err(e) = compare(&frame, &m) {
            panic!("scene {k} (class {}): {e}\n{s:#?}", k % 8);
        }
        assert_eq!(frame.cycles, expected_cycles(&s), "scene {k}: cycles");
        pixels += frame.pixels.len();
        for p in frame.pixels.iter().filter(|p| p.hit) {
            hits += 1;
            // a colour neither black nor clipped in some channel: the shading's arithmetic
            // showed, not only its clamps
            mid += usize::from(p.rgb.iter().any(|c| (1..=254).contains(c)));
            shapes_hit[s.objects[usize::from(p.obj)].shape.code() as usize] += 1;
        }
    }
    eprintln!(
        "{pixels} pixels, {hits} hits ({mid} in mid-tones, {shadowed} in shadow), per shape \
         {shapes_hit:?}, shadow slots of {slots:?} clocks"
    );
    assert!(hits * 5 > pixels, "too few hits: {hits} of {pixels}");
    assert!(
        shadowed * 10 > hits,
        "too few shadowed pixels: {shadowed} of {hits}"
    );
    assert!(
        slots.contains(&2),
        "no scene with the shortest slot (one object, one light)"
    );
    assert!(mid * 2 > hits, "too few mid-tone hits: {mid} of {hits}");
    assert!(
        shapes_hit.iter().all(|&n| n > 200),
        "a shape is hit too rarely: {shapes_hit:?}"
    );
}

#[test]
fn holding_the_core_changes_nothing_but_time() {
    let mut rng = SmallRng::seed_from_u64(0x686f_6c64);
    let mut core = Cast::new().expect("Verilated rt_cast");
    for k in 0..6u32 {
        let s = scene(&mut rng, k % 4);
        let (words, m) = model(&s);
        core.load(&words).expect("image fits");
        let mut held = 0u64;
        let mut hold_rng = SmallRng::seed_from_u64(u64::from(k));
        let frame = core
            .render(1 << 22, |_| {
                let h = hold_rng.gen_bool(0.3);
                held += u64::from(h);
                h
            })
            .expect("frame completes");
        if let Err(e) = compare(&frame, &m) {
            panic!("scene {k} under holds: {e}");
        }
        assert_eq!(
            frame.cycles,
            expected_cycles(&s) + held,
            "scene {k}: every held edge adds one cycle"
        );
    }
}

/// A change to a scene.
type Edit = Box<dyn Fn(&mut Scene)>;

/// Each scene feature the core does not build raises its own refusal bit.
#[test]
fn what_the_core_does_not_build_is_refused() {
    let mut rng = SmallRng::seed_from_u64(0x7265_6675);
    let mut core = Cast::new().expect("Verilated rt_cast");
    let base = loop {
        let s = scene(&mut rng, 0);
        if !s.lights.is_empty() {
            break s;
        }
    };
    let cases: Vec<(&str, u8, Edit)> = vec![
        ("nothing", 0, Box::new(|_| {})),
        ("2 samples per pixel", 1 << 1, Box::new(|s| s.spp = 2)),
        ("shadows (built)", 0, Box::new(|s| s.shadows = true)),
        (
            "a spot light",
            1 << 6,
            Box::new(|s| {
                s.lights[0].spot = Some(rt::Spot {
                    direction: [0.0, -1.0, 0.0],
                    cos_outer: 0.5,
                    cos_inner: 0.7,
                })
            }),
        ),
        (
            "Oren-Nayar",
            1 << 7,
            Box::new(|s| s.materials[0].diffuse_model = DiffuseModel::OrenNayar { sigma2: 0.3 }),
        ),
        (
            "a reflection at depth 2",
            1 << 7,
            Box::new(|s| {
                s.depth = 2;
                s.materials[0].reflection = Reflection::Constant(0.5);
            }),
        ),
    ];
    for (what, bits, edit) in cases {
        let mut s = base.clone();
        edit(&mut s);
        let regs = jobs::scene::to_regs(&s).expect("scene fits the registers");
        let words: Vec<u32> = regs.words().collect();
        core.load(&words).expect("image fits");
        let frame = core.render(1 << 22, |_| false).expect("frame completes");
        assert_eq!(frame.err, bits, "{what}: err {:#010b}", frame.err);
    }
    // more lights than the core's lanes: the map itself holds only one point light, so
    // the word is written directly
    let regs = jobs::scene::to_regs(&base).expect("scene fits the registers");
    let mut words: Vec<u32> = regs.words().collect();
    words[protocol::scene::hdr::LIGHT_COUNT] = 3;
    core.load(&words).expect("image fits");
    let frame = core.render(1 << 22, |_| false).expect("frame completes");
    assert_eq!(frame.err, 1 << 6, "three lights: err {:#010b}", frame.err);
}

/// The reference scene reduced to what the core builds: textures and reflections off,
/// the spot light a point light, Oren–Nayar as Lambert, Torrance–Sparrow as Blinn–Phong
/// with its exponent; its shadows stay on.
fn reduced_reference(width: u32, height: u32) -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../examples/reference.toml"
    ))
    .expect("examples/reference.toml");
    let mut s = jobs::scene::parse(&text, "reference.toml").expect("reference parses");
    s.width = width;
    s.height = height;
    s.depth = 1;
    for l in &mut s.lights {
        l.spot = None;
    }
    for m in &mut s.materials {
        m.texture = None;
        m.reflection = Reflection::None;
        m.diffuse_model = DiffuseModel::Lambert;
        if let Some(sp) = &mut m.specular {
            sp.model = SpecularModel::BlinnPhong;
        }
    }
    s
}

/// The reduced reference scene at 160 × 90: every plane equal to the model's. Prints the
/// Verilated core's wall time and pairs per second (the figures docs/rt-core.md quotes).
#[test]
fn the_reduced_reference_scene_matches_the_model() {
    let s = reduced_reference(160, 90);
    let (words, m) = model(&s);
    let mut core = Cast::new().expect("Verilated rt_cast");
    core.load(&words).expect("image fits");
    let start = std::time::Instant::now();
    let frame = core.render(1 << 26, |_| false).expect("frame completes");
    let secs = start.elapsed().as_secs_f64();
    assert_eq!(frame.err, 0, "the core refused the reduced reference scene");
    if let Err(e) = compare(&frame, &m) {
        panic!("reduced reference: {e}");
    }
    assert!(s.shadows, "the reference scene has shadows");
    assert_eq!(frame.cycles, expected_cycles(&s));
    // pairs the unit tested: every slot's clocks, primary and shadow
    let pairs = u64::from(s.width * s.height) * CoreFrame::of(&s).slot();
    eprintln!(
        "reduced reference 160x90: {} cycles, {:.2} s Verilated, {:.0} pairs/s, {:.0} rays/s",
        frame.cycles,
        secs,
        pairs as f64 / secs,
        f64::from(s.width * s.height) / secs
    );
}
