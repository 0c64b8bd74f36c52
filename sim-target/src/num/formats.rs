//! Saturating fixed-point formats (see the module docs of [`crate::num`] for why saturating).
//! Every clip is counted ([`super::saturation`]), on the clipping branch only.

use super::saturation::saturated;
use super::Scalar;
use core::ops::{Add, Div, Mul, Neg, Sub};
use fixed::types::{I16F16, I24F8, I32F32, I8F24};

/// Truncating (toward zero) fixed-point quotient (a·2^frac)/b of raw bits, b ≠ 0,
/// saturated by the sign of the true quotient — bit for bit `fixed`'s `saturating_div`.
///
/// When a·2^frac fits in 53 bits (i32 formats with frac ≤ 21: Q16.16, Q24.8) the quotient
/// goes through one f64 division instead of a 64-bit integer divide: numerator and
/// divisor are exact in f64, and a non-integer quotient n/d is at least 1/|d| from the
/// nearest integer while the rounding error is at most 2⁻⁵³·|n/d| < 1/|d|, so truncating
/// the rounded quotient gives the exact integer quotient; the saturating `as` cast then
/// clips exactly as `fixed` does. Other formats use the integer divide.
#[inline(always)]
fn div_bits<B: DivBits, const FRAC: u32>(a: B, b: B) -> B {
    B::div_bits::<FRAC>(a, b)
}

trait DivBits: Copy {
    fn div_bits<const FRAC: u32>(a: Self, b: Self) -> Self;
}

impl DivBits for i32 {
    #[inline(always)]
    fn div_bits<const FRAC: u32>(a: i32, b: i32) -> i32 {
        if FRAC + 32 <= 53 {
            let q = a as f64 * (1u64 << FRAC) as f64 / b as f64;
            // the cast truncates toward zero: it clips exactly outside (MIN − 1, MAX + 1)
            if !(q > i32::MIN as f64 - 1.0 && q < i32::MAX as f64 + 1.0) {
                saturated();
            }
            q as i32
        } else {
            let q = ((a as i64) << FRAC) / b as i64;
            let c = q.clamp(i32::MIN as i64, i32::MAX as i64);
            if c != q {
                saturated();
            }
            c as i32
        }
    }
}

impl DivBits for i64 {
    #[inline(always)]
    fn div_bits<const FRAC: u32>(a: i64, b: i64) -> i64 {
        let q = ((a as i128) << FRAC) / b as i128;
        let c = q.clamp(i64::MIN as i128, i64::MAX as i128);
        if c != q {
            saturated();
        }
        c as i64
    }
}

/// ⌊(p + 2^(frac−1)) / 2^frac⌋ of a saturated accumulator p, i.e. `p.saturating_add(half)
/// >> frac`, without the saturating add: halving first leaves room for the half-LSB, and
/// with p = 2k + b (b ∈ {0, 1}) the odd b cannot carry past a multiple of 2^frac, so
/// (k + 2^(frac−2)) >> (frac − 1) is the same integer; only where the saturating add
/// clipped (p within half an LSB of MAX) is it one more, and the clamp to the word that
/// follows maps both to the word's maximum. One instruction less per dot product
/// (tests/num_approx.rs `same_bits`).
macro_rules! round_shift {
    ($p:expr, $frac:literal) => {
        (($p >> 1) + (1 << ($frac - 2))) >> ($frac - 1)
    };
}

macro_rules! fixed_scalar {
    ($(#[$m:meta])* $name:ident, $inner:ty, $bits:ty, $wide:ty, $frac:literal, $label:literal) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name(pub $inner);

        impl Add for $name {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self {
                match self.0.to_bits().checked_add(o.0.to_bits()) {
                    Some(r) => Self(<$inner>::from_bits(r)),
                    None => Self::sat_add(self, o),
                }
            }
        }
        impl Sub for $name {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self {
                match self.0.to_bits().checked_sub(o.0.to_bits()) {
                    Some(r) => Self(<$inner>::from_bits(r)),
                    None => Self::sat_sub(self, o),
                }
            }
        }
        impl Mul for $name {
            type Output = Self;
            #[inline(always)]
            fn mul(self, o: Self) -> Self {
                // One widening multiply and an arithmetic shift (floor, as `fixed`); the
                // product of two $bits fits the double width, so the only overflow is of
                // the shifted result, and clamping it saturates exactly as
                // `fixed::saturating_mul` (sign of the true product).
                let p = (self.0.to_bits() as $wide * o.0.to_bits() as $wide) >> $frac;
                Self::narrow(p)
            }
        }
        impl Div for $name {
            type Output = Self;
            #[inline(always)]
            fn div(self, o: Self) -> Self {
                if o.0 == <$inner>::ZERO {
                    saturated();
                    if self.0 >= <$inner>::ZERO {
                        Self(<$inner>::MAX)
                    } else {
                        Self(<$inner>::MIN)
                    }
                } else {
                    Self(<$inner>::from_bits(div_bits::<$bits, $frac>(
                        self.0.to_bits(),
                        o.0.to_bits(),
                    )))
                }
            }
        }
        impl Neg for $name {
            type Output = Self;
            #[inline(always)]
            fn neg(self) -> Self {
                match self.0.to_bits().checked_neg() {
                    Some(r) => Self(<$inner>::from_bits(r)),
                    None => {
                        saturated();
                        Self(<$inner>::MAX)
                    }
                }
            }
        }
        impl $name {
            /// A double-width result clipped to the word: the saturation of `*`, `dot2`,
            /// `dot3` and `mul_rn`. Why a branch and not a clamp: a clipped result is rare
            /// (a value beyond the format's range), so the predicted compare-and-branch
            /// costs two instructions where the clamp's two compares and two
            /// conditional moves sit on every product's dependency chain; the clipping
            /// itself is out of line.
            #[inline(always)]
            fn narrow(p: $wide) -> Self {
                let r = p as $bits;
                if r as $wide == p {
                    Self(<$inner>::from_bits(r))
                } else {
                    Self::clip(p)
                }
            }
            #[cold]
            #[inline(never)]
            fn clip(p: $wide) -> Self {
                saturated();
                Self(<$inner>::from_bits(
                    p.clamp(<$bits>::MIN as $wide, <$bits>::MAX as $wide) as $bits,
                ))
            }
            /// The saturating sum of double-width products, out of line (see
            /// [`Self::narrow`]). Not counted: its result is beyond the word, so the
            /// [`Self::narrow`] that follows clips it and counts once.
            #[cold]
            #[inline(never)]
            fn sat_sum3(a: $wide, b: $wide, c: $wide) -> $wide {
                a.saturating_add(b).saturating_add(c)
            }
            /// The saturating sum, out of line for the same reason as [`Self::clip`].
            #[cold]
            #[inline(never)]
            fn sat_add(self, o: Self) -> Self {
                saturated();
                Self(self.0.saturating_add(o.0))
            }
            #[cold]
            #[inline(never)]
            fn sat_sub(self, o: Self) -> Self {
                saturated();
                Self(self.0.saturating_sub(o.0))
            }
            /// [`Scalar::from_f64`] of x = r·2⁻ᶠ for a positive r already in units of the
            /// LSB: the same round half away from zero and saturation.
            #[inline(always)]
            fn from_scaled_pos(r: f64) -> Self {
                Self(<$inner>::from_bits((r + 0.5) as $bits))
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
                let r = scaled + 0.5f64.copysign(scaled);
                // The cast clips r ≥ 2^(n−1) and r whose truncation is below −2^(n−1):
                // r ≤ −2^(n−1) − 1, which for i64 (where −2^63 − 1 rounds to −2^63) is
                // r < −2^63, hence both tests. Folds away for literals like the rest.
                let limit = -(<$bits>::MIN as f64);
                if r >= limit || (r < -limit && r <= -limit - 1.0) {
                    saturated();
                }
                Self(<$inner>::from_bits(r as $bits))
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self.0.to_bits() as f64 / (1u64 << $frac) as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // √(b·2⁻ᶠ)·2ᶠ = √b·2^(f/2) with f even: scaling by an even power of two
                // commutes with the correctly rounded √ and is exact, so the core's
                // result (`from_f64(self.to_f64().sqrt())`) is one multiply from √b
                if self.0 <= <$inner>::ZERO {
                    Self(<$inner>::ZERO)
                } else {
                    let r = (self.0.to_bits() as f64).sqrt() * (1u64 << ($frac / 2)) as f64;
                    Self::from_scaled_pos(r)
                }
            }
            #[inline(always)]
            fn rsqrt(self) -> Self {
                // 1/√(b·2⁻ᶠ)·2ᶠ = 2^(3f/2)/√b, for the same reason bit for bit the core's
                // `from_f64(1.0 / self.to_f64().sqrt())` without its two scalings
                if self.0 <= <$inner>::ZERO {
                    saturated();
                    Self(<$inner>::MAX)
                } else {
                    let r = (1u64 << ($frac + $frac / 2)) as f64
                        / (self.0.to_bits() as f64).sqrt();
                    // beyond the word only in Q8.24 (2³⁶/√b for b < 1024)
                    if r + 0.5 >= -(<$bits>::MIN as f64) {
                        saturated();
                    }
                    Self::from_scaled_pos(r)
                }
            }
            #[inline(always)]
            fn mul_rn(self, o: Self) -> Self {
                // round half up: add half an LSB of the result before the floor shift
                let p = self.0.to_bits() as $wide * o.0.to_bits() as $wide;
                let p = match p.checked_add(1 << ($frac - 1)) {
                    Some(p) => p,
                    None => Self::sat_sum3(p, 1 << ($frac - 1), 0),
                } >> $frac;
                Self::narrow(p)
            }
            #[inline(always)]
            fn half_rn(self) -> Self {
                // in the double width: b + 1 overflows the word at MAX
                let b = self.0.to_bits() as $wide;
                Self(<$inner>::from_bits(((b + 1) >> 1) as $bits))
            }
            #[inline(always)]
            fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self {
                let w = |x: Self| x.0.to_bits() as $wide;
                let (ab, cd) = (w(a) * w(b), w(c) * w(d));
                let p = match ab.checked_add(cd) {
                    Some(p) => p,
                    None => Self::sat_sum3(ab, cd, 0),
                };
                let p = round_shift!(p, $frac);
                Self::narrow(p)
            }
            #[inline(always)]
            fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self {
                // A product of two $bits needs at most 2·bits − 1 bits of $wide; the sum of
                // three can reach 3·2⁶² > i64::MAX for the 32-bit formats (and beyond
                // i128 for Q32.32) only with operands near the word's limits, whose result
                // clips anyway: the saturating adds keep the sign, so the clamp below gives
                // the word's limit just as the exact sum would.
                let w = |x: Self| x.0.to_bits() as $wide;
                let (ab, cd, ef) = (w(a) * w(b), w(c) * w(d), w(e) * w(f));
                let p = match ab.checked_add(cd).and_then(|s| s.checked_add(ef)) {
                    Some(p) => p,
                    None => Self::sat_sum3(ab, cd, ef),
                };
                let p = round_shift!(p, $frac);
                Self::narrow(p)
            }
            fn max_value() -> Self {
                Self(<$inner>::MAX)
            }
            fn rounding() -> Option<(f64, f64)> {
                Some((0.0, <$inner>::DELTA.to_num::<f64>()))
            }
            #[inline(always)]
            fn floor(self) -> Self {
                Self(self.0.saturating_floor())
            }
            #[inline(always)]
            fn floor_i64(self) -> i64 {
                // the arithmetic shift drops the fraction toward −∞: ⌊x⌋ exactly, and
                // every format's integer part fits i64
                (self.0.to_bits() >> $frac) as i64
            }
            #[inline(always)]
            fn int_to_i64(self) -> i64 {
                // exact for an integral word, and the floor's integer for any other
                (self.0.to_bits() >> $frac) as i64
            }
            #[inline(always)]
            fn fract(self) -> Self {
                // x − ⌊x⌋ is the fraction bits (the floor clears them; it cannot overflow
                // with at least one integer bit, nor can the difference, which is in
                // [0, 1)): one mask instead of a saturating floor and subtraction
                Self(<$inner>::from_bits(
                    self.0.to_bits() & ((1 << $frac) - 1),
                ))
            }
            #[inline(always)]
            fn zero() -> Self {
                Self(<$inner>::ZERO)
            }
            composed!(one, recip, abs, min, max, clamp, is_finite, atan_core, acos_core);
        }
    };
}

fixed_scalar!(
    /// Signed Q16.16: the seed's `ap_fixed<32,16>` (range ±32768, step 2⁻¹⁶).
    Q16_16,
    I16F16,
    i32,
    i64,
    16,
    "q16.16"
);
fixed_scalar!(
    /// Signed Q8.24: fine fraction for unit vectors, but only ±128 of range.
    Q8_24,
    I8F24,
    i32,
    i64,
    24,
    "q8.24"
);
fixed_scalar!(
    /// Signed Q24.8: large scenes, coarse fraction (step 1/256).
    Q24_8,
    I24F8,
    i32,
    i64,
    8,
    "q24.8"
);
fixed_scalar!(
    /// Signed Q32.32 in 64 bits: what a wider datapath buys.
    Q32_32,
    I32F32,
    i64,
    i128,
    32,
    "q32.32"
);
