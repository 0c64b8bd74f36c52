//! The ray-casting core's RTL (`hw/rt-core/rtl/`), Verilated, as a Rust library, so that
//! its differential tests can hold it to the golden model (`sim-target`) from Rust: its
//! Q16.16 arithmetic units ([`MathUnits`]) and its intersection unit ([`Intersect`]), one
//! operand set per clock, the frame core ([`Cast`]): a scene image in, a result per
//! pixel out, and the core on its bus ([`Device`]): AXI4-Lite accesses in, the memory
//! port's records out.
//!
//! The build script Verilates the RTL when verilator is installed (`cargo xtask setup`
//! installs it); without it the crate still builds and [`MathUnits::new`] says what was
//! missing. `FPGFX_RT_RTL_DIR=<dir>` builds against another copy of `rtl/` (a deliberately
//! broken unit, to watch the tests fail).
//!
//! Every value crosses as its Q16.16 bits in an `i32`.
//!
//! With the `trace` feature every model can write a VCD of its signals (`trace_to`), for
//! the replay of a failing differential case; the suite builds without it, because
//! tracing doubles the Verilated C++ to compile, and rebuilds with it only when a case
//! fails.

mod cast;
mod device;
mod ffi;

pub use cast::{Cast, CastError, CastFrame, CastPixel};
pub use device::{AxiError, Device, Jitter, MemRecord, HANDSHAKE_BOUND};

use std::ptr::NonNull;

/// Why no model could be had.
#[derive(Debug, thiserror::Error)]
pub enum RtlError {
    /// The crate was built where verilator could not be found, so it holds no model.
    #[error("verilator not found when rt-core-rtl-sim was built: run `cargo xtask setup` (installs verilator from Debian), then rebuild")]
    NoVerilator,
    /// The crate was built before `hw/rt-core/sim/` had its `rt_math_top` module.
    #[error("hw/rt-core/sim/ had no `rt_math_top` module when rt-core-rtl-sim was built")]
    NoRtl,
    /// Allocating the model failed.
    #[error("cannot construct the Verilated model")]
    Construct,
    /// A waveform was asked of a model built without tracing.
    #[error(
        "this model cannot write a waveform: rt-core-rtl-sim was built without its `trace` feature"
    )]
    NoTrace,
    /// The waveform's file could not be opened (or one is already being written).
    #[error("cannot write a waveform to {0}")]
    Trace(String),
}

/// Whether this build's models can write a waveform (the `trace` feature).
pub const TRACE: bool = cfg!(feature = "trace");

/// Starts a waveform through `open` (the model's shim call) at `path`, or says why not.
fn trace(
    path: &std::path::Path,
    open: impl FnOnce(&std::ffi::CStr) -> bool,
) -> Result<(), RtlError> {
    if !TRACE {
        return Err(RtlError::NoTrace);
    }
    let name = path.display().to_string();
    let c = std::ffi::CString::new(name.clone()).map_err(|_| RtlError::Trace(name.clone()))?;
    if open(&c) {
        Ok(())
    } else {
        Err(RtlError::Trace(name))
    }
}

/// One of the core's arithmetic units, as `rt_math_top` lays them side by side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unit {
    /// `q16_dot` with one term, floor: the model's Q16.16 `*`.
    Mul,
    /// `q16_dot` with one term, rounded: `mul_rn`.
    MulRn,
    /// `q16_dot` with two terms: `dot2`.
    Dot2,
    /// `q16_dot` with three terms: `dot3`.
    Dot3,
    /// `q16_div`: `/`.
    Div,
    /// `q16_sqrt`: `sqrt`.
    Sqrt,
    /// `q16_rsqrt`: `rsqrt`.
    Rsqrt,
    /// `q16_to_f32`: `to_f64() as f32`, the planes' binary32 (the result is its bits).
    ToF32,
}

impl Unit {
    /// Every unit, in the order of [`Outputs::of`]'s slots.
    pub const ALL: [Unit; 8] = [
        Unit::Mul,
        Unit::MulRn,
        Unit::Dot2,
        Unit::Dot3,
        Unit::Div,
        Unit::Sqrt,
        Unit::Rsqrt,
        Unit::ToF32,
    ];

    /// Cycles from an operand set's clock edge to the edge after which its result is out,
    /// as each module's header states (a test holds the RTL to these).
    pub const fn latency(self) -> u64 {
        match self {
            Unit::Mul | Unit::MulRn | Unit::Dot2 | Unit::Dot3 => 4,
            Unit::ToF32 => 2,
            Unit::Div => 35,
            Unit::Sqrt => 27,
            Unit::Rsqrt => 79,
        }
    }
}

/// Operands of one clock: the words a0, a1, a2 and b0, b1, b2 (Q16.16 bits); see
/// `hw/rt-core/sim/rt_math_top.v` for which unit reads which.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Operands {
    /// a0, a1, a2.
    pub a: [i32; 3],
    /// b0, b1, b2.
    pub b: [i32; 3],
}

/// One unit's output after a clock edge.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Output {
    /// A result is out this cycle.
    pub valid: bool,
    /// The result's Q16.16 bits (meaningful while `valid`).
    pub y: i32,
    /// The result was clipped to the word's range.
    pub sat: bool,
}

/// Every unit's output after a clock edge.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Outputs([Output; 8]);

impl Outputs {
    /// The output of `unit`.
    pub fn of(&self, unit: Unit) -> Output {
        let i = Unit::ALL.iter().position(|u| *u == unit).unwrap_or(0);
        self.0[i]
    }
}

/// The Verilated `rt_math_top`: every arithmetic unit of the core on one set of operands
/// per clock, out of reset.
pub struct MathUnits {
    model: NonNull<ffi::RtMath>,
    cycle: u64,
}

// SAFETY: the model is owned by this value alone and only used through `&mut self`.
unsafe impl Send for MathUnits {}

impl MathUnits {
    /// A fresh model, reset for four cycles.
    pub fn new() -> Result<Self, RtlError> {
        Ok(Self {
            model: ffi::new()?,
            cycle: 0,
        })
    }

    /// One clock edge with `input` (None: no operand set this cycle); the outputs after
    /// it.
    pub fn cycle(&mut self, input: Option<Operands>) -> Outputs {
        self.edge(input, true)
    }

    /// One clock edge with the clock enable low: every unit holds, and `input`, offered
    /// with its valid high, must not be taken. Not counted in [`Self::cycles`].
    pub fn hold(&mut self, input: Operands) -> Outputs {
        self.edge(Some(input), false)
    }

    fn edge(&mut self, input: Option<Operands>, ce: bool) -> Outputs {
        let ops = input.unwrap_or_default();
        let word = |v: i32| v as u32;
        let inputs = [
            u32::from(input.is_some()),
            word(ops.a[0]),
            word(ops.a[1]),
            word(ops.a[2]),
            word(ops.b[0]),
            word(ops.b[1]),
            word(ops.b[2]),
            u32::from(ce),
        ];
        let raw = ffi::cycle(self.model, &inputs);
        if ce {
            self.cycle += 1;
        }
        let mut out = [Output::default(); 8];
        for (k, o) in out.iter_mut().enumerate() {
            *o = Output {
                valid: raw[3 * k] != 0,
                y: raw[3 * k + 1] as i32,
                sat: raw[3 * k + 2] != 0,
            };
        }
        Outputs(out)
    }

    /// Clock edges with the enable high since reset.
    pub fn cycles(&self) -> u64 {
        self.cycle
    }

    /// Starts a VCD of every signal at `path` from the next clock edge on, closed when the
    /// model is dropped (the replay of a failing case); only with the `trace` feature.
    pub fn trace_to(&mut self, path: &std::path::Path) -> Result<(), RtlError> {
        trace(path, |c| ffi::math_trace(self.model, c))
    }
}

impl Drop for MathUnits {
    fn drop(&mut self) {
        ffi::free(self.model);
    }
}

/// One (ray, object) pair for the intersection unit: the ray in the object's space.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Pair {
    /// The object's shape code (`protocol::scene::Shape::code`).
    pub shape: u8,
    /// The ray's origin in object space.
    pub o: [i32; 3],
    /// The ray's direction in object space (not normalised).
    pub d: [i32; 3],
    /// The smallest distance that counts (the scene's bias).
    pub tmin: i32,
    /// The largest distance that counts.
    pub tmax: i32,
    /// Carried to the result unchanged (the unit's `TB` = 16 bits).
    pub tag: u16,
}

/// The intersection unit's result for one pair.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Hit {
    /// A result is out this cycle.
    pub valid: bool,
    /// The ray meets the shape at a distance in [tmin, tmax].
    pub hit: bool,
    /// That distance (meaningful with `hit`).
    pub t: i32,
    /// The pair's shape is not built into this unit.
    pub unsupported: bool,
    /// The pair's tag.
    pub tag: u16,
}

/// The Verilated `rt_isect` with every shape built: one (ray, object) pair per clock.
pub struct Intersect {
    model: NonNull<ffi::RtIsect>,
    cycle: u64,
}

// SAFETY: the model is owned by this value alone and only used through `&mut self`.
unsafe impl Send for Intersect {}

impl Intersect {
    /// Clock edges from a pair going in to its result coming out (`rt_isect.v`).
    pub const LATENCY: u64 = 82;

    /// A fresh model, reset for four cycles.
    pub fn new() -> Result<Self, RtlError> {
        Ok(Self {
            model: ffi::isect_new()?,
            cycle: 0,
        })
    }

    /// One clock edge with `pair` (None: no pair this cycle); the output after it.
    pub fn cycle(&mut self, pair: Option<Pair>) -> Hit {
        self.edge(pair, true)
    }

    /// One clock edge with the clock enable low: the unit holds, and `pair`, offered with
    /// its valid high, must not be taken. Not counted in [`Self::cycles`].
    pub fn hold(&mut self, pair: Pair) -> Hit {
        self.edge(Some(pair), false)
    }

    fn edge(&mut self, pair: Option<Pair>, ce: bool) -> Hit {
        let p = pair.unwrap_or_default();
        let w = |v: i32| v as u32;
        let inputs = [
            u32::from(pair.is_some()),
            u32::from(p.shape),
            w(p.o[0]),
            w(p.o[1]),
            w(p.o[2]),
            w(p.d[0]),
            w(p.d[1]),
            w(p.d[2]),
            w(p.tmin),
            w(p.tmax),
            u32::from(p.tag),
            u32::from(ce),
        ];
        let raw = ffi::isect_cycle(self.model, &inputs);
        if ce {
            self.cycle += 1;
        }
        Hit {
            valid: raw[0] != 0,
            hit: raw[1] != 0,
            t: raw[2] as i32,
            unsupported: raw[3] != 0,
            tag: raw[4] as u16,
        }
    }

    /// Clock edges with the enable high since reset.
    pub fn cycles(&self) -> u64 {
        self.cycle
    }

    /// Starts a VCD of every signal at `path` from the next clock edge on, closed when the
    /// model is dropped (the replay of a failing case); only with the `trace` feature.
    pub fn trace_to(&mut self, path: &std::path::Path) -> Result<(), RtlError> {
        trace(path, |c| ffi::isect_trace(self.model, c))
    }
}

impl Drop for Intersect {
    fn drop(&mut self) {
        ffi::isect_free(self.model);
    }
}
