//! The controller's view of the FPGA: the signals and memories the seeds' MCU drives.
//!
//! The seed boards differ in transport (the FITkit's MSP430 shifts bits over SPI into a
//! 36-bit FIFO; ViRAY's MicroBlaze writes AXI4-Lite registers) but the controller needs
//! the same handful of operations from both, so one trait covers them and each transport
//! (in-process model, serial FPGA link, a real SPI peripheral) is one implementation.

use protocol::frame::{DeviceCounters, FrameDone, ReadRequest, StartFrame};
use protocol::raster::RasterSetup;

/// Operations the controller needs from an FPGA.
pub trait FpgaBus {
    /// What can go wrong on the transport.
    type Error: core::fmt::Debug;

    /// Records the input FIFO can take now (the FITkit's FIFO_FREE line). The controller
    /// never pushes more than this, so nothing is dropped for lack of space.
    fn fifo_free(&mut self) -> Result<usize, Self::Error>;

    /// Pushes one packed command ([`protocol::bus::pack`]) into the input FIFO, addressed
    /// to `channel` (the FITkit's SPI address; layouts with an opcode use one channel).
    /// The caller guarantees `records.len() <= fifo_free()`, so a packet is never split.
    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Self::Error>;

    /// Gives the FPGA time while the controller waits for FIFO space or for a frame (on a
    /// board this is a short sleep; an in-process model runs here).
    fn wait(&mut self) -> Result<(), Self::Error>;

    /// Whether every pushed record has been executed (FIFO empty, pipeline idle).
    fn idle(&mut self) -> Result<bool, Self::Error>;

    /// Programs the raster block's frame registers (size, sub-pixel precision, AA,
    /// culling, traversal) and clears the framebuffer.
    fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), Self::Error>;

    /// Writes consecutive 32-bit ray-tracer registers ([`protocol::scene`]).
    fn write_regs(&mut self, offset: u16, words: &[u32]) -> Result<(), Self::Error>;

    /// Writes texture memory, `bytes` being little-endian 32-bit texels.
    fn write_texels(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error>;

    /// Starts (or, with auto-restart, keeps restarting) a frame on a block.
    fn start(&mut self, start: &StartFrame) -> Result<(), Self::Error>;

    /// Stops auto-restart after the current frame.
    fn stop(&mut self) -> Result<(), Self::Error>;

    /// A frame that finished since the last call, if any.
    fn poll_done(&mut self) -> Result<Option<FrameDone>, Self::Error>;

    /// Total size in bytes of a read-back, or `None` if the request names a buffer or
    /// rectangle the FPGA does not have.
    fn read_len(&mut self, req: &ReadRequest) -> Result<Option<u32>, Self::Error>;

    /// Copies read-back bytes `offset..offset + out.len()` of `req` into `out`.
    fn read(&mut self, req: &ReadRequest, offset: u32, out: &mut [u8]) -> Result<(), Self::Error>;

    /// The FPGA side of the counters (fragments, cycles, frames); the controller adds its
    /// own (commands, bus words, stalls, queue).
    fn counters(&mut self) -> Result<DeviceCounters, Self::Error>;

    /// Returns the FPGA to its power-on state.
    fn reset(&mut self) -> Result<(), Self::Error>;
}

/// Why a raster command did not reach the FIFO.
#[derive(Debug)]
pub(crate) enum PushError<E> {
    /// The layout cannot carry the command (or its channel does not exist).
    Pack(protocol::bus::BusError),
    /// The bus failed.
    Bus(E),
}

/// Packs `cmd` in `layout` and pushes it once FIFO_FREE covers the whole packet (a packet
/// is never split), returning the records pushed and the waits it took. The engine's
/// host commands and the embedded-graphics canvas both draw through this, so the two
/// cannot disagree on packing or back-pressure.
pub(crate) fn push_command<B: FpgaBus>(
    bus: &mut B,
    layout: &protocol::bus::BusLayout,
    cmd: &protocol::raster::RasterCmd,
    opts: protocol::bus::PackOptions,
) -> Result<(usize, u64), PushError<B::Error>> {
    let kind = protocol::bus::Kind::of(cmd);
    let channel = protocol::bus::channel(layout, kind).map_err(PushError::Pack)?;
    let records = protocol::bus::pack(layout, cmd, opts).map_err(PushError::Pack)?;
    let mut stalls = 0;
    while bus.fifo_free().map_err(PushError::Bus)? < records.len() {
        stalls += 1;
        bus.wait().map_err(PushError::Bus)?;
    }
    bus.push_packet(channel, &records).map_err(PushError::Bus)?;
    Ok((records.len(), stalls))
}
