//! Shading terms of docs/requirements.md §4.4 (seed eq. 1.2.80–1.2.93, 3.2.8–3.2.10), each a free function so the
//! tests can check it against hand-computed values.

use super::vec::V3;
use crate::num::{self, Scalar, SqrtKind};
use core::f64::consts::{FRAC_1_PI, PI};

/// Unpolarised Fresnel reflectance (R⊥ + R∥)/2 of a surface with index η − ik for
/// incidence cosine `cos_i` ∈ [0, 1]. k > 0 is a conductor (θt = 0); a dielectric uses
/// Snell's law and returns 1 on total internal reflection (η < 1).
pub fn fresnel<S: Scalar>(cos_i: S, eta: S, k: S, sq: SqrtKind) -> S {
    let zero = S::zero();
    let one = S::one();
    let ci = cos_i.clamp(zero, one);
    let ct = if k > zero {
        one
    } else {
        let sin2_t = (one - ci * ci) / (eta * eta);
        if sin2_t >= one {
            return one;
        }
        num::sqrt(one - sin2_t, sq)
    };
    let two = S::from_f64(2.0);
    let nk = eta * eta + k * k;
    let cross = two * eta * ci * ct;
    let (ci2, ct2) = (ci * ci, ct * ct);
    let rs = (nk * ct2 - cross + ci2) / (nk * ct2 + cross + ci2);
    let rp = (nk * ci2 - cross + ct2) / (nk * ci2 + cross + ct2);
    (rs + rp) * S::from_f64(0.5)
}

/// Lambert: 1/π.
pub fn lambert<S: Scalar>(_n: V3<S>, _wi: V3<S>, _wo: V3<S>, _p: &DiffuseParams<S>) -> S {
    S::from_f64(FRAC_1_PI)
}

/// Precomputed Oren–Nayar A and B.
#[derive(Debug, Clone, Copy)]
pub struct DiffuseParams<S> {
    /// A = 1 − σ²/(2(σ² + 0.33)).
    pub a: S,
    /// B = 0.45σ²/(σ² + 0.09).
    pub b: S,
    /// Square root used for sin/tan.
    pub sqrt: SqrtKind,
}

impl<S: Scalar> DiffuseParams<S> {
    /// From σ² (0 = Lambert).
    pub fn oren_nayar(sigma2: f64, sqrt: SqrtKind) -> Self {
        Self {
            a: S::from_f64(1.0 - sigma2 / (2.0 * (sigma2 + 0.33))),
            b: S::from_f64(0.45 * sigma2 / (sigma2 + 0.09)),
            sqrt,
        }
    }
}

/// Oren–Nayar (1/π)(A + B·max(0, cos(φi − φo))·sin α·tan β), α = max(θi, θo),
/// β = min(θi, θo); sin and tan come from the cosines, so no acos is needed.
pub fn oren_nayar<S: Scalar>(n: V3<S>, wi: V3<S>, wo: V3<S>, p: &DiffuseParams<S>) -> S {
    let zero = S::zero();
    let one = S::one();
    let ci = n.dot(wi).clamp(zero, one);
    let co = n.dot(wo).clamp(zero, one);
    // projections onto the tangent plane
    let ti = wi - n.scale(ci);
    let to = wo - n.scale(co);
    let li = ti.dot(ti);
    let lo = to.dot(to);
    let mut cos_phi = zero;
    if li > zero && lo > zero {
        // normalise each projection on its own: li·lo underflows in fixed point
        cos_phi = ti.dot(to) * num::rsqrt(li, p.sqrt) * num::rsqrt(lo, p.sqrt);
    }
    let cos_phi = cos_phi.clamp(zero, one);
    // α = max θ ⇒ cos α = min cos; β = min θ ⇒ cos β = max cos
    let cos_a = ci.min(co);
    let cos_b = ci.max(co);
    let sin_a = num::sqrt(one - cos_a * cos_a, p.sqrt);
    let sin_b = num::sqrt(one - cos_b * cos_b, p.sqrt);
    let tan_b = if cos_b > zero { sin_b / cos_b } else { zero };
    S::from_f64(FRAC_1_PI) * (p.a + p.b * cos_phi * sin_a * tan_b)
}

/// Precomputed specular constants.
#[derive(Debug, Clone, Copy)]
pub struct SpecParams<S> {
    /// Phong exponent e of (n·h)^e ([`crate::rt::Specular::exponent`]).
    pub e: u32,
    /// (e + 2)/(2π).
    pub norm: S,
    /// η for Torrance–Sparrow's F.
    pub eta: S,
    /// k for Torrance–Sparrow's F.
    pub k: S,
    /// Which √ the BRDF's normalisations use ([`crate::rt::Math::sqrt`]).
    pub sqrt: SqrtKind,
}

impl<S: Scalar> SpecParams<S> {
    /// From exponent and Fresnel index.
    pub fn new(e: u32, eta: f64, k: f64, sqrt: SqrtKind) -> Self {
        Self {
            e,
            norm: S::from_f64((e as f64 + 2.0) / (2.0 * PI)),
            eta: S::from_f64(eta),
            k: S::from_f64(k),
            sqrt,
        }
    }
}

/// Normalised Blinn–Phong (e + 2)/(2π)·(n·ωh)^e.
pub fn blinn_phong<S: Scalar>(n: V3<S>, wi: V3<S>, wo: V3<S>, p: &SpecParams<S>) -> S {
    let h = (wi + wo).normalize(p.sqrt);
    let nh = n.dot(h).max(S::zero());
    p.norm * num::powi(nh, p.e)
}

/// Torrance–Sparrow D·G·F/(4 cos θo cos θi).
pub fn torrance_sparrow<S: Scalar>(n: V3<S>, wi: V3<S>, wo: V3<S>, p: &SpecParams<S>) -> S {
    let zero = S::zero();
    let one = S::one();
    let ci = n.dot(wi);
    let co = n.dot(wo);
    if ci <= zero || co <= zero {
        return zero;
    }
    let h = (wi + wo).normalize(p.sqrt);
    let nh = n.dot(h).max(zero);
    let oh = wo.dot(h);
    if oh <= zero {
        return zero;
    }
    let d = p.norm * num::powi(nh, p.e);
    let two = S::from_f64(2.0);
    let g = one.min(two * nh * co / oh).min(two * nh * ci / oh);
    let f = fresnel(oh, p.eta, p.k, p.sqrt);
    d * g * f / (S::from_f64(4.0) * co * ci)
}

/// Spot factor clamp((l_dir·(−ωi) − cos α/2)/(cos β/2 − cos α/2), 0, 1); `inv_width` is
/// 1/(cos_inner − cos_outer), precomputed (∞ → a hard edge).
pub fn spot_factor<S: Scalar>(l_dir: V3<S>, wi: V3<S>, cos_outer: S, inv_width: S) -> S {
    let c = -(l_dir.dot(wi));
    ((c - cos_outer) * inv_width).clamp(S::zero(), S::one())
}
