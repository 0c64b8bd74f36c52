//! Number formats and the seed's approximations, so that one ray-trace kernel can be run in
//! any of them and the cost of each format/approximation measured against the f64 reference.
//!
//! Fixed-point formats are newtypes over `fixed` with **saturating** arithmetic: the hardware
//! the seed targets (`ap_fixed` with `AP_SAT`) clips instead of wrapping, and a wrapped
//! coordinate would teleport a hit point across the scene while a clipped one only misplaces
//! it at the format's limit. Division by zero saturates to the signed maximum (or minimum for
//! a negative dividend), the behaviour of a divider core that flags but does not trap.

mod approx;
mod formats;

pub use approx::*;
pub use formats::*;

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A real-number format the ray-trace kernel computes in.
///
/// Everything the kernel needs beyond `+ − × ÷` is here so that the kernel never leaves the
/// format (no silent detour through f64 except where a method documents it as modelling a
/// hardware core, e.g. `sqrt`).
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
    /// square root); x ≤ 0 gives the format's maximum.
    #[inline(always)]
    fn rsqrt(self) -> Self {
        if self > Self::zero() {
            Self::one() / self.sqrt()
        } else {
            Self::max_value()
        }
    }
    /// x·y rounded to nearest. Floats already round every product, so the default is
    /// `*`; the fixed formats override it because their `*` truncates (floor, `ap_fixed`'s
    /// default AP_TRN): a biased error of up to one LSB per product that the vector
    /// operations accumulate (ray directions, hit points). Rounding is one more adder on
    /// the product's first discarded bit (AP_RND).
    #[inline(always)]
    fn mul_rn(self, o: Self) -> Self {
        self * o
    }
    /// `self.mul_rn(½)`: the texture mappings' (x + 1)/2. The fixed formats override it
    /// with (b + 1) ≫ 1 on the word b, the same integer as the rounded product
    /// (b·2^(f−1) + 2^(f−1)) ≫ f, without the product and the clamp it cannot need.
    #[inline(always)]
    fn half_rn(self) -> Self {
        self.mul_rn(Self::from_f64(0.5))
    }
    /// a·b + c·d, with the same contract as [`Scalar::dot3`] (one rounding in fixed point).
    #[inline(always)]
    fn dot2(a: Self, b: Self, c: Self, d: Self) -> Self {
        a * b + c * d
    }
    /// a·b + c·d + e·f (a 3-term dot product). The default is the plain expression (what
    /// floats do); the fixed formats override it with the exact sum of the double-width
    /// products and one rounding at the end, as a DSP cascade with a wide accumulator
    /// computes it: one rounding error instead of five.
    #[inline(always)]
    fn dot3(a: Self, b: Self, c: Self, d: Self, e: Self, f: Self) -> Self {
        a * b + c * d + e * f
    }
    /// Largest finite value: the kernel's "infinity" for formats without one.
    fn max_value() -> Self;
    /// The format's rounding as (relative, absolute): one operation's result near
    /// magnitude m is off by about relative·m + absolute. The planned kernel sizes and
    /// admits its culling with it (`rt::cull`); `None`, the default, turns culling off, so
    /// a format that does not declare it (e.g. an instrumented wrapper) is always tested
    /// exhaustively, like the board.
    fn rounding() -> Option<(f64, f64)> {
        None
    }
    /// Largest integer not above `self`.
    fn floor(self) -> Self {
        Self::from_f64(self.to_f64().floor())
    }
    /// ⌊self⌋ as an integer (saturating at the i64 range, NaN → 0): a texel address. The
    /// default goes through f64 as the kernel always did; the fixed formats override it
    /// with the arithmetic shift that a hardware address unit uses (the same integer).
    #[inline(always)]
    fn floor_i64(self) -> i64 {
        self.floor().int_to_i64()
    }
    /// An integral value (a floor's result) as i64, saturating, NaN → 0: so that a caller
    /// that needs both ⌊x⌋ and its integer floors once (the compiler does not merge two
    /// inlined float floors across their branches).
    #[inline(always)]
    fn int_to_i64(self) -> i64 {
        self.to_f64() as i64
    }
    /// Additive identity.
    #[inline(always)]
    fn zero() -> Self {
        Self::default()
    }
    /// Multiplicative identity.
    #[inline(always)]
    fn one() -> Self {
        Self::from_f64(1.0)
    }
    /// 1/x with the format's own divider.
    #[inline(always)]
    fn recip(self) -> Self {
        Self::one() / self
    }
    /// |x| (saturating for the most negative fixed value).
    #[inline(always)]
    fn abs(self) -> Self {
        if self < Self::zero() {
            -self
        } else {
            self
        }
    }
    /// Smaller of two values (`other` if incomparable, so NaN does not stick).
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        if self < other {
            self
        } else {
            other
        }
    }
    /// Larger of two values.
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        if self > other {
            self
        } else {
            other
        }
    }
    /// Clamp into `[lo, hi]`.
    #[inline(always)]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
    /// False for NaN/∞ (always true for fixed point).
    fn is_finite(self) -> bool {
        self.to_f64().is_finite()
    }
    /// Fractional part in `[0, 1)`.
    fn fract(self) -> Self {
        self - self.floor()
    }
    /// arctan of a correctly rounded core (CORDIC in hardware), modelled through f64: a
    /// method rather than a free function so that an op-counting format can see it.
    #[inline(always)]
    fn atan_core(self) -> Self {
        Self::from_f64(self.to_f64().atan())
    }
    /// arccos of a correctly rounded core, modelled through f64 (see [`Scalar::atan_core`]).
    #[inline(always)]
    fn acos_core(self) -> Self {
        Self::from_f64(self.to_f64().clamp(-1.0, 1.0).acos())
    }
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
}
