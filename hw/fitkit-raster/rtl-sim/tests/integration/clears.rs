//! Clears: stand-alone clear packets back to back, and CB on a line or a triangle (the
//! frame cleared to the set-up's background first, seed 000).

use protocol::fitkit_spi as wire;
use protocol::raster::{Cull, RasterCmd, Rgb};
use rand::Rng;

use crate::cases;
use crate::draw::{self, extent, Class};
use crate::harness::{self, Counters, Pair};
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

/// The set-up's clear: W · H clear cycles, and it completes at cycle W · H + 1 (one
/// cycle to latch the frame), on the RTL and in the model alike; it is no packet.
#[test]
fn the_set_up_clear_is_counted() {
    for (w, h) in [(1, 1), (7, 3), (320, 240), (512, 512)] {
        let mut pair = Pair::new(harness::setup(w, h, Rgb::new(0, 0, 85), Cull::None));
        let s = pair.status();
        let area = u32::from(w) * u32::from(h);
        assert_eq!(
            (s.clear_cycles, s.end_cycle, s.packets, s.fragments),
            (area, area + 1, 0, 0),
            "{w}x{h}: {s:?}"
        );
        assert_ne!(s.flags & wire::FLAG_SETUP_DONE, 0);
        let model = pair.model_counters();
        assert_eq!(
            model,
            Counters {
                clear: u64::from(area),
                ..Counters::default()
            },
            "the model's set-up"
        );
        let end = pair.model.raster().map(|r| r.stats().end_cycle);
        assert_eq!(end, Some(u64::from(area) + 1), "the model's set-up end");
        pair.assert_frames_equal(&format!("{w}x{h} set-up"));
    }
}
