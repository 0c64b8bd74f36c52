//! Ray–shape intersection in object space. Every function takes the object-space ray
//! o′ + t·d′ (d′ not normalised, so t is the world-space parameter too) and returns the
//! smallest valid t in [tmin, tmax].

use super::scene::Shape;
use super::vec::V3;
use super::Math;
use crate::num::{self, Scalar};

/// How the quadratic's roots are formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quadratic {
    /// q = −½(b + sign(b)√Δ), t₁ = q/a, t₂ = c/q: no cancellation in the roots; and the
    /// curved shapes form Δ by Lagrange's identity ([`solve_lagrange`]), so that it is
    /// not a small difference of large numbers.
    #[default]
    Stable,
    /// (−b ± √Δ)/2a as the seed: loses digits when b² ≫ 4ac.
    Textbook,
}

/// Both roots of a t² + b t + c = 0 in ascending order, or None if Δ < 0 or a = b = 0.
#[inline]
pub fn solve_quadratic<S: Scalar>(a: S, b: S, c: S, m: &Math) -> Option<(S, S)> {
    let zero = S::zero();
    if a == zero {
        if b == zero {
            return None;
        }
        let t = -c / b;
        return Some((t, t));
    }
    let disc = b * b - S::from_f64(4.0) * a * c;
    if disc < zero {
        return None;
    }
    let sq = num::sqrt(disc, m.sqrt);
    let (t1, t2) = match m.quadratic {
        Quadratic::Stable => {
            let q = if b < zero {
                S::from_f64(-0.5) * (b - sq)
            } else {
                S::from_f64(-0.5) * (b + sq)
            };
            if q == zero {
                (zero, zero)
            } else {
                (q / a, c / q)
            }
        }
        Quadratic::Textbook => {
            let two_a = a + a;
            ((-b - sq) / two_a, (-b + sq) / two_a)
        }
    };
    Some(if t1 <= t2 { (t1, t2) } else { (t2, t1) })
}

#[inline(always)]
fn in_range<S: Scalar>(t: S, tmin: S, tmax: S) -> bool {
    t >= tmin && t <= tmax
}

/// Hit t ∈ [tmin, tmax] of the ray o + t·d with the unit sphere at the origin (object
/// space): [`sphere_c`] with c = |o|² − 1 computed here.
#[inline]
pub fn sphere<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, m: &Math) -> Option<S> {
    sphere_c(o, d, o.dot(o) - S::one(), tmin, tmax, m)
}

/// Roots of a t² + 2h t + c = 0 (h = b/2) given its quarter discriminant Δ′ = h² − ac,
/// stable form: q = −(h + sign(h)√Δ′), t₁ = q/a, t₂ = c/q.
///
/// Why Δ′ is an argument: the curved shapes compute it by Lagrange's identity instead of
/// h² − ac. With the eye ten object radii away, c = |o|² − 1 ≈ 100 and h² − ac is the
/// difference of two numbers near 100·a whose rounding (≈ 2⁻¹⁶ relative each in Q16.16)
/// leaves an absolute error of ≈ 0.005 in Δ′; near a silhouette, where Δ′ → 0, √Δ′ then
/// moves the hit by up to 0.03 along the ray, which flips texture lookups (the dots at the
/// cone's edges and apex) and bends reflections (the rim of the gold sphere). For a sphere
/// h² − ac = |d|² − |d × o|² exactly, and |d × o| is |d| times the distance of the centre
/// from the ray, O(1) for any ray near the sphere: Δ′ comes out of O(1) terms with errors
/// of a few LSB, for nine more products and no divide. (Cylinder and cone: the same
/// identity in the x–z plane and in the cone's indefinite metric.)
#[inline(always)]
pub fn solve_lagrange<S: Scalar>(a: S, h: S, c: S, disc: S, m: &Math) -> Option<(S, S)> {
    let zero = S::zero();
    if a == zero {
        if h == zero {
            return None;
        }
        let t = -c / (h + h);
        return Some((t, t));
    }
    if disc < zero {
        return None;
    }
    let sq = num::sqrt(disc, m.sqrt);
    let q = if h < zero { sq - h } else { -(h + sq) };
    let (t1, t2) = if q == zero {
        (zero, zero)
    } else {
        (q / a, c / q)
    };
    Some(if t1 <= t2 { (t1, t2) } else { (t2, t1) })
}

/// True when the plain quarter discriminant h² − ac is so negative that the ray misses in
/// any format: below −2⁻⁸·(h² + |ac|) − 2⁻⁶, far beyond its rounding (a few ulp relative
/// in the floats, f16 included; a few LSB of |h|, |a|, |c| in the fixed formats, whose
/// saturation can only push a saturated a·c further down). Why: the Lagrange form costs
/// nine products more; with this test only rays passing near the shape pay them, and the
/// result is bit for bit the Lagrange form's (a rejected ray misses either way).
#[inline(always)]
fn clearly_misses<S: Scalar>(a: S, h: S, c: S) -> bool {
    let hh = h * h;
    let ac = a * c;
    hh - ac < -((hh + ac.abs()) * S::from_f64(1.0 / 256.0) + S::from_f64(1.0 / 64.0))
}

/// Unit sphere with c = |o|² − 1 given: the same operations as [`sphere`], so that a
/// kernel can compute c once for all rays from one origin (bit-identical result).
#[inline(always)]
pub fn sphere_c<S: Scalar>(o: V3<S>, d: V3<S>, c: S, tmin: S, tmax: S, m: &Math) -> Option<S> {
    let a = d.dot(d);
    let (t1, t2) = if m.quadratic == Quadratic::Stable {
        let h = d.dot(o);
        if clearly_misses(a, h, c) {
            return None;
        }
        let x = d.cross2(o);
        solve_lagrange(a, h, c, a - x.dot(x), m)?
    } else {
        let b = S::from_f64(2.0) * d.dot(o);
        solve_quadratic(a, b, c, m)?
    };
    if in_range(t1, tmin, tmax) {
        Some(t1)
    } else if in_range(t2, tmin, tmax) {
        Some(t2)
    } else {
        None
    }
}

#[inline(always)]
fn plane_t<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S) -> Option<S> {
    if d.y == S::zero() {
        return None;
    }
    let t = -o.y / d.y;
    in_range(t, tmin, tmax).then_some(t)
}

/// Plane y = 0.
pub fn plane<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, _m: &Math) -> Option<S> {
    plane_t(o, d, tmin, tmax)
}

/// Unit disk in y = 0.
pub fn disk<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, _m: &Math) -> Option<S> {
    let t = plane_t(o, d, tmin, tmax)?;
    let x = o.x + d.x * t;
    let z = o.z + d.z * t;
    (x * x + z * z <= S::one()).then_some(t)
}

/// Square |x|, |z| ≤ 1 in y = 0.
pub fn square<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, _m: &Math) -> Option<S> {
    let t = plane_t(o, d, tmin, tmax)?;
    let x = o.x + d.x * t;
    let z = o.z + d.z * t;
    (x.abs() <= S::one() && z.abs() <= S::one()).then_some(t)
}

#[inline(always)]
fn pick_in_height<S: Scalar>(
    roots: (S, S),
    o: V3<S>,
    d: V3<S>,
    tmin: S,
    tmax: S,
    lo: S,
    hi: S,
) -> Option<S> {
    for t in [roots.0, roots.1] {
        if in_range(t, tmin, tmax) {
            let y = o.y + d.y * t;
            if y >= lo && y <= hi {
                return Some(t);
            }
        }
    }
    None
}

/// Open cylinder x² + z² = 1, y ∈ [−1, 1].
pub fn cylinder<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, m: &Math) -> Option<S> {
    let a = d.x * d.x + d.z * d.z;
    if a == S::zero() {
        return None; // parallel to the axis: the open tube is never crossed
    }
    let c = o.x * o.x + o.z * o.z - S::one();
    let r = if m.quadratic == Quadratic::Stable {
        let h = S::dot2(d.x, o.x, d.z, o.z);
        if clearly_misses(a, h, c) {
            return None;
        }
        // 2-D Lagrange: h² − ac = a − (dx·oz − dz·ox)²
        let x = S::dot2(d.x, o.z, -d.z, o.x);
        solve_lagrange(a, h, c, a - x * x, m)?
    } else {
        let b = S::from_f64(2.0) * (d.x * o.x + d.z * o.z);
        solve_quadratic(a, b, c, m)?
    };
    pick_in_height(r, o, d, tmin, tmax, -S::one(), S::one())
}

/// Open cone x² − (y − 1)² + z² = 0, y ∈ [0, 1].
pub fn cone<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, m: &Math) -> Option<S> {
    let two = S::from_f64(2.0);
    let a = d.x * d.x - d.y * d.y + d.z * d.z;
    let r = if m.quadratic == Quadratic::Stable {
        // from the apex: p = o − (0, 1, 0), metric diag(1, −1, 1)
        let p = V3::new(o.x, o.y - S::one(), o.z);
        let h = S::dot3(d.x, p.x, -d.y, p.y, d.z, p.z);
        let c = S::dot3(p.x, p.x, -p.y, p.y, p.z, p.z);
        if clearly_misses(a, h, c) {
            return None;
        }
        // Lagrange in the indefinite metric: h² − ac = Σ −εᵢεⱼ(dᵢpⱼ − dⱼpᵢ)², ε = (1, −1, 1)
        let xy = S::dot2(d.x, p.y, -d.y, p.x);
        let yz = S::dot2(d.y, p.z, -d.z, p.y);
        let xz = S::dot2(d.x, p.z, -d.z, p.x);
        solve_lagrange(a, h, c, S::dot3(xy, xy, yz, yz, -xz, xz), m)?
    } else {
        let b = two * (d.x * o.x - d.y * o.y + d.y + d.z * o.z);
        let c = o.x * o.x - o.y * o.y + two * o.y - S::one() + o.z * o.z;
        solve_quadratic(a, b, c, m)?
    };
    pick_in_height(r, o, d, tmin, tmax, S::zero(), S::one())
}

/// Cube [−1, 1]³ by the slab test; from inside, the exit face.
pub fn cube<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, _m: &Math) -> Option<S> {
    let one = S::one();
    let mut near = -S::max_value();
    let mut far = S::max_value();
    for (oa, da) in [(o.x, d.x), (o.y, d.y), (o.z, d.z)] {
        if da == S::zero() {
            if oa.abs() > one {
                return None;
            }
            continue;
        }
        let t0 = (-one - oa) / da;
        let t1 = (one - oa) / da;
        let (lo, hi) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        near = near.max(lo);
        far = far.min(hi);
    }
    if near > far {
        return None;
    }
    if in_range(near, tmin, tmax) {
        Some(near)
    } else if in_range(far, tmin, tmax) {
        Some(far)
    } else {
        None
    }
}

/// Object-space outward normal (not normalised) at an object-space surface point.
pub fn normal<S: Scalar>(shape: Shape, p: V3<S>) -> V3<S> {
    let zero = S::zero();
    match shape {
        Shape::Sphere => p,
        Shape::Plane | Shape::Disk | Shape::Square => V3::new(zero, S::one(), zero),
        Shape::Cylinder => V3::new(p.x, zero, p.z),
        Shape::Cone => V3::new(p.x, S::one() - p.y, p.z),
        Shape::Cube => {
            let (ax, ay, az) = (p.x.abs(), p.y.abs(), p.z.abs());
            let sgn = |v: S| if v < zero { -S::one() } else { S::one() };
            if ax >= ay && ax >= az {
                V3::new(sgn(p.x), zero, zero)
            } else if ay >= az {
                V3::new(zero, sgn(p.y), zero)
            } else {
                V3::new(zero, zero, sgn(p.z))
            }
        }
    }
}

/// Intersection function of a shape, chosen once per object by the plan.
pub type IntersectFn<S> = fn(V3<S>, V3<S>, S, S, &Math) -> Option<S>;

/// The intersection function for a shape.
pub fn intersect_fn<S: Scalar>(shape: Shape) -> IntersectFn<S> {
    match shape {
        Shape::Sphere => sphere::<S>,
        Shape::Plane => plane::<S>,
        Shape::Disk => disk::<S>,
        Shape::Square => square::<S>,
        Shape::Cylinder => cylinder::<S>,
        Shape::Cone => cone::<S>,
        Shape::Cube => cube::<S>,
    }
}

/// The same dispatch by a `match` on the shape (inlinable), for measuring the plan's
/// function-pointer dispatch against it.
#[inline(always)]
pub fn intersect<S: Scalar>(
    shape: Shape,
    o: V3<S>,
    d: V3<S>,
    tmin: S,
    tmax: S,
    m: &Math,
) -> Option<S> {
    match shape {
        Shape::Sphere => sphere(o, d, tmin, tmax, m),
        Shape::Plane => plane(o, d, tmin, tmax, m),
        Shape::Disk => disk(o, d, tmin, tmax, m),
        Shape::Square => square(o, d, tmin, tmax, m),
        Shape::Cylinder => cylinder(o, d, tmin, tmax, m),
        Shape::Cone => cone(o, d, tmin, tmax, m),
        Shape::Cube => cube(o, d, tmin, tmax, m),
    }
}
