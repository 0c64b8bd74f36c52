//! Intersections against analytic answers, shading terms against hand-computed values,
//! Fresnel limits, textures and mappings.

use sim_target::num::SqrtKind;
use sim_target::rt::shade::{self, DiffuseParams, SpecParams};
use sim_target::rt::shapes;
use sim_target::rt::texture;
use sim_target::rt::Math;
use sim_target::rt::V3;
use sim_target::rt::{Mapping, Shape, TextureKind};
use std::f64::consts::{FRAC_1_PI, PI};

const M: Math = Math {
    sqrt: SqrtKind::Exact,
    quadratic: shapes::Quadratic::Stable,
    atan: sim_target::num::AtanKind::Minimax11,
    acos: sim_target::num::AcosKind::Sqrt8,
};

fn v(x: f64, y: f64, z: f64) -> V3<f64> {
    V3::new(x, y, z)
}

fn hit(shape: Shape, o: V3<f64>, d: V3<f64>) -> Option<f64> {
    shapes::intersect_fn::<f64>(shape)(o, d, 0.001, 1e6, &M)
}

fn close(a: Option<f64>, b: f64) {
    let a = a.expect("hit expected");
    assert!((a - b).abs() < 1e-12, "{a} vs {b}");
}

#[test]
fn sphere_front_inside_tangent_behind() {
    close(hit(Shape::Sphere, v(0.0, 0.0, 5.0), v(0.0, 0.0, -1.0)), 4.0);
    // from inside: the exit
    close(hit(Shape::Sphere, v(0.0, 0.0, 0.0), v(0.0, 0.0, -1.0)), 1.0);
    close(
        hit(Shape::Sphere, v(0.0, 0.5, 0.0), v(1.0, 0.0, 0.0)),
        0.75f64.sqrt(),
    );
    // tangent: y = 1 grazes at one point
    close(hit(Shape::Sphere, v(-5.0, 1.0, 0.0), v(1.0, 0.0, 0.0)), 5.0);
    assert_eq!(
        hit(Shape::Sphere, v(-5.0, 1.0001, 0.0), v(1.0, 0.0, 0.0)),
        None
    );
    // behind the origin
    assert_eq!(hit(Shape::Sphere, v(0.0, 0.0, 5.0), v(0.0, 0.0, 1.0)), None);
    // unnormalised direction: t scales
    close(hit(Shape::Sphere, v(0.0, 0.0, 5.0), v(0.0, 0.0, -2.0)), 2.0);
}

#[test]
fn stable_quadratic_keeps_small_root() {
    // b² ≫ 4ac: textbook form cancels, stable form does not
    let (t1, _) = shapes::solve_quadratic(1.0f64, -1e8, 1.0, &M).expect("roots");
    assert!((t1 - 1e-8).abs() < 1e-20, "{t1}");
    let textbook = Math {
        quadratic: shapes::Quadratic::Textbook,
        ..M
    };
    let (tb, _) = shapes::solve_quadratic(1.0f64, -1e8, 1.0, &textbook).expect("roots");
    assert!(
        (tb - 1e-8).abs() > 1e-10,
        "textbook unexpectedly exact: {tb}"
    );
}

#[test]
fn planes_disk_square() {
    close(hit(Shape::Plane, v(3.0, 2.0, 7.0), v(0.0, -1.0, 0.0)), 2.0);
    assert_eq!(hit(Shape::Plane, v(0.0, 2.0, 0.0), v(1.0, 0.0, 0.0)), None);
    assert_eq!(hit(Shape::Plane, v(0.0, 2.0, 0.0), v(0.0, 1.0, 0.0)), None);
    close(hit(Shape::Disk, v(0.6, 1.0, 0.6), v(0.0, -1.0, 0.0)), 1.0);
    assert_eq!(hit(Shape::Disk, v(0.8, 1.0, 0.8), v(0.0, -1.0, 0.0)), None);
    close(hit(Shape::Square, v(0.8, 1.0, 0.8), v(0.0, -1.0, 0.0)), 1.0);
    assert_eq!(
        hit(Shape::Square, v(1.01, 1.0, 0.0), v(0.0, -1.0, 0.0)),
        None
    );
}

#[test]
fn cylinder_height_limits_and_inside() {
    close(
        hit(Shape::Cylinder, v(-5.0, 0.5, 0.0), v(1.0, 0.0, 0.0)),
        4.0,
    );
    // above the top: miss (open, height limited)
    assert_eq!(
        hit(Shape::Cylinder, v(-5.0, 1.5, 0.0), v(1.0, 0.0, 0.0)),
        None
    );
    // slanted: first root above the top, second (far wall) inside → the far wall
    // o = (−2, 1.5, 0), d = (1, −0.25, 0): x = −1 at t = 1 (y = 1.25), x = 1 at t = 3 (y = 0.75)
    close(
        hit(Shape::Cylinder, v(-2.0, 1.5, 0.0), v(1.0, -0.25, 0.0)),
        3.0,
    );
    // from inside
    close(
        hit(Shape::Cylinder, v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0)),
        1.0,
    );
    // along the axis: never crosses the tube
    assert_eq!(
        hit(Shape::Cylinder, v(0.0, -5.0, 0.0), v(0.0, 1.0, 0.0)),
        None
    );
}

#[test]
fn cone_height_limits() {
    // at y = 0.5 the radius is 0.5
    close(hit(Shape::Cone, v(-5.0, 0.5, 0.0), v(1.0, 0.0, 0.0)), 4.5);
    // the mirrored nappe above the apex is rejected
    assert_eq!(hit(Shape::Cone, v(-5.0, 1.5, 0.0), v(1.0, 0.0, 0.0)), None);
    // below the base: miss
    assert_eq!(hit(Shape::Cone, v(-5.0, -0.5, 0.0), v(1.0, 0.0, 0.0)), None);
    // from inside near the base
    close(hit(Shape::Cone, v(0.0, 0.2, 0.0), v(1.0, 0.0, 0.0)), 0.8);
}

#[test]
fn cube_slabs() {
    close(hit(Shape::Cube, v(0.3, 0.2, 5.0), v(0.0, 0.0, -1.0)), 4.0);
    close(hit(Shape::Cube, v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)), 1.0);
    assert_eq!(hit(Shape::Cube, v(0.0, 1.5, 5.0), v(0.0, 0.0, -1.0)), None);
    // diagonal onto the corner edge
    close(hit(Shape::Cube, v(-3.0, -3.0, 0.0), v(1.0, 1.0, 0.0)), 2.0);
    let n = shapes::normal(Shape::Cube, v(0.2, -1.0, 0.5));
    assert_eq!(n, v(0.0, -1.0, 0.0));
    let n = shapes::normal(Shape::Cone, v(0.5, 0.5, 0.0));
    assert_eq!(n, v(0.5, 0.5, 0.0));
}

#[test]
fn fresnel_limits() {
    for (eta, k) in [(1.5, 0.0), (1.33, 0.0), (0.47, 2.83), (2.0, 1.0)] {
        let r0 = shade::fresnel(1.0f64, eta, k, SqrtKind::Exact);
        let want = ((eta - 1.0f64).powi(2) + k * k) / ((eta + 1.0f64).powi(2) + k * k);
        assert!((r0 - want).abs() < 1e-12, "η={eta} k={k}: {r0} vs {want}");
        let graze = shade::fresnel(1e-9f64, eta, k, SqrtKind::Exact);
        assert!(graze > 0.999_999, "grazing {graze}");
    }
    // total internal reflection: from glass into air (η = 1/1.5) beyond the critical angle
    let crit = (1.0f64 / 1.5).asin();
    let cos_beyond = (crit + 0.05).cos();
    assert_eq!(
        shade::fresnel(cos_beyond, 1.0 / 1.5, 0.0, SqrtKind::Exact),
        1.0
    );
    assert!(shade::fresnel((crit - 0.05).cos(), 1.0 / 1.5, 0.0, SqrtKind::Exact) < 1.0);
}

#[test]
fn diffuse_and_specular_hand_values() {
    let n = v(0.0, 0.0, 1.0);
    let wi = v(0.0, 0.6, 0.8);
    let wo = v(0.0, -0.6, 0.8);
    let lam = DiffuseParams::<f64>::oren_nayar(0.0, SqrtKind::Exact);
    assert_eq!(shade::lambert(n, wi, wo, &lam), FRAC_1_PI);
    // σ² = 0 is Lambert
    assert!((shade::oren_nayar(n, wi, wo, &lam) - FRAC_1_PI).abs() < 1e-15);
    // σ² = 0.25, ωi and ωo in the same plane on the same side: cos φ = 1 (wo mirrored in y → cos φ = −1 → B term off)
    let p = DiffuseParams::<f64>::oren_nayar(0.25, SqrtKind::Exact);
    let a = 1.0 - 0.25 / (2.0 * 0.58);
    assert!((shade::oren_nayar(n, wi, wo, &p) - a / PI).abs() < 1e-15);
    let wo2 = v(0.0, 0.28, 0.96);
    // θi: cos 0.8 sin 0.6; θo: cos 0.96 sin 0.28 → α = θi, β = θo
    let b = 0.45 * 0.25 / 0.34;
    let want = (a + b * 1.0 * 0.6 * (0.28 / 0.96)) / PI;
    assert!((shade::oren_nayar(n, wi, wo2, &p) - want).abs() < 1e-12);
    // Blinn–Phong at the mirror direction: n·ωh = 1 → (e+2)/2π
    let sp = SpecParams::<f64>::new(32, 1.5, 0.0, SqrtKind::Exact);
    assert!((shade::blinn_phong(n, wi, wo, &sp) - 34.0 / (2.0 * PI)).abs() < 1e-12);
    // Torrance–Sparrow at the same geometry: ωh = n, G = min(1, 2·0.8/0.8, ..) = 1,
    // F(cos = ωo·ωh = 0.8), /(4·0.8·0.8)
    let f = shade::fresnel(0.8f64, 1.5, 0.0, SqrtKind::Exact);
    let want = 34.0 / (2.0 * PI) * f / (4.0 * 0.64);
    assert!((shade::torrance_sparrow(n, wi, wo, &sp) - want).abs() < 1e-12);
    // spot factor: inside the inner cone 1, outside the outer 0, linear between
    let dir = v(0.0, 0.0, -1.0);
    assert_eq!(
        shade::spot_factor(dir, v(0.0, 0.0, 1.0), 0.7, 1.0 / 0.2),
        1.0
    );
    assert_eq!(
        shade::spot_factor(dir, v(0.0, 0.8, 0.6), 0.7, 1.0 / 0.2),
        0.0
    );
    assert!((shade::spot_factor(dir, v(0.0, 0.6, 0.8), 0.7, 1.0 / 0.2) - 0.5).abs() < 1e-12);
}

#[test]
fn texture_generators() {
    assert_eq!(texture::texel(TextureKind::Xor, 3, 5, 256), 0x06_0606);
    assert_eq!(texture::texel(TextureKind::Xor, 255, 0, 256), 0xFF_FFFF);
    let ch = TextureKind::Checkerboard { cell: 8 };
    assert_eq!(texture::texel(ch, 0, 0, 64), 0xFF_FFFF);
    assert_eq!(texture::texel(ch, 8, 0, 64), 0);
    assert_eq!(texture::texel(ch, 8, 8, 64), 0xFF_FFFF);
    let d: Vec<u32> = (0..4)
        .map(|x| texture::texel(TextureKind::RgbDots, x, 0, 64))
        .collect();
    assert_eq!(d, vec![0xFF0000, 0x00FF00, 0x0000FF, 0xFF0000]);
    // marble/wood: deterministic for a seed, different across seeds, not constant
    for k in [
        TextureKind::Marble { seed: 1 },
        TextureKind::Wood { seed: 1 },
    ] {
        let a: Vec<u32> = (0..64).map(|x| texture::texel(k, x, 17, 64)).collect();
        let b: Vec<u32> = (0..64).map(|x| texture::texel(k, x, 17, 64)).collect();
        assert_eq!(a, b);
        assert!(a.iter().any(|t| *t != a[0]));
    }
    assert_ne!(
        texture::texel(TextureKind::Marble { seed: 1 }, 10, 10, 64),
        texture::texel(TextureKind::Marble { seed: 2 }, 10, 10, 64)
    );
    assert_eq!(texture::side_for(1), 256);
    assert_eq!(texture::side_for(4), 128);
    assert_eq!(texture::side_for(5), 64);
}

#[test]
fn mappings() {
    let (u, v_) = texture::map_uv(Mapping::Planar, v(-1.0, 0.3, 1.0), &M);
    assert_eq!((u, v_), (0.0, 1.0));
    let (u, v_) = texture::map_uv(Mapping::Cylindrical, v(1.0, 0.0, 0.0), &M);
    assert!((u - 0.25).abs() < 1e-5 && v_ == 0.5);
    let (u, _) = texture::map_uv(Mapping::Cylindrical, v(-1.0, 0.0, 0.0), &M);
    assert!((u - 0.75).abs() < 1e-5, "{u}");
    let (_, v_) = texture::map_uv(Mapping::Spherical, v(0.0, 1.0, 0.0), &M);
    assert!((v_ - 1.0).abs() < 1e-6);
    let (_, v_) = texture::map_uv(Mapping::Spherical, v(1.0, 0.0, 0.0), &M);
    assert!((v_ - 0.5).abs() < 1e-6);
}
