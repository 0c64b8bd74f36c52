//! A full input FIFO: far more than 512 records queued behind a long triangle, the
//! driver holding each packet until FIFO_FREE says it fits. Nothing is lost (no overrun,
//! pixels equal) and the occupancy reached the top.

use protocol::raster::Cull;

use crate::cases;
use crate::harness::{self, Pair};
use crate::tally::Tally;

#[test]
fn full_fifo_is_respected_through_fifo_free() {
    let mut t = Tally::default();
    let mut rng = cases::rng(0x51);
    let bg = cases::color(&mut rng);
    let mut pair = Pair::new(harness::setup(512, 512, bg, Cull::None));
    // The whole frame's bounding box: the triangle unit is busy for ~2^18 cycles while
    // the SPI queues a packet every ~700.
    let big = cases::triangle(
        [(0, 0), (511, 0), (0, 511)],
        cases::color_except(&mut rng, bg),
    );
    pair.send(&big, false);
    let mut records = 0;
    for _ in 0..320 {
        let a = cases::point(&mut rng, 511, 511);
        let cmd = cases::line(
            a,
            cases::near(&mut rng, a, 6),
            cases::color_except(&mut rng, bg),
        );
        let (_, r) = pair.pack(&cmd, false);
        records += r.len();
        pair.send(&cmd, false);
    }
    assert!(records > 512, "{records} records queued");
    let step = pair.settle("full FIFO");
    let s = pair.status();
    assert_eq!(s.fifo_max_pairs, 255, "the FIFO never filled: {s:?}");
    t.add(
        "full FIFO",
        || "a full-frame triangle and 320 lines".into(),
        &step,
    );
    t.assert_exact();
}
