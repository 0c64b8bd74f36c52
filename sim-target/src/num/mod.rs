//! Number formats and the seed's approximations, so that one ray-trace kernel can be run in
//! any of them and the cost of each format/approximation measured against the f64 reference.
//!
//! Fixed-point formats are newtypes over `fixed` with **saturating** arithmetic: the hardware
//! the seed targets (`ap_fixed` with `AP_SAT`) clips instead of wrapping, and a wrapped
//! coordinate would teleport a hit point across the scene while a clipped one only misplaces
//! it at the format's limit. Division by zero saturates to the signed maximum (or minimum for
//! a negative dividend), the behaviour of a divider core that flags but does not trap.
//!
//! [`Scalar`] has no default method bodies: every format, and every wrapper of
//! [`instrumented`], spells out each method, so that a method the trait gains is a compile
//! error wherever it has not been decided (see [`instrumented`] for why that matters). The
//! formulas a format uses when it has nothing cheaper of its own are in [`composed`]; the
//! `composed!` macro below writes the forwarding methods for the formats that use them.
//!
//! Saturation is silent in the values but counted: a crate-private counter tallies every
//! clipped result on the thread computing it, and a frame reports its total
//! ([`crate::rt::Stats::saturations`], the device's counters).
//!
//! The formats and the approximations are re-exported here from private modules. Two
//! modules stay public as namespaces callers name on purpose: [`composed`]`::rsqrt` is the
//! composed form of a method, not a second `rsqrt` (the `composed!` lists name them so),
//! and [`instrumented`] is a family of wrapper formats with its own counters
//! (`instrumented::count`, `instrumented::Probe`).

/// Writes the named [`Scalar`] methods inside a format's `impl Scalar` as calls of their
/// [`composed`] forms: the list at each use is the one place that says which methods a
/// format does not specialise.
macro_rules! composed {
    ($($m:ident),* $(,)?) => { $(composed!(@ $m);)* };
    (@ rsqrt) => {
        #[inline(always)]
        fn rsqrt(self) -> Self {
            $crate::num::composed::rsqrt(self)
        }
    };
    (@ mul_rn) => {
        #[inline(always)]
        fn mul_rn(self, o: Self) -> Self {
            $crate::num::composed::mul_rn(self, o)
        }
    };
    (@ half_rn) => {
        #[inline(always)]
        fn half_rn(self) -> Self {
            $crate::num::composed::half_rn(self)
        }
    };
    (@ dot2) => {
        #[inline(always)]
        fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self {
            $crate::num::composed::dot2(a, b, c, d)
        }
    };
    (@ dot3) => {
        #[inline(always)]
        fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self {
            $crate::num::composed::dot3(a, b, c, d, e, f)
        }
    };
    (@ floor) => {
        fn floor(self) -> Self {
            $crate::num::composed::floor(self)
        }
    };
    (@ floor_i64) => {
        #[inline(always)]
        fn floor_i64(self) -> i64 {
            $crate::num::composed::floor_i64(self)
        }
    };
    (@ int_to_i64) => {
        #[inline(always)]
        fn int_to_i64(self) -> i64 {
            $crate::num::composed::int_to_i64(self)
        }
    };
    (@ zero) => {
        #[inline(always)]
        fn zero() -> Self {
            $crate::num::composed::zero()
        }
    };
    (@ one) => {
        #[inline(always)]
        fn one() -> Self {
            $crate::num::composed::one()
        }
    };
    (@ recip) => {
        #[inline(always)]
        fn recip(self) -> Self {
            $crate::num::composed::recip(self)
        }
    };
    (@ abs) => {
        #[inline(always)]
        fn abs(self) -> Self {
            $crate::num::composed::abs(self)
        }
    };
    (@ min) => {
        #[inline(always)]
        fn min(self, other: Self) -> Self {
            $crate::num::composed::min(self, other)
        }
    };
    (@ max) => {
        #[inline(always)]
        fn max(self, other: Self) -> Self {
            $crate::num::composed::max(self, other)
        }
    };
    (@ clamp) => {
        #[inline(always)]
        fn clamp(self, lo: Self, hi: Self) -> Self {
            $crate::num::composed::clamp(self, lo, hi)
        }
    };
    (@ is_finite) => {
        fn is_finite(self) -> bool {
            $crate::num::composed::is_finite(self)
        }
    };
    (@ fract) => {
        fn fract(self) -> Self {
            $crate::num::composed::fract(self)
        }
    };
    (@ atan_core) => {
        #[inline(always)]
        fn atan_core(self) -> Self {
            $crate::num::composed::atan_core(self)
        }
    };
    (@ acos_core) => {
        #[inline(always)]
        fn acos_core(self) -> Self {
            $crate::num::composed::acos_core(self)
        }
    };
}

mod approx;
pub mod composed;
mod formats;
pub mod instrumented;
pub(crate) mod saturation;

pub use approx::{
    acos, acos_table, atan, atan2, div_lut_nr, div_nr, powi, powi_with, pre_d, pre_d_lut, pre_s,
    pre_s_lut, pre_s_seamless, rsqrt, rsqrt_nr, sqrt, AcosKind, AtanKind, SqrtKind, ACOS_BINADES,
    ACOS_SEGMENTS, MAX_POW_EXPONENT, RECIP_LUT_ENTRIES,
};
pub use formats::{Q16_16, Q24_8, Q32_32, Q8_24};

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A real-number format the ray-trace kernel computes in.
///
/// Everything the kernel needs beyond `+ − × ÷` is here so that the kernel never leaves the
/// format (no silent detour through f64 except where a method documents it as modelling a
/// hardware core, e.g. `sqrt`).
///
/// No method has a default body, on purpose: a wrapper format ([`instrumented`]) that
/// inherited one would compute that method from its other operations instead of with the
/// wrapped format's own, which is silently different wherever a format specialises the
/// method. Formats call the [`composed`] forms explicitly.
pub trait Scalar:
    Copy
    + Clone
    + Send
    + Sync
    + PartialOrd
    + PartialEq
    + Debug
    + Default
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Short name used in tables and benches.
    const NAME: &'static str;
    /// Nearest representable value (saturating for fixed point; NaN maps to 0 there).
    fn from_f64(x: f64) -> Self;
    /// Exact widening to f64 (every supported format fits in f64 exactly).
    fn to_f64(self) -> f64;
    /// Square root of the best quality the format offers (a correctly rounded core for
    /// fixed point, modelled through f64); negative input gives 0 so that a slightly
    /// negative discriminant from rounding cannot produce NaN.
    fn sqrt(self) -> Self;
    /// 1/√x of the best quality the format offers (for fixed point a correctly rounded
    /// reciprocal-square-root core, modelled through f64, instead of a divider after the
    /// square root); x ≤ 0 gives the format's maximum. Floats: [`composed::rsqrt`].
    fn rsqrt(self) -> Self;
    /// x·y rounded to nearest. Floats already round every product, so theirs is `*`
    /// ([`composed::mul_rn`]); the fixed formats' `*` truncates (floor, `ap_fixed`'s
    /// default AP_TRN): a biased error of up to one LSB per product that the vector
    /// operations accumulate (ray directions, hit points). Rounding is one more adder on
    /// the product's first discarded bit (AP_RND).
    fn mul_rn(self, o: Self) -> Self;
    /// `self.mul_rn(½)`: the texture mappings' (x + 1)/2 ([`composed::half_rn`]). The fixed
    /// formats compute it as (b + 1) ≫ 1 on the word b, the same integer as the rounded
    /// product (b·2^(f−1) + 2^(f−1)) ≫ f, without the product and the clamp it cannot need.
    fn half_rn(self) -> Self;
    /// a·b + c·d, with the same contract as [`Scalar::dot3`] (one rounding in fixed point).
    fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self;
    /// a·b + c·d + e·f (a 3-term dot product). Floats evaluate the plain expression
    /// ([`composed::dot3`]); the fixed formats form the exact sum of the double-width
    /// products and round once at the end, as a DSP cascade with a wide accumulator
    /// computes it: one rounding error instead of five.
    fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self;
    /// Largest finite value: the kernel's "infinity" for formats without one.
    fn max_value() -> Self;
    /// The format's rounding as (relative, absolute): one operation's result near
    /// magnitude m is off by about relative·m + absolute. The planned kernel sizes and
    /// admits its culling with it (`rt::cull`); `None` turns culling off, so such a format
    /// is always tested exhaustively, like the board. The wrappers of [`instrumented`]
    /// declare their format's: a caller that wants the exhaustive operation stream asks
    /// for it (`RenderOptions::cull`).
    fn rounding() -> Option<(f64, f64)>;
    /// Largest integer not above `self`. [`composed::floor`] goes through f64.
    fn floor(self) -> Self;
    /// ⌊self⌋ as an integer (saturating at the i64 range, NaN → 0): a texel address.
    /// Floats go through f64 as the kernel always did ([`composed::floor_i64`]); the fixed
    /// formats use the arithmetic shift that a hardware address unit uses (the same
    /// integer).
    fn floor_i64(self) -> i64;
    /// An integral value (a floor's result) as i64, saturating, NaN → 0: so that a caller
    /// that needs both ⌊x⌋ and its integer floors once (the compiler does not merge two
    /// inlined float floors across their branches).
    fn int_to_i64(self) -> i64;
    /// 0, exact in every format: the start of every sum.
    fn zero() -> Self;
    /// 1, exact in every format (the fixed formats all have an integer part).
    fn one() -> Self;
    /// 1/x with the format's own divider.
    fn recip(self) -> Self;
    /// |x| (saturating for the most negative fixed value).
    fn abs(self) -> Self;
    /// Smaller of two values (`other` if incomparable, so NaN does not stick).
    fn min(self, other: Self) -> Self;
    /// Larger of two values.
    fn max(self, other: Self) -> Self;
    /// Clamp into `[lo, hi]`.
    fn clamp(self, lo: Self, hi: Self) -> Self;
    /// False for NaN/∞ (always true for fixed point).
    fn is_finite(self) -> bool;
    /// Fractional part in `[0, 1)`.
    fn fract(self) -> Self;
    /// arctan of a correctly rounded core (CORDIC in hardware), modelled through f64: a
    /// method rather than a free function so that an op-counting format can see it.
    fn atan_core(self) -> Self;
    /// arccos of a correctly rounded core, modelled through f64 (see [`Scalar::atan_core`]).
    fn acos_core(self) -> Self;
}
/// `f64::floor` without the libm call that baseline x86-64 (no SSE4.1 `roundsd`) makes.
/// Below 2⁵² in magnitude, x ± 2⁵² (sign of x) lies in a binade of spacing 1, so the
/// addition rounds x to the nearest integer r and the subtraction is exact; one step down
/// where r > x gives the floor. Floor never changes the sign bit (so −0 and (−1, 0) keep
/// it through `copysign`); larger values, ±∞ and NaN are already integral or propagate
/// unchanged. Two additions instead of a saturating float→int→float round trip (session
/// 5: fewer instructions; the earlier truncation form gave the same bits). Bit-identical
/// to `f64::floor` (tested in `tests/num_approx.rs`).
#[inline(always)]
pub fn floor_f64(x: f64) -> f64 {
    const TWO52: f64 = 4_503_599_627_370_496.0;
    if x.abs() < TWO52 {
        let magic = TWO52.copysign(x);
        let r = (x + magic) - magic;
        (if r > x { r - 1.0 } else { r }).copysign(x)
    } else {
        x
    }
}

/// `f32::floor` without the libm call; see [`floor_f64`].
#[inline(always)]
pub fn floor_f32(x: f32) -> f32 {
    const TWO23: f32 = 8_388_608.0;
    if x.abs() < TWO23 {
        let magic = TWO23.copysign(x);
        let r = (x + magic) - magic;
        (if r > x { r - 1.0 } else { r }).copysign(x)
    } else {
        x
    }
}

impl Scalar for f64 {
    const NAME: &'static str = "f64";
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        if self > 0.0 {
            f64::sqrt(self)
        } else {
            0.0
        }
    }
    fn max_value() -> Self {
        f64::MAX
    }
    fn rounding() -> Option<(f64, f64)> {
        Some((f64::EPSILON / 2.0, f64::MIN_POSITIVE))
    }
    #[inline(always)]
    fn floor(self) -> Self {
        floor_f64(self)
    }
    composed!(int_to_i64);
    composed!(
        rsqrt, mul_rn, half_rn, dot2, dot3, floor_i64, zero, one, recip, abs, min, max, clamp,
        is_finite, fract, atan_core, acos_core
    );
}

impl Scalar for f32 {
    const NAME: &'static str = "f32";
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        if self > 0.0 {
            f32::sqrt(self)
        } else {
            0.0
        }
    }
    fn max_value() -> Self {
        f32::MAX
    }
    fn rounding() -> Option<(f64, f64)> {
        Some((f32::EPSILON as f64 / 2.0, f32::MIN_POSITIVE as f64))
    }
    #[inline(always)]
    fn floor(self) -> Self {
        floor_f32(self)
    }
    #[inline(always)]
    fn int_to_i64(self) -> i64 {
        // f32 → i64 saturates and maps NaN to 0 exactly as f32 → f64 → i64 (the f64
        // holds every f32 exactly): one conversion less
        self as i64
    }
    composed!(
        rsqrt, mul_rn, half_rn, dot2, dot3, floor_i64, zero, one, recip, abs, min, max, clamp,
        is_finite, fract, atan_core, acos_core
    );
}

impl Scalar for half::f16 {
    const NAME: &'static str = "f16";
    fn from_f64(x: f64) -> Self {
        half::f16::from_f64(x)
    }
    fn to_f64(self) -> f64 {
        half::f16::to_f64(self)
    }
    fn sqrt(self) -> Self {
        let x = self.to_f32();
        if x > 0.0 {
            half::f16::from_f32(x.sqrt())
        } else {
            half::f16::ZERO
        }
    }
    fn max_value() -> Self {
        half::f16::MAX
    }
    fn rounding() -> Option<(f64, f64)> {
        Some((
            half::f16::EPSILON.to_f64() / 2.0,
            half::f16::MIN_POSITIVE.to_f64(),
        ))
    }
    composed!(floor, int_to_i64);
    composed!(
        rsqrt, mul_rn, half_rn, dot2, dot3, floor_i64, zero, one, recip, abs, min, max, clamp,
        is_finite, fract, atan_core, acos_core
    );
}
