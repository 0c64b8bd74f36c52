//! Flat triangles: random, tiny, slivers, edges through pixel centres, at the viewport
//! limits, partly outside the frame, and culled by winding.

use fitkit_rtl_sim::Build;
use protocol::raster::Cull;
use rand::Rng;

use crate::cases::{self, MAX_COORD};
use crate::draw::{self, extent, Class};
use crate::harness;
use crate::tally::Tally;

#[test]
fn triangles_match_the_model() {
    every_class(Build::DEFAULT);
}

/// The same triangles on the block testing eight pixels of a row per cycle: pixels
/// equal, cycles as the model counts a step (max(1, covered pixels)).
#[test]
fn triangles_match_the_model_with_eight_lanes() {
    every_class(Build::TRI_LANES_8);
}

/// The same triangles on the triangle-only build for the seed's XC3S50: the unit is
/// the same, so pixels and cycles are too.
#[test]
fn triangles_match_the_model_on_the_triangle_only_build() {
    every_class(Build::TRI);
}

/// Every class of triangles through one build of the block.
fn every_class(build: Build) {
    let mut t = Tally::default();
    Class {
        name: "triangle random",
        seed: 0x21,
        frames: 25,
        per_frame: 20,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let v = [(); 3].map(|_| cases::point(rng, mx, my));
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "triangle tiny (<= 2 px)",
        seed: 0x22,
        frames: 8,
        per_frame: 25,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let a = cases::point(rng, mx, my);
            let v = [a, cases::near(rng, a, 2), cases::near(rng, a, 2)];
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "triangle sliver",
        seed: 0x23,
        frames: 8,
        per_frame: 25,
        frame: &draw::small_frame,
        cmd: &|rng, s| {
            let (mx, my) = extent(s);
            let v = cases::sliver(rng, mx, my);
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "triangle edges through pixel centres",
        seed: 0x24,
        frames: 8,
        per_frame: 25,
        frame: &|rng| harness::setup(96, 96, cases::color(rng), Cull::None),
        cmd: &|rng, s| {
            let v = cases::through_centres(rng, 95);
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "triangle viewport limits 0 and 511",
        seed: 0x25,
        frames: 4,
        per_frame: 15,
        frame: &draw::full_frame,
        cmd: &|rng, s| {
            let mut c = || cases::limit_coord(rng);
            let v = [(c(), c()), (c(), c()), (c(), c())];
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "triangle partly outside 320x240",
        seed: 0x26,
        frames: 8,
        per_frame: 20,
        frame: &draw::qvga_frame,
        cmd: &|rng, s| {
            let v = [
                cases::point(rng, MAX_COORD, MAX_COORD),
                cases::point(rng, 319, 239),
                cases::point(rng, MAX_COORD, MAX_COORD),
            ];
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    Class {
        name: "triangle culled by winding",
        seed: 0x27,
        frames: 12,
        per_frame: 10,
        frame: &|rng| {
            let cull = [Cull::Clockwise, Cull::CounterClockwise][rng.gen_range(0..2)];
            harness::setup(64, 64, cases::color(rng), cull)
        },
        cmd: &|rng, s| {
            let v = [(); 3].map(|_| cases::point(rng, 63, 63));
            (
                cases::triangle(v, cases::color_except(rng, s.background)),
                false,
            )
        },
    }
    .run_on(&mut t, build);
    assert!(t.cases() >= 1_300, "{} triangle cases", t.cases());
    t.assert_exact();
}
