//! The FITkit raster block's Verilog (`hw/fitkit-raster/rtl/`), Verilated, as a Rust
//! library: what the differential tests drive to hold the RTL to the golden model
//! (`sim-target`), and what a driver written against `embedded-hal` can talk to before
//! there is a board.
//!
//! [`Rtl`] owns the model and is clocked one cycle at a time; its inputs are the pins of
//! docs/rtl.md's `fitkit_raster` plus the memory's `mem_wait` (held low, or a seeded
//! pseudo-random stall pattern, [`MemWait`]), and its framebuffer RAM is readable
//! directly ([`Rtl::pixel`], [`Rtl::frame`]) without costing the block a cycle.
//! [`RtlSpi`] is an `embedded_hal::spi::SpiDevice` that bit-bangs mode 0 on those pins,
//! and [`RtlDelay`] an `embedded_hal::delay::DelayNs` that lets the clock run, so a
//! driver's "wait while the FPGA works" advances the RTL. Both share the model through
//! an `Rc<RefCell<Rtl>>`: the Verilated model is single-threaded.
//!
//! Every wait has a cycle bound ([`Rtl::wait_until`]), so a stuck block is an error, not a
//! hang. Without verilator at build time the crate still builds and [`Rtl::new`] says
//! how to get it (docs/rtl.md, "Simulating the RTL from Rust").

#![warn(missing_docs)]

mod build_table;
mod ffi;
mod spi;

pub use build_table::Build;

pub use spi::{RtlDelay, RtlSpi, SpiConfig, SpiError, MIN_CS_HIGH, MIN_HALF_PERIOD};

use std::cell::RefCell;
use std::ptr::NonNull;
use std::rc::Rc;

/// Bytes of the simulated framebuffer RAM: 2^18 RGB332 pixels.
pub const RAM_BYTES: usize = 1 << 18;
/// Pixels per RAM row: the block addresses pixel `(x, y)` at `y · 512 + x`.
pub const RAM_STRIDE: u32 = 512;
/// Clock cycles `rst` is held by [`Rtl::reset`]: the block's reset is synchronous, and a
/// few cycles also flush the SPI synchronisers.
pub const RESET_CYCLES: u64 = 4;

impl Build {
    /// The build with `TRI_LANES` = `lanes` and both units, if one is Verilated.
    pub fn with_tri_lanes(lanes: u32) -> Result<Build, RtlError> {
        Build::ALL
            .into_iter()
            .find(|b| b.tri_lanes == lanes && b.line_unit && b.tri_unit && !b.tri_small)
            .ok_or(RtlError::TriLanes(lanes))
    }

    /// The shim's index of this build.
    fn index(self) -> u32 {
        Build::ALL
            .iter()
            .position(|b| *b == self)
            .map_or(u32::MAX, |i| i as u32)
    }
}

/// The model shared between the SPI device, the delay and the test that owns them.
pub type SharedRtl = Rc<RefCell<Rtl>>;

/// Why the model cannot be used or a wait failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RtlError {
    /// The crate was built where verilator could not be found, so it holds no model.
    #[error("verilator not found when fitkit-rtl-sim was built: run `cargo xtask setup` (installs verilator from Debian), then rebuild")]
    NoVerilator,
    /// The crate was built before `hw/fitkit-raster/sim/` had the `fitkit_sim_top` module.
    #[error(
        "hw/fitkit-raster/sim/ had no `fitkit_sim_top` module when fitkit-rtl-sim was built: the RTL is not there yet"
    )]
    NoRtl,
    /// The Verilated model has no single public 2^18-byte array to read the framebuffer
    /// from (docs/rtl.md: the sim RAM is `/*verilator public*/`).
    #[error("the Verilated fitkit_sim_top has no single public 2^18 x 8-bit RAM array")]
    NoRam,
    /// Allocating the model failed.
    #[error("cannot construct the Verilated model")]
    Construct,
    /// A condition did not come true within its cycle bound.
    #[error("{what} not reached within {bound} clock cycles")]
    Timeout {
        /// What was waited for.
        what: &'static str,
        /// The bound, in cycles.
        bound: u64,
    },
    /// No build of the block with this `TRI_LANES` and both units is Verilated
    /// ([`Build::ALL`]).
    #[error("no Verilated build with TRI_LANES = {0} (built: 1 and 8)")]
    TriLanes(u32),
    /// A waveform could not be started at the path.
    #[error("cannot write a waveform to {0} (a path with a NUL, a folder that cannot be written, or one already open)")]
    Trace(String),
    /// A pixel outside the RAM's 512 × 512 grid.
    #[error("pixel ({x}, {y}) outside the 512 x 512 framebuffer RAM")]
    Outside {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
    },
}

/// What the memory's `mem_wait` input does, cycle by cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MemWait {
    /// Never asserted: the memory takes a request every cycle.
    #[default]
    Off,
    /// Asserted in about `duty` of every 256 cycles, from a xorshift generator seeded with
    /// `seed`, so a failing case replays exactly.
    Random {
        /// Generator seed (0 is replaced by a fixed non-zero value).
        seed: u64,
        /// Cycles with `mem_wait` high per 256, on average.
        duty: u8,
    },
    /// Storms: `mem_wait` held high for a random run of 1 to `max_high` cycles, then low
    /// for 1 to `max_low`, from a seeded generator. Long holds fill the fragment FIFO and
    /// stall every unit behind it, which per-cycle noise never does.
    Bursts {
        /// Generator seed (0 is replaced by a fixed non-zero value).
        seed: u64,
        /// Longest run with `mem_wait` high.
        max_high: u32,
        /// Longest run with `mem_wait` low.
        max_low: u32,
    },
}

/// The Verilated `fitkit_sim_top`: the block, its framebuffer RAM and the clock.
pub struct Rtl {
    model: NonNull<ffi::FitkitRtl>,
    inputs: u32,
    outputs: u32,
    cycle: u64,
    mem_wait: MemWait,
    rng: u64,
    /// Cycles left in the current `MemWait::Bursts` run, and whether it is high.
    burst: (u32, bool),
    /// Cycles `[from, to)` during which `rst` is driven high by [`Rtl::pulse_reset_at`].
    reset_window: Option<(u64, u64)>,
    /// `mem_wait` of every cycle since [`Rtl::record_mem_wait`], and the cycle it started.
    wait_log: Option<(u64, Vec<bool>)>,
}

impl std::fmt::Debug for Rtl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Rtl")
            .field("cycle", &self.cycle)
            .field("inputs", &self.inputs)
            .field("outputs", &self.outputs)
            .field("mem_wait", &self.mem_wait)
            .finish()
    }
}

impl Rtl {
    /// A model after [`Rtl::reset`], with `spi_cs_n` high and `mem_wait` off.
    pub fn new() -> Result<Self, RtlError> {
        Self::with_x_seed(0)
    }

    /// As [`Rtl::new`], every register and memory (the framebuffer RAM too) starting at
    /// random values drawn from `seed` instead of 0 (the model is Verilated with
    /// `--x-initial unique`): what a reset leaves undefined then differs from seed to
    /// seed, so equal results across seeds show no X reaches an output.
    pub fn with_x_seed(seed: u64) -> Result<Self, RtlError> {
        Self::build(seed, Build::DEFAULT)
    }

    /// As [`Rtl::new`], the block built with `TRI_LANES` = `lanes` and both units.
    pub fn with_tri_lanes(lanes: u32) -> Result<Self, RtlError> {
        Self::build(0, Build::with_tri_lanes(lanes)?)
    }

    /// As [`Rtl::new`], one of the Verilated builds ([`Build::ALL`]).
    pub fn with_build(build: Build) -> Result<Self, RtlError> {
        Self::build(0, build)
    }

    fn build(seed: u64, build: Build) -> Result<Self, RtlError> {
        let model = ffi::new(seed, build.index())?;
        let mut rtl = Self {
            model,
            inputs: ffi::IN_CS_N,
            outputs: 0,
            cycle: 0,
            mem_wait: MemWait::Off,
            rng: 0,
            burst: (0, false),
            reset_window: None,
            wait_log: None,
        };
        rtl.reset();
        Ok(rtl)
    }

    /// Starts a VCD of every signal at `path` from the next cycle on (a failing case
    /// replays into one, so the message can name its waveform).
    pub fn trace_to(&mut self, path: &std::path::Path) -> Result<(), RtlError> {
        let name = path.to_string_lossy().into_owned();
        let c = std::ffi::CString::new(name.clone()).map_err(|_| RtlError::Trace(name.clone()))?;
        if ffi::trace(self.model, &c) {
            Ok(())
        } else {
            Err(RtlError::Trace(name))
        }
    }

    /// Records `mem_wait` on every cycle from now on (what the memory did, for a model that
    /// counts the stalls it caused).
    pub fn record_mem_wait(&mut self) {
        self.wait_log = Some((self.cycle, Vec::new()));
    }

    /// `mem_wait` on the cycles `[from, to)` as recorded (cycles outside the recording
    /// read as low).
    pub fn mem_wait_between(&self, from: u64, to: u64) -> Vec<bool> {
        (from..to)
            .map(|c| {
                self.wait_log.as_ref().is_some_and(|(start, log)| {
                    c.checked_sub(*start)
                        .and_then(|i| log.get(usize::try_from(i).ok()?))
                        == Some(&true)
                })
            })
            .collect()
    }

    /// Drives `rst` high for `cycles` cycles from cycle `at` on, whatever the SPI master
    /// is doing at the time: a reset in the middle of a transaction, a drawing or a
    /// read-back, as a board's reset button or a brown-out gives one.
    pub fn pulse_reset_at(&mut self, at: u64, cycles: u64) {
        self.reset_window = Some((at, at + cycles));
    }

    /// Whether the pulse of [`Rtl::pulse_reset_at`] is over (false while none is set).
    pub fn reset_pulsed(&self) -> bool {
        self.reset_window.is_some_and(|(_, to)| self.cycle >= to)
    }

    /// The model behind a shared handle, for [`RtlSpi`] and [`RtlDelay`].
    pub fn shared() -> Result<SharedRtl, RtlError> {
        Self::new().map(|r| Rc::new(RefCell::new(r)))
    }

    /// Holds `rst` for [`RESET_CYCLES`] cycles with `spi_cs_n` high, then releases it:
    /// FIFOs, units, counters and errors clear (the RAM keeps its contents).
    pub fn reset(&mut self) {
        self.set(ffi::IN_CS_N, true);
        self.set(ffi::IN_SCK, false);
        self.set(ffi::IN_RST, true);
        self.run(RESET_CYCLES);
        self.set(ffi::IN_RST, false);
        self.tick();
    }

    /// One clock cycle: the inputs as last set (and this cycle's `mem_wait`) are applied,
    /// then a rising and a falling edge.
    pub fn tick(&mut self) {
        let wait = self.next_mem_wait();
        let mut inputs =
            (self.inputs & !ffi::IN_MEM_WAIT) | if wait { ffi::IN_MEM_WAIT } else { 0 };
        if self
            .reset_window
            .is_some_and(|(from, to)| (from..to).contains(&self.cycle))
        {
            inputs |= ffi::IN_RST;
        }
        if let Some((_, log)) = &mut self.wait_log {
            log.push(wait);
        }
        self.outputs = ffi::tick(self.model, inputs);
        self.cycle += 1;
    }

    /// `n` clock cycles.
    pub fn run(&mut self, n: u64) {
        for _ in 0..n {
            self.tick();
        }
    }

    /// Clock cycles since construction (a gated clock's included: they are time).
    pub fn cycle(&self) -> u64 {
        self.cycle
    }

    /// Drives `spi_sck` from the next cycle on.
    pub fn set_sck(&mut self, high: bool) {
        self.set(ffi::IN_SCK, high);
    }

    /// Drives `spi_cs_n` from the next cycle on.
    pub fn set_cs_n(&mut self, high: bool) {
        self.set(ffi::IN_CS_N, high);
    }

    /// Drives `spi_mosi` from the next cycle on.
    pub fn set_mosi(&mut self, high: bool) {
        self.set(ffi::IN_MOSI, high);
    }

    /// `spi_miso` after the last cycle.
    pub fn miso(&self) -> bool {
        self.outputs & ffi::OUT_MISO != 0
    }

    /// `busy` after the last cycle: a packet queued or executing, or fragments pending.
    pub fn busy(&self) -> bool {
        self.outputs & ffi::OUT_BUSY != 0
    }

    /// `fifo_free` after the last cycle: the input FIFO can take one more whole packet.
    pub fn fifo_free(&self) -> bool {
        self.outputs & ffi::OUT_FIFO_FREE != 0
    }

    /// Sets what `mem_wait` does from the next cycle on.
    pub fn set_mem_wait(&mut self, mode: MemWait) {
        self.mem_wait = mode;
        self.burst = (0, false);
        if let MemWait::Random { seed, .. } | MemWait::Bursts { seed, .. } = mode {
            self.rng = if seed == 0 {
                0x9E37_79B9_7F4A_7C15
            } else {
                seed
            };
        }
    }

    /// Stops (or restarts) the clock: while gated, cycles pass and inputs are applied but
    /// the block sees no edge, as a block whose clock has failed. For testing that every
    /// wait is bounded.
    pub fn set_clock_gated(&mut self, gated: bool) {
        self.set(ffi::IN_CLOCK_GATED, gated);
    }

    /// Ticks until `done` holds, at most `bound` cycles; returns the cycles it took.
    /// `done` is checked before the first cycle, so a condition that already holds costs
    /// none, and a bound of 0 fails at once on one that does not.
    pub fn wait_until(
        &mut self,
        what: &'static str,
        bound: u64,
        done: impl Fn(&Self) -> bool,
    ) -> Result<u64, RtlError> {
        for n in 0..=bound {
            if done(self) {
                return Ok(n);
            }
            if n < bound {
                self.tick();
            }
        }
        Err(RtlError::Timeout { what, bound })
    }

    /// Ticks until `busy` is low, at most `bound` cycles.
    pub fn wait_idle(&mut self, bound: u64) -> Result<u64, RtlError> {
        self.wait_until("busy low", bound, |r| !r.busy())
    }

    /// The RGB332 pixel at `(x, y)` of the RAM, read without a clock cycle.
    pub fn pixel(&self, x: u32, y: u32) -> Result<u8, RtlError> {
        if x >= RAM_STRIDE || y >= RAM_STRIDE {
            return Err(RtlError::Outside { x, y });
        }
        Ok(self.ram()[(y * RAM_STRIDE + x) as usize])
    }

    /// The top-left `width × height` pixels of the RAM, row by row (RGB332).
    pub fn frame(&self, width: u32, height: u32) -> Result<Vec<u8>, RtlError> {
        if width > RAM_STRIDE || height > RAM_STRIDE {
            return Err(RtlError::Outside {
                x: width.saturating_sub(1),
                y: height.saturating_sub(1),
            });
        }
        let ram = self.ram();
        let mut out = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            let row = (y * RAM_STRIDE) as usize;
            out.extend_from_slice(&ram[row..row + width as usize]);
        }
        Ok(out)
    }

    /// The whole RAM, `y · 512 + x`.
    pub fn ram(&self) -> &[u8] {
        ffi::ram(self.model)
    }

    fn set(&mut self, bit: u32, high: bool) {
        if high {
            self.inputs |= bit;
        } else {
            self.inputs &= !bit;
        }
    }

    /// The next draw of the xorshift64 generator: cheap, and the same sequence on every
    /// platform.
    fn draw(&mut self) -> u64 {
        let mut x = self.rng;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.rng = x;
        x
    }

    fn next_mem_wait(&mut self) -> bool {
        match self.mem_wait {
            MemWait::Off => false,
            MemWait::Random { duty, .. } => ((self.draw() >> 32) as u8) < duty,
            MemWait::Bursts {
                max_high, max_low, ..
            } => {
                if self.burst.0 == 0 {
                    let high = !self.burst.1;
                    let max = u64::from(if high { max_high } else { max_low }.max(1));
                    self.burst = ((self.draw() % max) as u32 + 1, high);
                }
                self.burst.0 -= 1;
                self.burst.1
            }
        }
    }
}

impl Drop for Rtl {
    fn drop(&mut self) {
        ffi::free(self.model);
    }
}
