//! A block that never finishes is a bounded-wait error, not a hang.

use fitkit_rtl_sim::RtlError;
use protocol::raster::{Cull, Rgb};

use crate::cases;
use crate::harness::{self, Pair};

fn busy_pair() -> Pair {
    let mut pair = Pair::new(harness::setup(512, 512, Rgb::new(0, 0, 0), Cull::None));
    pair.send(
        &cases::triangle([(0, 0), (511, 0), (0, 511)], Rgb::new(0, 0, 255)),
        false,
    );
    assert!(
        pair.rtl.borrow().busy(),
        "the triangle should keep the block busy"
    );
    pair
}

#[test]
fn a_gated_clock_times_out() {
    let pair = busy_pair();
    let mut rtl = pair.rtl.borrow_mut();
    rtl.set_clock_gated(true);
    let before = rtl.cycle();
    assert_eq!(
        rtl.wait_idle(10_000),
        Err(RtlError::Timeout {
            what: "busy low",
            bound: 10_000
        })
    );
    assert_eq!(
        rtl.cycle() - before,
        10_000,
        "the wait ran exactly its bound"
    );
    assert!(rtl.busy(), "no clock, no progress");
    // The clock back on, the same block finishes.
    rtl.set_clock_gated(false);
    rtl.wait_idle(harness::WAIT_BOUND)
        .expect("finishes with a clock");
}

#[test]
fn a_zero_bound_fails_at_once() {
    let pair = busy_pair();
    let mut rtl = pair.rtl.borrow_mut();
    let before = rtl.cycle();
    assert!(matches!(
        rtl.wait_idle(0),
        Err(RtlError::Timeout { bound: 0, .. })
    ));
    assert_eq!(rtl.cycle(), before);
}
