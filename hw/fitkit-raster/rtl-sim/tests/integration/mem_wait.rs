//! `mem_wait` toggling: the memory refuses requests on a seeded pseudo-random pattern,
//! switched on and off between commands. Pixels and fragment counts must not change;
//! cycles only grow (the units stall on a full fragment FIFO).

use fitkit_rtl_sim::MemWait;
use protocol::raster::Cull;
use rand::Rng;

use crate::cases;
use crate::harness::{self, Pair};

#[test]
fn stalls_change_no_pixel() {
    let mut rng = cases::rng(0x61);
    for (k, duty) in [32u8, 128, 224].into_iter().enumerate() {
        let bg = cases::color(&mut rng);
        let setup = harness::setup(64, 48, bg, Cull::None);
        let wait = MemWait::Random {
            seed: 0x6100 + k as u64,
            duty,
        };
        let mut pair = Pair::with(setup, wait);
        for n in 0..40 {
            let c = cases::color_except(&mut rng, bg);
            let cmd = match rng.gen_range(0..4) {
                0 => cases::line(
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
            let case = format!("mem_wait duty {duty}/256 (on: {on}) cmd {n}");
            let step = pair.step(&case, &cmd, false);
            assert_eq!(step.rtl.fragments, step.model.fragments, "{case}: {cmd:?}");
            let (r, m) = (step.rtl, step.model);
            assert!(
                r.line >= m.line && r.triangle >= m.triangle && r.clear >= m.clear,
                "{case}: {cmd:?}: stalls made a unit faster: rtl {r:?} model {m:?}"
            );
        }
    }
}
