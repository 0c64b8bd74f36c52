//! Saturating fixed-point formats (see the module docs of [`crate::num`] for why saturating).

use super::Scalar;
use core::ops::{Add, Div, Mul, Neg, Sub};
use fixed::types::{I16F16, I24F8, I32F32, I8F24};

macro_rules! fixed_scalar {
    ($(#[$m:meta])* $name:ident, $inner:ty, $bits:ty, $frac:literal, $label:literal) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub $inner);

        impl Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                Self(self.0.saturating_add(o.0))
            }
        }
        impl Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                Self(self.0.saturating_sub(o.0))
            }
        }
        impl Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                Self(self.0.saturating_mul(o.0))
            }
        }
        impl Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                if o.0 == <$inner>::ZERO {
                    if self.0 >= <$inner>::ZERO {
                        Self(<$inner>::MAX)
                    } else {
                        Self(<$inner>::MIN)
                    }
                } else {
                    Self(self.0.saturating_div(o.0))
                }
            }
        }
        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                Self(self.0.saturating_neg())
            }
        }
        impl Scalar for $name {
            const NAME: &'static str = $label;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                // Round half away from zero (add ±½, truncate: no libm `round` call on
                // baseline x86-64); `as` saturates at the integer range and maps NaN to 0,
                // which is exactly the saturating conversion wanted — and, unlike
                // `saturating_from_num`, folds to a constant for literals.
                let scaled = x * (1u64 << $frac) as f64;
                Self(<$inner>::from_bits((scaled + 0.5f64.copysign(scaled)) as $bits))
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self.0.to_bits() as f64 / (1u64 << $frac) as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                if self.0 <= <$inner>::ZERO {
                    Self(<$inner>::ZERO)
                } else {
                    Self::from_f64(self.to_f64().sqrt())
                }
            }
            #[inline(always)]
            fn rsqrt(self) -> Self {
                if self.0 <= <$inner>::ZERO {
                    Self(<$inner>::MAX)
                } else {
                    Self::from_f64(1.0 / self.to_f64().sqrt())
                }
            }
            fn max_value() -> Self {
                Self(<$inner>::MAX)
            }
            #[inline(always)]
            fn floor(self) -> Self {
                Self(self.0.saturating_floor())
            }
            #[inline(always)]
            fn zero() -> Self {
                Self(<$inner>::ZERO)
            }
        }
    };
}

fixed_scalar!(
    /// Signed Q16.16: the seed's `ap_fixed<32,16>` (range ±32768, step 2⁻¹⁶).
    Q16_16,
    I16F16,
    i32,
    16,
    "q16.16"
);
fixed_scalar!(
    /// Signed Q8.24: fine fraction for unit vectors, but only ±128 of range.
    Q8_24,
    I8F24,
    i32,
    24,
    "q8.24"
);
fixed_scalar!(
    /// Signed Q24.8: large scenes, coarse fraction (step 1/256).
    Q24_8,
    I24F8,
    i32,
    8,
    "q24.8"
);
fixed_scalar!(
    /// Signed Q32.32 in 64 bits: what a wider datapath buys.
    Q32_32,
    I32F32,
    i64,
    32,
    "q32.32"
);
