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
    /// curved shapes solve their quadric from the ray point nearest the shape's centre
    /// ([`centred`]), so that Δ = b² − 4ac is not a small difference of large numbers.
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

/// Unit sphere.
#[inline]
pub fn sphere<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, m: &Math) -> Option<S> {
    sphere_c(o, d, o.dot(o) - S::one(), tmin, tmax, m)
}

/// The ray parameter t₀ = −((o − m)·d)/(d·d) of the point nearest `m`, and that point
/// o + t₀·d: the origin from which [`Quadratic::Stable`] solves a curved shape's quadric.
///
/// Why: with the eye ten object radii away, c = |o|² − 1 ≈ 100 and Δ = b² − 4ac is the
/// difference of two numbers near 400·a whose rounding (≈ 2⁻¹⁶ relative each in Q16.16)
/// leaves an absolute error of ≈ 0.02 in Δ; √Δ then misplaces the hit by up to 10⁻² near
/// a silhouette, where Δ → 0, which flips texture lookups (the dots at the cone's edges
/// and apex) and bends reflections (the rim of the gold sphere). From the nearest point,
/// |o₂| ≤ the shape's size, so c₂ and Δ are O(1) with errors of a few LSB. Any t₀ gives
/// the same roots in exact arithmetic (t = t₀ + t₂), so a rounded t₀ costs nothing; the
/// price is one divide per curved shape. The seed's textbook formula keeps its origin.
#[inline(always)]
pub fn centred<S: Scalar>(o: V3<S>, d: V3<S>, centre: V3<S>) -> (S, V3<S>) {
    let a = d.dot(d);
    if a <= S::zero() {
        return (S::zero(), o);
    }
    let t0 = -((o - centre).dot(d) / a);
    (t0, o + d.scale(t0))
}

/// Unit sphere with c = |o|² − 1 given: the same operations as [`sphere`], so that a
/// kernel can compute c once for all rays from one origin (bit-identical result). With
/// [`Quadratic::Stable`] the quadric is solved from the ray point nearest the centre
/// ([`centred`]) and `c` is not used.
#[inline(always)]
pub fn sphere_c<S: Scalar>(o: V3<S>, d: V3<S>, c: S, tmin: S, tmax: S, m: &Math) -> Option<S> {
    let a = d.dot(d);
    let (t1, t2) = if m.quadratic == Quadratic::Stable {
        let (t0, o2) = centred(o, d, V3::zero());
        let b = S::from_f64(2.0) * d.dot(o2);
        let c2 = o2.dot(o2) - S::one();
        let (t1, t2) = solve_quadratic(a, b, c2, m)?;
        (t0 + t1, t0 + t2)
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
    let two = S::from_f64(2.0);
    let (t0, o2) = if m.quadratic == Quadratic::Stable {
        // nearest approach to the axis (in x, z only): the centred origin of `centred`
        let t0 = -((d.x * o.x + d.z * o.z) / a);
        (t0, o + d.scale(t0))
    } else {
        (S::zero(), o)
    };
    let b = two * (d.x * o2.x + d.z * o2.z);
    let c = o2.x * o2.x + o2.z * o2.z - S::one();
    let (t1, t2) = solve_quadratic(a, b, c, m)?;
    pick_in_height((t0 + t1, t0 + t2), o, d, tmin, tmax, -S::one(), S::one())
}

/// Open cone x² − (y − 1)² + z² = 0, y ∈ [0, 1].
pub fn cone<S: Scalar>(o: V3<S>, d: V3<S>, tmin: S, tmax: S, m: &Math) -> Option<S> {
    let two = S::from_f64(2.0);
    let (t0, o2) = if m.quadratic == Quadratic::Stable {
        // from the ray point nearest the middle of the axis (see `centred`)
        centred(o, d, V3::new(S::zero(), S::from_f64(0.5), S::zero()))
    } else {
        (S::zero(), o)
    };
    let a = d.x * d.x - d.y * d.y + d.z * d.z;
    let b = two * (d.x * o2.x - d.y * o2.y + d.y + d.z * o2.z);
    let c = o2.x * o2.x - o2.y * o2.y + two * o2.y - S::one() + o2.z * o2.z;
    let (t1, t2) = solve_quadratic(a, b, c, m)?;
    pick_in_height((t0 + t1, t0 + t2), o, d, tmin, tmax, S::zero(), S::one())
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
