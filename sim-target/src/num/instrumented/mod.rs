//! Number formats that watch the one they wrap, for the tools that measure the kernel
//! without changing it: [`Probe`] (`fpgfx stress`) checks every result against the exact
//! one and counts saturations, NaN and wrap-arounds; [`Counted`] (`fpgfx bench`) counts
//! the operations a frame executes, for the hardware cost model. Both hand the kernel bit
//! for bit the values of the bare format (`tests/integration/instrumented.rs` checks every
//! method in every format), so only the counts are new.
//!
//! # Why a wrapper cannot miss a method
//!
//! A wrapper is only as faithful as its forwarding: a [`Scalar`] method it did not
//! implement would be computed from its other operations instead of by the wrapped
//! format's own method, which is a different computation wherever a format specialises
//! the method (the fixed formats' `mul_rn`, `half_rn`, `floor_i64`, `int_to_i64`, …): equal
//! results would then rest on documented equivalences at best, and a new specialisation
//! would silently go unforwarded. So [`Scalar`] has **no default method bodies**: each
//! wrapper implements every method, each forwarding to the same method of the wrapped
//! format and adding only its check or count. A method the trait gains is a compile error
//! in both wrappers (and in every format) until it is forwarded; the formulas the formats
//! share are functions in [`super::composed`] that a format names, not defaults a type
//! inherits.
//!
//! # Counting
//!
//! The counters are thread-local and read through [`count`], a scope: it saves the
//! thread's counters, runs the closure from zero, returns what it counted and restores
//! the saved counters (also when the closure panics). Nested scopes (a stress case inside
//! a bench) and scopes on other threads therefore never mix their counts; an outer scope
//! does not see an inner one's. Only operations on the calling thread are counted: render
//! with [`crate::rt::render_instrumented`], which runs the rows on the calling thread, so
//! that one scope sees exactly one frame.
//!
//! [`Scalar`]: super::Scalar

mod counted;
mod probe;

pub use counted::Counted;
pub use probe::{BinOp, Exact, Probe};

use core::cell::Cell;

/// What the probes saw.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Seen {
    /// Results clipped to the format's range (fixed point), or finite operands that
    /// overflowed to ±∞ (floating point), division by zero included.
    pub saturations: u64,
    /// NaN results from finite operands (0/0, a NaN from nothing): always a bug.
    pub nans: u64,
    /// NaN results from an infinite operand (∞ − ∞, 0·∞): the aftermath of an overflow
    /// already counted as a saturation; reported, not failed (see docs/stress.md).
    pub overflow_nans: u64,
    /// Results that are neither the exact value nor the clipped one: a wrap-around.
    pub wraps: u64,
}

/// The operator kinds [`Counted`] tells apart: the ones the hardware cost model prices.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum OpKind {
    /// Addition or subtraction (negation is free: a sign flip).
    AddSub,
    /// Multiplication (also each product of `mul_rn`, `half_rn`, `dot2`, `dot3`).
    Mul,
    /// Division (also `recip`).
    Div,
    /// The √ core.
    Sqrt,
    /// The 1/√ core.
    Rsqrt,
    /// The arctan core.
    Atan,
    /// The arccos core.
    Acos,
    /// A floor (table indexing, `fract`).
    Floor,
}

impl OpKind {
    /// Every kind, in the order of [`Ops`]' counts.
    pub const ALL: [OpKind; 8] = [
        OpKind::AddSub,
        OpKind::Mul,
        OpKind::Div,
        OpKind::Sqrt,
        OpKind::Rsqrt,
        OpKind::Atan,
        OpKind::Acos,
        OpKind::Floor,
    ];
}

/// Operations counted by [`Counted`], per [`OpKind`] (index: `kind as usize`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Ops(pub [u64; 8]);

impl Ops {
    /// The count of one kind.
    pub fn get(&self, kind: OpKind) -> u64 {
        self.0[kind as usize]
    }
}

/// Everything one [`count`] scope saw.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counts {
    /// What [`Probe`]s saw.
    pub seen: Seen,
    /// What [`Counted`] counted.
    pub ops: Ops,
}

thread_local! {
    static SEEN: Cell<Seen> = const { Cell::new(Seen { saturations: 0, nans: 0, overflow_nans: 0, wraps: 0 }) };
    static OPS: [Cell<u64>; 8] = const { [const { Cell::new(0) }; 8] };
    static TRAP: Cell<bool> = const { Cell::new(false) };
}

/// Swaps this thread's counters for `c`; returns the ones it had.
fn replace(c: Counts) -> Counts {
    let seen = SEEN.with(|s| s.replace(c.seen));
    let mut ops = Ops::default();
    OPS.with(|o| {
        for ((cell, new), old) in o.iter().zip(c.ops.0).zip(&mut ops.0) {
            *old = cell.replace(new);
        }
    });
    Counts { seen, ops }
}

/// Runs `f` with this thread's counters at zero and returns its result with what it
/// counted; the counters are then what they were before (also if `f` panics), so that
/// scopes nest without mixing counts.
pub fn count<R>(f: impl FnOnce() -> R) -> (R, Counts) {
    struct Restore(Counts);
    impl Drop for Restore {
        fn drop(&mut self) {
            replace(self.0);
        }
    }
    let outer = Restore(replace(Counts::default()));
    let r = f();
    let inner = replace(Counts::default());
    drop(outer);
    (r, inner)
}

/// Makes the first NaN a [`Probe`] produces on this thread panic with a backtrace (a
/// debugging aid: `FPGFX_STRESS_TRAP=1 fpgfx stress --case K` says where a NaN came
/// from); returns the previous setting.
pub fn set_nan_trap(on: bool) -> bool {
    TRAP.with(|t| t.replace(on))
}

/// Records what a probe saw; panics at a new NaN if [`set_nan_trap`] asked for it.
#[inline]
fn note(f: impl FnOnce(&mut Seen)) {
    SEEN.with(|s| {
        let mut v = s.get();
        let before = v;
        f(&mut v);
        s.set(v);
        if v.nans > before.nans && TRAP.with(Cell::get) {
            panic!(
                "first NaN produced at\n{}",
                std::backtrace::Backtrace::force_capture()
            );
        }
    });
}

/// Adds `n` operations of `kind`.
#[inline(always)]
fn tally(kind: OpKind, n: u64) {
    OPS.with(|o| {
        let c = &o[kind as usize];
        c.set(c.get() + n);
    });
}
