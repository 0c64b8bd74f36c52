//! The fixed-point secondary-ray gate of `rt::cull` (`cull::Secondary`): shadow and
//! reflected rays are culled against a cylinder or cone only where their own quadratic
//! coefficient |a| = |dᵀFd| passes the gate. Two kinds of evidence:
//!
//! - **probes** of the datapath itself: rays along (and near) a cylinder's axis or a cone's
//!   generator, from just outside the bound and from far away, with scales up to 16:1,
//!   through exactly the f32 gate the pretest evaluates and the format's own intersector;
//!   a ray the gate and the sphere test would cull must never get a hit, and rays that do
//!   get false hits must exist below the gate (so the gate is what keeps them out);
//! - **renders** of scenes built around those directions (lights above an axis or on a
//!   generator's extension, mirrors, far-off placements, anisotropic and rotated objects),
//!   culled and unculled, bit for bit, in every fixed format.

use sim_target::num::{Scalar, Q16_16, Q24_8, Q32_32, Q8_24};
use sim_target::rt::{cull, shapes, Math, Numeric, Reflection, Scene, V3};
use sim_target::rt::{Object, Shape};

use crate::common;

use common::Rng;

fn obj(shape: Shape, t: [f64; 3], scale: [f64; 3], rotate: [f64; 3], material: usize) -> Object {
    Object {
        shape,
        translate: t,
        scale,
        rotate,
        material,
    }
}

/// The reference scene's materials and light with `objects` and a camera at `eye`
/// looking at `at`, framing a radius `r`.
fn scene(objects: Vec<Object>, eye: [f64; 3], at: [f64; 3], r: f64) -> Scene {
    let mut s = jobs::scene::parse(
        include_str!("../../../examples/reference.toml"),
        "reference",
    )
    .expect("parses");
    s.objects = objects;
    let d = ((eye[0] - at[0]).powi(2) + (eye[1] - at[1]).powi(2) + (eye[2] - at[2]).powi(2)).sqrt();
    s.camera.position = eye;
    s.camera.look_at = at;
    s.camera.up = [0.0, 1.0, 0.0];
    s.camera.fov_y = (2.0 * (1.3 * r / d).min(0.99).atan()).to_degrees();
    s
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / l)
}

/// Whether the line o + t·d, t ≥ 0, stays outside the ball (c, r).
fn misses(o: [f64; 3], d: [f64; 3], c: [f64; 3], r: f64) -> bool {
    let v = [o[0] - c[0], o[1] - c[1], o[2] - c[2]];
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let t = (-(v[0] * d[0] + v[1] * d[1] + v[2] * d[2]) / dd).max(0.0);
    let p = [v[0] + t * d[0], v[1] + t * d[1], v[2] + t * d[2]];
    p[0] * p[0] + p[1] * p[1] + p[2] * p[2] > r * r
}

/// |dᵀFd| as the pretest evaluates it in f32 (the ray's products d_i·d_j first, then the
/// coefficients F₀₀, F₁₁, F₂₂, 2F₀₁, 2F₀₂, 2F₁₂ in that order) and its threshold rounded
/// up as the pretest rounds it.
fn gate_f32(g: &cull::Secondary, d: [f64; 3]) -> (f32, f32) {
    let d = d.map(|v| v as f32);
    let p = [
        d[0] * d[0],
        d[1] * d[1],
        d[2] * d[2],
        d[0] * d[1],
        d[0] * d[2],
        d[1] * d[2],
    ];
    let q = &g.form;
    let f = [
        q[0][0] as f32,
        q[1][1] as f32,
        q[2][2] as f32,
        (2.0 * q[0][1]) as f32,
        (2.0 * q[0][2]) as f32,
        (2.0 * q[1][2]) as f32,
    ];
    let a = f[0] * p[0] + f[1] * p[1] + f[2] * p[2] + f[3] * p[3] + f[4] * p[4] + f[5] * p[5];
    (a.abs(), (g.a_min * (1.0 + 2f64.powi(-22))) as f32)
}

/// Where a probe's rays start.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    /// Near the shape in object space (the origins of `rt_cull`'s probe, which
    /// find the false hits of rays along a generator).
    Near,
    /// Lines that pass just outside the world bound, from origins near it.
    Skim,
    /// The same lines from up to the gate's safe distance away.
    Far,
}

/// What a probe run saw.
#[derive(Debug, Default)]
struct Probe {
    /// Rays that miss the widened bound from within the gate's safe distance.
    candidates: usize,
    /// ... of which the gate passes (culled by the pretest).
    culled: usize,
    /// Culled rays that the datapath hits: must be 0.
    violations: usize,
    /// Datapath hits on rays that miss the bound (all of them below the gate).
    false_hits: usize,
    /// The largest f32 |a| among those false hits.
    max_false_a: f64,
    /// The gate's threshold, the model's |a| and safe distance (for the printout).
    a_min: f64,
    #[allow(dead_code)]
    a_model: f64,
    #[allow(dead_code)]
    safe: f64,
}

/// `n` rays against one unrotated cylinder or cone (translated by `t`, scaled by `scale`)
/// in format `S`: along the axis (cylinder) or a generator (cone) with an angular
/// perturbation from 10⁻⁷ to 1, from origins as `mode` says. `a_scale` multiplies the gate's
/// threshold (1: the real gate; below 1: a weakened one, to show the probe notices).
fn probe<S: Scalar>(
    shape: Shape,
    t: [f64; 3],
    scale: [f64; 3],
    mode: Mode,
    n: usize,
    a_scale: f64,
) -> Probe {
    let m = Math::default();
    let o = obj(shape, t, scale, [0.0; 3], 4);
    let floor = obj(
        Shape::Square,
        [t[0], t[1] - 5.0, t[2]],
        [8.0, 1.0, 8.0],
        [0.0; 3],
        0,
    );
    let s = scene(vec![o, floor], [t[0], t[1] + 3.0, t[2] + 12.0], t, 2.0);
    let b = cull::bounds::<S>(&s, &m)[0];
    let (Some(b), Some(g)) = (b, b.and_then(|b| b.secondary)) else {
        println!("{} {shape:?} {scale:?}: no gate", S::NAME);
        return Probe::default();
    };
    assert_eq!(
        b.safe_distance, 0.0,
        "no ungated culling of a fixed quadric"
    );
    let mut out = Probe {
        a_min: g.a_min,
        a_model: g.a_model,
        safe: g.safe_distance,
        ..Default::default()
    };
    let g = cull::Secondary {
        a_min: g.a_min * a_scale,
        ..g
    };
    let inv = V3::<S>::from_f64(scale.map(|v| 1.0 / v));
    let ts = V3::<S>::from_f64(t);
    let (bias, tmax) = (
        S::from_f64(0.001),
        S::from_f64(1e6f64.min(S::max_value().to_f64())),
    );
    let mut rng = Rng(0x5eed ^ n as u64);
    for _ in 0..n {
        let cone = shape == Shape::Cone;
        // object space: a point near the shape and a direction along the degenerate one
        let eps = 10f64.powf(rng.range(-7.0, 0.0));
        let (po, dir) = if cone {
            let th = rng.range(0.0, std::f64::consts::TAU);
            let o = [
                rng.range(-1.6, 1.6),
                rng.range(-1.5, 1.5),
                rng.range(-1.6, 1.6),
            ];
            (
                o,
                [th.cos() + eps * rng.range(-1.0, 1.0), rng.sign(), th.sin()],
            )
        } else {
            // out through an end, as in `rt_cull`
            let (th, r) = (rng.range(0.0, 6.3), rng.range(1.03, 1.3));
            let o = [
                r * th.cos(),
                rng.sign() * rng.range(0.85, 1.0),
                r * th.sin(),
            ];
            let e = [eps * rng.range(-1.0, 1.0), eps * rng.range(-1.0, 1.0)];
            (o, [e[0], o[1].signum(), e[1]])
        };
        let dir = norm(dir);
        let dw = norm([scale[0] * dir[0], scale[1] * dir[1], scale[2] * dir[2]]);
        let ow = match mode {
            Mode::Near => [
                t[0] + scale[0] * po[0],
                t[1] + scale[1] * po[1],
                t[2] + scale[2] * po[2],
            ],
            Mode::Skim | Mode::Far => {
                // the line's closest approach to the centre just outside the bound, the
                // origin before it (near, or up to the safe distance), or a little past
                let v = [
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                ];
                let vd = v[0] * dw[0] + v[1] * dw[1] + v[2] * dw[2];
                let u = norm([v[0] - vd * dw[0], v[1] - vd * dw[1], v[2] - vd * dw[2]]);
                let rho = b.radius * rng.range(1.0, 1.15);
                let tau = if mode == Mode::Skim {
                    b.radius * rng.range(-0.5, 2.0)
                } else {
                    10f64.powf(rng.range(0.0, (0.95 * g.safe_distance).log10()))
                };
                [
                    t[0] + rho * u[0] - tau * dw[0],
                    t[1] + rho * u[1] - tau * dw[1],
                    t[2] + rho * u[2] - tau * dw[2],
                ]
            }
        };
        let (os, ds) = (V3::<S>::from_f64(ow), V3::<S>::from_f64(dw));
        let (oe, de) = (os.to_f64(), ds.to_f64());
        let dist = {
            let v = [
                oe[0] - b.centre[0],
                oe[1] - b.centre[1],
                oe[2] - b.centre[2],
            ];
            (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
        };
        if !misses(oe, de, b.centre, b.radius) || dist > g.safe_distance {
            continue;
        }
        out.candidates += 1;
        let (a, thr) = gate_f32(&g, de);
        let gated = a >= thr;
        out.culled += usize::from(gated);
        // the kernel's object-space ray of an unrotated object
        let (lo, ld) = ((os - ts).hadamard(inv), ds.hadamard(inv));
        let hit = if cone {
            shapes::cone(lo, ld, bias, tmax, &m)
        } else {
            shapes::cylinder(lo, ld, bias, tmax, &m)
        };
        if hit.is_some() {
            if gated {
                out.violations += 1;
                if out.violations < 4 {
                    println!(
                        "{} {shape:?} culled but hit: o={oe:?} d={de:?} |a|={a} t={:?}",
                        S::NAME,
                        hit.map(|v| v.to_f64())
                    );
                }
            } else {
                out.false_hits += 1;
                out.max_false_a = out.max_false_a.max(a as f64);
            }
        }
    }
    out
}

const SCALES: [[f64; 3]; 5] = [
    [1.0; 3],
    [0.6, 1.0, 0.6],
    [0.25, 4.0, 1.0],
    [4.0, 0.25, 4.0],
    [0.05, 0.05, 0.05],
];

fn probe_all<S: Scalar>(n: usize) -> Vec<(String, Probe)> {
    let mut out = Vec::new();
    for shape in [Shape::Cylinder, Shape::Cone] {
        for scale in SCALES {
            for mode in [Mode::Near, Mode::Skim, Mode::Far] {
                let t = [0.375, -0.5, 1.25];
                let p = probe::<S>(shape, t, scale, mode, n, 1.0);
                out.push((format!("{} {shape:?} {scale:?} {mode:?}", S::NAME), p));
            }
        }
    }
    out
}

/// No ray that the gate and the sphere test would cull gets a hit from the datapath, in
/// any admitted fixed format. (False hits are rare: these probes find none even with
/// the gate removed, 3·10⁵ near rays tried; the one known is pinned below.)
#[test]
fn gated_rays_never_hit_in_fixed_point() {
    let (mut gated, mut culled) = (0, 0);
    for (label, p) in probe_all::<Q16_16>(6_000)
        .into_iter()
        .chain(probe_all::<Q8_24>(3_000))
        .chain(probe_all::<Q32_32>(3_000))
    {
        println!("{label}: {p:?}");
        assert_eq!(p.violations, 0, "{label}: culled rays hit");
        assert!(p.max_false_a < p.a_min || p.false_hits == 0, "{label}");
        gated += usize::from(p.a_min > 0.0);
        culled += p.culled;
    }
    println!("{gated} of 90 probe set-ups gated, {culled} rays culled");
    assert!(
        gated >= 45 && culled > 50_000,
        "the probes must exercise the gate"
    );
}

/// The known false hit (`rt_cull`: a Q16.16 ray along the unit cone's
/// generator that misses the widened bound from 1.5 units away and still gets t = 0.5)
/// is culled by the sphere test from within the safe distance, and only the gate stops
/// it: its |a| is far below the threshold, so a gate lowered below that |a| (or none)
/// would change the image.
#[test]
fn the_gate_stops_the_known_false_hit() {
    let o = [0.67620849609375, 1.2515869140625, 0.449371337890625];
    let d = [0.18963623046875, -0.7071075439453125, -0.6811981201171875];
    let m = Math::default();
    let s = scene(
        vec![obj(Shape::Cone, [0.0; 3], [1.0; 3], [0.0; 3], 5)],
        [0.0, 2.0, 9.0],
        [0.0; 3],
        1.0,
    );
    let b = cull::bounds::<Q16_16>(&s, &m)[0].expect("culled");
    let g = b.secondary.expect("gated");
    let dist = (o[0] * o[0] + o[1] * o[1] + o[2] * o[2]).sqrt();
    assert!(misses(o, d, b.centre, b.radius) && dist <= g.safe_distance);
    let q = |v: [f64; 3]| V3::<Q16_16>::from_f64(v);
    let hit = shapes::cone(
        q(o),
        q(d),
        Q16_16::from_f64(0.001),
        Q16_16::from_f64(1e6),
        &m,
    );
    assert!(hit.is_some(), "the datapath's false hit");
    let (a, thr) = gate_f32(&g, q(d).to_f64());
    println!("|a| = {a:e}, gate {thr:e} (a_model {:e})", g.a_model);
    assert!(a < thr && f64::from(a) < 1e-3 * g.a_model);
}

/// Q24.8 is not admitted (its step is far above the slack): no bounds, no gate.
#[test]
fn q24_8_has_no_gate() {
    let s = scene(
        vec![obj(Shape::Cone, [0.0; 3], [1.0; 3], [0.0; 3], 5)],
        [0.0, 2.0, 9.0],
        [0.0; 3],
        1.0,
    );
    assert!(cull::bounds::<Q24_8>(&s, &Math::default())[0].is_none());
    // and the float formats keep their κ floor instead of a gate
    let f = cull::bounds::<f32>(&s, &Math::default())[0].expect("f32 culls the cone");
    assert!(f.secondary.is_none() && f.safe_distance > 0.0);
}

/// The reference scene's cylinder and cone are gated in Q16.16, with a safe distance that
/// covers every other bounded object and the eye, and a threshold well below the |a| of
/// the scene's shadow rays (≈ 0.3 for rays from the floor to the light).
#[test]
fn the_reference_scene_gates_its_quadrics() {
    let s = jobs::scene::parse(
        include_str!("../../../examples/reference.toml"),
        "reference",
    )
    .expect("parses");
    let b = cull::bounds::<Q16_16>(&s, &Math::default());
    for (k, o) in s.objects.iter().enumerate() {
        let g = b[k].and_then(|b| b.secondary);
        match o.shape {
            Shape::Cylinder | Shape::Cone => {
                let g = g.expect("gated");
                println!("{:?}: {g:?}", o.shape);
                // the cylinder reaches every object and the eye; the cone (2.2:0.9) only
                // the objects near it (the model's α·t·Σ term at |a| ≤ dlo²/2)
                assert!(g.safe_distance > 4.5, "{:?}", o.shape);
                assert!(g.a_min < 0.1, "{:?}", o.shape);
                // the margins are small next to the model's threshold
                assert!(g.a_min - g.a_model < 0.05 * g.a_model);
            }
            _ => assert!(g.is_none()),
        }
    }
}

/// Culled and unculled renders (64×36, AOVs and ray counts included) in every fixed
/// format: Q24.8 is not culled at all, the others gate their quadrics.
const FIXED: [Numeric; 4] = [
    Numeric::Q16_16,
    Numeric::Q8_24,
    Numeric::Q32_32,
    Numeric::Q24_8,
];

fn mirrors(mut s: Scene, light: [f64; 3]) -> Scene {
    s.lights.truncate(1);
    s.lights[0].position = light;
    s.lights[0].spot = None;
    for m in &mut s.materials {
        m.reflection = Reflection::Constant(0.5);
    }
    s.depth = 3;
    s
}

/// A cylinder and a cone (scaled `scale`, rotated `rot`) on a mirror floor at offset
/// `off`, lit from above the cylinder's axis or from the cone's generator extended
/// beyond the apex: shadow rays from the floor run along the axis and the generator,
/// reflected rays between the mirrors at every angle.
fn edge_scenes(off: [f64; 3], scale: [f64; 3], rot: [f64; 3]) -> Vec<(String, Scene)> {
    let (cyl_at, cone_at) = (
        [off[0] - 1.5, off[1], off[2]],
        [off[0] + 1.5, off[1] - 1.0, off[2]],
    );
    let objs = vec![
        obj(
            Shape::Square,
            [off[0], off[1] - 1.0, off[2]],
            [6.0, 1.0, 6.0],
            [0.0; 3],
            0,
        ),
        obj(Shape::Cylinder, cyl_at, scale, rot, 4),
        obj(Shape::Cone, cone_at, scale, rot, 5),
        obj(
            Shape::Sphere,
            [off[0], off[1], off[2] - 1.5],
            [0.6; 3],
            [0.0; 3],
            3,
        ),
    ];
    let eye = [off[0] + 0.5, off[1] + 2.5, off[2] + 7.0];
    let mut out = Vec::new();
    // above the cylinder's axis (unrotated: straight up; the light 25 above)
    let up = [cyl_at[0], cyl_at[1] + 25.0, cyl_at[2]];
    out.push(("axis light".to_string(), up));
    // on the cone's generator beyond the apex (object space apex + k(−1, 1, 0))
    let k = 12.0;
    let gen = [
        cone_at[0] - k * scale[0],
        cone_at[1] + scale[1] * (1.0 + k),
        cone_at[2],
    ];
    out.push(("generator light".to_string(), gen));
    out.into_iter()
        .map(|(name, light)| {
            (
                format!("{name} off={off:?} scale={scale:?} rot={rot:?}"),
                mirrors(scene(objs.clone(), eye, off, 4.0), light),
            )
        })
        .collect()
}

#[test]
fn renders_near_the_gate_are_unchanged() {
    let mut list = Vec::new();
    for scale in [[0.5, 1.0, 0.5], [0.25, 4.0, 1.0], [1.0, 0.25, 1.0]] {
        list.extend(edge_scenes([0.0; 3], scale, [0.0; 3]));
    }
    list.extend(edge_scenes([0.0; 3], [0.25, 4.0, 1.0], [25.0, -40.0, 10.0]));
    let mut gated = 0;
    for (name, s) in &list {
        // the gate is in force for most quadrics (not the 16:1 cone in Q16.16)
        let b = cull::bounds::<Q16_16>(s, &Math::default());
        gated += b
            .iter()
            .filter(|b| b.and_then(|b| b.secondary).is_some())
            .count();
        for numeric in FIXED {
            common::assert_cull_invisible(s, numeric, Some((64, 36)), name);
        }
    }
    assert!(gated >= 12, "{gated} of 16 quadrics gated");
}

/// Far from the origin (Q16.16's coordinates at 2000, Q8.24 at 40, near its ±128 range)
/// and with the floor's shadow and reflected rays starting up to the safe distance away.
#[test]
fn far_renders_near_the_gate_are_unchanged() {
    for (numeric, off) in [
        (Numeric::Q16_16, [2000.0, 30.0, -1500.0]),
        (Numeric::Q32_32, [2000.0, 30.0, -1500.0]),
        (Numeric::Q8_24, [40.0, 10.0, -30.0]),
    ] {
        for (name, s) in edge_scenes(off, [0.5, 1.0, 0.5], [0.0; 3]) {
            common::assert_cull_invisible(&s, numeric, Some((64, 36)), &name);
        }
    }
}
