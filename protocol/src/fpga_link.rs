//! Messages between the controller and an FPGA reached over a serial line (the "FPGA
//! link"): the board's second UART when the FPGA is `fpgfx-sim --fpga-link`.
//!
//! On the seeds' boards the controller drives the FPGA directly (the FITkit's MSP430 shifts
//! 36-bit records over SPI, ViRAY's MicroBlaze writes AXI4-Lite registers). When the FPGA
//! is emulated on a PC, that wiring becomes a byte stream, so each bus operation of the
//! firmware's `FpgaBus` trait becomes one [`FpgaRequest`], carried by the same
//! [`crate::link`] as the host frames (COBS, CRC-32, retransmission): a lost byte on the
//! FPGA side must not corrupt a frame any more than on the host side.
//!
//! Writes are posted — the controller does not wait for an answer — because a round trip
//! per FIFO packet would make the link's latency, not its bandwidth, the limit. Only
//! questions ([`FpgaRequest::Status`], [`FpgaRequest::ReadLen`], [`FpgaRequest::Read`],
//! [`FpgaRequest::Counters`], [`FpgaRequest::Identify`]) are answered. A posted write that
//! the FPGA refuses is reported by the next answer as [`FpgaReply::Fault`], so an error is
//! late but never lost.
//!
//! The FIFO is never overrun although pushes are posted: the controller only pushes what
//! the last [`FpgaStatus::fifo_free`] allowed, minus what it pushed since, which is a lower
//! bound of the real free space (the FPGA only ever drains the FIFO).

use crate::bus::LayoutId;

use heapless::Vec;
use postcard_schema::Schema;
use serde::{Deserialize, Serialize};

use crate::frame::{
    Caps, DeviceCounters, FrameDone, ReadRequest, StartFrame, READ_CHUNK, REG_WRITE_WORDS,
};
use crate::raster::RasterSetup;

/// FIFO records in one [`FpgaRequest::Push`]: 24 worst-case 10-byte varints and the
/// header stay within [`crate::MAX_PAYLOAD`]. Longer packets travel as several pushes, and
/// the FPGA queues a packet only when its last part has arrived, so a packet is never
/// executed half.
pub const PUSH_RECORDS: usize = 24;

/// The schema hash of the FPGA link's message set, exchanged by [`FpgaRequest::Identify`]
/// so that a controller and an FPGA emulator built from different sources refuse each
/// other instead of misreading records.
pub const FPGA_SCHEMA_HASH: u64 = u64::from_le_bytes(
    postcard_schema::key::Key::for_path::<(FpgaRequest<'static>, FpgaReply)>("fpgfx/fpga")
        .to_bytes(),
);

/// Controller → FPGA: one message per operation of the firmware's `FpgaBus` trait; each
/// variant says whether it is answered or posted.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub enum FpgaRequest<'a> {
    /// Who are you? Answered with [`FpgaReply::Identity`]. Sent once after the link is
    /// (re)synchronised, before anything else.
    Identify,
    /// Return to the power-on state (FIFO, framebuffers, registers, counters). Posted.
    Reset,
    /// How is the FIFO and did a frame finish? Answered with [`FpgaReply::Status`].
    Status,
    /// Part of a FIFO packet for `channel`. Posted; the packet enters the FIFO when the
    /// part with `last` arrives.
    Push {
        /// The FITkit's SPI address of the command (see [`crate::bus::channel`]).
        channel: u8,
        /// This part ends the packet.
        last: bool,
        /// Records, in FIFO order.
        records: Vec<u64, PUSH_RECORDS>,
    },
    /// Program the raster block's frame registers and clear its buffers. Posted.
    RasterSetup(RasterSetup),
    /// Write consecutive ray-tracer registers. Posted.
    Regs {
        /// Word offset of the first register in the [`crate::scene`] map.
        offset: u16,
        /// Values for `offset`, `offset + 1`, …; a longer run travels as several writes.
        words: Vec<u32, REG_WRITE_WORDS>,
    },
    /// Write texture memory. Posted.
    Texels {
        /// Index of the first texel written.
        offset: u32,
        /// Little-endian 32-bit texels, at most [`crate::frame::TEXTURE_CHUNK`] bytes (one host
        /// texture write).
        #[serde(borrow)]
        bytes: &'a [u8],
    },
    /// Start a frame. Posted; completion shows in [`FpgaStatus::done`].
    Start(StartFrame),
    /// Stop auto-restart after the current frame. Posted.
    Stop,
    /// Size of a read-back. Answered with [`FpgaReply::ReadLen`].
    ReadLen(ReadRequest),
    /// Bytes `offset .. offset + len` of a read-back (`len` ≤ [`READ_CHUNK`]). Answered
    /// with [`FpgaReply::Data`].
    Read {
        /// The read-back this part belongs to, as the host asked for it.
        req: ReadRequest,
        /// Byte offset of the part within the whole read-back.
        offset: u32,
        /// Bytes in the part, at most [`READ_CHUNK`].
        len: u16,
    },
    /// The FPGA's counters. Answered with [`FpgaReply::Counters`].
    Counters,
}

/// The FPGA's state as [`FpgaRequest::Status`] reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct FpgaStatus {
    /// Records the input FIFO can take now.
    pub fifo_free: u16,
    /// Every queued record has been executed.
    pub idle: bool,
    /// A frame that finished since the last status, reported once.
    pub done: Option<FrameDone>,
}

/// Why the FPGA refused a posted request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub enum FaultCode {
    /// A FIFO packet did not decode with the FPGA's layout, or a block refused it.
    Packet,
    /// More records than the FIFO had room for (the controller broke the credit rule).
    Overrun,
    /// A register, texel or read-back address outside the FPGA's memories.
    OutOfRange,
    /// The register image does not describe a scene the ray tracer can render.
    Scene,
    /// The raster block was used without, or with an invalid, set-up.
    Setup,
    /// A request that does not decode, or a part of a packet out of order.
    Malformed,
    /// The block stayed busy (or its FIFO full) past the bound its driver waits: a stuck
    /// RTL, reported instead of hanging the link.
    Stuck,
    /// The bus between the FPGA end of the link and the block failed (an SPI transfer,
    /// or a status block that does not read back as one).
    Bus,
}

/// A refused posted request: which one and why.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct Fault {
    /// Index of the refused request, counted from 0 after the last [`FpgaRequest::Reset`]
    /// (every request counts, answered or not), so the controller's log can name it.
    pub request: u32,
    /// What was wrong with it, for the controller's log and its reset decision.
    pub code: FaultCode,
}

/// What the FPGA answers to an [`FpgaRequest::Identify`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub struct Identity {
    /// [`FPGA_SCHEMA_HASH`] of the FPGA side's build.
    pub schema_hash: u64,
    /// What the blocks can do; the controller advertises it to the host.
    pub caps: Caps,
    /// The FIFO record layout.
    pub layout: LayoutId,
}

/// FPGA → controller, only ever in answer to a question.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, Schema)]
pub enum FpgaReply {
    /// Answer to [`FpgaRequest::Identify`].
    Identity(Identity),
    /// Answer to [`FpgaRequest::Status`].
    Status(FpgaStatus),
    /// Answer to [`FpgaRequest::ReadLen`]: `None` if the FPGA has no such buffer or
    /// rectangle.
    ReadLen(Option<u32>),
    /// Answer to [`FpgaRequest::Read`].
    Data(#[serde(with = "crate::bytes")] Vec<u8, READ_CHUNK>),
    /// Answer to [`FpgaRequest::Counters`].
    Counters(DeviceCounters),
    /// Sent instead of the answer to a question when a posted request before it failed.
    /// The FPGA stays usable; the controller decides whether to reset it.
    Fault(Fault),
}
