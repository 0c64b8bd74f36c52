//! The generated scenes the frame core and the device are held to the model with, the
//! model's frame of one, and the comparison of every pixel.
//!
//! Scenes: random cameras (position, aim, up, field of view) and one to eight objects of
//! every shape, rotated or not, scaled per axis, in front of, around and behind the
//! camera; mixed in: duplicated objects (coincident surfaces: the later one must win the
//! tie, as the model's t <= best does), touching spheres, a max_distance that cuts
//! through the scene, a zero bias, far scenes whose values come near the edge of
//! Q16.16's range, scenes without objects, and a light in a plane (its shadow rays end
//! on the plane).

use rand::rngs::SmallRng;
use rand::Rng;
use rt_core_rtl_sim::CastFrame;
use sim_target::rt::core::CoreFrame;
use sim_target::rt::{
    self, Camera, DiffuseModel, Light, Material, Numeric, Object, Reflection, RenderOptions, Scene,
    Shape, Specular, SpecularModel, Term, NO_OBJECT,
};
use sim_target::scene_regs::from_regs;

/// A Lambert material, with or without an ambient term and a Blinn-Phong highlight.
pub(crate) fn material(rng: &mut SmallRng) -> Material {
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

pub(crate) fn v3(rng: &mut SmallRng, s: f64) -> [f64; 3] {
    [0, 1, 2].map(|_| rng.gen_range(-s..=s))
}

/// A random scene of class `class` (see the module doc).
pub(crate) fn scene(rng: &mut SmallRng, class: u32) -> Scene {
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
pub(crate) fn expected_cycles(s: &Scene) -> u64 {
    CoreFrame::of(s).cycles()
}

/// The model's frame of `scene`, through the register image the core reads.
pub(crate) fn model(scene: &Scene) -> (Vec<u32>, rt::Frame) {
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

pub(crate) fn f(bits: i32) -> f32 {
    (f64::from(bits) / 65536.0) as f32
}

/// Every pixel of the core's frame against the model's planes; the first difference.
pub(crate) fn compare(rtl: &CastFrame, m: &rt::Frame) -> Result<(), String> {
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
