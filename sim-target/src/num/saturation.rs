//! The device's saturation counter: how many results of a frame a fixed-point format
//! clipped to its range ([`crate::num`] explains why they clip), for
//! `DeviceCounters::saturations` and `fpgfx render --stats`.
//!
//! Unlike [`super::instrumented::Probe`], which compares every result with the exact one
//! (`fpgfx stress`, many times slower), this counts in the bare formats as users run them,
//! so it must cost next to nothing. Every clip of the products, sums, dot products and
//! negations already leaves the hot path for a cold out-of-line function
//! (`narrow`/`clip`, `sat_add`, …): the count is one thread-local increment there, so a
//! frame that does not saturate executes no extra instruction on them. The divider, the
//! 1/√ core and `from_f64` clip through saturating casts instead, and gain one predicted
//! compare each. What counts is what `Probe` calls a saturation in the fixed formats: a
//! result beyond the range (division by zero and 1/√ of x ≤ 0 included, whose defined
//! answers are the format's limits), plus a 1/√ result beyond the range (Q8.24 only).
//!
//! Floats count nothing: they do not saturate. An overflow becomes ±∞ and propagates
//! visibly; spotting it would need a test after every float operation of the hot loop,
//! which is what `Probe` does.
//!
//! # Threads
//!
//! The counter is a thread-local running total, read through [`count`]: the difference
//! over a closure on the calling thread, so scopes nest (an outer one includes an inner
//! one's). The renderer counts each row in its own scope (a row runs on one rayon worker)
//! and the frame's set-up on the calling thread, and adds them: the frame's count, whatever
//! the thread pool did.

use core::cell::Cell;

thread_local! {
    static SATURATIONS: Cell<u64> = const { Cell::new(0) };
}

/// Counts one clipped result. Out of line and cold, so that the callers' hot paths keep
/// their layout: only the clipping branch, already cold, calls it.
#[cold]
#[inline(never)]
pub(crate) fn saturated() {
    SATURATIONS.with(|c| c.set(c.get().wrapping_add(1)));
}

/// This thread's running total, for a caller whose region is not one closure (take the
/// difference of two readings, wrapping).
pub(crate) fn total() -> u64 {
    SATURATIONS.with(Cell::get)
}

/// Runs `f` and returns its result with the results it saw clipped on this thread.
pub(crate) fn count<R>(f: impl FnOnce() -> R) -> (R, u64) {
    let before = SATURATIONS.with(Cell::get);
    let r = f();
    (r, SATURATIONS.with(Cell::get).wrapping_sub(before))
}
