//! The FITkit raster block's SPI transactions (docs/rtl.md): what the MCU clocks out to
//! reach the input FIFO, the set-up, the status block and the framebuffer.
//!
//! Seed 000's MCU talks to the FPGA through the FITkit's SPI address decoder: the first
//! byte of a transaction (one `CS` low period, mode 0, MSB first) is an address, the rest
//! is that address's payload. The seed defines only the packets ([`crate::bus`], layout
//! [`FITKIT`](crate::bus::FITKIT)); the set-up, status and read-back addresses are fpgfx's,
//! because a testbench and a user need the pixels and the error flags back, and the
//! FITkit shows them only on VGA.
//!
//! Everything here is a pure function of bytes, so the firmware's SPI driver, the
//! Verilator bridge's tests and the RTL's own testbenches agree on one definition.

use core::fmt::Write as _;

use crate::raster::Cull;

/// Address of the set-up packet: frame size, background and culling, executed in FIFO
/// order (earlier packets finish first), then the framebuffer is cleared.
pub const ADDR_SETUP: u8 = 0x00;
/// Address of line packets. The seed gives no addresses; these are fpgfx's choice, and
/// [`crate::bus`] sends a [`FITKIT`](crate::bus::FITKIT) packet to the address of its kind.
pub const ADDR_LINE: u8 = 0x01;
/// Address of triangle packets.
pub const ADDR_TRIANGLE: u8 = 0x02;
/// Address of stand-alone clears.
pub const ADDR_CLEAR: u8 = 0x03;
/// Address of the status block ([`Status`]): a read, as long as the master clocks.
pub const ADDR_STATUS: u8 = 0x20;
/// Address of the framebuffer read-back ([`read_header`]).
pub const ADDR_READ: u8 = 0x30;
/// Address of the block reset: no payload, the same as the `rst` pin.
pub const ADDR_RESET: u8 = 0x7F;

/// Bits of one input FIFO record (RAMB16_S36_S36).
pub const RECORD_BITS: u32 = 36;
/// Records the input FIFO holds.
pub const FIFO_RECORDS: u16 = 512;
/// The widest packet, in records: a line or a triangle.
pub const MAX_PACKET_RECORDS: usize = 2;
/// Payload bytes of the widest packet (72 record bits).
pub const MAX_PACKET_BYTES: usize = 9;
/// Bits of a coordinate: whole pixels, unsigned ([`crate::bus::FITKIT`]).
pub const COORD_BITS: u8 = 9;
/// Bits of a colour: RGB332.
pub const COLOR_BITS: u8 = 8;
/// Side of the framebuffer the 9-bit coordinates address.
pub const FRAME_SIDE: u16 = 512;
/// Bytes of the status block ([`Status::decode`]).
pub const STATUS_BYTES: usize = 32;
/// Bytes between the read-back's address and its first pixel, which give the block time
/// to fetch from external memory.
pub const READ_TURNAROUND: usize = 1;
/// Bytes before the first pixel of a read-back transaction: address, 3 address bytes,
/// turnaround.
pub const READ_HEADER_BYTES: usize = 4 + READ_TURNAROUND;

/// Where each field of the status block starts (byte offsets; multi-byte fields are big
/// endian). The RTL's `status` module serialises the same offsets from the generated
/// header.
pub mod status_byte {
    /// Free input FIFO records, 2 bytes.
    pub const FREE: usize = 0;
    /// The `FLAG_*` bits.
    pub const FLAGS: usize = 2;
    /// The sticky error's code ([`super::ErrorCode`]), 0 without one.
    pub const ERROR_CODE: usize = 3;
    /// The address (channel) of the packet that raised the error.
    pub const ERROR_CHANNEL: usize = 4;
    /// The index of that packet (commits before it), 2 bytes.
    pub const ERROR_PACKET: usize = 5;
    /// Packets executed, 4 bytes.
    pub const PACKETS: usize = 7;
    /// Fragments written, 4 bytes.
    pub const FRAGMENTS: usize = 11;
    /// Cycles the line unit was busy, 4 bytes.
    pub const LINE_CYCLES: usize = 15;
    /// Cycles the triangle unit was busy, 4 bytes.
    pub const TRIANGLE_CYCLES: usize = 19;
    /// Cycles spent clearing, 4 bytes.
    pub const CLEAR_CYCLES: usize = 23;
    /// The cycle the last packet finished at, 4 bytes.
    pub const END_CYCLE: usize = 27;
    /// Highest input FIFO occupancy ÷ 2, saturating.
    pub const FIFO_MAX_PAIRS: usize = 31;
}

/// Why a transaction could not be built or a status block not decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum SpiFrameError {
    /// A record has bits above the 36 a FIFO record holds.
    #[error("record {index} = {value:#x} is wider than 36 bits")]
    RecordTooWide {
        /// Position in the packet.
        index: usize,
        /// The record.
        value: u64,
    },
    /// More records than any packet has, or none.
    #[error("a packet of {records} records (FITkit packets have 1 or 2)")]
    PacketLength {
        /// Records given.
        records: usize,
    },
    /// The output buffer cannot hold the transaction.
    #[error("transaction needs {needed} bytes, buffer has {capacity}")]
    BufferTooSmall {
        /// Bytes the transaction needs.
        needed: usize,
        /// Bytes the buffer has.
        capacity: usize,
    },
    /// A set-up value outside what the block's registers hold.
    #[error("set-up `{field}` = {value} is outside {min}..={max}")]
    SetupRange {
        /// `width` or `height`.
        field: &'static str,
        /// The offending value.
        value: u32,
        /// Smallest allowed.
        min: u32,
        /// Largest allowed.
        max: u32,
    },
    /// A pixel address outside the 512 × 512 framebuffer.
    #[error("pixel ({x}, {y}) is outside the {FRAME_SIDE}×{FRAME_SIDE} framebuffer")]
    Pixel {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
    },
    /// A status block whose reserved bits or codes are not what the block sends: the
    /// MISO line is not connected, or another device answered.
    #[error("status byte {byte} = {value:#04x} is not a valid {field}")]
    Status {
        /// Offset in the block.
        byte: usize,
        /// What was read there.
        value: u8,
        /// What the byte should hold.
        field: &'static str,
    },
}

/// Writes the transaction that pushes one packet: `address`, then the records' 36-bit
/// strings concatenated MSB first and zero-padded to whole bytes (9 bytes for two records,
/// 5 for one). Returns the bytes used.
pub fn packet(address: u8, records: &[u64], out: &mut [u8]) -> Result<usize, SpiFrameError> {
    if records.is_empty() || records.len() > MAX_PACKET_RECORDS {
        return Err(SpiFrameError::PacketLength {
            records: records.len(),
        });
    }
    let bits = records.len() * RECORD_BITS as usize;
    let needed = 1 + bits.div_ceil(8);
    if out.len() < needed {
        return Err(SpiFrameError::BufferTooSmall {
            needed,
            capacity: out.len(),
        });
    }
    let out = &mut out[..needed];
    out.fill(0);
    out[0] = address;
    let mut pos = 0usize;
    for (index, &value) in records.iter().enumerate() {
        if value >> RECORD_BITS != 0 {
            return Err(SpiFrameError::RecordTooWide { index, value });
        }
        for bit in (0..RECORD_BITS).rev() {
            if value >> bit & 1 == 1 {
                out[1 + pos / 8] |= 0x80 >> (pos % 8);
            }
            pos += 1;
        }
    }
    Ok(needed)
}

/// The frame registers the set-up packet writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Setup {
    /// Frame width in pixels, 1…512; fragments at `x ≥ width` are not written.
    pub width: u16,
    /// Frame height in pixels, 1…512.
    pub height: u16,
    /// RGB332 colour the frame is cleared to, and that CB clears to.
    pub background: u8,
    /// Which triangles the triangle unit discards by winding.
    pub cull: Cull,
}

impl Setup {
    /// The set-up record: `width − 1` (9 bits), `height − 1` (9), background (8), cull
    /// (2: none 0, clockwise 1, counter-clockwise 2), 8 zero bits.
    pub fn record(&self) -> Result<u64, SpiFrameError> {
        let side = |field, v: u16| {
            if (1..=FRAME_SIDE).contains(&v) {
                Ok(u64::from(v - 1))
            } else {
                Err(SpiFrameError::SetupRange {
                    field,
                    value: u32::from(v),
                    min: 1,
                    max: u32::from(FRAME_SIDE),
                })
            }
        };
        let cull = match self.cull {
            Cull::None => 0u64,
            Cull::Clockwise => 1,
            Cull::CounterClockwise => 2,
        };
        Ok(side("width", self.width)? << 27
            | side("height", self.height)? << 18
            | u64::from(self.background) << 10
            | cull << 8)
    }
}

/// Framebuffer address of a pixel: `y · 512 + x`, as the block's memory port uses it.
pub fn pixel_address(x: u32, y: u32) -> Result<u32, SpiFrameError> {
    let side = u32::from(FRAME_SIDE);
    if x >= side || y >= side {
        return Err(SpiFrameError::Pixel { x, y });
    }
    Ok(y * side + x)
}

/// The bytes that open a read-back from pixel `(x, y)`: address, the 18-bit pixel address
/// right-aligned in three bytes, and the turnaround byte. The pixels follow, one RGB332
/// byte per byte the master clocks, from consecutive addresses (row-major, wrapping to the
/// next row at x = 512).
pub fn read_header(x: u32, y: u32) -> Result<[u8; READ_HEADER_BYTES], SpiFrameError> {
    let a = pixel_address(x, y)?;
    Ok([ADDR_READ, (a >> 16) as u8, (a >> 8) as u8, a as u8, 0])
}

/// A sticky error the block latched: the first thing that went wrong since reset.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("FITkit raster block: {code} on address {channel:#04x}, packet #{packet}")]
pub struct BlockError {
    /// What went wrong.
    pub code: ErrorCode,
    /// The SPI address of the transaction that caused it.
    pub channel: u8,
    /// Packets committed to the FIFO before it (the failing packet's index).
    pub packet: u16,
}

/// The block's error codes (status byte 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ErrorCode {
    /// A write's payload was not the packet's byte count.
    #[error("wrong payload length")]
    Length,
    /// The bits after the packet's fields were not zero.
    #[error("non-zero padding")]
    Padding,
    /// The packet did not fit the FIFO's free records.
    #[error("input FIFO overrun")]
    Overrun,
    /// A clear packet with CB = 0.
    #[error("clear without CB")]
    ClearWithoutCb,
    /// An address the decoder does not know.
    #[error("unknown address")]
    UnknownAddress,
    /// The read-back's memory fetch was late for the SPI clock.
    #[error("read-back underrun")]
    ReadUnderrun,
}

impl ErrorCode {
    /// Every code, in the order of their numbers (1, 2, …).
    pub const ALL: [ErrorCode; 6] = [
        Self::Length,
        Self::Padding,
        Self::Overrun,
        Self::ClearWithoutCb,
        Self::UnknownAddress,
        Self::ReadUnderrun,
    ];

    /// Bits the status block and the RTL give a code.
    pub const BITS: u32 = 3;

    /// The code as the status block carries it: its place in [`ErrorCode::ALL`] plus one
    /// (0 is "no error").
    pub fn code(self) -> u8 {
        match self {
            Self::Length => 1,
            Self::Padding => 2,
            Self::Overrun => 3,
            Self::ClearWithoutCb => 4,
            Self::UnknownAddress => 5,
            Self::ReadUnderrun => 6,
        }
    }

    /// The code from its status byte; `None` for 0 (no error) and for codes the block
    /// does not send.
    pub fn from_code(code: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|e| e.code() == code)
    }

    /// The name of the code's macro in the generated Verilog header (`FITKIT_ERR_…`).
    pub fn verilog_name(self) -> &'static str {
        match self {
            Self::Length => "LENGTH",
            Self::Padding => "PADDING",
            Self::Overrun => "OVERRUN",
            Self::ClearWithoutCb => "CLEAR_WITHOUT_CB",
            Self::UnknownAddress => "UNKNOWN_ADDRESS",
            Self::ReadUnderrun => "READ_UNDERRUN",
        }
    }
}

/// Flags byte: a packet is queued or executing, or fragments are not yet written.
pub const FLAG_BUSY: u8 = 1 << 0;
/// Flags byte: a sticky error is latched (bytes 3–6 say which).
pub const FLAG_ERROR: u8 = 1 << 1;
/// Flags byte: the input FIFO is empty.
pub const FLAG_FIFO_EMPTY: u8 = 1 << 2;
/// Flags byte: a set-up has run since reset, so the frame registers are valid.
pub const FLAG_SETUP_DONE: u8 = 1 << 3;
/// Flags byte: this build of the block has no line unit (its `LINE_UNIT` parameter is 0),
/// so line packets are refused as an unknown address. Set for the life of the bitstream:
/// the seed's XC3S50 holds lines and triangles only as two designs, and the controller
/// learns from this bit which one it talks to. Clear on the full block, so a status block
/// from a build before the bit existed reads the same.
pub const FLAG_NO_LINE: u8 = 1 << 4;
/// Flags byte: this build of the block has no triangle unit (`TRI_UNIT` = 0), as
/// [`FLAG_NO_LINE`] for triangle packets.
pub const FLAG_NO_TRIANGLE: u8 = 1 << 5;
/// Every flag bit the block sends; the others are reserved and read as 0.
pub const FLAGS_ALL: u8 =
    FLAG_BUSY | FLAG_ERROR | FLAG_FIFO_EMPTY | FLAG_SETUP_DONE | FLAG_NO_LINE | FLAG_NO_TRIANGLE;

/// The status block, a snapshot the block takes when the address byte completes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Status {
    /// Records the input FIFO can take now (0…512).
    pub free: u16,
    /// `FLAG_*` bits.
    pub flags: u8,
    /// The first error since reset, if any.
    pub error: Option<BlockError>,
    /// Packets executed since the set-up.
    pub packets: u32,
    /// Fragments written to the framebuffer since the set-up.
    pub fragments: u32,
    /// Cycles the line unit was busy.
    pub line_cycles: u32,
    /// Cycles the triangle unit was busy.
    pub triangle_cycles: u32,
    /// Cycles spent clearing (set-up and clear packets).
    pub clear_cycles: u32,
    /// Cycle, counted from the set-up, at which the last packet finished.
    pub end_cycle: u32,
    /// Highest input FIFO occupancy seen, in records ÷ 2, saturating at 255.
    pub fifo_max_pairs: u8,
}

impl Status {
    /// Whether every pushed packet has run and its fragments are written.
    pub fn idle(&self) -> bool {
        self.flags & FLAG_BUSY == 0
    }

    /// Whether this build of the block draws lines ([`FLAG_NO_LINE`] clear).
    pub fn has_line_unit(&self) -> bool {
        self.flags & FLAG_NO_LINE == 0
    }

    /// Whether this build of the block draws triangles ([`FLAG_NO_TRIANGLE`] clear).
    pub fn has_triangle_unit(&self) -> bool {
        self.flags & FLAG_NO_TRIANGLE == 0
    }

    /// Decodes the 32 status bytes, refusing values the block never sends (a free count
    /// above 512, reserved flag bits, unknown error codes), which is what a floating MISO
    /// or a different device produces.
    pub fn decode(b: &[u8; STATUS_BYTES]) -> Result<Self, SpiFrameError> {
        let u32_at = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        use status_byte as at;
        let free = u16::from_be_bytes([b[at::FREE], b[at::FREE + 1]]);
        if free > FIFO_RECORDS {
            return Err(SpiFrameError::Status {
                byte: at::FREE,
                value: b[at::FREE],
                field: "free-record count (0..=512)",
            });
        }
        let flags = b[at::FLAGS];
        if flags & !FLAGS_ALL != 0 {
            return Err(SpiFrameError::Status {
                byte: at::FLAGS,
                value: flags,
                field: "flags byte",
            });
        }
        let error = match (flags & FLAG_ERROR != 0, b[at::ERROR_CODE]) {
            (false, 0) => None,
            (true, code) => Some(BlockError {
                code: ErrorCode::from_code(code).ok_or(SpiFrameError::Status {
                    byte: at::ERROR_CODE,
                    value: code,
                    field: "error code",
                })?,
                channel: b[at::ERROR_CHANNEL],
                packet: u16::from_be_bytes([b[at::ERROR_PACKET], b[at::ERROR_PACKET + 1]]),
            }),
            (false, code) => {
                return Err(SpiFrameError::Status {
                    byte: at::ERROR_CODE,
                    value: code,
                    field: "error code (the error flag is clear)",
                })
            }
        };
        Ok(Self {
            free,
            flags,
            error,
            packets: u32_at(status_byte::PACKETS),
            fragments: u32_at(status_byte::FRAGMENTS),
            line_cycles: u32_at(status_byte::LINE_CYCLES),
            triangle_cycles: u32_at(status_byte::TRIANGLE_CYCLES),
            clear_cycles: u32_at(status_byte::CLEAR_CYCLES),
            end_cycle: u32_at(status_byte::END_CYCLE),
            fifo_max_pairs: b[status_byte::FIFO_MAX_PAIRS],
        })
    }

    /// The bytes the block sends for this status: [`Status::decode`]'s inverse, for
    /// models and testbenches that must answer as the block does.
    pub fn encode(&self) -> [u8; STATUS_BYTES] {
        let mut b = [0u8; STATUS_BYTES];
        use status_byte as at;
        b[at::FREE..at::FREE + 2].copy_from_slice(&self.free.to_be_bytes());
        b[at::FLAGS] = self.flags & !FLAG_ERROR;
        if let Some(e) = self.error {
            b[at::FLAGS] |= FLAG_ERROR;
            b[at::ERROR_CODE] = e.code.code();
            b[at::ERROR_CHANNEL] = e.channel;
            b[at::ERROR_PACKET..at::ERROR_PACKET + 2].copy_from_slice(&e.packet.to_be_bytes());
        }
        for (i, v) in [
            (status_byte::PACKETS, self.packets),
            (status_byte::FRAGMENTS, self.fragments),
            (status_byte::LINE_CYCLES, self.line_cycles),
            (status_byte::TRIANGLE_CYCLES, self.triangle_cycles),
            (status_byte::CLEAR_CYCLES, self.clear_cycles),
            (status_byte::END_CYCLE, self.end_cycle),
        ] {
            b[i..i + 4].copy_from_slice(&v.to_be_bytes());
        }
        b[status_byte::FIFO_MAX_PAIRS] = self.fifo_max_pairs;
        b
    }
}

/// One `define of the generated Verilog header: the macro's name after `FITKIT_`, its
/// width in bits (0 for a plain number such as a byte offset) and its value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapEntry {
    /// Name after the `FITKIT_` prefix.
    pub name: &'static str,
    /// Width of a sized literal (`8'h20`); 0 writes a plain decimal number.
    pub bits: u32,
    /// The value.
    pub value: u32,
    /// One line saying what it is, written above it.
    pub doc: &'static str,
}

const fn entry(name: &'static str, bits: u32, value: u32, doc: &'static str) -> MapEntry {
    MapEntry {
        name,
        bits,
        value,
        doc,
    }
}

/// Everything about the block the RTL and its testbenches must agree on with this crate:
/// addresses, error codes, flag bits, status offsets and the FIFO's geometry.
/// [`write_verilog_header`] turns it into `fitkit_map.vh`, so no number here is typed
/// twice; the error codes follow in [`ErrorCode::ALL`]'s order.
pub const MAP: [MapEntry; 35] = [
    entry(
        "ADDR_SETUP",
        8,
        ADDR_SETUP as u32,
        "set-up packet (frame size, background, culling, then a clear)",
    ),
    entry("ADDR_LINE", 8, ADDR_LINE as u32, "line packets (2 records)"),
    entry(
        "ADDR_TRIANGLE",
        8,
        ADDR_TRIANGLE as u32,
        "triangle packets (2 records)",
    ),
    entry(
        "ADDR_CLEAR",
        8,
        ADDR_CLEAR as u32,
        "stand-alone clear packets (1 record)",
    ),
    entry("ADDR_STATUS", 8, ADDR_STATUS as u32, "status block read"),
    entry("ADDR_READ", 8, ADDR_READ as u32, "framebuffer read-back"),
    entry(
        "ADDR_RESET",
        8,
        ADDR_RESET as u32,
        "block reset, no payload",
    ),
    entry(
        "RECORD_BITS",
        0,
        RECORD_BITS,
        "bits of one input FIFO record",
    ),
    entry(
        "FIFO_RECORDS",
        0,
        FIFO_RECORDS as u32,
        "records the input FIFO holds",
    ),
    entry(
        "MAX_PACKET_BYTES",
        0,
        MAX_PACKET_BYTES as u32,
        "payload bytes of the widest packet",
    ),
    entry(
        "FRAME_SIDE",
        0,
        FRAME_SIDE as u32,
        "side of the framebuffer the coordinates address",
    ),
    entry("COORD_BITS", 0, COORD_BITS as u32, "bits of a coordinate"),
    entry(
        "COLOR_BITS",
        0,
        COLOR_BITS as u32,
        "bits of a colour (RGB332)",
    ),
    entry(
        "STATUS_BYTES",
        0,
        STATUS_BYTES as u32,
        "bytes of the status block",
    ),
    entry(
        "READ_TURNAROUND",
        0,
        READ_TURNAROUND as u32,
        "bytes between the read-back's address and its first pixel",
    ),
    entry(
        "READ_HEADER_BYTES",
        0,
        READ_HEADER_BYTES as u32,
        "bytes before the first pixel of a read-back",
    ),
    entry("ERR_BITS", 0, ErrorCode::BITS, "bits of an error code"),
    entry(
        "FLAG_BUSY",
        0,
        FLAG_BUSY.trailing_zeros(),
        "flags bit: a packet is queued or executing",
    ),
    entry(
        "FLAG_ERROR",
        0,
        FLAG_ERROR.trailing_zeros(),
        "flags bit: a sticky error is latched",
    ),
    entry(
        "FLAG_FIFO_EMPTY",
        0,
        FLAG_FIFO_EMPTY.trailing_zeros(),
        "flags bit: the input FIFO is empty",
    ),
    entry(
        "FLAG_SETUP_DONE",
        0,
        FLAG_SETUP_DONE.trailing_zeros(),
        "flags bit: a set-up has run since reset",
    ),
    entry(
        "FLAG_NO_LINE",
        0,
        FLAG_NO_LINE.trailing_zeros(),
        "flags bit: this build has no line unit",
    ),
    entry(
        "FLAG_NO_TRIANGLE",
        0,
        FLAG_NO_TRIANGLE.trailing_zeros(),
        "flags bit: this build has no triangle unit",
    ),
    entry(
        "STATUS_FREE",
        0,
        status_byte::FREE as u32,
        "status offset: free records, 2 bytes",
    ),
    entry(
        "STATUS_FLAGS",
        0,
        status_byte::FLAGS as u32,
        "status offset: flags",
    ),
    entry(
        "STATUS_ERROR_CODE",
        0,
        status_byte::ERROR_CODE as u32,
        "status offset: error code",
    ),
    entry(
        "STATUS_ERROR_CHANNEL",
        0,
        status_byte::ERROR_CHANNEL as u32,
        "status offset: the failing packet's address",
    ),
    entry(
        "STATUS_ERROR_PACKET",
        0,
        status_byte::ERROR_PACKET as u32,
        "status offset: the failing packet's index, 2 bytes",
    ),
    entry(
        "STATUS_PACKETS",
        0,
        status_byte::PACKETS as u32,
        "status offset: packets executed, 4 bytes",
    ),
    entry(
        "STATUS_FRAGMENTS",
        0,
        status_byte::FRAGMENTS as u32,
        "status offset: fragments written, 4 bytes",
    ),
    entry(
        "STATUS_LINE_CYCLES",
        0,
        status_byte::LINE_CYCLES as u32,
        "status offset: line unit busy cycles, 4 bytes",
    ),
    entry(
        "STATUS_TRIANGLE_CYCLES",
        0,
        status_byte::TRIANGLE_CYCLES as u32,
        "status offset: triangle unit busy cycles, 4 bytes",
    ),
    entry(
        "STATUS_CLEAR_CYCLES",
        0,
        status_byte::CLEAR_CYCLES as u32,
        "status offset: clearing cycles, 4 bytes",
    ),
    entry(
        "STATUS_END_CYCLE",
        0,
        status_byte::END_CYCLE as u32,
        "status offset: the last packet's end cycle, 4 bytes",
    ),
    entry(
        "STATUS_FIFO_MAX_PAIRS",
        0,
        status_byte::FIFO_MAX_PAIRS as u32,
        "status offset: highest FIFO occupancy / 2",
    ),
];

/// Writes `fitkit_map.vh`, the Verilog header every RTL module and testbench of the
/// FITkit block includes: one `` `define FITKIT_… `` per [`MAP`] entry and per
/// [`ErrorCode`], behind an include guard. The committed file is checked against this
/// output by a test, so the Verilog cannot drift from the Rust.
pub fn write_verilog_header(out: &mut impl core::fmt::Write) -> core::fmt::Result {
    writeln!(
        out,
        "// fitkit_map.vh -- the FITkit raster block's SPI map, status layout and FIFO geometry."
    )?;
    writeln!(out, "//")?;
    writeln!(
        out,
        "// GENERATED from protocol::fitkit_spi::MAP (protocol/src/fitkit_spi.rs); do not edit."
    )?;
    writeln!(
        out,
        "// `FPGFX_BLESS=1 cargo test -p protocol --test integration fitkit_map` rewrites it."
    )?;
    writeln!(out, "`ifndef FITKIT_MAP_VH")?;
    writeln!(out, "`define FITKIT_MAP_VH")?;
    let mut line = |name: &str, bits: u32, value: u32, doc: &str| -> core::fmt::Result {
        writeln!(out, "// {doc}")?;
        match bits {
            0 => writeln!(out, "`define FITKIT_{name} {value}"),
            8 => writeln!(out, "`define FITKIT_{name} {bits}'h{value:02X}"),
            _ => writeln!(out, "`define FITKIT_{name} {bits}'d{value}"),
        }
    };
    for e in MAP {
        line(e.name, e.bits, e.value, e.doc)?;
    }
    for e in ErrorCode::ALL {
        let mut name = heapless::String::<32>::new();
        // 32 bytes hold "ERR_" and the longest code name.
        let _ = write!(name, "ERR_{}", e.verilog_name());
        let mut doc = heapless::String::<48>::new();
        let _ = write!(doc, "error code: {e}");
        line(&name, ErrorCode::BITS, e.code() as u32, &doc)?;
    }
    writeln!(out, "`endif")
}
