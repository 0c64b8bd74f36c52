//! Lines: random, tiny, at the viewport limits, partly outside the frame, axis-aligned
//! and diagonal.

use fitkit_rtl_sim::Build;
use rand::Rng;

use crate::cases::{self, MAX_COORD};
use crate::draw::{self, extent, Class};
use crate::tally::Tally;

#[test]
fn lines_match_the_model() {
    every_class(Build::DEFAULT);
}

/// The same lines on the line-only build for the seed's XC3S50: the unit is the same,
/// so pixels and cycles are too.
#[test]
fn lines_match_the_model_on_the_line_only_build() {
    every_class(Build::LINE);
}

/// Every class of lines through one build of the block.
fn every_class(build: Build) {
    let mut t = Tally::default();
    Class {
        name: "line random",
        seed: 0x11,
        frames: 30,
        per_frame: 15,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let c = cases::color_except(rng, s.background);
            (
                cases::line(cases::point(rng, mx, my), cases::point(rng, mx, my), c),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "line tiny (<= 2 px)",
        seed: 0x12,
        frames: 10,
        per_frame: 20,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let a = cases::point(rng, mx, my);
            let b = cases::near(rng, a, 1);
            (
                cases::line(a, b, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "line viewport limits 0 and 511",
        seed: 0x13,
        frames: 4,
        per_frame: 20,
        frame: &draw::full_frame,
        cmd: &|rng, s| {
            let mut c = || cases::limit_coord(rng);
            let (a, b) = ((c(), c()), (c(), c()));
            (
                cases::line(a, b, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "line partly outside 320x240",
        seed: 0x14,
        frames: 8,
        per_frame: 20,
        frame: &draw::qvga_frame,
        cmd: &|rng, s| {
            let a = cases::point(rng, MAX_COORD, MAX_COORD);
            let b = cases::point(rng, 319, 239);
            (
                cases::line(a, b, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "line axis and diagonal",
        seed: 0x15,
        frames: 8,
        per_frame: 15,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let a = cases::point(rng, mx, my);
            let n = rng.gen_range(0..=mx.max(my));
            let b = match rng.gen_range(0..4) {
                0 => (a.0 + n, a.1),
                1 => (a.0, a.1 - n),
                2 => (a.0 + n, a.1 + n),
                _ => (a.0 - n, a.1 + n),
            };
            let b = (b.0.clamp(0, MAX_COORD), b.1.clamp(0, MAX_COORD));
            (
                cases::line(a, b, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    assert!(t.cases() >= 1_000, "{} line cases", t.cases());
    t.assert_exact();
}
