//! [`Probe`]: every arithmetic result is checked against the exact result (integer
//! arithmetic on the raw bits for fixed point), so a render through it counts saturations,
//! NaN produced from non-NaN operands and results that are neither exact nor the saturated
//! value (a wrap-around), while giving the kernel bit for bit the values the bare format
//! would. Nothing in the kernel changes.

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::note;
use crate::num::{Scalar, Q16_16, Q24_8, Q32_32, Q8_24};

/// Binary operations the probe checks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    /// a + b
    Add,
    /// a − b
    Sub,
    /// a · b
    Mul,
    /// a / b
    Div,
}

/// How a format's exact result is known.
pub trait Exact: Scalar {
    /// Checks `r = a op b` and records the outcome.
    fn check(op: BinOp, a: Self, b: Self, r: Self);
    /// Checks `r = −a`.
    fn check_neg(a: Self, r: Self);
    /// Checks `r = from_f64(x)`.
    fn check_from(x: f64, r: Self);
    /// Checks `r = Σ aᵢ·bᵢ` computed with one rounding (`mul_rn`, `dot2`, `dot3`).
    fn check_sum(pairs: &[(Self, Self)], r: Self);
}

macro_rules! exact_float {
    ($t:ty) => {
        impl Exact for $t {
            #[inline]
            fn check(_op: BinOp, a: Self, b: Self, r: Self) {
                let (a, b, r) = (a.to_f64(), b.to_f64(), r.to_f64());
                if r.is_nan() && a.is_finite() && b.is_finite() {
                    note(|s| s.nans += 1);
                } else if r.is_nan() && !a.is_nan() && !b.is_nan() {
                    note(|s| s.overflow_nans += 1);
                } else if r.is_infinite() && a.is_finite() && b.is_finite() {
                    note(|s| s.saturations += 1);
                }
            }
            #[inline]
            fn check_neg(_a: Self, _r: Self) {}
            #[inline]
            fn check_sum(pairs: &[(Self, Self)], r: Self) {
                let finite = pairs
                    .iter()
                    .all(|(a, b)| a.to_f64().is_finite() && b.to_f64().is_finite());
                // a product beyond the range overflows to ∞ first: a NaN after that
                // is an overflow NaN, as with the separate operations
                let max = <$t as Scalar>::max_value().to_f64();
                let overflow = pairs
                    .iter()
                    .any(|(a, b)| (a.to_f64() * b.to_f64()).abs() > max);
                let r = r.to_f64();
                if r.is_nan() && finite && !overflow {
                    note(|s| s.nans += 1);
                } else if r.is_nan() && finite {
                    note(|s| s.overflow_nans += 1);
                } else if r.is_infinite() && finite {
                    note(|s| s.saturations += 1);
                }
            }
            #[inline]
            fn check_from(x: f64, r: Self) {
                if r.to_f64().is_infinite() && x.is_finite() {
                    note(|s| s.saturations += 1);
                }
            }
        }
    };
}

exact_float!(f64);
exact_float!(f32);
exact_float!(half::f16);

macro_rules! exact_fixed {
    ($t:ty, $bits:ty, $frac:literal) => {
        impl Exact for $t {
            #[inline]
            fn check(op: BinOp, a: Self, b: Self, r: Self) {
                let (x, y) = (a.0.to_bits() as i128, b.0.to_bits() as i128);
                let exact = match op {
                    BinOp::Add => x + y,
                    BinOp::Sub => x - y,
                    BinOp::Mul => (x * y) >> $frac,
                    BinOp::Div => {
                        if y == 0 {
                            // The divider's defined answer: the signed maximum.
                            let want = if x >= 0 { <$bits>::MAX } else { <$bits>::MIN };
                            note(|s| {
                                s.saturations += 1;
                                if r.0.to_bits() != want {
                                    s.wraps += 1;
                                }
                            });
                            return;
                        }
                        (x << $frac) / y
                    }
                };
                settle(
                    exact,
                    r.0.to_bits() as i128,
                    <$bits>::MIN as i128,
                    <$bits>::MAX as i128,
                );
            }
            #[inline]
            fn check_sum(pairs: &[(Self, Self)], r: Self) {
                // the exact sum of the double-width products, then the one rounding
                // (either direction accepted: the mode is the format's business)
                let wide = pairs.iter().fold(0i128, |acc, (a, b)| {
                    acc.saturating_add(
                        (a.0.to_bits() as i128).saturating_mul(b.0.to_bits() as i128),
                    )
                });
                let exact = wide >> $frac;
                let (lo, hi) = (<$bits>::MIN as i128, <$bits>::MAX as i128);
                let clipped = exact.clamp(lo, hi);
                let got = r.0.to_bits() as i128;
                if clipped != exact || (got - clipped).abs() > 1 {
                    note(|s| {
                        if clipped != exact {
                            s.saturations += 1;
                        }
                        if (got - clipped).abs() > 1 {
                            s.wraps += 1;
                        }
                    });
                }
            }
            #[inline]
            fn check_neg(a: Self, r: Self) {
                let x = a.0.to_bits() as i128;
                settle(
                    -x,
                    r.0.to_bits() as i128,
                    <$bits>::MIN as i128,
                    <$bits>::MAX as i128,
                );
            }
            #[inline]
            fn check_from(x: f64, r: Self) {
                if x.is_nan() {
                    note(|s| s.nans += 1);
                    return;
                }
                let scaled = x * (1u64 << $frac) as f64;
                // Round half away from zero, as the format documents; `as i128` saturates.
                let exact = (scaled + 0.5f64.copysign(scaled)) as i128;
                settle(
                    exact,
                    r.0.to_bits() as i128,
                    <$bits>::MIN as i128,
                    <$bits>::MAX as i128,
                );
            }
        }
    };
}

/// Records whether `got` is `exact`, its clipped value (a saturation) or neither (a wrap).
#[inline]
fn settle(exact: i128, got: i128, lo: i128, hi: i128) {
    let clipped = exact.clamp(lo, hi);
    if clipped != exact || got != clipped {
        note(|s| {
            if clipped != exact {
                s.saturations += 1;
            }
            if got != clipped {
                s.wraps += 1;
            }
        });
    }
}

exact_fixed!(Q16_16, i32, 16);
exact_fixed!(Q8_24, i32, 24);
exact_fixed!(Q24_8, i32, 8);
exact_fixed!(Q32_32, i64, 32);

/// `S`, observed. Every method delegates to `S` (so results are identical) and then
/// checks the result.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Probe<S>(pub S);

macro_rules! bin {
    ($tr:ident, $m:ident, $op:expr) => {
        impl<S: Exact> $tr for Probe<S> {
            type Output = Self;
            #[inline]
            fn $m(self, o: Self) -> Self {
                let r = $tr::$m(self.0, o.0);
                S::check($op, self.0, o.0, r);
                Probe(r)
            }
        }
    };
}

bin!(Add, add, BinOp::Add);
bin!(Sub, sub, BinOp::Sub);
bin!(Mul, mul, BinOp::Mul);
bin!(Div, div, BinOp::Div);

impl<S: Exact> Neg for Probe<S> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        let r = -self.0;
        S::check_neg(self.0, r);
        Probe(r)
    }
}

impl<S: Exact> Scalar for Probe<S> {
    const NAME: &'static str = S::NAME;
    #[inline]
    fn from_f64(x: f64) -> Self {
        let r = S::from_f64(x);
        S::check_from(x, r);
        Probe(r)
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self.0.to_f64()
    }
    #[inline]
    fn sqrt(self) -> Self {
        let r = self.0.sqrt();
        if r.to_f64().is_nan() && !self.0.to_f64().is_nan() {
            note(|s| s.nans += 1);
        }
        Probe(r)
    }
    #[inline]
    fn rsqrt(self) -> Self {
        let r = self.0.rsqrt();
        if self.0 <= S::zero() {
            // The documented answer for x ≤ 0 is the format's maximum: a clip.
            note(|s| s.saturations += 1);
        }
        Probe(r)
    }
    fn max_value() -> Self {
        Probe(S::max_value())
    }
    fn rounding() -> Option<(f64, f64)> {
        S::rounding()
    }
    #[inline]
    fn mul_rn(self, o: Self) -> Self {
        let r = self.0.mul_rn(o.0);
        S::check_sum(&[(self.0, o.0)], r);
        Probe(r)
    }
    #[inline]
    fn half_rn(self) -> Self {
        let r = self.0.half_rn();
        S::check_sum(&[(self.0, S::from_f64(0.5))], r);
        Probe(r)
    }
    #[inline]
    fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self {
        let r = S::dot2(a.0, b.0, c.0, d.0);
        S::check_sum(&[(a.0, b.0), (c.0, d.0)], r);
        Probe(r)
    }
    #[inline]
    fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self {
        let r = S::dot3(a.0, b.0, c.0, d.0, e.0, f.0);
        S::check_sum(&[(a.0, b.0), (c.0, d.0), (e.0, f.0)], r);
        Probe(r)
    }
    #[inline]
    fn floor(self) -> Self {
        Probe(self.0.floor())
    }
    #[inline]
    fn floor_i64(self) -> i64 {
        self.0.floor_i64()
    }
    #[inline]
    fn int_to_i64(self) -> i64 {
        self.0.int_to_i64()
    }
    #[inline]
    fn zero() -> Self {
        Probe(S::zero())
    }
    #[inline]
    fn one() -> Self {
        Probe(S::one())
    }
    #[inline]
    fn recip(self) -> Self {
        let r = self.0.recip();
        S::check(BinOp::Div, S::one(), self.0, r);
        Probe(r)
    }
    #[inline]
    fn abs(self) -> Self {
        let r = self.0.abs();
        if self.0 < S::zero() {
            S::check_neg(self.0, r);
        }
        Probe(r)
    }
    #[inline]
    fn min(self, other: Self) -> Self {
        Probe(self.0.min(other.0))
    }
    #[inline]
    fn max(self, other: Self) -> Self {
        Probe(self.0.max(other.0))
    }
    #[inline]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        Probe(self.0.clamp(lo.0, hi.0))
    }
    #[inline]
    fn is_finite(self) -> bool {
        self.0.is_finite()
    }
    #[inline]
    fn fract(self) -> Self {
        Probe(self.0.fract())
    }
    #[inline]
    fn atan_core(self) -> Self {
        Probe(checked_core(self.0, self.0.atan_core()))
    }
    #[inline]
    fn acos_core(self) -> Self {
        Probe(checked_core(self.0, self.0.acos_core()))
    }
}

/// A core's result `r` of `x`, with a NaN from a non-NaN operand recorded (as for `sqrt`):
/// the cores are total, so that would be a bug of the model.
#[inline]
fn checked_core<S: Scalar>(x: S, r: S) -> S {
    if r.to_f64().is_nan() && !x.to_f64().is_nan() {
        note(|s| s.nans += 1);
    }
    r
}
