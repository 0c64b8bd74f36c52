//! Clears: stand-alone clear packets back to back, and CB on a line or a triangle (the
//! frame cleared to the set-up's background first, seed 000).

use protocol::frame::RasterCmd;
use rand::Rng;

use crate::cases;
use crate::draw::{self, extent, Class};
use crate::tally::Tally;

#[test]
fn back_to_back_clears_and_cb() {
    let mut t = Tally::default();
    Class {
        name: "clear back to back",
        seed: 0x41,
        frames: 4,
        per_frame: 6,
        frame: &draw::small_frame,
        cmd: &|rng, _| (RasterCmd::Clear(cases::color(rng)), true),
    }
    .run(&mut t);
    Class {
        name: "CB on a line or triangle",
        seed: 0x42,
        frames: 4,
        per_frame: 8,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let c = cases::color_except(rng, s.background);
            let cmd = match rng.gen_range(0..3) {
                0 => cases::line(cases::point(rng, mx, my), cases::point(rng, mx, my), c),
                1 => cases::triangle([(); 3].map(|_| cases::point(rng, mx, my)), c),
                // A clear to another colour first, so CB's clear is visible.
                _ => RasterCmd::Clear(cases::color_except(rng, s.background)),
            };
            (cmd, true)
        },
    }
    .run(&mut t);
    t.assert_exact();
}
