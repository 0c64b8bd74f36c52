//! The emulated FPGA as a soft core on its AXI4-Lite interconnect sees it: the whole
//! [`protocol::axi_lite`] map, word by word, over a [`Device`].
//!
//! [`Device`] takes the controller's operations whole (a packet, a set-up, a read-back
//! rectangle); a MicroBlaze beside ViRAY-style IP has only 32-bit reads and writes. This
//! is the register file between the two, with the control semantics Vivado HLS generates
//! for an `s_axilite` block (see the map's module docs for the bits):
//!
//! * `ap_start` is held until the frame's handshake: it reads 1 while the frame runs and
//!   is cleared when `ap_done` rises, unless `auto_restart` is set, in which case the
//!   block starts again at once (sampling its inputs then);
//! * `ap_idle` is low while a frame runs; `ap_done` and `ap_ready` rise together at the
//!   end of a frame (a plain, non-pipelined top function) and clear when the control word
//!   is read;
//! * [`axi_lite::ISR`] bits are set by enabled events and toggled by writing 1s;
//! * a frame is computed when it starts, but `ap_done` rises only after
//!   [`RegisterFile::set_done_after`] reads of the control word, so a driver has to poll
//!   as on silicon, and [`Liveness`] makes a block that never finishes, for tests of the
//!   driver's bounds.
//!
//! Everything a driver can get wrong is a [`RegisterError`] naming the register or
//! window, never a panic and never a silently ignored write.

use protocol::axi_lite::{
    self, ctrl, irq, raster as rr, readback as rb, sys, Location, COUNTERS, READ_WINDOW,
};
use protocol::bus::MAX_RECORDS;
use protocol::frame::{Block, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame};
use protocol::raster::RasterSetup;

use crate::device::{Device, DeviceError};

/// Reads of a block's control word, after its start, before `ap_done` rises by default:
/// enough that a driver which does not poll fails.
pub const DONE_AFTER_POLLS: u32 = 3;

// The texture window is the model's texture memory, word for word.
const _: () = assert!(axi_lite::TEXTURE_WORDS as usize == crate::raster::TEXTURE_WORDS);

/// Whether the blocks finish their frames: the knob that makes a stuck block for tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Liveness {
    /// Frames end after [`RegisterFile::set_done_after`] polls.
    #[default]
    Normal,
    /// A started frame never raises `ap_done` (`ap_idle` stays low).
    NeverDone,
    /// `ap_start` is never taken (`ap_idle` stays high, nothing runs).
    IgnoresStart,
}

/// A register access the device refuses: what a bus monitor or the block's error flag
/// would report on a board, naming the register or window.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RegisterError {
    /// Nothing is mapped there (or the address is not word-aligned).
    #[error("{} {addr:#x}: outside the AXI4-Lite map (no register or window there)", if *.write { "write to" } else { "read of" })]
    Unmapped {
        /// The byte address.
        addr: u32,
        /// A write (else a read).
        write: bool,
    },
    /// A write to a register that can only be read.
    #[error("write to {at} ({addr:#x}), which is read-only")]
    ReadOnly {
        /// The byte address.
        addr: u32,
        /// What it is.
        at: Location,
    },
    /// A read of a register or window that can only be written.
    #[error("read of {at} ({addr:#x}), which is write-only")]
    WriteOnly {
        /// The byte address.
        addr: u32,
        /// What it is.
        at: Location,
    },
    /// `ap_start` written while the block still runs a frame: the driver lost track of it.
    #[error(
        "ap_start written to {ctrl} while the {block} is still running a frame (wait for ap_done)"
    )]
    Busy {
        /// The block.
        block: &'static str,
        /// Its control register.
        ctrl: &'static str,
    },
    /// A value the register has no meaning for.
    #[error("{register} = {value:#x}: {expected}")]
    BadValue {
        /// The register's name.
        register: &'static str,
        /// The value written.
        value: u32,
        /// What it takes.
        expected: &'static str,
    },
    /// A read-back window word wholly past the end of the selected read-back.
    #[error(
        "READ_WINDOW read at byte {offset} of the read-back (page {page}), past its {len} bytes"
    )]
    PastReadBack {
        /// Byte offset in the read-back (page and window offset together).
        offset: u64,
        /// [`axi_lite::readback::PAGE`].
        page: u32,
        /// Bytes of the read-back.
        len: u32,
    },
    /// The read-back registers select nothing the device has.
    #[error("{0} read while READ_PLANE/READ_FORMAT/READ_RECT select no buffer the device has (READ_LEN reads NONE)")]
    NoReadBack(&'static str),
    /// The framebuffer read while the ray tracer is still writing it.
    #[error("{0} read while the ray tracer is still running its frame (wait for ap_done)")]
    ReadWhileBusy(&'static str),
    /// A 64-bit value's high word read without its low word just before.
    #[error("{at} read without its low word just before (a 64-bit value is read low word first)")]
    NotLatched {
        /// The high word.
        at: Location,
    },
    /// More records staged than a packet can have.
    #[error("PUSH_HI: more than {max} records staged without a COMMIT")]
    Staging {
        /// The longest packet.
        max: usize,
    },
    /// The device refused what the access asked of it.
    #[error("{at}: {source}")]
    Device {
        /// The register or window whose access made the request.
        at: &'static str,
        /// The device's complaint.
        source: DeviceError,
    },
}

/// One block's HLS control word.
#[derive(Debug, Default)]
struct Ctrl {
    start: bool,
    auto_restart: bool,
    done: bool,
    ready: bool,
    /// Control-word reads since the running frame started.
    running: Option<u32>,
    /// Cycles and work of the running frame, shown at its end.
    pending: (u64, u64),
    /// Cycles and work of the last finished frame.
    last: (u64, u64),
}

impl Ctrl {
    fn idle(&self) -> bool {
        self.running.is_none()
    }
}

/// The device's AXI4-Lite register file ([`axi_lite`]'s map) over a [`Device`].
pub struct RegisterFile {
    device: Device,
    s: State,
    done_after: u32,
    liveness: Liveness,
}

/// What the registers hold; all of it returns to power-on at a reset.
struct State {
    rt: Ctrl,
    raster: Ctrl,
    gie: u32,
    ier: u32,
    isr: u32,
    numeric: Numeric,
    aovs: u32,
    /// The high word latched by the last low-word read: its address and value.
    latch: Option<(u32, u32)>,
    push_lo: u32,
    staged: heapless::Vec<u64, MAX_RECORDS>,
    size: u32,
    subpixel: u32,
    background: u32,
    aa: u32,
    mode: u32,
    plane: Plane,
    format: PixelFormat,
    rect_xy: u32,
    rect_wh: u32,
    page: u32,
}

impl Default for State {
    /// Power-on: every register 0, as HLS resets them (0 is each code's first value).
    fn default() -> Self {
        Self {
            rt: Ctrl::default(),
            raster: Ctrl::default(),
            gie: 0,
            ier: 0,
            isr: 0,
            numeric: Numeric::ALL[0],
            aovs: 0,
            latch: None,
            push_lo: 0,
            staged: heapless::Vec::new(),
            size: 0,
            subpixel: 0,
            background: 0,
            aa: 0,
            mode: 0,
            plane: Plane::Color,
            format: PixelFormat::Rgb888,
            rect_xy: 0,
            rect_wh: 0,
            page: 0,
        }
    }
}

impl RegisterFile {
    /// The register file of `device` at power-on.
    pub fn new(device: Device) -> Self {
        Self {
            device,
            s: State::default(),
            done_after: DONE_AFTER_POLLS,
            liveness: Liveness::Normal,
        }
    }

    /// The device behind the registers (its capabilities, its raster block).
    pub fn device(&self) -> &Device {
        &self.device
    }

    /// Control-word reads after a start before `ap_done` rises (0: on the first read).
    pub fn set_done_after(&mut self, polls: u32) {
        self.done_after = polls;
    }

    /// Makes the blocks finish normally, never finish, or never start.
    pub fn set_liveness(&mut self, liveness: Liveness) {
        self.liveness = liveness;
    }

    /// The ray tracer's interrupt line: GIE and an enabled, pending ISR bit.
    pub fn interrupt(&self) -> bool {
        self.s.gie & 1 != 0 && self.s.isr != 0
    }

    /// Reads the word at byte address `addr`.
    pub fn read(&mut self, addr: u32) -> Result<u32, RegisterError> {
        let at = axi_lite::locate(addr).ok_or(RegisterError::Unmapped { addr, write: false })?;
        if !at.access().readable() {
            return Err(RegisterError::WriteOnly { addr, at });
        }
        let value = match at {
            Location::Scene(i) => self.device.regs().get(i).copied().unwrap_or(0),
            Location::ReadBack(off) => self.window(off)?,
            Location::Counter { index, high: false } => {
                let counters = self.device.counters();
                self.wide(addr, COUNTERS.get(index).map_or(0, |c| (c.get)(&counters)))
            }
            Location::Counter { high: true, .. } => self.high(addr, at)?,
            Location::Texture(_) => return Err(RegisterError::WriteOnly { addr, at }),
            Location::Register(_) => self.register(addr, at)?,
        };
        Ok(value)
    }

    fn register(&mut self, addr: u32, at: Location) -> Result<u32, RegisterError> {
        Ok(match addr {
            axi_lite::AP_CTRL => self.read_ctrl(Block::RayTrace)?,
            axi_lite::GIE => self.s.gie,
            axi_lite::IER => self.s.ier,
            axi_lite::ISR => self.s.isr,
            axi_lite::NUMERIC => axi_lite::numeric_code(self.s.numeric),
            axi_lite::AOVS => self.s.aovs,
            sys::ID => axi_lite::DEVICE_ID,
            sys::VERSION => axi_lite::MAP_VERSION,
            sys::RT_CYCLES => self.wide(addr, self.s.rt.last.0),
            sys::RT_WORK => self.wide(addr, self.s.rt.last.1),
            rr::CYCLES => self.wide(addr, self.s.raster.last.0),
            rr::WORK => self.wide(addr, self.s.raster.last.1),
            a if [sys::RT_CYCLES, sys::RT_WORK, rr::CYCLES, rr::WORK]
                .contains(&a.wrapping_sub(4)) =>
            {
                self.high(addr, at)?
            }
            rr::CTRL => self.read_ctrl(Block::Raster)?,
            rr::FIFO_FREE => {
                self.run_fifo("FIFO_FREE")?;
                self.device.fifo_free() as u32
            }
            rr::IDLE => {
                self.run_fifo("RASTER_IDLE")?;
                u32::from(self.device.idle())
            }
            rr::SIZE => self.s.size,
            rr::SUBPIXEL => self.s.subpixel,
            rr::BACKGROUND => self.s.background,
            rr::AA => self.s.aa,
            rr::MODE => self.s.mode,
            rb::PLANE => axi_lite::plane_code(self.s.plane),
            rb::FORMAT => axi_lite::format_code(self.s.format),
            rb::RECT_XY => self.s.rect_xy,
            rb::RECT_WH => self.s.rect_wh,
            rb::LEN => {
                self.check_not_rendering("READ_LEN")?;
                self.device.read_len(&self.request()).unwrap_or(rb::NONE)
            }
            rb::PAGE => self.s.page,
            _ => return Err(RegisterError::Unmapped { addr, write: false }),
        })
    }

    /// Writes `value` to the word at byte address `addr`.
    pub fn write(&mut self, addr: u32, value: u32) -> Result<(), RegisterError> {
        let at = axi_lite::locate(addr).ok_or(RegisterError::Unmapped { addr, write: true })?;
        if !at.access().writable() {
            return Err(RegisterError::ReadOnly { addr, at });
        }
        match at {
            Location::Scene(i) => self
                .device
                .write_regs(i as u16, &[value])
                .map_err(|source| RegisterError::Device {
                    at: "scene window",
                    source,
                }),
            Location::Texture(i) => {
                self.device
                    .write_texels(i, &value.to_le_bytes())
                    .map_err(|source| RegisterError::Device {
                        at: "texture window",
                        source,
                    })
            }
            Location::Counter { .. } | Location::ReadBack(_) => {
                Err(RegisterError::ReadOnly { addr, at })
            }
            Location::Register(r) => self.write_register(addr, r.name, value),
        }
    }

    fn write_register(
        &mut self,
        addr: u32,
        name: &'static str,
        value: u32,
    ) -> Result<(), RegisterError> {
        let bad = |expected| RegisterError::BadValue {
            register: name,
            value,
            expected,
        };
        match addr {
            axi_lite::AP_CTRL => self.write_ctrl(Block::RayTrace, value)?,
            axi_lite::GIE => self.s.gie = value & 1,
            axi_lite::IER => self.s.ier = value & (irq::DONE | irq::READY),
            axi_lite::ISR => self.s.isr ^= value & (irq::DONE | irq::READY),
            axi_lite::NUMERIC => {
                self.s.numeric = axi_lite::numeric_from_code(value).ok_or(bad(
                    "no number format has this code (protocol::axi_lite::numeric_code)",
                ))?
            }
            axi_lite::AOVS => self.s.aovs = value & 1,
            sys::RESET => self.reset(),
            rr::CTRL => self.write_ctrl(Block::Raster, value)?,
            rr::PUSH_LO => self.s.push_lo = value,
            rr::PUSH_HI => {
                let record = u64::from(value) << 32 | u64::from(self.s.push_lo);
                self.s
                    .staged
                    .push(record)
                    .map_err(|_| RegisterError::Staging { max: MAX_RECORDS })?;
            }
            rr::COMMIT => {
                let channel = u8::try_from(value).map_err(|_| bad("a channel is 0–255"))?;
                let records = core::mem::take(&mut self.s.staged);
                self.device
                    .push_packet(channel, &records)
                    .map_err(|source| RegisterError::Device {
                        at: "COMMIT",
                        source,
                    })?;
            }
            rr::SIZE => self.s.size = value,
            rr::SUBPIXEL if value > 0xFF => return Err(bad("sub-pixel bits are 0–255")),
            rr::SUBPIXEL => self.s.subpixel = value,
            rr::BACKGROUND if value >> 24 != 0 => return Err(bad("a colour is 0x00RRGGBB")),
            rr::BACKGROUND => self.s.background = value,
            rr::AA => {
                axi_lite::aa_from_reg(value).ok_or(bad("an AA pattern code | samples << 8"))?;
                self.s.aa = value;
            }
            rr::MODE => {
                axi_lite::mode_from_reg(value).ok_or(bad("a cull code | traversal code << 8"))?;
                self.s.mode = value;
            }
            rr::SETUP => {
                let setup = self.setup();
                self.device
                    .raster_setup(&setup)
                    .map_err(|source| RegisterError::Device {
                        at: "RASTER_SETUP",
                        source,
                    })?;
            }
            rb::PLANE => {
                self.s.plane =
                    axi_lite::plane_from_code(value).ok_or(bad("no plane has this code"))?
            }
            rb::FORMAT => {
                self.s.format = axi_lite::format_from_code(value).ok_or(bad(
                    "unsupported value format (no pixel format has this code)",
                ))?
            }
            rb::RECT_XY => self.s.rect_xy = value,
            rb::RECT_WH => self.s.rect_wh = value,
            rb::PAGE => self.s.page = value,
            _ => return Err(RegisterError::Unmapped { addr, write: true }),
        }
        Ok(())
    }

    fn ctrl(&mut self, block: Block) -> &mut Ctrl {
        match block {
            Block::RayTrace => &mut self.s.rt,
            Block::Raster => &mut self.s.raster,
        }
    }

    fn write_ctrl(&mut self, block: Block, value: u32) -> Result<(), RegisterError> {
        let regs = axi_lite::block_regs(block);
        let c = self.ctrl(block);
        if value & ctrl::AP_START != 0 {
            if !c.idle() {
                return Err(RegisterError::Busy {
                    block: regs.name,
                    ctrl: ctrl_name(block),
                });
            }
            c.start = true;
        }
        // Written with every write of the word, as HLS does: a 0 stops auto-restart.
        c.auto_restart = value & ctrl::AUTO_RESTART != 0;
        if c.start && c.idle() {
            self.begin(block)?;
        }
        Ok(())
    }

    /// The block takes `ap_start` (unless [`Liveness::IgnoresStart`]) and computes its
    /// frame from the inputs as they are now.
    fn begin(&mut self, block: Block) -> Result<(), RegisterError> {
        if self.liveness == Liveness::IgnoresStart {
            return Ok(());
        }
        let start = StartFrame {
            frame_id: 0,
            block,
            numeric: self.s.numeric,
            auto_restart: false,
            aovs: self.s.aovs & 1 != 0,
        };
        let at = ctrl_name(block);
        self.device
            .start(&start)
            .map_err(|source| RegisterError::Device { at, source })?;
        let done = self.device.poll_done();
        let c = self.ctrl(block);
        c.pending = done.map_or((0, 0), |d| (d.cycles, d.work));
        c.running = Some(0);
        Ok(())
    }

    fn read_ctrl(&mut self, block: Block) -> Result<u32, RegisterError> {
        let (done_after, liveness) = (self.done_after, self.liveness);
        let c = self.ctrl(block);
        let mut finished = false;
        if let Some(polls) = &mut c.running {
            *polls += 1;
            if *polls > done_after && liveness != Liveness::NeverDone {
                c.running = None;
                c.last = c.pending;
                c.done = true;
                c.ready = true;
                // The handshake: ap_start stays only for another run.
                c.start = c.auto_restart;
                finished = true;
            }
        }
        // An auto-restarted block never goes idle: the next frame starts with the end.
        let restart = finished && c.start;
        let value = [
            (c.start, ctrl::AP_START),
            (c.done, ctrl::AP_DONE),
            (c.idle() && !restart, ctrl::AP_IDLE),
            (c.ready, ctrl::AP_READY),
            (c.auto_restart, ctrl::AUTO_RESTART),
        ]
        .iter()
        .filter(|(set, _)| *set)
        .fold(0, |word, (_, bit)| word | bit);
        (c.done, c.ready) = (false, false);
        if finished && block == Block::RayTrace {
            self.s.isr |= self.s.ier & (irq::DONE | irq::READY);
        }
        if restart {
            self.begin(block)?;
        }
        Ok(value)
    }

    /// Lets the raster block work for the moment a register read takes.
    fn run_fifo(&mut self, at: &'static str) -> Result<(), RegisterError> {
        self.device
            .wait()
            .map_err(|source| RegisterError::Device { at, source })
    }

    fn setup(&self) -> RasterSetup {
        let (width, height) = axi_lite::unpair16(self.s.size);
        // AA and MODE were checked when written; their reset values decode too.
        let aa = axi_lite::aa_from_reg(self.s.aa).unwrap_or_default();
        let (cull, traversal) = axi_lite::mode_from_reg(self.s.mode).unwrap_or_default();
        RasterSetup {
            width,
            height,
            subpixel_bits: self.s.subpixel as u8,
            background: axi_lite::rgb_from_reg(self.s.background),
            aa,
            cull,
            traversal,
        }
    }

    fn request(&self) -> ReadRequest {
        let (x, y) = axi_lite::unpair16(self.s.rect_xy);
        let (w, h) = axi_lite::unpair16(self.s.rect_wh);
        ReadRequest {
            plane: self.s.plane,
            rect: Rect { x, y, w, h },
            format: self.s.format,
        }
    }

    fn check_not_rendering(&self, at: &'static str) -> Result<(), RegisterError> {
        match self.s.rt.idle() {
            true => Ok(()),
            false => Err(RegisterError::ReadWhileBusy(at)),
        }
    }

    /// The read-back word at byte `off` of the window on the current page.
    fn window(&mut self, off: u32) -> Result<u32, RegisterError> {
        self.check_not_rendering("READ_WINDOW")?;
        let req = self.request();
        let len = self
            .device
            .read_len(&req)
            .ok_or(RegisterError::NoReadBack("READ_WINDOW"))?;
        let offset = u64::from(self.s.page) * u64::from(READ_WINDOW) + u64::from(off);
        if offset >= u64::from(len) {
            return Err(RegisterError::PastReadBack {
                offset,
                page: self.s.page,
                len,
            });
        }
        let mut word = [0u8; 4];
        // offset < len ≤ u32::MAX.
        self.device.read(&req, offset as u32, &mut word);
        Ok(u32::from_le_bytes(word))
    }

    /// The low word of a 64-bit `value` at `addr`, latching its high word.
    fn wide(&mut self, addr: u32, value: u64) -> u32 {
        self.s.latch = Some((addr + 4, (value >> 32) as u32));
        value as u32
    }

    fn high(&mut self, addr: u32, at: Location) -> Result<u32, RegisterError> {
        match self.s.latch {
            Some((a, hi)) if a == addr => Ok(hi),
            _ => Err(RegisterError::NotLatched { at }),
        }
    }

    /// Power-on state; the test knobs stay (they are the model's, not the device's).
    fn reset(&mut self) {
        self.device.reset();
        self.s = State::default();
    }
}

/// The name of `block`'s control register, from the map's table.
fn ctrl_name(block: Block) -> &'static str {
    axi_lite::register_name(axi_lite::block_regs(block).ctrl)
}
