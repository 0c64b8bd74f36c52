//! Accuracy of the Q16.16 datapath against f64 on the same (quantised) inputs, one test
//! per fix of the PSNR work (docs/rt.md, "Q16.16 accuracy: the error budget and what fixed it"): each bound
//! sits between what the kernel reaches now and what it did before the fix, so that
//! undoing a fix fails here and not only in the whole-frame PSNR of `rt_render`.

use sim_target::num::{AcosKind, AtanKind, Scalar, SqrtKind, Q16_16};
use sim_target::rt::shapes::{self, Quadratic};
use sim_target::rt::texture;
use sim_target::rt::Math;
use sim_target::rt::V3;
use sim_target::rt::{Mapping, Shape};

const M: Math = Math {
    sqrt: SqrtKind::Exact,
    quadratic: Quadratic::Stable,
    atan: AtanKind::Minimax11,
    acos: AcosKind::Sqrt8,
};

/// The value a Q16.16 register holds for x, as f64 (so both kernels see the same input).
fn qv(x: f64) -> f64 {
    Q16_16::from_f64(x).to_f64()
}

fn q3(a: [f64; 3]) -> V3<Q16_16> {
    V3::from_f64(a)
}

fn f3(a: [f64; 3]) -> V3<f64> {
    V3::from_f64(a)
}

/// Worst |Δt|·|d| (how far along the ray the Q16.16 hit is from the f64 hit) over rays
/// from `o` towards points on the segment `from`–`to`, which crosses the silhouette.
fn worst_hit_error(shape: Shape, o: [f64; 3], from: [f64; 3], to: [f64; 3]) -> (f64, usize) {
    let o = o.map(qv);
    let (mut worst, mut hits) = (0.0f64, 0usize);
    for k in 0..=4000 {
        let s = k as f64 / 4000.0;
        let target: [f64; 3] = core::array::from_fn(|i| from[i] + (to[i] - from[i]) * s);
        let d: [f64; 3] = core::array::from_fn(|i| target[i] - o[i]);
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let d = d.map(|v| qv(v / l));
        let tf = shapes::intersect_fn::<f64>(shape)(f3(o), f3(d), 1e-3, 1e6, &M);
        let tq = shapes::intersect_fn::<Q16_16>(shape)(
            q3(o),
            q3(d),
            Q16_16::from_f64(1e-3),
            Q16_16::max_value(),
            &M,
        );
        if let (Some(tf), Some(tq)) = (tf, tq) {
            hits += 1;
            worst = worst.max((tq.to_f64() - tf).abs());
        }
    }
    (worst, hits)
}

/// Fix 1: the curved shapes form the discriminant by Lagrange's identity
/// (`shapes::solve_lagrange`). From 12 radii away b² − 4ac gave c ≈ 140 and an absolute
/// error of ≈ 0.02 in Δ, so hits near the silhouette (Δ → 0) moved along the ray by up to
/// 0.024–0.030 in Q16.16 (measured before the fix: sphere 0.029, cylinder 0.030, cone
/// 0.024); with the identity the worst is 1–3·10⁻⁴. The bound, 2·10⁻³, is 7× above the
/// new worst and 12× below the old.
#[test]
fn silhouette_hits_from_afar_are_accurate_in_q16_16() {
    let cases = [
        // sphere: rays from z = 12 sweeping across the rim at x = 1
        (
            Shape::Sphere,
            [0.3, 0.4, 12.0],
            [0.6, 0.4, 0.0],
            [1.2, 0.4, 0.0],
        ),
        // cylinder: across its side silhouette at x = 1
        (
            Shape::Cylinder,
            [0.2, 0.3, 12.0],
            [0.6, 0.1, 0.0],
            [1.2, 0.1, 0.0],
        ),
        // cone: across the apex region and a side
        (
            Shape::Cone,
            [-3.7, 1.45, 11.3],
            [0.0, 0.2, 0.0],
            [0.9, 0.95, 0.0],
        ),
    ];
    for (shape, o, from, to) in cases {
        let (worst, hits) = worst_hit_error(shape, o, from, to);
        eprintln!("{shape:?}: worst |Δt| {worst:.4} over {hits} hits");
        assert!(hits > 500, "{shape:?}: only {hits} hits");
        assert!(worst < 2e-3, "{shape:?}: worst |Δt| {worst}");
    }
}

/// Fix 2 (rounded products in the mapping): the cylindrical u of object-space points in
/// Q16.16 against f64 on the same points. The atan polynomial and the 1/2π scale used
/// truncating products, a biased error: worst 3.56·10⁻⁵ (2.3 LSB) before the fix,
/// 2.69·10⁻⁵ (1.8 LSB) with rounded products; the rest is the quantised polynomial
/// coefficients and the truncating y/x, common to every fixed-point atan of this shape.
#[test]
fn cylindrical_u_of_q16_16_points_is_within_a_few_lsb() {
    let mut worst = 0.0f64;
    for k in 0..20_000 {
        let a = k as f64 / 20_000.0 * std::f64::consts::TAU;
        let r = 0.05 + 0.9 * ((k * 7919) % 1000) as f64 / 1000.0;
        let p = [qv(r * a.sin()), qv(0.3), qv(r * a.cos())];
        let (uf, _) = texture::map_uv(Mapping::Cylindrical, f3(p), &M);
        let (uq, _) = texture::map_uv(Mapping::Cylindrical, q3(p), &M);
        // u wraps at 1: compare on the circle
        let mut e = (uq.to_f64() - uf).abs();
        e = e.min(1.0 - e);
        worst = worst.max(e);
    }
    eprintln!("cylindrical u: worst |Δu| {worst:.3e}");
    assert!(worst < 3.0e-5, "worst |Δu| {worst}");
}
