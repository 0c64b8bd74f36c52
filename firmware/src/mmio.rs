//! [`FpgaBus`] over memory-mapped AXI4-Lite registers: the controller as a soft core
//! (seed 002's MicroBlaze, a RISC-V) beside ViRAY-style HLS IP, every operation a few
//! 32-bit reads and writes at [`protocol::axi_lite`]'s addresses.
//!
//! [`Registers`] is the one thing a target provides: a word read and a word write.
//! [`VolatileRegisters`] is that for a core whose bus bridge maps the device at a fixed
//! base; a model implements it in tests. Nothing here allocates or spins unbounded:
//! every wait on the device counts its polls and gives up with [`MmioError::Stuck`]
//! naming the register, because a block that never raises `ap_done` must end a session
//! with a message, not hang the controller.

use core::convert::Infallible;

use heapless::Deque;
use protocol::axi_lite::{
    self, block_regs, ctrl, raster, readback, scene_word_addr, sys, BlockRegs, COUNTERS, READ_BASE,
    READ_WINDOW, TEXTURE_BASE, TEXTURE_WORDS,
};
use protocol::frame::{Block, DeviceCounters, FrameDone, ReadRequest, StartFrame};
use protocol::raster::RasterSetup;

use crate::fpga::FpgaBus;

/// 32-bit word access to the device's register space.
pub trait Registers {
    /// What can go wrong on the access (nothing, on silicon: [`Infallible`]).
    type Error: core::fmt::Debug;

    /// Reads the word at byte address `addr` (a multiple of 4).
    fn read(&mut self, addr: u32) -> Result<u32, Self::Error>;

    /// Writes the word at byte address `addr` (a multiple of 4).
    fn write(&mut self, addr: u32, value: u32) -> Result<(), Self::Error>;
}

/// The device's registers mapped into this core's address space at a fixed base.
pub struct VolatileRegisters {
    base: *mut u32,
}

impl VolatileRegisters {
    /// The registers at `base`.
    ///
    /// # Safety
    ///
    /// `base` must be where the device's AXI4-Lite map starts in this core's address
    /// space, with all [`axi_lite::DEVICE_ADDR_BITS`] bits of it mapped to the device
    /// and to nothing else, and nothing else may access it meanwhile.
    pub unsafe fn new(base: *mut u32) -> Self {
        Self { base }
    }
}

impl Registers for VolatileRegisters {
    type Error = Infallible;

    fn read(&mut self, addr: u32) -> Result<u32, Infallible> {
        // SAFETY: `new`'s contract: the map is ours, so every word address is valid.
        Ok(unsafe { core::ptr::read_volatile(self.base.add((addr / 4) as usize)) })
    }

    fn write(&mut self, addr: u32, value: u32) -> Result<(), Infallible> {
        // SAFETY: as for `read`.
        unsafe { core::ptr::write_volatile(self.base.add((addr / 4) as usize), value) };
        Ok(())
    }
}

/// What went wrong on the register bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum MmioError<E> {
    /// The access itself failed (a model's refusal; silicon has none).
    #[error("register access failed: {0}")]
    Access(E),
    /// A wait on the device ran out of polls.
    #[error("{register} ({addr:#06x}): {waiting_for} not seen after {polls} polls")]
    Stuck {
        /// The register polled.
        register: &'static str,
        /// Its address.
        addr: u32,
        /// What the driver waited for.
        waiting_for: &'static str,
        /// Polls spent ([`MmioBus::poll_limit`]).
        polls: u32,
    },
    /// The ID or VERSION register does not read as this map's.
    #[error(
        "no fpgfx device at the register base: ID {id:#010x}, VERSION {version} (expected \
         {:#010x}, {})",
        axi_lite::DEVICE_ID,
        axi_lite::MAP_VERSION
    )]
    Identity {
        /// What [`sys::ID`] read.
        id: u32,
        /// What [`sys::VERSION`] read.
        version: u32,
    },
    /// An index past what the map has (a scene word, a texel).
    #[error("{what} {index} is outside the register map")]
    OutOfMap {
        /// Which kind of word.
        what: &'static str,
        /// Its index.
        index: u32,
    },
    /// Texel bytes that are not whole 32-bit texels.
    #[error("texture write of {0} bytes: not whole 32-bit texels")]
    Texels(usize),
}

#[cfg(feature = "defmt")]
impl<E> defmt::Format for MmioError<E> {
    // By hand, as for the FPGA link's error: names and numbers are all a log needs.
    fn format(&self, f: defmt::Formatter<'_>) {
        match self {
            MmioError::Access(_) => defmt::write!(f, "register access failed"),
            MmioError::Stuck {
                register, polls, ..
            } => defmt::write!(f, "{=str} stuck after {=u32} polls", register, polls),
            MmioError::Identity { id, version } => {
                defmt::write!(
                    f,
                    "no fpgfx device: ID {=u32:x} VERSION {=u32}",
                    id,
                    version
                )
            }
            MmioError::OutOfMap { what, index } => {
                defmt::write!(f, "{=str} {=u32} outside the map", what, index)
            }
            MmioError::Texels(n) => defmt::write!(f, "texture write of {=usize} bytes", n),
        }
    }
}

/// Register reads and writes a driver made, for figures such as writes per frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Accesses {
    /// Words read.
    pub reads: u64,
    /// Words written.
    pub writes: u64,
}

/// Polls of one wait before [`MmioError::Stuck`] by default: about seven minutes of
/// back-to-back AXI4-Lite reads at 10 M/s, beyond any frame of a full-HD scene in the
/// slowest format, yet finite.
pub const DEFAULT_POLL_LIMIT: u32 = u32::MAX;

/// A block's frame as the driver tracks it.
#[derive(Debug, Clone, Copy, Default)]
struct Frame {
    /// The id of the frame running, if one is.
    running: Option<u32>,
    /// `auto_restart` is set: the block starts the next frame by itself.
    auto: bool,
}

/// The FPGA on memory-mapped registers ([`protocol::axi_lite`]'s map).
pub struct MmioBus<R> {
    regs: R,
    /// By block: [`Block::Raster`], [`Block::RayTrace`].
    frames: [Frame; 2],
    done: Deque<FrameDone, 4>,
    /// What the read-back registers hold, so that chunked reads do not re-program them.
    request: Option<ReadRequest>,
    page: Option<u32>,
    /// The register the last unanswered wait polled, and how many waits in a row.
    waiting_on: u32,
    waits: u32,
    polls: u32,
    accesses: Accesses,
    /// Polls of any one wait (FIFO space, idle, `ap_start` taken, `ap_done`) before
    /// giving up.
    pub poll_limit: u32,
}

const fn slot(block: Block) -> usize {
    match block {
        Block::Raster => 0,
        Block::RayTrace => 1,
    }
}

impl<R: Registers> MmioBus<R> {
    /// A driver over `regs`; [`MmioBus::probe`] checks the device before use.
    pub fn new(regs: R) -> Self {
        Self {
            regs,
            frames: [Frame::default(); 2],
            done: Deque::new(),
            request: None,
            page: None,
            waiting_on: raster::FIFO_FREE,
            waits: 0,
            polls: 0,
            accesses: Accesses::default(),
            poll_limit: DEFAULT_POLL_LIMIT,
        }
    }

    /// Checks that the registers are this map's device: [`sys::ID`] and [`sys::VERSION`].
    pub fn probe(&mut self) -> Result<(), MmioError<R::Error>> {
        let id = self.rd(sys::ID)?;
        let version = self.rd(sys::VERSION)?;
        if id == axi_lite::DEVICE_ID && version == axi_lite::MAP_VERSION {
            Ok(())
        } else {
            Err(MmioError::Identity { id, version })
        }
    }

    /// The register access, e.g. a model to inspect in tests.
    pub fn registers(&mut self) -> &mut R {
        &mut self.regs
    }

    /// Reads and writes made so far.
    pub fn accesses(&self) -> Accesses {
        self.accesses
    }

    fn rd(&mut self, addr: u32) -> Result<u32, MmioError<R::Error>> {
        self.accesses.reads += 1;
        self.regs.read(addr).map_err(MmioError::Access)
    }

    fn wr(&mut self, addr: u32, value: u32) -> Result<(), MmioError<R::Error>> {
        self.accesses.writes += 1;
        self.regs.write(addr, value).map_err(MmioError::Access)
    }

    fn wr_all(
        &mut self,
        mut writes: impl Iterator<Item = (u32, u32)>,
    ) -> Result<(), MmioError<R::Error>> {
        writes.try_for_each(|(a, v)| self.wr(a, v))
    }

    /// A 64-bit value, low word first (which latches the high word).
    fn rd64(&mut self, addr: u32) -> Result<u64, MmioError<R::Error>> {
        let lo = self.rd(addr)?;
        let hi = self.rd(addr + 4)?;
        Ok(u64::from(hi) << 32 | u64::from(lo))
    }

    fn stuck(&self, addr: u32, waiting_for: &'static str) -> MmioError<R::Error> {
        MmioError::Stuck {
            register: axi_lite::register_name(addr),
            addr,
            waiting_for,
            polls: self.poll_limit,
        }
    }

    /// Takes a control word the driver read: when it shows `ap_done`, the block's frame
    /// is queued as done (and, with auto-restart, the next one is running).
    fn observe(&mut self, block: Block, word: u32) -> Result<bool, MmioError<R::Error>> {
        let regs: BlockRegs = block_regs(block);
        let frame = self.frames[slot(block)];
        let Some(id) = frame.running.filter(|_| word & ctrl::AP_DONE != 0) else {
            return Ok(false);
        };
        let cycles = self.rd64(regs.cycles)?;
        let work = self.rd64(regs.work)?;
        // Four frames unread would mean the engine stopped polling; the oldest is the one
        // it no longer waits for.
        if self.done.is_full() {
            self.done.pop_front();
        }
        let _ = self.done.push_back(FrameDone {
            frame_id: id,
            cycles,
            work,
        });
        // A restarted frame's id is the next one until `start` says otherwise.
        self.frames[slot(block)].running = frame.auto.then_some(id.wrapping_add(1));
        Ok(true)
    }

    /// Polls `block`'s control word until its running frame is done.
    fn finish(&mut self, block: Block) -> Result<(), MmioError<R::Error>> {
        let ctrl_addr = block_regs(block).ctrl;
        for _ in 0..self.poll_limit {
            let word = self.rd(ctrl_addr)?;
            if self.observe(block, word)? {
                return Ok(());
            }
        }
        Err(self.stuck(ctrl_addr, "ap_done"))
    }

    /// A wait that made no progress: counted towards [`MmioBus::poll_limit`].
    fn no_progress(&mut self, waiting_for: &'static str) -> Result<(), MmioError<R::Error>> {
        self.waits += 1;
        if self.waits > self.poll_limit {
            self.waits = 0;
            return Err(self.stuck(self.waiting_on, waiting_for));
        }
        Ok(())
    }

    /// Selects `req` in the read-back registers, unless they hold it already.
    fn select(&mut self, req: &ReadRequest) -> Result<(), MmioError<R::Error>> {
        if self.request != Some(*req) {
            self.wr_all(axi_lite::read_request_writes(req))?;
            self.request = Some(*req);
        }
        Ok(())
    }
}

impl<R: Registers> FpgaBus for MmioBus<R> {
    type Error = MmioError<R::Error>;

    fn fifo_free(&mut self) -> Result<usize, Self::Error> {
        self.waiting_on = raster::FIFO_FREE;
        Ok(self.rd(raster::FIFO_FREE)? as usize)
    }

    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Self::Error> {
        for &r in records {
            self.wr(raster::PUSH_LO, r as u32)?;
            self.wr(raster::PUSH_HI, (r >> 32) as u32)?;
        }
        self.wr(raster::COMMIT, u32::from(channel))?;
        self.waits = 0;
        Ok(())
    }

    fn wait(&mut self) -> Result<(), Self::Error> {
        // The block runs beside the core; the next register read is the moment it gets.
        self.no_progress("the raster block's progress")
    }

    fn idle(&mut self) -> Result<bool, Self::Error> {
        self.waiting_on = raster::IDLE;
        let idle = self.rd(raster::IDLE)? != 0;
        if idle {
            self.waits = 0;
        }
        Ok(idle)
    }

    fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), Self::Error> {
        self.wr_all(axi_lite::raster_setup_writes(setup))
    }

    fn write_regs(&mut self, offset: u16, words: &[u32]) -> Result<(), Self::Error> {
        for (i, &w) in words.iter().enumerate() {
            let index = usize::from(offset) + i;
            let addr = scene_word_addr(index).ok_or(MmioError::OutOfMap {
                what: "scene word",
                index: index as u32,
            })?;
            self.wr(addr, w)?;
        }
        Ok(())
    }

    fn write_texels(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        if !bytes.len().is_multiple_of(4) {
            return Err(MmioError::Texels(bytes.len()));
        }
        for (i, t) in bytes.chunks_exact(4).enumerate() {
            let index = offset.saturating_add(i as u32);
            if index >= TEXTURE_WORDS {
                return Err(MmioError::OutOfMap {
                    what: "texel",
                    index,
                });
            }
            self.wr(
                TEXTURE_BASE + 4 * index,
                u32::from_le_bytes([t[0], t[1], t[2], t[3]]),
            )?;
        }
        Ok(())
    }

    fn start(&mut self, start: &StartFrame) -> Result<(), Self::Error> {
        let s = slot(start.block);
        let frame = self.frames[s];
        if frame.auto && start.auto_restart && frame.running.is_some() {
            // The block restarted by itself when the last frame ended: this is that frame.
            self.frames[s].running = Some(start.frame_id);
            return Ok(());
        }
        if frame.running.is_some() {
            self.finish(start.block)?;
        }
        let ctrl_addr = block_regs(start.block).ctrl;
        self.frames[s] = Frame {
            running: Some(start.frame_id),
            auto: start.auto_restart,
        };
        match start.block {
            Block::RayTrace => self.wr_all(axi_lite::start_writes(start))?,
            Block::Raster => {
                let restart = if start.auto_restart {
                    ctrl::AUTO_RESTART
                } else {
                    0
                };
                self.wr(ctrl_addr, ctrl::AP_START | restart)?
            }
        }
        self.polls = 0;
        // Taken once ap_idle falls (or the frame is over already).
        for _ in 0..self.poll_limit {
            let word = self.rd(ctrl_addr)?;
            if self.observe(start.block, word)? || word & ctrl::AP_IDLE == 0 {
                return Ok(());
            }
        }
        self.frames[s] = Frame::default();
        Err(self.stuck(ctrl_addr, "ap_start taken (ap_idle low)"))
    }

    fn stop(&mut self) -> Result<(), Self::Error> {
        for block in [Block::Raster, Block::RayTrace] {
            if self.frames[slot(block)].auto {
                // A control write without ap_start only clears auto_restart: the running
                // frame ends and the block stays idle.
                self.wr(block_regs(block).ctrl, 0)?;
                self.frames[slot(block)].auto = false;
            }
        }
        Ok(())
    }

    fn poll_done(&mut self) -> Result<Option<FrameDone>, Self::Error> {
        if self.done.is_empty() {
            let mut running = None;
            for block in [Block::Raster, Block::RayTrace] {
                if self.frames[slot(block)].running.is_some() {
                    running = Some(block);
                    let word = self.rd(block_regs(block).ctrl)?;
                    self.observe(block, word)?;
                }
            }
            match (running, self.done.is_empty()) {
                (Some(block), true) => {
                    self.polls += 1;
                    if self.polls > self.poll_limit {
                        self.polls = 0;
                        return Err(self.stuck(block_regs(block).ctrl, "ap_done"));
                    }
                }
                _ => self.polls = 0,
            }
        }
        Ok(self.done.pop_front())
    }

    fn read_len(&mut self, req: &ReadRequest) -> Result<Option<u32>, Self::Error> {
        self.select(req)?;
        let len = self.rd(readback::LEN)?;
        Ok((len != readback::NONE).then_some(len))
    }

    fn read(&mut self, req: &ReadRequest, offset: u32, out: &mut [u8]) -> Result<(), Self::Error> {
        self.select(req)?;
        let mut pos = offset;
        let mut filled = 0;
        while filled < out.len() {
            let page = pos / READ_WINDOW;
            if self.page != Some(page) {
                self.wr(readback::PAGE, page)?;
                self.page = Some(page);
            }
            let in_window = pos % READ_WINDOW;
            let word = self.rd(READ_BASE + (in_window & !3))?.to_le_bytes();
            let skip = (in_window % 4) as usize;
            let n = (4 - skip).min(out.len() - filled);
            out[filled..filled + n].copy_from_slice(&word[skip..skip + n]);
            filled += n;
            pos += n as u32;
        }
        Ok(())
    }

    fn counters(&mut self) -> Result<DeviceCounters, Self::Error> {
        let mut c = DeviceCounters::default();
        for (i, counter) in COUNTERS.iter().enumerate() {
            let v = self.rd64(axi_lite::counter_addr(i))?;
            (counter.set)(&mut c, v);
        }
        Ok(c)
    }

    fn reset(&mut self) -> Result<(), Self::Error> {
        self.wr(sys::RESET, 1)?;
        self.frames = [Frame::default(); 2];
        self.done.clear();
        self.request = None;
        self.page = None;
        self.waits = 0;
        self.polls = 0;
        Ok(())
    }
}
