//! One case = the same commands into the Verilated block (over SPI, framed as docs/rtl.md
//! says) and into the golden model (`Device` with the FITkit layout), then their
//! framebuffers and counters side by side.

use embedded_hal::spi::{Operation, SpiDevice};
use fitkit_rtl_sim::{Build, MemWait, Rtl, RtlSpi, SharedRtl, SpiConfig};
use protocol::bus::{self, PackOptions, FITKIT};
use protocol::fitkit_spi::{self as wire, Status};
use protocol::raster::{Cull, RasterCmd, RasterSetup, Rgb, Traversal};
use sim_target::Device;

/// Cycle bound of every wait on the RTL: above the longest case (a 512 × 512 bounding
/// box is 262 144 cycles, a full FIFO of them far more, but the cases queue few).
pub const WAIT_BOUND: u64 = 20_000_000;

/// Cycles from the CS_n rise that ends a packet to its unit's first cycle, when the
/// block was idle: the synchroniser and the decoder's commit, the FIFO's read and the
/// executor's dispatch take 9 for a one-record packet (a clear); a two-record packet
/// (a line, a triangle) reads its second record and passes the executor's DRAW state, 2
/// more (docs/rtl.md).
pub fn unit_start(cmd: &RasterCmd) -> u64 {
    match cmd {
        RasterCmd::Clear(_) => 9,
        _ => 11,
    }
}

/// The model's traversal whose cycle accounting the RTL's triangle unit follows.
pub const MODEL_TRAVERSAL: Traversal = Traversal::BoundingBox;

/// The RTL with its SPI master, and the model, fed the same commands.
pub struct Pair {
    pub rtl: SharedRtl,
    pub spi: RtlSpi,
    pub model: Device,
    pub setup: RasterSetup,
    /// The triangle unit's pixel tests per cycle on both sides (the RTL's `TRI_LANES`),
    /// and whether it is the small unit (`TRI_SMALL`).
    tri_lanes: u32,
    tri_small: bool,
    /// Both sides' counters after the last [`Pair::step`] (or the set-up).
    last: (Counters, Counters),
}

/// A set-up for a `width × height` frame, FITkit style: whole pixels, no AA.
pub fn setup(width: u16, height: u16, background: Rgb, cull: Cull) -> RasterSetup {
    RasterSetup {
        width,
        height,
        subpixel_bits: 0,
        background,
        aa: Default::default(),
        cull,
        traversal: MODEL_TRAVERSAL,
    }
}

/// The model and the RTL must see one colour: FITkit colours are RGB332.
pub fn rgb332(c: Rgb) -> u8 {
    bus::rgb332_encode(c).unwrap_or_else(|| panic!("{c:?} is not an RGB332 colour"))
}

/// A fresh RTL; a missing model is a failure with `Rtl::new`'s message, never a skip.
/// While a failing case replays (`replay`), it writes the case's waveform.
pub fn rtl() -> SharedRtl {
    crate::replay::traced(Rtl::shared().unwrap_or_else(|e| panic!("{e}")))
}

/// As [`rtl`], every register and memory starting at random values drawn from `seed`.
pub fn rtl_x(seed: u64) -> SharedRtl {
    let r = Rtl::with_x_seed(seed).unwrap_or_else(|e| panic!("{e}"));
    crate::replay::traced(std::rc::Rc::new(std::cell::RefCell::new(r)))
}

impl Pair {
    /// A fresh RTL and model, both set up with `setup`.
    pub fn new(setup: RasterSetup) -> Self {
        Self::with(setup, MemWait::Off)
    }

    /// As [`Pair::new`] with `mem_wait` driven as `wait`.
    pub fn with(setup: RasterSetup, wait: MemWait) -> Self {
        Self::with_spi(setup, wait, SpiConfig::default())
    }

    /// As [`Pair::with`], the SPI master timed by `config`.
    pub fn with_spi(setup: RasterSetup, wait: MemWait, config: SpiConfig) -> Self {
        Self::on(rtl(), setup, wait, config)
    }

    /// As [`Pair::with_spi`] on a given RTL (one whose registers start at random values,
    /// say).
    pub fn on(rtl: SharedRtl, setup: RasterSetup, wait: MemWait, config: SpiConfig) -> Self {
        Self::make(rtl, setup, wait, config, Build::DEFAULT)
    }

    /// As [`Pair::new`] on one Verilated build of the block, the model's triangle cycles
    /// counted for the build's `TRI_LANES`. The model has every unit: a case sends a
    /// build only the commands it draws.
    pub fn with_build(setup: RasterSetup, build: Build) -> Self {
        let rtl = Rtl::with_build(build).unwrap_or_else(|e| panic!("{e}"));
        let rtl = crate::replay::traced(std::rc::Rc::new(std::cell::RefCell::new(rtl)));
        Self::make(rtl, setup, MemWait::Off, SpiConfig::default(), build)
    }

    fn make(
        rtl: SharedRtl,
        setup: RasterSetup,
        wait: MemWait,
        config: SpiConfig,
        build: Build,
    ) -> Self {
        rtl.borrow_mut().set_mem_wait(wait);
        let spi = RtlSpi::new(rtl.clone(), config).expect("SPI config within the contract");
        let mut pair = Self {
            rtl,
            spi,
            model: Device::new(&FITKIT),
            setup,
            tri_lanes: build.tri_lanes,
            tri_small: build.tri_small,
            last: Default::default(),
        };
        pair.restart();
        pair
    }

    /// A fresh model, and the set-up into both: what a controller does after the block
    /// was reset. The RTL must then behave as a fresh block, whatever it was doing.
    pub fn restart(&mut self) {
        let setup = self.setup;
        self.model = Device::new(&FITKIT);
        self.model.raster_setup(&setup).expect("model set-up");
        self.model
            .raster_mut()
            .expect("set up")
            .set_tri_lanes(self.tri_lanes)
            .expect("a built TRI_LANES");
        self.model
            .raster_mut()
            .expect("set up")
            .set_tri_small(self.tri_small)
            .expect("the small unit has one lane");
        let record = wire::Setup {
            width: setup.width,
            height: setup.height,
            background: rgb332(setup.background),
            cull: setup.cull,
        }
        .record()
        .expect("set-up in range");
        self.write_packet(wire::ADDR_SETUP, &[record]);
        let s = self.finish();
        assert!(s.error.is_none(), "set-up {setup:?}: {s:?}");
        self.last = (Counters::from(s), self.model_counters());
    }

    /// Sends `cmd` to both, waits for the RTL, and checks the frames are equal; returns
    /// what the command added to each side's counters.
    pub fn step(&mut self, case: &str, cmd: &RasterCmd, cb: bool) -> Step {
        self.send(cmd, cb);
        self.settle(&format!("{case}: {cmd:?}"))
    }

    /// Waits for the RTL, checks it latched no error and that the frames are equal;
    /// returns what the commands since the last call added to each side's counters.
    pub fn settle(&mut self, case: &str) -> Step {
        let s = self.finish();
        assert!(s.error.is_none(), "{case}: block error {:?}", s.error);
        self.assert_frames_equal(case);
        let now = (Counters::from(s), self.model_counters());
        let step = Step {
            rtl: now.0.minus(&self.last.0),
            model: now.1.minus(&self.last.1),
        };
        self.last = now;
        step
    }

    /// As [`Pair::step`], the model told what the memory did: the command runs on the RTL
    /// first, then the model counts its unit's stalls from the `mem_wait` the RTL's memory
    /// drove from the unit's first cycle ([`unit_start`] cycles after CS_n rose) on.
    /// The RTL must be recording `mem_wait` ([`fitkit_rtl_sim::Rtl::record_mem_wait`]).
    pub fn step_stalled(&mut self, case: &str, cmd: &RasterCmd) -> Step {
        let (channel, records) = self.pack(cmd, false);
        self.write_packet(channel, &records);
        let start = self.spi.last_cs_rise() + unit_start(cmd);
        self.rtl
            .borrow_mut()
            .wait_idle(WAIT_BOUND)
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        let now = self.rtl.borrow().cycle();
        let wait = self.rtl.borrow().mem_wait_between(start, now);
        self.model
            .raster_mut()
            .expect("set up")
            .set_mem_wait(Some(wait));
        self.model
            .push_packet(channel, &records)
            .expect("model FIFO");
        self.model.drain().expect("model runs the command");
        self.settle(&format!("{case}: {cmd:?}"))
    }

    /// Waits for FIFO_FREE, then writes the packet of `records` to `address`.
    pub fn write_packet(&mut self, address: u8, records: &[u64]) {
        self.wait_fifo_free();
        let mut buf = [0u8; 1 + wire::MAX_PACKET_BYTES];
        let n = wire::packet(address, records, &mut buf).expect("packet frames");
        self.write_raw(&buf[..n]);
    }

    /// Waits (bounded) until FIFO_FREE is high.
    pub fn wait_fifo_free(&mut self) {
        self.rtl
            .borrow_mut()
            .wait_until("fifo_free", WAIT_BOUND, |r| r.fifo_free())
            .unwrap_or_else(|e| panic!("{e}"));
    }

    /// Writes `bytes` (address first) in one transaction, without looking at FIFO_FREE.
    pub fn write_raw(&mut self, bytes: &[u8]) {
        self.spi.write(bytes).expect("SPI write");
    }

    /// The FITkit packet of `cmd` (CB = `cb`): its channel and records.
    pub fn pack(
        &self,
        cmd: &RasterCmd,
        cb: bool,
    ) -> (u8, heapless::Vec<u64, { bus::MAX_RECORDS }>) {
        let opts = PackOptions {
            subpixel_bits: self.setup.subpixel_bits,
            clear: cb,
        };
        let records = bus::pack(&FITKIT, cmd, opts).unwrap_or_else(|e| panic!("{cmd:?}: {e}"));
        let channel = bus::channel(&FITKIT, bus::Kind::of(cmd)).expect("FITkit channel");
        (channel, records)
    }

    /// `cmd` into both.
    pub fn send(&mut self, cmd: &RasterCmd, cb: bool) {
        let (channel, records) = self.pack(cmd, cb);
        self.write_packet(channel, &records);
        self.model
            .push_packet(channel, &records)
            .expect("model FIFO");
        self.model.drain().expect("model runs the command");
    }

    /// Waits until the RTL is idle (bounded) and reads its status.
    pub fn finish(&mut self) -> Status {
        self.rtl
            .borrow_mut()
            .wait_idle(WAIT_BOUND)
            .unwrap_or_else(|e| panic!("{e}"));
        self.status()
    }

    /// The status block over SPI.
    pub fn status(&mut self) -> Status {
        let mut b = [0u8; wire::STATUS_BYTES];
        self.spi
            .transaction(&mut [
                Operation::Write(&[wire::ADDR_STATUS]),
                Operation::Read(&mut b),
            ])
            .expect("SPI read");
        Status::decode(&b).unwrap_or_else(|e| panic!("status {b:02x?}: {e}"))
    }

    /// `n` pixels from `(x, y)` on over the read-back channel.
    pub fn read_pixels(&mut self, x: u32, y: u32, n: usize) -> Vec<u8> {
        let header = wire::read_header(x, y).expect("pixel inside the RAM");
        let mut buf = vec![0u8; n];
        self.spi
            .transaction(&mut [Operation::Write(&header), Operation::Read(&mut buf)])
            .expect("SPI read");
        buf
    }

    /// Pixels where the RTL's RAM and the model's framebuffer differ, as `(x, y, rtl,
    /// model)`, the model's RGB888 quantised (it is exact for FITkit colours).
    pub fn frame_diff(&self) -> Vec<(u32, u32, u8, u8)> {
        let (w, h) = (u32::from(self.setup.width), u32::from(self.setup.height));
        let rtl = self.rtl.borrow();
        let got = rtl.frame(w, h).expect("frame inside the RAM");
        let fb = self.model.raster().expect("set up").framebuffer();
        let mut diff = Vec::new();
        for y in 0..h {
            for x in 0..w {
                let want = fb.pixel(x, y).expect("inside");
                let want = bus::rgb332_encode(bus::quantize_rgb332(want)).unwrap_or(0);
                let g = got[(y * w + x) as usize];
                if g != want {
                    diff.push((x, y, g, want));
                }
            }
        }
        diff
    }

    /// Panics with the first differing pixels unless the frames are equal.
    pub fn assert_frames_equal(&self, case: &str) {
        let d = self.frame_diff();
        assert!(
            d.is_empty(),
            "{case}: {} pixels differ (x, y, rtl, model), first: {:?}",
            d.len(),
            &d[..d.len().min(8)]
        );
    }

    /// The model's counters in the status block's terms.
    pub fn model_counters(&self) -> Counters {
        let s = self.model.raster().expect("set up").stats();
        Counters {
            packets: s.commands,
            fragments: s.fragments,
            line: s.cycles.line,
            triangle: s.cycles.triangle,
            clear: s.cycles.clear,
        }
    }
}

/// Per-unit counters of one case, from either side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counters {
    pub packets: u64,
    pub fragments: u64,
    pub line: u64,
    pub triangle: u64,
    pub clear: u64,
}

impl Counters {
    pub fn minus(&self, o: &Self) -> Self {
        Self {
            packets: self.packets - o.packets,
            fragments: self.fragments - o.fragments,
            line: self.line - o.line,
            triangle: self.triangle - o.triangle,
            clear: self.clear - o.clear,
        }
    }
}

/// What one command added to the counters of the RTL and of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    pub rtl: Counters,
    pub model: Counters,
}

impl From<Status> for Counters {
    fn from(s: Status) -> Self {
        Self {
            packets: u64::from(s.packets),
            fragments: u64::from(s.fragments),
            line: u64::from(s.line_cycles),
            triangle: u64::from(s.triangle_cycles),
            clear: u64::from(s.clear_cycles),
        }
    }
}
