//! The ray-trace category: tiny frames in every number format through [`Probe`] (so
//! every operation's saturation, NaN and wrap-around is counted), on scenes built to be
//! hard: grazing and parallel rays, huge and tiny scales, near-coincident surfaces, and
//! scenes where no lit pixel can be in shadow (acne).

use jobs::scene::range::{format_max, range_demand};
use protocol::frame::Numeric;
use protocol::names::Named;
use rand::rngs::SmallRng;
use rand::Rng;
use sim_target::num::instrumented::{self, Probe};
use sim_target::num::{Q16_16, Q24_8, Q32_32, Q8_24};
use sim_target::rt::f;
use sim_target::rt::{
    self, Camera, DiffuseModel, Filter as TexFilter, Frame, Light, Mapping, Material, Object,
    Reflection, RenderOptions, Scene, Shape, Specular, SpecularModel, Spot, Term, Texture,
    TextureKind,
};

use super::report::{AcneDetail, AcnePixel, CaseResult};

/// Rendered side of an rt case.
const RT_SIDE: u32 = 8;

/// log-uniform in [10^lo, 10^hi]
fn log_uniform(rng: &mut SmallRng, lo: f64, hi: f64) -> f64 {
    10f64.powf(rng.gen_range(lo..=hi))
}

fn matte() -> Material {
    Material {
        name: "matte".into(),
        ambient: None,
        diffuse: Term {
            k: 1.0,
            color: [1.0, 1.0, 1.0],
        },
        diffuse_model: DiffuseModel::Lambert,
        specular: None,
        reflection: Reflection::None,
        texture: None,
    }
}

fn random_material(rng: &mut SmallRng) -> Material {
    let mut m = matte();
    m.ambient = rng.gen::<bool>().then(|| Term {
        k: rng.gen_range(0.0..=1.0),
        color: [rng.gen(), rng.gen(), rng.gen()],
    });
    m.diffuse.k = rng.gen_range(0.0..=1.0);
    if rng.gen() {
        m.diffuse_model = DiffuseModel::OrenNayar {
            sigma2: rng.gen_range(0.0..=1.0),
        };
    }
    if rng.gen() {
        m.specular = Some(Specular {
            k: rng.gen_range(0.0..=1.0),
            color: [1.0, 1.0, 1.0],
            model: if rng.gen() {
                SpecularModel::BlinnPhong
            } else {
                SpecularModel::TorranceSparrow {
                    eta: rng.gen_range(1.0..3.0),
                    k: rng.gen_range(0.0..4.0),
                }
            },
            exponent: if rng.gen() {
                rng.gen_range(0..=1023)
            } else {
                rng.gen_range(0..64)
            },
        });
    }
    m.reflection = match rng.gen_range(0..4) {
        0 => Reflection::None,
        1 => Reflection::Constant(rng.gen_range(0.0..=1.0)),
        2 => Reflection::Fresnel {
            eta: rng.gen_range(0.1..4.0),
            k: rng.gen_range(0.0..4.0),
        },
        _ => Reflection::Glass {
            eta: rng.gen_range(1.0..2.5),
        },
    };
    if rng.gen_ratio(1, 3) {
        m.texture = Some(Texture {
            kind: match rng.gen_range(0..5) {
                0 => TextureKind::Xor,
                1 => TextureKind::Checkerboard {
                    cell: rng.gen_range(1..64),
                },
                2 => TextureKind::RgbDots,
                3 => TextureKind::Marble { seed: rng.gen() },
                _ => TextureKind::Wood { seed: rng.gen() },
            },
            mapping: [Mapping::Planar, Mapping::Cylindrical, Mapping::Spherical]
                [rng.gen_range(0..3)],
            scale: [log_uniform(rng, -3.0, 3.0), log_uniform(rng, -3.0, 3.0)],
            offset: [rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3)],
            color2: [rng.gen(), rng.gen(), rng.gen()],
            filter: if rng.gen() {
                TexFilter::Nearest
            } else {
                TexFilter::Bilinear
            },
        });
    }
    m
}

fn base_scene(camera: Camera) -> Scene {
    Scene {
        width: RT_SIDE,
        height: RT_SIDE,
        depth: 1,
        bias: 0.001,
        max_distance: 1e6,
        background: [0.0; 3],
        spp: 1,
        camera,
        ambient: [0.0; 3],
        lights: Vec::new(),
        materials: vec![matte()],
        objects: Vec::new(),
        shadows: true,
    }
}

fn unit_dir(rng: &mut SmallRng) -> [f64; 3] {
    loop {
        let v: [f64; 3] = [
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        ];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 && n <= 1.0 {
            return [v[0] / n, v[1] / n, v[2] / n];
        }
    }
}

/// Kinds of rt case.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RtKind {
    /// One convex or flat object and one light: no lit point can be in shadow.
    Acne,
    /// A square lying (almost) on a plane, lit from above: coincident within CORE_BIAS/4.
    Coincident,
    /// The camera in or just above a plane/face, rays parallel to it.
    Grazing,
    /// Everything random: shapes, huge and tiny scales, materials, spot lights, depth.
    Wild,
}

/// One rt case; `acne_detail` keeps the scene and black pixels of acne in
/// [`CaseResult::acne`] ([`AcneList::Pixels`](super::report::AcneList::Pixels)).
pub(super) fn rt_case(rng: &mut SmallRng, acne_detail: bool) -> CaseResult {
    let mut r = CaseResult::default();
    let kind = [
        RtKind::Acne,
        RtKind::Coincident,
        RtKind::Grazing,
        RtKind::Wild,
    ][rng.gen_range(0..4)];
    let scene = match kind {
        RtKind::Acne => acne_scene(rng),
        RtKind::Coincident => coincident_scene(rng),
        RtKind::Grazing => grazing_scene(rng),
        RtKind::Wild => wild_scene(rng),
    };
    let fmt = rng.gen_range(0..Numeric::ALL.len());
    let opts = RenderOptions {
        aovs: true,
        ..RenderOptions::default()
    };
    let numeric = Numeric::ALL[fmt];
    // the same render with the plan's culling off: must match bit for bit (its probe
    // counts are dropped, the culled render's are kept)
    let (unculled, _) = instrumented::count(|| {
        render_probed(
            &scene,
            &RenderOptions {
                cull: false,
                ..opts
            },
            numeric,
        )
    });
    let (frame, counts) = instrumented::count(|| render_probed(&scene, &opts, numeric));
    let seen = counts.seen;
    if let (Ok(a), Ok(b)) = (&frame, &unculled) {
        let bits = |v: &Option<Vec<f32>>| -> Vec<u32> {
            v.iter().flatten().map(|x| x.to_bits()).collect()
        };
        if a.rgb8 != b.rgb8
            || bits(&a.depth) != bits(&b.depth)
            || bits(&a.normal) != bits(&b.normal)
        {
            r.counts.cull_mismatches = 1;
            r.failure = Some(format!(
                "{kind:?} scene in {}: culling changed the render; scene {scene:?}",
                numeric.name()
            ));
            return r;
        }
    }
    let frame = match frame {
        Ok(f) => f,
        Err(_) => {
            r.counts.rejected += 1;
            return r;
        }
    };
    let mut nonfinite = seen.nans;
    let mut wraps = seen.wraps;
    let (depth, normal) = match (&frame.depth, &frame.normal) {
        (Some(d), Some(n)) => (d, n),
        _ => {
            r.failure = Some("render returned no AOVs".into());
            r.counts.nonfinite += 1;
            return r;
        }
    };
    for (k, &t) in depth.iter().enumerate() {
        let n = &normal[3 * k..3 * k + 3];
        let hit = n.iter().any(|v| *v != 0.0);
        if t.is_nan() || (hit && !t.is_finite()) || n.iter().any(|v| !v.is_finite()) {
            nonfinite += 1;
        }
        if t < 0.0 {
            // A distance below zero: a sign flipped somewhere on the way to the pixel.
            wraps += 1;
        }
    }
    let fits = range_demand(&scene) <= format_max(numeric);
    if fits {
        r.counts.nonfinite = nonfinite;
    } else {
        r.counts.out_of_range = 1;
        r.counts.nonfinite_out_of_range = nonfinite;
    }
    r.counts.wraps = wraps;
    r.counts.saturations = seen.saturations;
    r.counts.overflow_nans = seen.overflow_nans;
    if matches!(kind, RtKind::Acne | RtKind::Coincident) {
        if let Ok(reference) = rt::render(
            &scene,
            &RenderOptions {
                numeric: Numeric::F64,
                ..opts
            },
        ) {
            let mut pixels = acne_detail.then(Vec::new);
            let (acne, checked) = count_acne(&scene, &reference, &frame, pixels.as_mut());
            if acne > 0 {
                r.acne = pixels.map(|pixels| AcneDetail {
                    kind: format!("{kind:?}"),
                    scene: scene.clone(),
                    pixels,
                });
            }
            if fits {
                r.counts.acne = acne;
                r.counts.acne_checked = checked;
            } else {
                r.counts.acne_out_of_range = acne;
            }
        }
    }
    let f = &mut r.formats[fmt];
    f.renders = 1;
    f.saturations = r.counts.saturations;
    f.overflow_nans = r.counts.overflow_nans;
    f.out_of_range = r.counts.out_of_range;
    f.nonfinite_out_of_range = r.counts.nonfinite_out_of_range;
    f.nonfinite = r.counts.nonfinite;
    f.acne = r.counts.acne;
    f.acne_checked = r.counts.acne_checked;
    f.acne_out_of_range = r.counts.acne_out_of_range;
    if r.counts.nonfinite + r.counts.wraps > 0 {
        r.failure = Some(format!(
            "{kind:?} scene in {}: {} NaN/inf, {} wraps; scene {scene:?}",
            numeric.name(),
            r.counts.nonfinite,
            r.counts.wraps
        ));
    }
    r
}

/// A render in `n` through [`Probe`], on the calling thread (so that the caller's
/// [`instrumented::count`] scope sees the whole frame).
fn render_probed(scene: &Scene, opts: &RenderOptions, n: Numeric) -> Result<Frame, rt::RtError> {
    match n {
        Numeric::F64 => rt::render_instrumented::<Probe<f64>>(scene, opts),
        Numeric::F32 => rt::render_instrumented::<Probe<f32>>(scene, opts),
        Numeric::F16 => rt::render_instrumented::<Probe<half::f16>>(scene, opts),
        Numeric::Q16_16 => rt::render_instrumented::<Probe<Q16_16>>(scene, opts),
        Numeric::Q8_24 => rt::render_instrumented::<Probe<Q8_24>>(scene, opts),
        Numeric::Q24_8 => rt::render_instrumented::<Probe<Q24_8>>(scene, opts),
        Numeric::Q32_32 => rt::render_instrumented::<Probe<Q32_32>>(scene, opts),
    }
}

/// Light intensity that makes n·ωᵢ ≥ 0.25 saturate white at distance `d` (Lambert 1/π).
fn bright(d: f64) -> [f64; 3] {
    let i = 4.0 * std::f64::consts::PI * d * d;
    [i, i, i]
}

fn look_at(rng: &mut SmallRng, target: [f64; 3], dist: f64) -> Camera {
    let dir = unit_dir(rng);
    Camera {
        position: f::add(target, f::scale(dir, dist)),
        look_at: target,
        up: if dir[1].abs() > 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        },
        fov_y: rng.gen_range(5.0..120.0),
    }
}

fn acne_scene(rng: &mut SmallRng) -> Scene {
    let shape = [
        Shape::Sphere,
        Shape::Cube,
        Shape::Plane,
        Shape::Disk,
        Shape::Square,
    ][rng.gen_range(0..5)];
    let s = if rng.gen_ratio(1, 4) {
        log_uniform(rng, -4.0, 4.0)
    } else {
        log_uniform(rng, -1.0, 1.5)
    };
    let centre = [
        rng.gen_range(-10.0..10.0) * s,
        rng.gen_range(-10.0..10.0) * s,
        rng.gen_range(-10.0..10.0) * s,
    ];
    let dist = s * rng.gen_range(2.0..8.0);
    let mut scene = base_scene(look_at(rng, centre, dist));
    let flat = matches!(shape, Shape::Plane | Shape::Disk | Shape::Square);
    if flat {
        // Look from above so that the lit side is seen.
        let mut p = scene.camera.position;
        p[1] = centre[1] + (p[1] - centre[1]).abs().max(0.2 * s);
        scene.camera.position = p;
        scene.camera.up = [1.0, 0.0, 0.0];
    }
    scene.objects.push(Object {
        shape,
        translate: centre,
        scale: [s, s, s],
        rotate: if rng.gen() {
            [
                rng.gen_range(0.0..360.0),
                rng.gen_range(0.0..360.0),
                rng.gen_range(0.0..360.0),
            ]
        } else {
            [0.0; 3]
        },
        material: 0,
    });
    // The light on the camera's side, sometimes grazing (almost in the tangent plane).
    let mut ld = unit_dir(rng);
    let to_cam = norm(f::add(scene.camera.position, f::scale(centre, -1.0)));
    if f::dot(ld, to_cam) < 0.0 {
        ld = f::scale(ld, -1.0);
    }
    if flat {
        ld[1] = if rng.gen_ratio(1, 3) {
            0.02
        } else {
            ld[1].abs().max(0.05)
        };
        ld = norm(ld);
    }
    let dl = s * rng.gen_range(2.0..20.0);
    scene.lights.push(Light {
        position: f::add(centre, f::scale(ld, dl)),
        color: bright(dl * 2.0),
        spot: None,
    });
    scene
}

fn coincident_scene(rng: &mut SmallRng) -> Scene {
    let s = log_uniform(rng, -1.0, 2.0);
    let delta = [0.0, 1e-9, 1e-6, 0.00025][rng.gen_range(0..4)];
    let mut scene = base_scene(Camera {
        position: [
            rng.gen_range(-1.0..1.0) * s,
            s * rng.gen_range(0.3..3.0),
            s * rng.gen_range(1.0..4.0),
        ],
        look_at: [0.0, 0.0, 0.0],
        up: [0.0, 1.0, 0.0],
        fov_y: rng.gen_range(20.0..90.0),
    });
    scene.objects.push(Object {
        shape: Shape::Plane,
        translate: [0.0, 0.0, 0.0],
        scale: [s, s, s],
        rotate: [0.0; 3],
        material: 0,
    });
    scene.objects.push(Object {
        shape: if rng.gen() {
            Shape::Square
        } else {
            Shape::Disk
        },
        translate: [0.0, delta, 0.0],
        scale: [s, s, s],
        rotate: [0.0; 3],
        material: 0,
    });
    let l = [
        rng.gen_range(-1.0..1.0) * s,
        s * rng.gen_range(0.5..4.0),
        rng.gen_range(-1.0..1.0) * s,
    ];
    let d = f::dot(l, l).sqrt();
    scene.lights.push(Light {
        position: l,
        color: bright(d * 2.0),
        spot: None,
    });
    scene
}

fn grazing_scene(rng: &mut SmallRng) -> Scene {
    let s = log_uniform(rng, -3.0, 3.0);
    let h = [0.0, 1e-9, 1e-6, 1e-3, -1e-6][rng.gen_range(0..5)] * s;
    let shape = [
        Shape::Plane,
        Shape::Square,
        Shape::Disk,
        Shape::Cube,
        Shape::Cylinder,
        Shape::Sphere,
    ][rng.gen_range(0..6)];
    // For a cube or cylinder the camera sits on the level of a face/cap (y = s).
    let level = if matches!(shape, Shape::Cube | Shape::Cylinder | Shape::Sphere) {
        s
    } else {
        0.0
    };
    let cam = Camera {
        position: [0.0, level + h, s * rng.gen_range(1.5..10.0)],
        look_at: [rng.gen_range(-0.5..0.5) * s, level + h, 0.0],
        up: [0.0, 1.0, 0.0],
        fov_y: rng.gen_range(1.0..170.0),
    };
    let mut scene = base_scene(cam);
    scene.materials.push(random_material(rng));
    scene.objects.push(Object {
        shape,
        translate: [0.0; 3],
        scale: [s, s, s],
        rotate: [0.0; 3],
        material: rng.gen_range(0..2),
    });
    let ld = unit_dir(rng);
    scene.lights.push(Light {
        position: f::scale(ld, s * rng.gen_range(1.1..10.0)),
        color: bright(s * 10.0),
        spot: None,
    });
    scene.depth = rng.gen_range(1..=3);
    scene
}

fn wild_scene(rng: &mut SmallRng) -> Scene {
    let world = log_uniform(rng, -6.0, 6.0);
    let dist = world * rng.gen_range(1.0..10.0);
    let cam = look_at(rng, [0.0; 3], dist);
    let mut scene = base_scene(cam);
    scene.bias = [0.001, 0.0, 1e-6, 0.1][rng.gen_range(0..4)];
    scene.max_distance = [1e6, 1e3, 1e12, 10.0][rng.gen_range(0..4)];
    scene.depth = rng.gen_range(1..=4);
    scene.ambient = [rng.gen(), rng.gen(), rng.gen()];
    scene.background = [rng.gen(), rng.gen(), rng.gen()];
    scene.materials = (0..rng.gen_range(1..=3))
        .map(|_| random_material(rng))
        .collect();
    for _ in 0..rng.gen_range(1..=8) {
        let scale = |rng: &mut SmallRng| {
            if rng.gen_ratio(1, 3) {
                log_uniform(rng, -6.0, 6.0)
            } else {
                world * log_uniform(rng, -1.0, 0.5)
            }
        };
        scene.objects.push(Object {
            shape: Shape::ALL[rng.gen_range(0..Shape::ALL.len())],
            translate: f::scale(unit_dir(rng), world * rng.gen_range(0.0..3.0)),
            scale: [scale(rng), scale(rng), scale(rng)],
            rotate: if rng.gen() {
                [
                    rng.gen_range(-720.0..720.0),
                    rng.gen_range(-720.0..720.0),
                    rng.gen_range(-720.0..720.0),
                ]
            } else {
                [0.0; 3]
            },
            material: rng.gen_range(0..scene.materials.len()),
        });
    }
    for _ in 0..rng.gen_range(0..=2) {
        let pos = f::scale(unit_dir(rng), world * rng.gen_range(0.5..5.0));
        let spot = rng.gen::<bool>().then(|| {
            let outer = rng.gen_range(-1.0..1.0);
            Spot {
                direction: f::scale(unit_dir(rng), log_uniform(rng, -3.0, 3.0)),
                cos_outer: outer,
                cos_inner: if rng.gen_ratio(1, 4) {
                    outer
                } else {
                    rng.gen_range(outer..=1.0)
                },
            }
        });
        scene.lights.push(Light {
            position: pos,
            color: f::scale(
                [rng.gen(), rng.gen(), rng.gen()],
                log_uniform(rng, -3.0, 8.0),
            ),
            spot,
        });
    }
    scene
}

/// The primary ray direction of pixel (i, j) as the camera of docs/requirements.md §4.2 defines it.
fn primary_dir(c: &Camera, w: u32, h: u32, i: u32, j: u32) -> [f64; 3] {
    let wv = norm(f::add(c.position, f::scale(c.look_at, -1.0)));
    let u = norm(f::cross(c.up, wv));
    let v = f::cross(wv, u);
    let s = (c.fov_y.to_radians() / 2.0).tan();
    let a = w as f64 / h as f64;
    let x = (2.0 * (i as f64 + 0.5) / w as f64 - 1.0) * s * a;
    let y = (1.0 - 2.0 * (j as f64 + 0.5) / h as f64) * s;
    norm(f::add(
        f::add(f::scale(u, x), f::scale(v, y)),
        f::scale(wv, -1.0),
    ))
}

/// Acne: a pixel the f64 reference hits on a face turned well towards the light (n·ωᵢ ≥
/// 0.3, so the light alone saturates it white), which the tested format hits on the same
/// face (normals within 25°) and renders black. In these scenes no lit point *seen from
/// outside* can be shadowed (one convex or flat object; or a square on a plane within
/// CORE_BIAS/4 with the light above), so black can only be a false self-shadow.
///
/// Pixels that show the inside of a closed object (sphere or cube) are not checked: valid
/// hits start at t = CORE_BIAS (docs/requirements.md §4.3), so an eye nearer than
/// CORE_BIAS to the object sees its near face clipped away and the far face from inside,
/// where the near face rightly shadows it (seed 1, case 551791: a cube of half-size
/// 1.15·10⁻³ seen from 2.4·10⁻³, 22 black pixels in f64). The normal AOV faces the eye, so
/// such a hit is the one whose normal points towards the object's centre.
///
/// `black`, when given, receives each black pixel with what the reference saw there.
fn count_acne(
    scene: &Scene,
    reference: &Frame,
    test: &Frame,
    mut black: Option<&mut Vec<AcnePixel>>,
) -> (u64, u64) {
    let (Some(rd), Some(rn), Some(tn)) = (&reference.depth, &reference.normal, &test.normal) else {
        return (0, 0);
    };
    let Some(light) = scene.lights.first() else {
        return (0, 0);
    };
    let (mut acne, mut checked) = (0, 0);
    for j in 0..reference.height {
        for i in 0..reference.width {
            let k = (j * reference.width + i) as usize;
            let t = rd[k] as f64;
            if !t.is_finite() {
                continue;
            }
            let n = [rn[3 * k] as f64, rn[3 * k + 1] as f64, rn[3 * k + 2] as f64];
            let d = primary_dir(&scene.camera, reference.width, reference.height, i, j);
            let p = f::add(scene.camera.position, f::scale(d, t));
            let wi = norm(f::add(light.position, f::scale(p, -1.0)));
            if f::dot(n, wi) < 0.3 || seen_from_inside(scene, p, n) {
                continue;
            }
            let m = [tn[3 * k] as f64, tn[3 * k + 1] as f64, tn[3 * k + 2] as f64];
            if f::dot(n, m) < 0.9 {
                continue;
            }
            checked += 1;
            if test.rgb8[3 * k..3 * k + 3].iter().all(|&c| c == 0) {
                if let Some(black) = black.as_deref_mut() {
                    let to_light = f::add(light.position, f::scale(p, -1.0));
                    let rgb = &reference.rgb8[3 * k..3 * k + 3];
                    black.push(AcnePixel {
                        x: i,
                        y: j,
                        t,
                        point: p,
                        normal: n,
                        n_dot_wi: f::dot(n, wi),
                        light_distance: f::dot(to_light, to_light).sqrt(),
                        reference_rgb: [rgb[0], rgb[1], rgb[2]],
                    });
                }
                acne += 1;
            }
        }
    }
    (acne, checked)
}

/// Whether the hit at `p` with eye-facing normal `n` is on the inside of a scene's only
/// object, a closed convex one (its centre is inside, so the outward normal points away
/// from it).
fn seen_from_inside(scene: &Scene, p: [f64; 3], n: [f64; 3]) -> bool {
    match scene.objects.as_slice() {
        [o] if matches!(o.shape, Shape::Sphere | Shape::Cube) => {
            f::dot(n, f::add(p, f::scale(o.translate, -1.0))) < 0.0
        }
        _ => false,
    }
}

/// `a` scaled to unit length by the reciprocal of its length (not [`f::normalize`], which
/// divides each component: the generated scenes are functions of these bits).
fn norm(a: [f64; 3]) -> [f64; 3] {
    f::scale(a, 1.0 / f::length(a))
}
