//! The instrumented formats are their format, bit for bit: every [`Scalar`] method (and
//! operator) of `Probe<S>` and `Counted<S>` gives exactly what `S` gives, for every format
//! of `Numeric::ALL`, on raw-bit inputs (fixed point: any word, words at and near the
//! saturation limits, small words; floats: NaN, ±∞, subnormals, ±0, extremes). And their
//! counting is reentrant: nested scopes and threads never mix counts, and a frame rendered
//! with `render_instrumented` is counted whole by the scope around it.

use proptest::prelude::*;
use protocol::frame::Numeric;
use protocol::names::Named;
use sim_target::num::instrumented::{self, Counted, Exact, OpKind, Probe};
use sim_target::num::{Scalar, Q16_16, Q24_8, Q32_32, Q8_24};
use sim_target::rt::{self, RenderOptions};

/// A format's raw bits: equality of results means equality of these (so −0 ≠ +0), except
/// that every NaN is one value. Rust leaves the sign and payload of a NaN result
/// unspecified (the compiler may commute an addition of two NaNs, and x86 makes a negative
/// NaN where the other operand order gives a positive one), so two evaluations of the same
/// bare expression are not promised the same NaN bits either; what is promised, and what
/// the kernel can observe, is that the result is NaN.
trait Bits: Exact {
    fn bits(self) -> u64;
}

/// The one value every NaN compares as: all ones, which no non-NaN float's bits are.
const NAN: u64 = u64::MAX;

/// A float's bits, or [`NAN`] for every NaN.
fn float_bits(nan: bool, bits: u64) -> u64 {
    if nan {
        NAN
    } else {
        bits
    }
}

impl Bits for f64 {
    fn bits(self) -> u64 {
        float_bits(self.is_nan(), self.to_bits())
    }
}
impl Bits for f32 {
    fn bits(self) -> u64 {
        float_bits(self.is_nan(), self.to_bits() as u64)
    }
}
impl Bits for half::f16 {
    fn bits(self) -> u64 {
        float_bits(self.is_nan(), self.to_bits() as u64)
    }
}
macro_rules! fixed_bits {
    ($($t:ty),*) => {$(
        impl Bits for $t {
            fn bits(self) -> u64 {
                self.0.to_bits() as u64
            }
        }
    )*};
}
fixed_bits!(Q16_16, Q8_24, Q24_8, Q32_32);

/// A wrapper of `S`: how the test gets in and out of it.
trait Wrapper<S>: Scalar {
    fn wrap(s: S) -> Self;
    fn inner(self) -> S;
}
impl<S: Exact> Wrapper<S> for Probe<S> {
    fn wrap(s: S) -> Self {
        Probe(s)
    }
    fn inner(self) -> S {
        self.0
    }
}
impl<S: Scalar> Wrapper<S> for Counted<S> {
    fn wrap(s: S) -> Self {
        Counted(s)
    }
    fn inner(self) -> S {
        self.0
    }
}

/// Every method of [`Scalar`] and every operator, on the operands `v` and the conversion
/// input `x`, in the wrapper `W` and in `S`: the results must have the same bits.
fn same<S: Bits, W: Wrapper<S>>(v: [S; 6], x: f64) -> Result<(), TestCaseError> {
    let [a, b, c, d, e, f] = v;
    let w = W::wrap;
    let ctx = format!(
        "{} in {}: operands {v:?}, x = {x:e}",
        S::NAME,
        core::any::type_name::<W>()
    );
    macro_rules! eq {
        ($name:literal, $got:expr, $want:expr) => {{
            let (got, want): (S, S) = ($got.inner(), $want);
            prop_assert_eq!(
                got.bits(),
                want.bits(),
                "{} ({:?} vs {:?}), {}",
                $name,
                got,
                want,
                ctx
            );
        }};
    }
    macro_rules! eq_val {
        ($name:literal, $got:expr, $want:expr) => {{
            let (got, want) = ($got, $want);
            prop_assert_eq!(got, want, "{}, {}", $name, ctx);
        }};
    }
    prop_assert_eq!(W::NAME, S::NAME);
    eq!("from_f64", W::from_f64(x), S::from_f64(x));
    eq_val!("to_f64", w(a).to_f64().bits(), a.to_f64().bits());
    eq!("sqrt", w(a).sqrt(), a.sqrt());
    eq!("rsqrt", w(a).rsqrt(), a.rsqrt());
    eq!("mul_rn", w(a).mul_rn(w(b)), a.mul_rn(b));
    eq!("half_rn", w(a).half_rn(), a.half_rn());
    eq!("dot2", W::dot2(w(a), w(b), w(c), w(d)), S::dot2(a, b, c, d));
    eq!(
        "dot3",
        W::dot3(w(a), w(b), w(c), w(d), w(e), w(f)),
        S::dot3(a, b, c, d, e, f)
    );
    eq!("max_value", W::max_value(), S::max_value());
    eq_val!(
        "rounding",
        W::rounding().map(|(r, a)| (r.to_bits(), a.to_bits())),
        S::rounding().map(|(r, a)| (r.to_bits(), a.to_bits()))
    );
    eq!("floor", w(a).floor(), a.floor());
    eq_val!("floor_i64", w(a).floor_i64(), a.floor_i64());
    eq_val!("int_to_i64", w(a).int_to_i64(), a.int_to_i64());
    eq!("zero", W::zero(), S::zero());
    eq!("one", W::one(), S::one());
    eq!("recip", w(a).recip(), a.recip());
    eq!("abs", w(a).abs(), a.abs());
    eq!("min", w(a).min(w(b)), a.min(b));
    eq!("max", w(a).max(w(b)), a.max(b));
    eq!("clamp", w(a).clamp(w(b), w(c)), a.clamp(b, c));
    eq_val!("is_finite", w(a).is_finite(), a.is_finite());
    eq!("fract", w(a).fract(), a.fract());
    eq!("atan_core", w(a).atan_core(), a.atan_core());
    eq!("acos_core", w(a).acos_core(), a.acos_core());
    eq!("+", w(a) + w(b), a + b);
    eq!("-", w(a) - w(b), a - b);
    eq!("*", w(a) * w(b), a * b);
    eq!("/", w(a) / w(b), a / b);
    eq!("neg", -w(a), -a);
    eq_val!("partial_cmp", w(a).partial_cmp(&w(b)), a.partial_cmp(&b));
    eq_val!("==", w(a) == w(b), a == b);
    Ok(())
}

/// Both wrappers of `S` against `S`.
fn both<S: Bits>(v: [S; 6], x: f64) -> Result<(), TestCaseError> {
    // the probe's counts are of no interest here: counted in a scope of their own
    let (r, _) = instrumented::count(|| {
        same::<S, Probe<S>>(v, x)?;
        same::<S, Counted<S>>(v, x)
    });
    r
}

/// Raw words of a fixed format with `bits` bits: anything, at and near both saturation
/// limits, and near zero (where ±1 and the small fractions are).
fn word(bits: u32) -> impl Strategy<Value = i64> {
    let (min, max) = (i64::MIN >> (64 - bits), i64::MAX >> (64 - bits));
    prop_oneof![
        any::<i64>().prop_map(move |v| v.clamp(min, max)),
        (min..=max),
        (0..=4096i64).prop_map(move |k| max - k),
        (0..=4096i64).prop_map(move |k| min + k),
        (-(1i64 << 26)..=(1i64 << 26)),
        prop::sample::select(vec![0, 1, -1, min, max, min + 1, max - 1]),
    ]
}

/// A conversion input: any f64 (NaN, ±∞ and subnormals included), values at the fixed
/// formats' limits (±128 … ±2³¹), and ordinary magnitudes.
fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>(),
        any::<u64>().prop_map(f64::from_bits),
        prop::sample::select(vec![128.0, 32768.0, 8_388_608.0, 2_147_483_648.0])
            .prop_flat_map(|m: f64| (0.99 * m..1.01 * m, any::<bool>()))
            .prop_map(|(v, neg)| if neg { -v } else { v }),
        -1e3..1e3f64,
        prop::sample::select(vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::MIN_POSITIVE / 3.0,
            f64::MAX,
            65504.0,
            65520.0,
        ]),
    ]
}

fn f64s() -> impl Strategy<Value = f64> {
    any_f64()
}

fn f32s() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<f32>(),
        any::<u32>().prop_map(f32::from_bits),
        prop::sample::select(vec![
            0.0f32,
            -0.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE / 3.0,
            f32::MAX,
            -f32::MAX,
            1.0,
            -1.0,
        ]),
    ]
}

fn f16s() -> impl Strategy<Value = half::f16> {
    // 2¹⁶ patterns: uniform raw bits reach NaN, ±∞ and the subnormals often enough
    any::<u16>().prop_map(half::f16::from_bits)
}

macro_rules! fixed_strategy {
    ($name:ident, $t:ty, $inner:ty, $raw:ty, $bits:literal) => {
        fn $name() -> impl Strategy<Value = $t> {
            word($bits).prop_map(|v| <$t>::from_inner(<$inner>::from_bits(v as $raw)))
        }
    };
}

trait FromInner<I> {
    fn from_inner(i: I) -> Self;
}
macro_rules! from_inner {
    ($($t:ty: $i:ty),*) => {$(
        impl FromInner<$i> for $t {
            fn from_inner(i: $i) -> Self {
                Self(i)
            }
        }
    )*};
}
use fixed::types::{I16F16, I24F8, I32F32, I8F24};
from_inner!(Q16_16: I16F16, Q8_24: I8F24, Q24_8: I24F8, Q32_32: I32F32);

fixed_strategy!(q16_16s, Q16_16, I16F16, i32, 32);
fixed_strategy!(q8_24s, Q8_24, I8F24, i32, 32);
fixed_strategy!(q24_8s, Q24_8, I24F8, i32, 32);
fixed_strategy!(q32_32s, Q32_32, I32F32, i64, 64);

/// Every format of [`Numeric::ALL`] has its test below (matched by name): a format added
/// to the protocol fails here until it is.
#[test]
fn every_format_is_tested() {
    let tested = [
        f64::NAME,
        f32::NAME,
        half::f16::NAME,
        Q16_16::NAME,
        Q8_24::NAME,
        Q24_8::NAME,
        Q32_32::NAME,
    ];
    for n in Numeric::ALL {
        assert!(
            tested.contains(&n.name()),
            "{n:?} has no bit-equality test (or its Scalar::NAME is not its protocol name)"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn f64_wrappers_are_f64(v in prop::array::uniform6(f64s()), x in any_f64()) {
        both(v, x)?;
    }

    #[test]
    fn f32_wrappers_are_f32(v in prop::array::uniform6(f32s()), x in any_f64()) {
        both(v, x)?;
    }

    #[test]
    fn f16_wrappers_are_f16(v in prop::array::uniform6(f16s()), x in any_f64()) {
        both(v, x)?;
    }

    #[test]
    fn q16_16_wrappers_are_q16_16(v in prop::array::uniform6(q16_16s()), x in any_f64()) {
        both(v, x)?;
    }

    #[test]
    fn q8_24_wrappers_are_q8_24(v in prop::array::uniform6(q8_24s()), x in any_f64()) {
        both(v, x)?;
    }

    #[test]
    fn q24_8_wrappers_are_q24_8(v in prop::array::uniform6(q24_8s()), x in any_f64()) {
        both(v, x)?;
    }

    #[test]
    fn q32_32_wrappers_are_q32_32(v in prop::array::uniform6(q32_32s()), x in any_f64()) {
        both(v, x)?;
    }
}

/// Bytes in which two images differ (0: the same image).
fn differing(a: &[u8], b: &[u8]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count() + a.len().abs_diff(b.len())
}

fn ops(c: &instrumented::Counts) -> [u64; 8] {
    c.ops.0
}

fn adds(n: usize) {
    let x = Counted(1.0f64);
    for _ in 0..n {
        std::hint::black_box(x + x);
    }
}

#[test]
fn nested_scopes_keep_their_own_counts() {
    let x = Counted(2.0f64);
    let sat = Probe(Q16_16::max_value());
    let ((inner, after_inner), outer) = instrumented::count(|| {
        adds(3);
        let _ = sat + sat; // one saturation, the outer scope's
        let ((), inner) = instrumented::count(|| {
            let _ = x * x;
            let _ = x * x;
            let _ = -sat - sat; // one saturation, the inner scope's
        });
        let ((), after) = instrumented::count(|| adds(1));
        adds(2);
        (inner, after)
    });
    assert_eq!(outer.ops.get(OpKind::AddSub), 5, "{outer:?}");
    assert_eq!(outer.ops.get(OpKind::Mul), 0, "{outer:?}");
    assert_eq!(outer.seen.saturations, 1, "{outer:?}");
    assert_eq!(inner.ops.get(OpKind::Mul), 2, "{inner:?}");
    assert_eq!(inner.ops.get(OpKind::AddSub), 0, "{inner:?}");
    assert_eq!(inner.seen.saturations, 1, "{inner:?}");
    assert_eq!(after_inner.ops.get(OpKind::AddSub), 1, "{after_inner:?}");
}

#[test]
fn a_panicking_scope_restores_the_outer_counts() {
    let ((), outer) = instrumented::count(|| {
        adds(2);
        let r = std::panic::catch_unwind(|| {
            instrumented::count(|| {
                adds(100);
                panic!("inside the inner scope");
            })
        });
        assert!(r.is_err());
        adds(1);
    });
    assert_eq!(outer.ops.get(OpKind::AddSub), 3, "{outer:?}");
}

#[test]
fn threads_count_apart() {
    let barrier = std::sync::Barrier::new(2);
    let ((), main) = instrumented::count(|| {
        std::thread::scope(|s| {
            let t: Vec<_> = [1000usize, 1777]
                .into_iter()
                .map(|n| {
                    let barrier = &barrier;
                    s.spawn(move || {
                        barrier.wait();
                        let ((), c) = instrumented::count(|| adds(n));
                        (n, c)
                    })
                })
                .collect();
            for h in t {
                let (n, c) = h.join().expect("thread");
                assert_eq!(c.ops.get(OpKind::AddSub), n as u64, "{c:?}");
            }
        });
    });
    assert_eq!(ops(&main), [0; 8], "{main:?}");
}

/// A frame through `render_instrumented` is counted whole by the scope around it (its
/// rows run on the calling thread): the same counts alone, nested in another scope, and
/// on two threads at once; and a probed frame is the bare format's image.
#[test]
fn instrumented_frames_are_counted_whole() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/reference.toml");
    let text = std::fs::read_to_string(path).expect("reference scene");
    let scene = jobs::scene::parse(&text, path).expect("parses");
    let opts = RenderOptions {
        size: Some((16, 9)),
        cull: false,
        ..RenderOptions::default()
    };
    let counted = || instrumented::count(|| rt::render_instrumented::<Counted<f64>>(&scene, &opts));
    let (frame, alone) = counted();
    let frame = frame.expect("renders");
    assert!(alone.ops.get(OpKind::Mul) > 16 * 9, "{alone:?}");
    let ((again, nested), _) = instrumented::count(|| {
        adds(7);
        counted()
    });
    assert_eq!(ops(&nested), ops(&alone));
    assert_eq!(differing(&again.expect("renders").rgb8, &frame.rgb8), 0);
    std::thread::scope(|s| {
        let a = s.spawn(counted);
        let b = s.spawn(counted);
        for h in [a, b] {
            let (_, c) = h.join().expect("thread");
            assert_eq!(ops(&c), ops(&alone));
        }
    });
    let bare = rt::render(
        &scene,
        &RenderOptions {
            numeric: Numeric::F64,
            ..opts
        },
    )
    .expect("renders");
    assert_eq!(
        differing(&frame.rgb8, &bare.rgb8),
        0,
        "Counted<f64> renders f64's image"
    );
    let (probed, _) =
        instrumented::count(|| rt::render_instrumented::<Probe<Q16_16>>(&scene, &opts));
    let q16 = rt::render(
        &scene,
        &RenderOptions {
            numeric: Numeric::Q16_16,
            ..opts
        },
    )
    .expect("renders");
    assert_eq!(
        differing(&probed.expect("renders").rgb8, &q16.rgb8),
        0,
        "Probe<Q16_16> renders Q16.16's image"
    );
}
