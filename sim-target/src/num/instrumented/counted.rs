//! [`Counted`]: the kernel is generic, so rendering in it counts exactly the adds,
//! multiplies, divides, cores and table-index floors a frame executes.

use core::ops::{Add, Div, Mul, Neg, Sub};

use super::{tally, OpKind};
use crate::num::Scalar;

/// `S`, with its operations counted per [`OpKind`]. Every method delegates to `S` (so
/// results are identical) and counts the operators the method stands for in hardware:
/// a fused `dot3` is three products and two sums whatever the format's rounding, a
/// `fract` a floor and a subtraction; comparisons, negation, conversions and constants
/// are free.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Counted<S>(pub S);

macro_rules! bin {
    ($tr:ident, $m:ident, $kind:ident) => {
        impl<S: Scalar> $tr for Counted<S> {
            type Output = Self;
            #[inline]
            fn $m(self, o: Self) -> Self {
                tally(OpKind::$kind, 1);
                Counted($tr::$m(self.0, o.0))
            }
        }
    };
}

bin!(Add, add, AddSub);
bin!(Sub, sub, AddSub);
bin!(Mul, mul, Mul);
bin!(Div, div, Div);

impl<S: Scalar> Neg for Counted<S> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Counted(-self.0)
    }
}

impl<S: Scalar> Scalar for Counted<S> {
    const NAME: &'static str = S::NAME;
    #[inline]
    fn from_f64(x: f64) -> Self {
        Counted(S::from_f64(x))
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self.0.to_f64()
    }
    #[inline]
    fn sqrt(self) -> Self {
        tally(OpKind::Sqrt, 1);
        Counted(self.0.sqrt())
    }
    #[inline]
    fn rsqrt(self) -> Self {
        tally(OpKind::Rsqrt, 1);
        Counted(self.0.rsqrt())
    }
    #[inline]
    fn mul_rn(self, o: Self) -> Self {
        tally(OpKind::Mul, 1);
        Counted(self.0.mul_rn(o.0))
    }
    #[inline]
    fn half_rn(self) -> Self {
        tally(OpKind::Mul, 1);
        Counted(self.0.half_rn())
    }
    #[inline]
    fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self {
        tally(OpKind::Mul, 2);
        tally(OpKind::AddSub, 1);
        Counted(S::dot2(a.0, b.0, c.0, d.0))
    }
    #[inline]
    fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self {
        tally(OpKind::Mul, 3);
        tally(OpKind::AddSub, 2);
        Counted(S::dot3(a.0, b.0, c.0, d.0, e.0, f.0))
    }
    #[inline]
    fn max_value() -> Self {
        Counted(S::max_value())
    }
    #[inline]
    fn rounding() -> Option<(f64, f64)> {
        S::rounding()
    }
    #[inline]
    fn floor(self) -> Self {
        tally(OpKind::Floor, 1);
        Counted(self.0.floor())
    }
    #[inline]
    fn floor_i64(self) -> i64 {
        tally(OpKind::Floor, 1);
        self.0.floor_i64()
    }
    #[inline]
    fn int_to_i64(self) -> i64 {
        self.0.int_to_i64()
    }
    #[inline]
    fn zero() -> Self {
        Counted(S::zero())
    }
    #[inline]
    fn one() -> Self {
        Counted(S::one())
    }
    #[inline]
    fn recip(self) -> Self {
        tally(OpKind::Div, 1);
        Counted(self.0.recip())
    }
    #[inline]
    fn abs(self) -> Self {
        Counted(self.0.abs())
    }
    #[inline]
    fn min(self, other: Self) -> Self {
        Counted(self.0.min(other.0))
    }
    #[inline]
    fn max(self, other: Self) -> Self {
        Counted(self.0.max(other.0))
    }
    #[inline]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        Counted(self.0.clamp(lo.0, hi.0))
    }
    #[inline]
    fn is_finite(self) -> bool {
        self.0.is_finite()
    }
    #[inline]
    fn fract(self) -> Self {
        tally(OpKind::Floor, 1);
        tally(OpKind::AddSub, 1);
        Counted(self.0.fract())
    }
    #[inline]
    fn atan_core(self) -> Self {
        tally(OpKind::Atan, 1);
        Counted(self.0.atan_core())
    }
    #[inline]
    fn acos_core(self) -> Self {
        tally(OpKind::Acos, 1);
        Counted(self.0.acos_core())
    }
}
