//! The FITkit raster block on SPI: the [`FpgaBus`] a FITkit MCU (seed 000's MSP430) runs,
//! over any embedded-hal 1.0 [`SpiDevice`].
//!
//! The block (docs/rtl.md) takes packets on the FITkit's address decoder, one transaction
//! each, and answers a status block and framebuffer reads on the same bus. FIFO space is
//! learnt from the status block rather than the FIFO_FREE pin: the pin says only "one more
//! packet fits", while a status read gives the exact free count, the busy flag and the
//! block's error latch in one transaction. The free count is cached and decremented as
//! packets go out (the FIFO only drains meanwhile), so a status read is needed only when
//! the cache runs low, not per packet.
//!
//! Waiting is a [`DelayNs`]: on a board a short sleep, in the Verilator bridge the RTL's
//! clock running. Every wait has a bound ([`FitkitSpi::with_limits`]), so a stuck block
//! is an error, not a hang.

use embedded_hal::delay::DelayNs;
use embedded_hal::spi::{Operation, SpiDevice};
use protocol::bus::{rgb332_decode, rgb332_encode};
use protocol::fitkit_spi::{
    self as wire, BlockError, Setup, SpiFrameError, Status, ADDR_CLEAR, ADDR_LINE, ADDR_RESET,
    ADDR_SETUP, ADDR_STATUS, ADDR_TRIANGLE, MAX_PACKET_BYTES, MAX_PACKET_RECORDS, STATUS_BYTES,
};
use protocol::frame::{
    Block, DeviceCounters, FrameDone, PixelFormat, Plane, ReadRequest, StartFrame,
};
use protocol::raster::{AaPattern, RasterSetup};

use crate::fpga::FpgaBus;

/// Why the FITkit block could not do what the controller asked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum FitkitSpiError<E> {
    /// The SPI peripheral failed.
    Spi(E),
    /// A transaction could not be framed, or the status block read back is not one the
    /// block sends (MISO not connected, another device answering).
    Frame(SpiFrameError),
    /// The block latched an error (its own error flags: which check, which address,
    /// which packet).
    Block(BlockError),
    /// The block stayed busy (or full) for longer than the configured bound.
    Timeout {
        /// What the driver was waiting for.
        waiting_for: &'static str,
        /// Status polls made before giving up.
        polls: u32,
    },
    /// The request needs something the FITkit block does not have.
    Unsupported(&'static str),
    /// A packet or a read arrived before the first set-up.
    NoSetup,
}

impl<E: core::fmt::Debug> core::fmt::Display for FitkitSpiError<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Spi(e) => write!(f, "SPI transfer to the FITkit block failed: {e:?}"),
            Self::Frame(e) => write!(f, "{e}"),
            Self::Block(e) => write!(f, "{e}"),
            Self::Timeout { waiting_for, polls } => write!(
                f,
                "FITkit block: still waiting for {waiting_for} after {polls} status polls"
            ),
            Self::Unsupported(what) => write!(f, "the FITkit raster block has no {what}"),
            Self::NoSetup => write!(f, "FITkit block: a packet or read before the set-up"),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for FitkitSpiError<E> {}

impl<E> From<SpiFrameError> for FitkitSpiError<E> {
    fn from(e: SpiFrameError) -> Self {
        Self::Frame(e)
    }
}

/// Pixels fetched per read-back transaction: bounds the stack buffer, and the header
/// (5 bytes) is paid once per this many pixels.
const READ_BURST: usize = 64;

/// The FITkit block behind an SPI device, driven as seed 000's MCU drives it.
pub struct FitkitSpi<S, D> {
    spi: S,
    delay: D,
    /// Lower bound of the FIFO's free records, from the last status read.
    free: usize,
    /// The units this build of the block has, from the last status read's flags (a
    /// line-only or triangle-only bitstream for the seed's XC3S50): a packet for a unit
    /// the block lacks is refused here, by name, rather than latched there as an unknown
    /// address.
    has_line: bool,
    has_triangle: bool,
    setup: Option<RasterSetup>,
    /// A raster frame was started and not yet reported done.
    pending: Option<u32>,
    frames: u32,
    poll_us: u32,
    max_polls: u32,
}

impl<S: SpiDevice, D: DelayNs> FitkitSpi<S, D> {
    /// A driver that polls every 10 µs and gives up after 1 000 000 polls (10 s of board
    /// time, far beyond the longest job: clearing 512 × 512 pixels at 1 pixel per cycle is
    /// 5 ms at 50 MHz).
    pub fn new(spi: S, delay: D) -> Self {
        Self::with_limits(spi, delay, 10, 1_000_000)
    }

    /// A driver with an explicit poll interval and bound on every wait.
    pub fn with_limits(spi: S, delay: D, poll_us: u32, max_polls: u32) -> Self {
        Self {
            spi,
            delay,
            free: 0,
            has_line: true,
            has_triangle: true,
            setup: None,
            pending: None,
            frames: 0,
            poll_us,
            max_polls,
        }
    }

    /// The SPI device and the delay back, e.g. to inspect a simulated block.
    pub fn release(self) -> (S, D) {
        (self.spi, self.delay)
    }

    /// Reads the status block, refreshing the cached free count; a latched block error
    /// becomes [`FitkitSpiError::Block`].
    pub fn status(&mut self) -> Result<Status, FitkitSpiError<S::Error>> {
        let mut buf = [0u8; STATUS_BYTES];
        self.spi
            .transaction(&mut [Operation::Write(&[ADDR_STATUS]), Operation::Read(&mut buf)])
            .map_err(FitkitSpiError::Spi)?;
        let s = Status::decode(&buf)?;
        if let Some(e) = s.error {
            return Err(FitkitSpiError::Block(e));
        }
        self.free = usize::from(s.free);
        self.has_line = s.has_line_unit();
        self.has_triangle = s.has_triangle_unit();
        Ok(s)
    }

    /// Polls the status until `done` holds, within the bound.
    fn wait_for(
        &mut self,
        waiting_for: &'static str,
        done: impl Fn(&Status) -> bool,
    ) -> Result<Status, FitkitSpiError<S::Error>> {
        for _ in 0..self.max_polls {
            let s = self.status()?;
            if done(&s) {
                return Ok(s);
            }
            self.delay.delay_us(self.poll_us);
        }
        Err(FitkitSpiError::Timeout {
            waiting_for,
            polls: self.max_polls,
        })
    }

    fn send(&mut self, address: u8, records: &[u64]) -> Result<(), FitkitSpiError<S::Error>> {
        let mut buf = [0u8; 1 + MAX_PACKET_BYTES];
        let n = wire::packet(address, records, &mut buf)?;
        self.spi.write(&buf[..n]).map_err(FitkitSpiError::Spi)?;
        self.free = self.free.saturating_sub(records.len());
        Ok(())
    }
}

impl<S: SpiDevice, D: DelayNs> FpgaBus for FitkitSpi<S, D> {
    type Error = FitkitSpiError<S::Error>;

    fn fifo_free(&mut self) -> Result<usize, Self::Error> {
        if self.free < MAX_PACKET_RECORDS {
            self.status()?;
        }
        Ok(self.free)
    }

    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Self::Error> {
        if self.setup.is_none() {
            return Err(FitkitSpiError::NoSetup);
        }
        match channel {
            ADDR_LINE if !self.has_line => Err(FitkitSpiError::Unsupported(
                "line unit (this build draws triangles only)",
            )),
            ADDR_TRIANGLE if !self.has_triangle => Err(FitkitSpiError::Unsupported(
                "triangle unit (this build draws lines only)",
            )),
            ADDR_LINE | ADDR_TRIANGLE | ADDR_CLEAR => self.send(channel, records),
            _ => Err(FitkitSpiError::Unsupported(
                "channel other than line, triangle, clear",
            )),
        }
    }

    fn wait(&mut self) -> Result<(), Self::Error> {
        self.delay.delay_us(self.poll_us);
        Ok(())
    }

    fn idle(&mut self) -> Result<bool, Self::Error> {
        Ok(self.status()?.idle())
    }

    fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), Self::Error> {
        if setup.aa.pattern != AaPattern::None {
            return Err(FitkitSpiError::Unsupported("anti-aliasing"));
        }
        if setup.subpixel_bits != 0 {
            return Err(FitkitSpiError::Unsupported("sub-pixel coordinates"));
        }
        let background = rgb332_encode(setup.background)
            .ok_or(FitkitSpiError::Unsupported("background outside RGB332"))?;
        let record = Setup {
            width: setup.width,
            height: setup.height,
            background,
            cull: setup.cull,
        }
        .record()?;
        self.wait_for("FIFO room for the set-up", |s| s.free >= 1)?;
        self.send(ADDR_SETUP, &[record])?;
        self.setup = Some(*setup);
        self.pending = None;
        Ok(())
    }

    fn write_regs(&mut self, _offset: u16, _words: &[u32]) -> Result<(), Self::Error> {
        Err(FitkitSpiError::Unsupported("ray-tracer registers"))
    }

    fn write_texels(&mut self, _offset: u32, _bytes: &[u8]) -> Result<(), Self::Error> {
        Err(FitkitSpiError::Unsupported("texture memory"))
    }

    fn start(&mut self, start: &StartFrame) -> Result<(), Self::Error> {
        match start.block {
            Block::Raster if self.setup.is_some() => {
                self.pending = Some(start.frame_id);
                Ok(())
            }
            Block::Raster => Err(FitkitSpiError::NoSetup),
            Block::RayTrace => Err(FitkitSpiError::Unsupported("ray-trace block")),
        }
    }

    fn stop(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }

    fn poll_done(&mut self) -> Result<Option<FrameDone>, Self::Error> {
        let Some(frame_id) = self.pending else {
            return Ok(None);
        };
        let s = self.status()?;
        if !s.idle() {
            return Ok(None);
        }
        self.pending = None;
        self.frames += 1;
        Ok(Some(FrameDone {
            frame_id,
            cycles: block_cycles(&s),
            work: u64::from(s.fragments),
        }))
    }

    fn read_len(&mut self, req: &ReadRequest) -> Result<Option<u32>, Self::Error> {
        let Some(setup) = self.setup else {
            return Ok(None);
        };
        let r = req.rect;
        let fits = req.plane == Plane::Color
            && matches!(req.format, PixelFormat::Rgb888 | PixelFormat::Rgb332)
            && r.w > 0
            && r.h > 0
            && u32::from(r.x) + u32::from(r.w) <= u32::from(setup.width)
            && u32::from(r.y) + u32::from(r.h) <= u32::from(setup.height);
        Ok(fits.then(|| u32::from(r.w) * u32::from(r.h) * req.format.bytes_per_pixel() as u32))
    }

    fn read(&mut self, req: &ReadRequest, offset: u32, out: &mut [u8]) -> Result<(), Self::Error> {
        if self.read_len(req)?.is_none() {
            return Err(FitkitSpiError::Unsupported("such a read-back"));
        }
        // Make sure every fragment is in memory before reading it.
        self.wait_for("the block to go idle before a read-back", Status::idle)?;
        let bpp = req.format.bytes_per_pixel();
        let (rx, ry, rw) = (
            u32::from(req.rect.x),
            u32::from(req.rect.y),
            u32::from(req.rect.w),
        );
        let mut pixel = offset as usize / bpp;
        let mut skip = offset as usize % bpp;
        let mut done = 0;
        while done < out.len() {
            // One burst stays within a row of the rectangle.
            let col = (pixel as u32) % rw;
            let row = (pixel as u32) / rw;
            let want = (out.len() - done + skip).div_ceil(bpp);
            let n = want.min(READ_BURST).min((rw - col) as usize);
            let header = wire::read_header(rx + col, ry + row)?;
            let mut px = [0u8; READ_BURST];
            self.spi
                .transaction(&mut [Operation::Write(&header), Operation::Read(&mut px[..n])])
                .map_err(FitkitSpiError::Spi)?;
            for &p in &px[..n] {
                let rgb = rgb332_decode(p);
                let bytes = [rgb.r, rgb.g, rgb.b];
                let src: &[u8] = match req.format {
                    PixelFormat::Rgb332 => core::slice::from_ref(&p),
                    _ => &bytes,
                };
                for &b in &src[skip..] {
                    if done == out.len() {
                        break;
                    }
                    out[done] = b;
                    done += 1;
                }
                skip = 0;
            }
            pixel += n;
        }
        // A late memory fetch shows up as the block's read-underrun error.
        self.status()?;
        Ok(())
    }

    fn counters(&mut self) -> Result<DeviceCounters, Self::Error> {
        let s = self.status()?;
        Ok(DeviceCounters {
            commands: s.packets,
            fragments: u64::from(s.fragments),
            cycles: block_cycles(&s),
            frames: self.frames,
            ..DeviceCounters::default()
        })
    }

    fn reset(&mut self) -> Result<(), Self::Error> {
        self.spi.write(&[ADDR_RESET]).map_err(FitkitSpiError::Spi)?;
        self.free = 0;
        self.setup = None;
        self.pending = None;
        self.frames = 0;
        Ok(())
    }
}

/// Busy cycles summed over the units, as the model's `Stats::total_cycles`.
fn block_cycles(s: &Status) -> u64 {
    u64::from(s.line_cycles) + u64::from(s.triangle_cycles) + u64::from(s.clear_cycles)
}
