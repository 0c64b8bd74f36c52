//! [`Scalar`] methods composed from a format's other operations (or, where a method models
//! a hardware core, computed through f64): what a format uses for a method it has no
//! cheaper way of its own to compute. The floats take most of them, the fixed formats the
//! few they do not specialise.
//!
//! They are functions rather than default bodies of the trait so that a format takes one
//! by naming it (the `composed!` list in its `impl`), and a wrapper format, which must
//! forward to its format's own method instead, cannot inherit one by omission
//! ([`super::instrumented`]).

use super::Scalar;

/// 1/√x as the format's divider after its √; x ≤ 0 gives the format's maximum.
#[inline(always)]
pub fn rsqrt<S: Scalar>(x: S) -> S {
    if x > S::zero() {
        S::one() / x.sqrt()
    } else {
        S::max_value()
    }
}

/// x·y rounded to nearest where `*` already rounds to nearest (floats).
#[inline(always)]
pub fn mul_rn<S: Scalar>(x: S, o: S) -> S {
    x * o
}

/// The rounded product by ½ (the texture mappings' (x + 1)/2).
#[inline(always)]
pub fn half_rn<S: Scalar>(x: S) -> S {
    x.mul_rn(S::from_f64(0.5))
}

/// a·b + c·d as written (each product and the sum rounded by the format).
#[inline(always)]
pub fn dot2<S: Scalar>(a: S, b: S, c: S, d: S) -> S {
    a * b + c * d
}

/// a·b + c·d + e·f as written, summed left to right.
#[inline(always)]
pub fn dot3<S: Scalar>(a: S, b: S, c: S, d: S, e: S, f: S) -> S {
    a * b + c * d + e * f
}

/// ⌊x⌋ through f64 (exact: every format widens to f64 exactly, and f64's floor of such a
/// value is representable in the format again).
pub fn floor<S: Scalar>(x: S) -> S {
    S::from_f64(x.to_f64().floor())
}

/// ⌊x⌋ as an integer: the format's floor, then its integer conversion.
#[inline(always)]
pub fn floor_i64<S: Scalar>(x: S) -> i64 {
    x.floor().int_to_i64()
}

/// An integral value as i64 through f64 (`as` saturates and maps NaN to 0).
#[inline(always)]
pub fn int_to_i64<S: Scalar>(x: S) -> i64 {
    x.to_f64() as i64
}

/// The additive identity as the format's `Default`.
#[inline(always)]
pub fn zero<S: Scalar>() -> S {
    S::default()
}

/// The multiplicative identity, converted from f64.
#[inline(always)]
pub fn one<S: Scalar>() -> S {
    S::from_f64(1.0)
}

/// 1/x with the format's own divider.
#[inline(always)]
pub fn recip<S: Scalar>(x: S) -> S {
    S::one() / x
}

/// |x| by negating below zero (so the most negative fixed value saturates, as its `−`).
#[inline(always)]
pub fn abs<S: Scalar>(x: S) -> S {
    if x < S::zero() {
        -x
    } else {
        x
    }
}

/// The smaller value, `other` when incomparable (NaN does not stick).
#[inline(always)]
pub fn min<S: Scalar>(x: S, other: S) -> S {
    if x < other {
        x
    } else {
        other
    }
}

/// The larger value, `other` when incomparable.
#[inline(always)]
pub fn max<S: Scalar>(x: S, other: S) -> S {
    if x > other {
        x
    } else {
        other
    }
}

/// `max` with `lo`, then `min` with `hi` (the format's own `min`/`max`).
#[inline(always)]
pub fn clamp<S: Scalar>(x: S, lo: S, hi: S) -> S {
    x.max(lo).min(hi)
}

/// Finiteness of the f64 widening (exact, so the format's own).
pub fn is_finite<S: Scalar>(x: S) -> bool {
    x.to_f64().is_finite()
}

/// x − ⌊x⌋ with the format's floor and subtraction.
pub fn fract<S: Scalar>(x: S) -> S {
    x - x.floor()
}

/// arctan of a correctly rounded core, modelled through f64.
#[inline(always)]
pub fn atan_core<S: Scalar>(x: S) -> S {
    S::from_f64(x.to_f64().atan())
}

/// arccos of a correctly rounded core, modelled through f64 (input clamped to [−1, 1]).
#[inline(always)]
pub fn acos_core<S: Scalar>(x: S) -> S {
    S::from_f64(x.to_f64().clamp(-1.0, 1.0).acos())
}
