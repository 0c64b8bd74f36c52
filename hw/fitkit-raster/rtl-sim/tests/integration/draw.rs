//! Runs a class of generated commands through both sides: batches of commands on one
//! frame each, every command's pixels and counters compared.

use protocol::raster::{Cull, RasterCmd, RasterSetup};
use rand::rngs::SmallRng;
use rand::Rng;

use fitkit_rtl_sim::Build;

use crate::cases;
use crate::harness::{self, Pair};
use crate::tally::Tally;

/// A class of cases: how its frames and commands are made.
pub struct Class<'a> {
    pub name: &'static str,
    pub seed: u64,
    /// Frames, each set up afresh on a new block.
    pub frames: usize,
    /// Commands per frame.
    pub per_frame: usize,
    pub frame: &'a dyn Fn(&mut SmallRng) -> RasterSetup,
    /// A command for the frame, and its CB bit.
    pub cmd: &'a dyn Fn(&mut SmallRng, &RasterSetup) -> (RasterCmd, bool),
}

impl Class<'_> {
    /// Runs every case, recording counter differences in `tally` (pixels are asserted
    /// as they come).
    pub fn run(&self, tally: &mut Tally) {
        self.run_on(tally, Build::DEFAULT);
    }

    /// As [`Class::run`] on one Verilated build of the block.
    /// A frame whose pixels differ is replayed into a waveform the failure names
    /// (`replay`); counter differences are collected in `tally` and reported together.
    pub fn run_on(&self, tally: &mut Tally, build: Build) {
        let mut rng = cases::rng(self.seed);
        for f in 0..self.frames {
            // each frame from its own generator state, so a replay draws the same frame
            let start = rng.clone();
            let steps = std::cell::RefCell::new(Vec::new());
            let after = std::cell::RefCell::new(None);
            let name = format!(
                "{}-seed{}-frame{f}-{}",
                self.name.replace(' ', "-"),
                self.seed,
                build.name
            );
            crate::replay::with_waveform(&name, || {
                let mut rng = start.clone();
                steps.borrow_mut().clear();
                let setup = (self.frame)(&mut rng);
                let mut pair = Pair::with_build(setup, build);
                for k in 0..self.per_frame {
                    let (cmd, cb) = (self.cmd)(&mut rng, &setup);
                    let case = format!("{} seed {} frame {f} cmd {k}", self.name, self.seed);
                    let step = pair.step(&case, &cmd, cb);
                    steps
                        .borrow_mut()
                        .push((format!("{case}: {setup:?} {cmd:?} cb={cb}"), step));
                }
                // the generator as the frame left it, for the next frame
                *after.borrow_mut() = Some(rng);
            });
            for (case, step) in steps.into_inner() {
                tally.add(self.name, || case, &step);
            }
            rng = after.into_inner().expect("the frame ran");
        }
    }
}

/// Mostly small frames (a set-up clears width × height cycles), a few full ones.
pub fn small_frame(rng: &mut SmallRng) -> RasterSetup {
    let (w, h) = if rng.gen_ratio(1, 10) {
        (512, 512)
    } else {
        (rng.gen_range(1..=96), rng.gen_range(1..=96))
    };
    let bg = cases::color(rng);
    harness::setup(w, h, bg, Cull::None)
}

/// The whole 512 × 512 frame the 9-bit coordinates reach.
pub fn full_frame(rng: &mut SmallRng) -> RasterSetup {
    harness::setup(512, 512, cases::color(rng), Cull::None)
}

/// A QVGA frame (the gallery's), with coordinates reaching past it to 511.
pub fn qvga_frame(rng: &mut SmallRng) -> RasterSetup {
    harness::setup(320, 240, cases::color(rng), Cull::None)
}

/// The largest coordinates inside `s`'s frame.
pub fn extent(s: &RasterSetup) -> (i32, i32) {
    (i32::from(s.width) - 1, i32::from(s.height) - 1)
}
