//! `mem_wait` toggling: the memory refuses requests on a seeded pseudo-random pattern or
//! in storms of long holds, switched on and off between commands. Pixels and fragment
//! counts must not change, and every unit's cycles equal the model's once the model is
//! told what the memory did (`Raster::set_mem_wait`: the units stall on a full fragment
//! FIFO).

use fitkit_rtl_sim::{Build, MemWait};
use protocol::raster::Cull;
use rand::Rng;

use crate::cases;
use crate::harness::{self, Pair};

/// One block under `wait`, with both units and `TRI_LANES` = `lanes`: 40 commands,
/// pixels and every counter exact.
fn stalls_are_counted(seed: u64, wait: MemWait, lanes: u32) {
    let build = Build::with_tri_lanes(lanes).unwrap_or_else(|e| panic!("{e}"));
    stalls_on(seed, wait, build);
}

/// As [`stalls_are_counted`] on any build: the commands it draws (lines, clears,
/// triangles), in the same mix.
fn stalls_on(seed: u64, wait: MemWait, build: Build) {
    let mut rng = cases::rng(seed);
    let bg = cases::color(&mut rng);
    let setup = harness::setup(64, 48, bg, Cull::None);
    let mut pair = Pair::with_build(setup, build);
    pair.rtl.borrow_mut().record_mem_wait();
    for n in 0..40 {
        let c = cases::color_except(&mut rng, bg);
        let cmd = match rng.gen_range(0..4) {
            0 if build.line_unit => cases::line(
                cases::point(&mut rng, 63, 47),
                cases::point(&mut rng, 63, 47),
                c,
            ),
            1 => protocol::raster::RasterCmd::Clear(c),
            _ => cases::triangle([(); 3].map(|_| cases::point(&mut rng, 63, 47)), c),
        };
        // Every third command runs with the memory always ready.
        let on = n % 3 != 2;
        pair.rtl
            .borrow_mut()
            .set_mem_wait(if on { wait } else { MemWait::Off });
        let case = format!("{wait:?} build {} (on: {on}) cmd {n}", build.name);
        let step = pair.step_stalled(&case, &cmd);
        assert_eq!(step.rtl, step.model, "{case}: {cmd:?}: counters");
    }
}

#[test]
fn stalls_are_counted_exactly() {
    for (k, duty) in [32u8, 128, 224].into_iter().enumerate() {
        let wait = MemWait::Random {
            seed: 0x6100 + k as u64,
            duty,
        };
        replay_case(&format!("mem-wait-duty-{duty}"), 0x61 + k as u64, wait, 1);
    }
    let storm = MemWait::Bursts {
        seed: 0x6200,
        max_high: 300,
        max_low: 60,
    };
    replay_case("mem-wait-storm", 0x62, storm, 1);
}

#[test]
fn stalls_are_counted_exactly_with_eight_lanes() {
    let wait = MemWait::Random {
        seed: 0x6300,
        duty: 160,
    };
    replay_case("mem-wait-lanes-8", 0x63, wait, 8);
    let storm = MemWait::Bursts {
        seed: 0x6400,
        max_high: 40,
        max_low: 40,
    };
    replay_case("mem-wait-storm-lanes-8", 0x64, storm, 8);
}

/// The small triangle unit of the triangle-only build (no queue between its walk and the
/// fragment stream) stalls as the model counts, in noise and in storms.
#[test]
fn stalls_are_counted_exactly_on_the_triangle_only_build() {
    let wait = MemWait::Random {
        seed: 0x6500,
        duty: 160,
    };
    crate::replay::with_waveform("mem-wait-tri", || stalls_on(0x65, wait, Build::TRI));
    let storm = MemWait::Bursts {
        seed: 0x6600,
        max_high: 40,
        max_low: 40,
    };
    crate::replay::with_waveform("mem-wait-storm-tri", || stalls_on(0x66, storm, Build::TRI));
}

fn replay_case(name: &str, seed: u64, wait: MemWait, lanes: u32) {
    crate::replay::with_waveform(name, || stalls_are_counted(seed, wait, lanes));
}
