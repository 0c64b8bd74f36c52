//! The culling's error model (`rt::cull`) at the edges of its gates: scenes whose camera
//! sits just inside a shape's primary gate in each admitted format, small and 16×
//! anisotropic objects, rays along a cylinder's axis or a cone's generator, edge-on flat
//! shapes, Q8.24 near its range limit, and mirrors everywhere (secondary rays from every
//! surface). Culled and unculled renders must be identical bit for bit. The probes at the
//! end check the intersectors directly on rays that the culling would skip.

use sim_target::num::{Scalar, Q16_16, Q32_32, Q8_24};
use sim_target::rt::{self, cull, shapes, Math, Numeric, Reflection, Scene, Shape, V3};

use crate::common;

use common::Rng;

fn culled(o: [f64; 3], d: [f64; 3], r2: f64) -> bool {
    let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    let od = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
    let t = (-od / dd).max(0.0);
    let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
    p[0] * p[0] + p[1] * p[1] + p[2] * p[2] > r2
}

fn probe<S: Scalar>(cone: bool, n: usize) -> usize {
    let m = Math::default();
    let mut rng = Rng(1);
    let mut bad = 0;
    for _ in 0..n {
        let o = if cone {
            [
                rng.range(-1.6, 1.6),
                rng.range(-1.5, 1.5),
                rng.range(-1.6, 1.6),
            ]
        } else {
            let (th, r) = (rng.range(0.0, 6.3), rng.range(1.03, 1.3));
            [
                r * th.cos(),
                rng.sign() * rng.range(0.85, 1.0),
                r * th.sin(),
            ]
        };
        let eps: f64 = 10f64.powf(rng.range(-6.0, -1.0));
        let mut d = if cone {
            let th: f64 = rng.range(0.0, std::f64::consts::TAU);
            [th.cos() + eps * rng.range(-1.0, 1.0), rng.sign(), th.sin()]
        } else {
            [
                eps * rng.range(-1.0, 1.0),
                o[1].signum(),
                eps * rng.range(-1.0, 1.0),
            ]
        };
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        d = d.map(|v| v / l);
        let (os, ds) = (V3::<S>::from_f64(o), V3::<S>::from_f64(d));
        let (oe, de) = (os.to_f64(), ds.to_f64());
        let r2 = if cone { 1.0404 } else { 2.0808 };
        if !culled(oe, de, r2) {
            continue;
        }
        let hit = if cone {
            shapes::cone(os, ds, S::from_f64(0.001), S::from_f64(1e6), &m)
        } else {
            shapes::cylinder(os, ds, S::from_f64(0.001), S::from_f64(1e6), &m)
        };
        if let Some(t) = hit {
            bad += 1;
            if bad < 5 {
                println!("{} cone={cone} o={oe:?} d={de:?} t={}", S::NAME, t.to_f64());
            }
        }
    }
    bad
}

/// The reference scene's materials, light and settings with `objects` and a camera at
/// `eye` looking at `at` with a field of view that frames a bound of radius `r`.
fn scene(objects: Vec<rt::Object>, eye: [f64; 3], at: [f64; 3], r: f64) -> Scene {
    let mut s = jobs::scene::parse(
        include_str!("../../../examples/reference.toml"),
        "reference",
    )
    .expect("parses");
    s.objects = objects;
    let d = ((eye[0] - at[0]).powi(2) + (eye[1] - at[1]).powi(2) + (eye[2] - at[2]).powi(2)).sqrt();
    s.camera.position = eye;
    s.camera.look_at = at;
    s.camera.up = if (eye[0] - at[0]).abs() + (eye[2] - at[2]).abs() < 1e-9 * d {
        [0.0, 0.0, 1.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    s.camera.fov_y = (2.0 * (1.3 * r / d).min(0.99).atan()).to_degrees();
    s
}

fn obj(
    shape: Shape,
    t: [f64; 3],
    scale: [f64; 3],
    rotate: [f64; 3],
    material: usize,
) -> rt::Object {
    rt::Object {
        shape,
        translate: t,
        scale,
        rotate,
        material,
    }
}

/// Culled and unculled renders at 64×36: RGB, depth and normal AOVs bit for bit.
fn assert_cull_invisible(scene: &Scene, numeric: Numeric, what: &str) {
    common::assert_cull_invisible(scene, numeric, Some((64, 36)), what);
}

/// The formats the culling admits.
const ADMITTED: [Numeric; 5] = [
    Numeric::F64,
    Numeric::F32,
    Numeric::Q16_16,
    Numeric::Q8_24,
    Numeric::Q32_32,
];

fn numeric_of<S: Scalar>() -> Numeric {
    S::NAME.parse().expect("known format")
}

/// The largest camera distance (along `dir` from the object's centre) at which format `S`
/// still culls object 0 for primary rays, by bisection on `cull::bounds`; None if it never
/// does in [1.1·bound, 10⁵].
fn gate<S: Scalar>(make: &dyn Fn(f64) -> Scene) -> Option<f64> {
    let admitted = |d: f64| {
        let s = make(d);
        cull::bounds::<S>(&s, &Math::default())[0].is_some_and(|b| b.primary.is_some())
    };
    let r = cull::world_bound(&make(10.0).objects[0]).map(|b| b.1)?;
    let (mut lo, mut hi) = (1.1 * r * 1.02, 1e5);
    if !admitted(lo) {
        return None;
    }
    if admitted(hi) {
        return Some(hi);
    }
    for _ in 0..24 {
        let mid = (lo * hi).sqrt();
        if admitted(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(lo)
}

const SHAPES: [Shape; 6] = [
    Shape::Sphere,
    Shape::Disk,
    Shape::Square,
    Shape::Cylinder,
    Shape::Cone,
    Shape::Cube,
];

/// One shape (scaled and rotated as given, material `m`) on its own, plus the reference
/// floor far below and the wall far behind as receivers, the camera `dist` away along `dir`.
fn lone(
    shape: Shape,
    scale: [f64; 3],
    rotate: [f64; 3],
    dir: [f64; 3],
    m: usize,
) -> impl Fn(f64) -> Scene {
    move |dist: f64| {
        let n = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt();
        let eye = [dist * dir[0] / n, dist * dir[1] / n, dist * dir[2] / n];
        let o = obj(shape, [0.0; 3], scale, rotate, m);
        let r = cull::world_bound(&o).map_or(1.0, |b| b.1);
        scene(vec![o], eye, [0.0; 3], r)
    }
}

fn check_at_gates<S: Scalar>(
    materials: &[usize],
    label: &str,
    scale: [f64; 3],
    rotate: [f64; 3],
    dir: [f64; 3],
) -> usize {
    let mut at_gate = 0;
    for shape in SHAPES {
        for &m in materials {
            let make = lone(shape, scale, rotate, dir, m);
            let Some(d) = gate::<S>(&make) else { continue };
            at_gate += 1;
            // just inside the gate (culled) and just beyond it (tested in full)
            for k in [0.999, 1.001] {
                let s = make(d * k);
                assert_cull_invisible(
                    &s,
                    numeric_of::<S>(),
                    &format!("{label} {shape:?} m{m} at {k}×{d:.3}"),
                );
            }
        }
    }
    at_gate
}

#[test]
fn cameras_at_the_primary_gates() {
    let dir = [0.3, 0.45, 1.0];
    let rot = [20.0, 35.0, -10.0];
    // every shape has a gate in Q16.16 and Q8.24 (Q32.32's are beyond 10⁵ for some)
    assert_eq!(
        check_at_gates::<Q16_16>(&[3, 6], "q16.16", [1.0; 3], rot, dir),
        12
    );
    assert_eq!(
        check_at_gates::<Q8_24>(&[3, 6], "q8.24", [1.0; 3], rot, dir),
        12
    );
    check_at_gates::<Q32_32>(&[3], "q32.32", [1.0; 3], rot, dir);
}

#[test]
fn small_and_anisotropic_objects_at_the_gates() {
    let dir = [-0.6, 0.3, 1.0];
    for (label, scale) in [
        ("small", [0.05, 0.05, 0.05]),
        ("aniso16", [0.25, 4.0, 1.0]),
        ("aniso16-flat", [4.0, 0.25, 4.0]),
    ] {
        for rot in [[0.0; 3], [31.0, -17.0, 53.0]] {
            let n = check_at_gates::<Q16_16>(&[3], label, scale, rot, dir);
            assert!(n > 0, "{label}: no gate in Q16.16");
            check_at_gates::<Q8_24>(&[3], label, scale, rot, dir);
        }
    }
}

/// Rays along a cylinder's axis, along a cone's generator, in a flat shape's plane, and
/// tangent to a sphere's silhouette: the directions where the quadrics' |a| → 0 (the
/// per-tile gate must keep them) and where the flat shapes' t = −o_y/d_y blows up.
#[test]
fn degenerate_and_grazing_primary_rays() {
    let mut scenes = Vec::new();
    for dist in [2.5, 6.0, 15.0] {
        // down the cylinder's axis, slightly off it
        let c = obj(Shape::Cylinder, [0.0; 3], [1.0; 3], [0.0; 3], 4);
        scenes.push((
            "cyl-axis",
            scene(vec![c.clone()], [0.02, dist, 0.01], [0.0; 3], 1.5),
        ));
        scenes.push((
            "cyl-axis-offset",
            scene(vec![c], [1.05, dist, 0.0], [1.05, 0.0, 0.0], 1.5),
        ));
        // along the cone's generator (the apex is at y = 1): on the upper nappe's extension
        let k = dist / std::f64::consts::SQRT_2;
        let e = obj(Shape::Cone, [0.0; 3], [1.0; 3], [0.0; 3], 5);
        scenes.push((
            "cone-generator",
            scene(vec![e.clone()], [k, 1.0 + k, 0.0], [0.0, 1.0, 0.0], 1.5),
        ));
        scenes.push((
            "cone-generator-off",
            scene(vec![e], [k + 0.05, 1.0 + k, 0.03], [0.3, 0.7, 0.0], 1.5),
        ));
        // edge-on flat shapes
        for shape in [Shape::Disk, Shape::Square] {
            let f = obj(shape, [0.0; 3], [1.0; 3], [0.0; 3], 7);
            for h in [0.0, 1e-4, 0.02] {
                scenes.push((
                    "edge-on",
                    scene(vec![f.clone()], [0.0, h, dist], [0.0, h, 0.0], 1.5),
                ));
            }
        }
    }
    for (name, s) in &scenes {
        for numeric in ADMITTED {
            assert_cull_invisible(s, numeric, name);
        }
    }
}

/// Secondary rays: every surface a mirror, depth 3, the light straight above the
/// cylinder's and the cone's axes (shadow rays along the axis), objects near Q8.24's
/// range limit.
#[test]
fn secondary_rays_along_axes_and_near_the_range_limit() {
    let mut list = Vec::new();
    for (off, scale) in [(0.0, 1.0), (40.0, 1.0), (55.0, 2.0)] {
        let objs = vec![
            obj(
                Shape::Square,
                [off, -1.0, 0.0],
                [6.0, 1.0, 6.0],
                [0.0; 3],
                0,
            ),
            obj(
                Shape::Cylinder,
                [off - 1.5, 0.0, 0.0],
                [0.5 * scale, scale, 0.5 * scale],
                [0.0; 3],
                4,
            ),
            obj(
                Shape::Cone,
                [off + 1.5, -1.0, 0.0],
                [0.7, 2.0, 0.7],
                [0.0; 3],
                5,
            ),
            obj(Shape::Sphere, [off, 0.0, -1.5], [0.8; 3], [0.0; 3], 3),
            obj(Shape::Cube, [off, -0.5, 1.5], [0.5; 3], [0.0, 30.0, 0.0], 6),
            obj(
                Shape::Disk,
                [off + 1.0, -0.99, 2.0],
                [0.8, 1.0, 0.8],
                [0.0; 3],
                7,
            ),
        ];
        for light_over in [off - 1.5, off + 1.5] {
            let mut s = scene(objs.clone(), [off + 0.5, 2.5, 7.0], [off, 0.0, 0.0], 4.0);
            s.lights.truncate(1);
            s.lights[0].position = [light_over, 30.0, 0.0];
            s.lights[0].spot = None;
            for m in &mut s.materials {
                m.reflection = Reflection::Constant(0.5);
            }
            s.depth = 3;
            list.push((format!("mirrors off={off} light x={light_over}"), s));
        }
    }
    for (name, s) in &list {
        for numeric in ADMITTED {
            assert_cull_invisible(s, numeric, name);
        }
    }
}

/// Why fixed point never culls a cylinder or cone for secondary rays: a ray whose exact
/// line stays 1.09 from the cone's apex region (outside the widened bound for t ≥ 0) but
/// runs along a generator (a = d·J·d ≈ 0, h ≈ 0) gets a hit from Q16.16's datapath, at a
/// point far from the surface; the secondary pretest cannot see the direction, so the
/// model's 1/|a| term has no bound there.
#[test]
fn q16_cone_hits_a_ray_that_misses_it_along_a_generator() {
    let o = [0.67620849609375, 1.2515869140625, 0.449371337890625];
    let d = [0.18963623046875, -0.7071075439453125, -0.6811981201171875];
    assert!(
        culled(o, d, 1.0404),
        "the exact ray misses the widened bound"
    );
    let q = |v: [f64; 3]| V3::<Q16_16>::from_f64(v);
    let m = Math::default();
    let t = shapes::cone(
        q(o),
        q(d),
        Q16_16::from_f64(0.001),
        Q16_16::from_f64(1e6),
        &m,
    );
    assert_eq!(t.map(|t| t.to_f64()), Some(0.5), "the datapath's false hit");
    // so the gate leaves it to the exhaustive test
    let s = scene(
        vec![obj(Shape::Cone, [0.0; 3], [1.0; 3], [0.0; 3], 5)],
        [0.0, 2.0, 9.0],
        [0.0; 3],
        1.0,
    );
    let b = cull::bounds::<Q16_16>(&s, &m)[0].expect("culled for primary rays");
    assert_eq!(b.safe_distance, 0.0);
    // f32 has the same ray right
    let f = |v: [f64; 3]| V3::<f32>::from_f64(v);
    assert_eq!(shapes::cone(f(o), f(d), 0.001f32, 1e6f32, &m), None);
}

/// Floating point: rays that miss a cylinder's or cone's widened bound while running
/// within 10⁻⁶…10⁻¹ rad of the axis (cylinder) or of a generator (cone), from origins just
/// outside the bound, never get a hit (the κ floor of the secondary gate relies on it).
#[test]
fn float_quadrics_miss_near_degenerate_culled_rays() {
    for cone in [false, true] {
        assert_eq!(probe::<f32>(cone, 30_000), 0, "f32 cone={cone}");
        assert_eq!(probe::<f64>(cone, 30_000), 0, "f64 cone={cone}");
    }
}
