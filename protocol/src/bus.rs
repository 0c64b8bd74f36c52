//! Bit-packed words from the controller into the FPGA raster block's input FIFO.
//!
//! Seed 000 (FITkit, fig. 6.2) packs every value of a command bit after bit into an N-byte
//! array that crosses SPI and lands in a FIFO of 36-bit records (RAMB16_S36_S36, 512
//! deep); the top bit, CB, asks for a framebuffer clear. That layout is [`FITKIT`]. The
//! same generic packer, driven by a [`BusLayout`], also serves [`EXTENDED`] (the same
//! 36-bit FIFO with an opcode, sub-pixel coordinates, RGB888, per-vertex colour, z,
//! perspective w, texture coordinates and every other [`RasterCmd`]) and [`WIDE`] (64-bit
//! records, D3D11-like 16.8 coordinates).
//!
//! # Bit order
//!
//! A command packet is a bit string written **most significant bit first** into the
//! record stream: its first bit is bit `record_bits − 1` of record 0, the next bit is
//! the one below, and after bit 0 of a record the string continues at the top of the
//! next record. Each field is itself written MSB first. Unused bits at the end of the last
//! record are zero, and [`unpack`] refuses a packet whose padding is not. Left alignment
//! lets the FPGA read CB, the opcode and the flags from the first record before it knows
//! how long the packet is (packets of the richer layouts have variable length).
//!
//! Fragments (raster block → framebuffer FIFO, [`pack_fragment`]) are fixed-length and,
//! as the seed says ("vyšší bity se nevyužívají"), **right-aligned**: the unused bits are
//! the top bits of the first record.
//!
//! # Field order
//!
//! Every packet starts with `CB` (1 bit) and, on layouts with `opcode_bits > 0`, the
//! opcode ([`Kind::opcode`]). The FITkit has no opcode: the SPI address (the "channel",
//! [`channel`]) tells line from triangle. Then, per command (a field in brackets exists
//! only when the layout has the feature, a field in braces only when the flag before it
//! is set; `c` = coordinate of `coord_bits`, `len` = unsigned length of `coord_bits`,
//! `px` = whole pixel of [`BusLayout::pixel_bits`], `col` = colour of `color_bits`):
//!
//! | command | fields after CB [, opcode] |
//! |---|---|
//! | clear | col |
//! | line | [gradient 1, aa 1, algo 1] x0 y0 x1 y1 [width len] col {color_to col} |
//! | triangle | [gouraud 1] [has_z 1] [has_w 1] [has_tex 1] x0 y0 x1 y1 x2 y2 col{×3 if gouraud} {z0 z1 z2} {w0 w1 w2 (32)} {base 16, wlog2 4, hlog2 4, u0 v0 u1 v1 u2 v2 (32 each), wrap 1, filter 2} |
//! | circle | cx cy radius(len) fill 1 col |
//! | fill | x(px) y(px) eight_connected 1 col |
//! | polygon | count−3 (4) even_odd 1 col, count × (x y) |
//! | bezier | cubic 1 tolerance(len) col, 3 or 4 × (x y) |
//! | patch | steps 8 col, 16 × (x y) |
//! | fragment (right-aligned) | x(px) y(px) col |
//!
//! [`fields`] lists them for any layout and command, and [`efficiency_table`] reports the
//! used fraction of the records.
//!
//! FITkit instance (docs/requirements.md §2.1), bit 44 … 0 of a line are
//! `CB x0 y0 x1 y1 col`, i.e. record 0 = bits 44…9 and record 1 = bits 8…0 in its top nine
//! bits; a triangle's 63 bits are `CB x0 y0 x1 y1 x2 y2 col`, record 0 = bits 62…27,
//! record 1 = bits 26…0 shifted up 9.
//!
//! # Colour
//!
//! `color_bits = 8` is RGB332 (`rrrgggbb`); 24 is RGB888 (`rrrrrrrr gggggggg bbbbbbbb`).
//! The 8-bit form expands by bit replication (`r₈ = r₃·0b100100100 >> 1`, i.e. `r3 << 5 |
//! r3 << 2 | r3 >> 1`; `b₈ = b₂ · 0x55`), so 0 and 7 map to 0 and 255. Packing a colour that
//! is not exactly one of those 256 values is an error rather than a silent rounding; a
//! caller that wants the nearest one says so with [`quantize_rgb332`].

use heapless::Vec;

use crate::fitkit_spi::{ADDR_CLEAR, ADDR_LINE, ADDR_TRIANGLE};

use crate::frame::{
    Bezier, BezierPatch, Circle, Connectivity, FillRule, Filter, Line, LineAlgo, Pixel, Point,
    Polygon, RasterCmd, Rgb, SeedFill, Shade, TexRef, Triangle, Wrap,
};

/// Records one packet can occupy in any built-in layout: the worst case is a textured,
/// perspective, z-tested Gouraud triangle or a 16-vertex polygon / Bézier patch on
/// [`EXTENDED`] (about 580 bits in 36-bit records).
pub const MAX_RECORDS: usize = 24;

/// Fields of one packet, for [`fields`]; a Bézier patch has the most (36).
pub const MAX_FIELDS: usize = 48;

/// Layout feature: triangles may carry one colour per vertex (Gouraud).
pub const FEAT_PER_VERTEX_COLOR: u16 = 1 << 0;
/// Layout feature: lines carry width, anti-aliasing, algorithm and an end colour.
pub const FEAT_LINE_STYLE: u16 = 1 << 1;
/// Layout feature: triangles may carry clip-space w for perspective-correct interpolation.
pub const FEAT_W: u16 = 1 << 2;
/// Layout feature: triangles may carry a texture reference.
pub const FEAT_TEXTURE: u16 = 1 << 3;

/// Bits of a texture base address: the texture memory holds 256 × 256 texels.
pub const TEX_BASE_BITS: u8 = 16;

/// The single address of layouts that carry an opcode in every packet.
pub const CHANNEL_STREAM: u8 = 0x04;

/// The shape of one bus: how wide its records are and how many bits each value gets.
/// Everything the packer does is derived from these numbers, so a new board is a new
/// constant rather than new code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusLayout {
    /// Name used in error messages and tables.
    pub name: &'static str,
    /// Width of one FIFO record, 1 … 64.
    pub record_bits: u8,
    /// Width of the opcode; 0 means the command kind travels in the SPI address instead.
    pub opcode_bits: u8,
    /// Width of one coordinate including its fraction bits.
    pub coord_bits: u8,
    /// Fraction bits of a coordinate.
    pub subpixel_bits: u8,
    /// Coordinates are two's complement (geometry may hang off the screen).
    pub signed_coords: bool,
    /// 8 (RGB332) or 24 (RGB888).
    pub color_bits: u8,
    /// Width of a per-vertex depth; 0 means the layout has no z.
    pub z_bits: u8,
    /// [`FEAT_PER_VERTEX_COLOR`] and the other `FEAT_*` bits: which optional fields the
    /// layout's packets have.
    pub features: u16,
    /// [`Kind::bit`] of every command the layout can carry.
    pub commands: u16,
}

const ALL_COMMANDS: u16 = (1 << 8) - 1;

/// Seed 000's FITkit bus, exactly as docs/requirements.md §2.1: 9-bit unsigned
/// whole-pixel coordinates, RGB332 colour, CB on top, 36-bit records, no opcode; lines,
/// triangles and a clear.
pub const FITKIT: BusLayout = BusLayout {
    name: "fitkit",
    record_bits: 36,
    opcode_bits: 0,
    coord_bits: 9,
    subpixel_bits: 0,
    signed_coords: false,
    color_bits: 8,
    z_bits: 0,
    features: 0,
    commands: Kind::Clear.bit() | Kind::Line.bit() | Kind::Triangle.bit(),
};

/// The same 36-bit FIFO carrying everything [`RasterCmd`] can say: 4-bit opcode, signed
/// 12.4 coordinates (±2048 pixels), RGB888, 24-bit z and every feature.
pub const EXTENDED: BusLayout = BusLayout {
    name: "extended",
    record_bits: 36,
    opcode_bits: 4,
    coord_bits: 16,
    subpixel_bits: 4,
    signed_coords: true,
    color_bits: 24,
    z_bits: 24,
    features: FEAT_PER_VERTEX_COLOR | FEAT_LINE_STYLE | FEAT_W | FEAT_TEXTURE,
    commands: ALL_COMMANDS,
};

/// A 64-bit FIFO (two RAMB36 ports side by side): 8-bit opcode, signed 16.8 coordinates
/// like D3D11 (±32768 pixels), RGB888, 24-bit z, every feature.
pub const WIDE: BusLayout = BusLayout {
    name: "wide",
    record_bits: 64,
    opcode_bits: 8,
    coord_bits: 24,
    subpixel_bits: 8,
    signed_coords: true,
    color_bits: 24,
    z_bits: 24,
    features: FEAT_PER_VERTEX_COLOR | FEAT_LINE_STYLE | FEAT_W | FEAT_TEXTURE,
    commands: ALL_COMMANDS,
};

/// Every built-in layout, for tables and tests.
pub const LAYOUTS: [BusLayout; 3] = [FITKIT, EXTENDED, WIDE];

impl BusLayout {
    /// Whether the layout has every `FEAT_*` bit in `f`.
    pub const fn has(&self, f: u16) -> bool {
        self.features & f == f
    }

    /// Whether the layout can carry commands of `kind` (fragments: always).
    pub const fn supports(&self, kind: Kind) -> bool {
        matches!(kind, Kind::Fragment) || self.commands & kind.bit() != 0
    }

    /// Bits of a whole-pixel position (seed fill, fragments): the integer part of a
    /// coordinate, without the sign bit.
    pub const fn pixel_bits(&self) -> u8 {
        self.coord_bits
            .saturating_sub(self.subpixel_bits)
            .saturating_sub(self.signed_coords as u8)
    }

    /// Checks that the numbers describe a bus the packer can drive: records of 1…64 bits,
    /// coordinates of 2…32 bits with at least one integer bit besides the sign and at most
    /// 16 pixel bits, colour of 8 or 24 bits, z of at most 32 bits, opcode of at most 8, and
    /// without an opcode only the commands that have a FITkit channel.
    pub const fn validate(&self) -> Result<(), BusError> {
        let reason = if self.record_bits == 0 || self.record_bits > 64 {
            Some("record_bits must be 1..=64")
        } else if self.coord_bits < 2 || self.coord_bits > 32 {
            Some("coord_bits must be 2..=32")
        } else if self.subpixel_bits as u16 + self.signed_coords as u16 >= self.coord_bits as u16
            || self.pixel_bits() > 16
        {
            Some("coordinates need 1..=16 integer bits")
        } else if self.color_bits != 8 && self.color_bits != 24 {
            Some("color_bits must be 8 or 24")
        } else if self.z_bits > 32 {
            Some("z_bits must be at most 32")
        } else if self.opcode_bits > 8 {
            Some("opcode_bits must be at most 8")
        } else if self.opcode_bits == 0
            && self.commands & !(Kind::Clear.bit() | Kind::Line.bit() | Kind::Triangle.bit()) != 0
        {
            Some("without an opcode only clear, line and triangle have a channel")
        } else {
            None
        };
        match reason {
            Some(reason) => Err(BusError::BadLayout {
                layout: self.name,
                reason,
            }),
            None => Ok(()),
        }
    }

    /// Smallest and largest raw coordinate value.
    pub const fn coord_range(&self) -> (i64, i64) {
        if self.signed_coords {
            (
                -(1i64 << (self.coord_bits - 1)),
                (1i64 << (self.coord_bits - 1)) - 1,
            )
        } else {
            (0, (1i64 << self.coord_bits) - 1)
        }
    }
}

/// A command kind: what an opcode (or a FITkit SPI address) selects.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// [`RasterCmd::Clear`].
    Clear,
    /// [`RasterCmd::Line`].
    Line,
    /// [`RasterCmd::Triangle`].
    Triangle,
    /// [`RasterCmd::Circle`].
    Circle,
    /// [`RasterCmd::Fill`].
    Fill,
    /// [`RasterCmd::Polygon`].
    Polygon,
    /// [`RasterCmd::Bezier`].
    Bezier,
    /// [`RasterCmd::Patch`].
    Patch,
    /// A rasterized pixel on its way to the framebuffer ([`pack_fragment`]).
    Fragment,
}

impl Kind {
    /// Every kind, commands first in opcode order.
    pub const ALL: [Kind; 9] = [
        Kind::Clear,
        Kind::Line,
        Kind::Triangle,
        Kind::Circle,
        Kind::Fill,
        Kind::Polygon,
        Kind::Bezier,
        Kind::Patch,
        Kind::Fragment,
    ];

    /// The opcode on layouts that have one; fragments have none (they use another FIFO).
    pub const fn opcode(self) -> Option<u8> {
        match self {
            Kind::Fragment => None,
            k => Some(k as u8),
        }
    }

    /// This kind's bit in [`BusLayout::commands`].
    pub const fn bit(self) -> u16 {
        1 << self as u8
    }

    /// Lower-case name for tables and errors.
    pub const fn name(self) -> &'static str {
        match self {
            Kind::Clear => "clear",
            Kind::Line => "line",
            Kind::Triangle => "triangle",
            Kind::Circle => "circle",
            Kind::Fill => "fill",
            Kind::Polygon => "polygon",
            Kind::Bezier => "bezier",
            Kind::Patch => "patch",
            Kind::Fragment => "fragment",
        }
    }

    /// The kind of a raster command.
    pub const fn of(cmd: &RasterCmd) -> Kind {
        match cmd {
            RasterCmd::Clear(_) => Kind::Clear,
            RasterCmd::Line(_) => Kind::Line,
            RasterCmd::Triangle(_) => Kind::Triangle,
            RasterCmd::Circle(_) => Kind::Circle,
            RasterCmd::Fill(_) => Kind::Fill,
            RasterCmd::Polygon(_) => Kind::Polygon,
            RasterCmd::Bezier(_) => Kind::Bezier,
            RasterCmd::Patch(_) => Kind::Patch,
        }
    }

    fn from_opcode(op: u64) -> Option<Kind> {
        Kind::ALL
            .iter()
            .copied()
            .find(|k| k.opcode().map(u64::from) == Some(op))
    }
}

/// Why a command could not be packed or a record string not unpacked. Every variant names
/// the field and the value, so that the host can tell the user which vertex of which
/// command does not fit the board.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum BusError {
    /// A value does not fit its field.
    #[error("{layout}: field `{field}` = {value} is outside {min}..={max}")]
    OutOfRange {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`] names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The offending value.
        value: i64,
        /// Smallest allowed value.
        min: i64,
        /// Largest allowed value.
        max: i64,
    },
    /// A coordinate has more fraction bits than the layout carries.
    #[error("{layout}: field `{field}` = {value} has fraction bits below the layout's {layout_bits} sub-pixel bits")]
    SubpixelPrecision {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`] names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The value in the caller's sub-pixel units.
        value: i64,
        /// The layout's sub-pixel bits.
        layout_bits: u8,
    },
    /// An 8-bit layout was given a colour that is not exactly an RGB332 value.
    #[error(
        "{layout}: field `{field}` = #{value:06x} is not an RGB332 colour (use quantize_rgb332)"
    )]
    ColorNotRepresentable {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`] names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The colour as 0xRRGGBB.
        value: u32,
    },
    /// The layout has no such command.
    #[error("{layout}: cannot carry {command} commands")]
    UnsupportedCommand {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// [`Kind::name`] of the command.
        command: &'static str,
    },
    /// The command uses a feature the layout lacks.
    #[error("{layout}: has no field for `{field}` (value {value})")]
    UnsupportedFeature {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field that would be needed.
        field: &'static str,
        /// The value that could not be sent.
        value: i64,
    },
    /// An opcode or enumeration value that names nothing.
    #[error("{layout}: field `{field}` = {value} is not a valid code")]
    InvalidCode {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The field as [`fields`] names it (`p0.x`, `radius`), so that the user can tell
        /// which vertex or value.
        field: &'static str,
        /// The value read from the records.
        value: u64,
    },
    /// A channel (SPI address) the layout does not use.
    #[error("{layout}: no command port at channel {channel:#04x}")]
    UnknownChannel {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// The SPI address given.
        channel: u8,
    },
    /// A record has bits set above the record width.
    #[error("record {index} = {value:#x} is wider than {record_bits} bits")]
    RecordTooWide {
        /// Index of the record.
        index: usize,
        /// The record as given, with bits set above `record_bits`.
        value: u64,
        /// The layout's record width.
        record_bits: u8,
    },
    /// The output buffer (or [`MAX_RECORDS`]) is too small for the packet.
    #[error("packet needs more than {capacity} records")]
    BufferTooSmall {
        /// Records available.
        capacity: usize,
    },
    /// The records end before the packet does.
    #[error("packet needs {needed} bits but the records hold {available}")]
    Truncated {
        /// Bits needed so far.
        needed: usize,
        /// Bits available.
        available: usize,
    },
    /// More records were given than the packet uses.
    #[error("packet uses {used} records but {given} were given")]
    TrailingRecords {
        /// Records the packet occupies.
        used: usize,
        /// Records passed in.
        given: usize,
    },
    /// Padding bits are not zero: the records are misaligned or corrupt.
    #[error("padding bits are not zero ({bits} bits = {value:#x})")]
    NonZeroPadding {
        /// Number of padding bits.
        bits: usize,
        /// The padding bits as read.
        value: u64,
    },
    /// A field wider than 64 bits or a record width outside 1…64.
    #[error("bad width {0}")]
    BadWidth(u8),
    /// A [`BusLayout`] whose numbers make no bus (see [`BusLayout::validate`]).
    #[error("layout {layout}: {reason}")]
    BadLayout {
        /// [`BusLayout::name`] of the refusing layout, so the message says which board.
        layout: &'static str,
        /// Which rule of [`BusLayout::validate`] the numbers break.
        reason: &'static str,
    },
}

const fn mask(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}

/// Writes bit fields MSB first into a string of records of `record_bits` bits each
/// (see the module's bit order). The records are zeroed on creation, so unused bits read 0.
#[derive(Debug)]
pub struct BitWriter<'a> {
    out: &'a mut [u64],
    record_bits: u8,
    pos: usize,
}

impl<'a> BitWriter<'a> {
    /// Starts writing at bit `start_bit` of the stream (0 = the top bit of `out[0]`).
    pub fn new(out: &'a mut [u64], record_bits: u8, start_bit: usize) -> Result<Self, BusError> {
        if record_bits == 0 || record_bits > 64 {
            return Err(BusError::BadWidth(record_bits));
        }
        out.iter_mut().for_each(|r| *r = 0);
        Ok(BitWriter {
            out,
            record_bits,
            pos: start_bit,
        })
    }

    /// Appends the low `width` bits of `value`, most significant first. A value with bits
    /// above `width` is refused rather than cut.
    pub fn write(&mut self, value: u64, width: u8) -> Result<(), BusError> {
        if width > 64 {
            return Err(BusError::BadWidth(width));
        }
        if value & !mask(u32::from(width)) != 0 {
            return Err(BusError::OutOfRange {
                layout: "",
                field: "bits",
                value: value as i64,
                min: 0,
                max: mask(u32::from(width)) as i64,
            });
        }
        let rb = usize::from(self.record_bits);
        if self.pos + usize::from(width) > self.out.len() * rb {
            return Err(BusError::BufferTooSmall {
                capacity: self.out.len(),
            });
        }
        let mut remaining = u32::from(width);
        while remaining > 0 {
            let rec = self.pos / rb;
            let avail = (rb - self.pos % rb) as u32;
            let take = avail.min(remaining);
            let chunk = (value >> (remaining - take)) & mask(take);
            self.out[rec] |= chunk << (avail - take);
            self.pos += take as usize;
            remaining -= take;
        }
        Ok(())
    }

    /// Bits written so far, counted from the start of the stream.
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Records touched so far.
    pub fn records_used(&self) -> usize {
        self.pos.div_ceil(usize::from(self.record_bits))
    }
}

/// Reads bit fields MSB first from a string of records (the inverse of [`BitWriter`]).
#[derive(Debug)]
pub struct BitReader<'a> {
    records: &'a [u64],
    record_bits: u8,
    pos: usize,
}

impl<'a> BitReader<'a> {
    /// Starts reading at bit `start_bit` of the stream. Records wider than `record_bits`
    /// are refused, so that a corrupt record cannot alias a valid one.
    pub fn new(records: &'a [u64], record_bits: u8, start_bit: usize) -> Result<Self, BusError> {
        if record_bits == 0 || record_bits > 64 {
            return Err(BusError::BadWidth(record_bits));
        }
        if let Some((index, &value)) = records
            .iter()
            .enumerate()
            .find(|(_, &r)| r & !mask(u32::from(record_bits)) != 0)
        {
            return Err(BusError::RecordTooWide {
                index,
                value,
                record_bits,
            });
        }
        Ok(BitReader {
            records,
            record_bits,
            pos: start_bit,
        })
    }

    /// Takes the next `width` bits as an unsigned value.
    pub fn read(&mut self, width: u8) -> Result<u64, BusError> {
        if width > 64 {
            return Err(BusError::BadWidth(width));
        }
        let rb = usize::from(self.record_bits);
        let available = self.records.len() * rb;
        if self.pos + usize::from(width) > available {
            return Err(BusError::Truncated {
                needed: self.pos + usize::from(width),
                available,
            });
        }
        let mut value = 0u64;
        let mut remaining = u32::from(width);
        while remaining > 0 {
            let rec = self.records[self.pos / rb];
            let avail = (rb - self.pos % rb) as u32;
            let take = avail.min(remaining);
            let chunk = (rec >> (avail - take)) & mask(take);
            value = if take >= 64 {
                chunk
            } else {
                (value << take) | chunk
            };
            self.pos += take as usize;
            remaining -= take;
        }
        Ok(value)
    }

    /// Bits consumed so far, counted from the start of the stream.
    pub fn position(&self) -> usize {
        self.pos
    }
}

/// How the caller's values relate to the packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PackOptions {
    /// Fraction bits of the caller's [`Point`]s and lengths (the frame's
    /// `RasterSetup::subpixel_bits`); they are rescaled to the layout's exactly or refused.
    pub subpixel_bits: u8,
    /// Set CB: clear the framebuffer before this command. [`RasterCmd::Clear`] always sets it.
    pub clear: bool,
}

/// A packet read back from records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Decoded {
    /// The CB bit: the packet asked for a clear before its command.
    pub clear: bool,
    /// The command, in the sub-pixel units asked of [`unpack`].
    pub cmd: RasterCmd,
}

/// One field of a packet, for documentation and efficiency figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// Name as used in errors.
    pub name: &'static str,
    /// Width in bits.
    pub bits: u8,
}

// ---------------------------------------------------------------------------------------
// The single description of every packet: a walk over the fields that encodes, decodes or
// lists them depending on `Io`, so the three can never disagree.

trait Io {
    const DECODE: bool;
    fn bits(&mut self, name: &'static str, width: u8, raw: u64) -> Result<u64, BusError>;
}

struct Enc<'a>(BitWriter<'a>);
impl Io for Enc<'_> {
    const DECODE: bool = false;
    fn bits(&mut self, _: &'static str, width: u8, raw: u64) -> Result<u64, BusError> {
        self.0.write(raw, width).map(|()| raw)
    }
}

struct Dec<'a>(BitReader<'a>);
impl Io for Dec<'_> {
    const DECODE: bool = true;
    fn bits(&mut self, _: &'static str, width: u8, _: u64) -> Result<u64, BusError> {
        self.0.read(width)
    }
}

struct Describe(Vec<Field, MAX_FIELDS>);
impl Io for Describe {
    const DECODE: bool = true;
    fn bits(&mut self, name: &'static str, bits: u8, _: u64) -> Result<u64, BusError> {
        self.0
            .push(Field { name, bits })
            .map_err(|_| BusError::BufferTooSmall {
                capacity: MAX_FIELDS,
            })?;
        Ok(0)
    }
}

struct Walker<'l, I> {
    io: I,
    layout: &'l BusLayout,
    /// The caller's sub-pixel bits.
    sub: u8,
}

const POINT_NAMES: [(&str, &str); 16] = [
    ("p0.x", "p0.y"),
    ("p1.x", "p1.y"),
    ("p2.x", "p2.y"),
    ("p3.x", "p3.y"),
    ("p4.x", "p4.y"),
    ("p5.x", "p5.y"),
    ("p6.x", "p6.y"),
    ("p7.x", "p7.y"),
    ("p8.x", "p8.y"),
    ("p9.x", "p9.y"),
    ("p10.x", "p10.y"),
    ("p11.x", "p11.y"),
    ("p12.x", "p12.y"),
    ("p13.x", "p13.y"),
    ("p14.x", "p14.y"),
    ("p15.x", "p15.y"),
];

fn rgb24(c: Rgb) -> u32 {
    (u32::from(c.r) << 16) | (u32::from(c.g) << 8) | u32::from(c.b)
}

/// The RGB332 byte of a colour that is exactly representable, or `None`.
pub fn rgb332_encode(c: Rgb) -> Option<u8> {
    let q = (c.r >> 5) << 5 | (c.g >> 5) << 2 | c.b >> 6;
    (rgb332_decode(q) == c).then_some(q)
}

/// Expands an RGB332 byte by bit replication (3-bit 7 and 2-bit 3 become 255).
pub fn rgb332_decode(q: u8) -> Rgb {
    let r3 = q >> 5;
    let g3 = (q >> 2) & 7;
    let b2 = q & 3;
    let e3 = |v: u8| (v << 5) | (v << 2) | (v >> 1);
    Rgb::new(e3(r3), e3(g3), b2 * 0x55)
}

/// The nearest RGB332 colour (per channel, by value): the explicit, lossy step a caller
/// takes before packing for an 8-bit layout.
pub fn quantize_rgb332(c: Rgb) -> Rgb {
    // Nearest of the levels bit replication actually produces (ties go to the darker).
    let nearest = |v: u8, levels: u8, expand: fn(u8) -> u8| {
        (0..levels)
            .min_by_key(|&k| (i16::from(expand(k)) - i16::from(v)).abs())
            .unwrap_or(0)
    };
    let e3 = |k: u8| (k << 5) | (k << 2) | (k >> 1);
    let e2 = |k: u8| k * 0x55;
    rgb332_decode(nearest(c.r, 8, e3) << 5 | nearest(c.g, 8, e3) << 2 | nearest(c.b, 4, e2))
}

impl<I: Io> Walker<'_, I> {
    fn range(&self, field: &'static str, value: i64, min: i64, max: i64) -> Result<(), BusError> {
        if value < min || value > max {
            Err(BusError::OutOfRange {
                layout: self.layout.name,
                field,
                value,
                min,
                max,
            })
        } else {
            Ok(())
        }
    }

    fn unsupported(&self, field: &'static str, value: i64) -> BusError {
        BusError::UnsupportedFeature {
            layout: self.layout.name,
            field,
            value,
        }
    }

    fn uint(&mut self, name: &'static str, width: u8, v: u64) -> Result<u64, BusError> {
        if !I::DECODE {
            self.range(name, v as i64, 0, mask(u32::from(width)) as i64)?;
        }
        self.io.bits(name, width, v)
    }

    fn u8f(&mut self, name: &'static str, width: u8, v: &mut u8) -> Result<(), BusError> {
        *v = self.uint(name, width, u64::from(*v))? as u8;
        Ok(())
    }

    fn u32f(&mut self, name: &'static str, width: u8, v: &mut u32) -> Result<(), BusError> {
        *v = self.uint(name, width, u64::from(*v))? as u32;
        Ok(())
    }

    fn i32f(&mut self, name: &'static str, v: &mut i32) -> Result<(), BusError> {
        *v = self.io.bits(name, 32, u64::from(*v as u32))? as u32 as i32;
        Ok(())
    }

    fn flag(&mut self, name: &'static str, b: &mut bool) -> Result<(), BusError> {
        *b = self.io.bits(name, 1, u64::from(*b))? != 0;
        Ok(())
    }

    fn code(&mut self, name: &'static str, width: u8, v: u64) -> Result<u64, BusError> {
        self.uint(name, width, v)
    }

    fn invalid(&self, field: &'static str, value: u64) -> BusError {
        BusError::InvalidCode {
            layout: self.layout.name,
            field,
            value,
        }
    }

    /// Caller units → layout units, exactly.
    fn to_layout(&self, field: &'static str, v: i64) -> Result<i64, BusError> {
        let (c, l) = (self.sub, self.layout.subpixel_bits);
        if c >= l {
            let d = c - l;
            if v & ((1i64 << d) - 1) != 0 {
                return Err(BusError::SubpixelPrecision {
                    layout: self.layout.name,
                    field,
                    value: v,
                    layout_bits: l,
                });
            }
            Ok(v >> d)
        } else {
            Ok(v << (l - c))
        }
    }

    /// Layout units → caller units, exactly.
    fn to_caller(&self, field: &'static str, raw: i64) -> Result<i64, BusError> {
        let (c, l) = (self.sub, self.layout.subpixel_bits);
        if c >= l {
            Ok(raw << (c - l))
        } else {
            let d = l - c;
            if raw & ((1i64 << d) - 1) != 0 {
                return Err(BusError::SubpixelPrecision {
                    layout: self.layout.name,
                    field,
                    value: raw,
                    layout_bits: l,
                });
            }
            Ok(raw >> d)
        }
    }

    fn coord(&mut self, name: &'static str, v: &mut i32) -> Result<(), BusError> {
        let bits = self.layout.coord_bits;
        let (min, max) = self.layout.coord_range();
        let mut raw = 0;
        if !I::DECODE {
            let l = self.to_layout(name, i64::from(*v))?;
            self.range(name, l, min, max)?;
            raw = (l as u64) & mask(u32::from(bits));
        }
        let got = self.io.bits(name, bits, raw)?;
        if I::DECODE {
            let signed = if self.layout.signed_coords && got >> (bits - 1) & 1 == 1 {
                got as i64 - (1i64 << bits)
            } else {
                got as i64
            };
            let c = self.to_caller(name, signed)?;
            *v = i32::try_from(c).map_err(|_| BusError::OutOfRange {
                layout: self.layout.name,
                field: name,
                value: c,
                min: i64::from(i32::MIN),
                max: i64::from(i32::MAX),
            })?;
        }
        Ok(())
    }

    fn point(
        &mut self,
        names: (&'static str, &'static str),
        p: &mut Point,
    ) -> Result<(), BusError> {
        self.coord(names.0, &mut p.x)?;
        self.coord(names.1, &mut p.y)
    }

    /// An unsigned length in sub-pixel units (radius, width, tolerance).
    fn length(&mut self, name: &'static str, v: &mut u32) -> Result<(), BusError> {
        let bits = self.layout.coord_bits;
        let mut raw = 0;
        if !I::DECODE {
            let l = self.to_layout(name, i64::from(*v))?;
            self.range(name, l, 0, mask(u32::from(bits)) as i64)?;
            raw = l as u64;
        }
        let got = self.io.bits(name, bits, raw)?;
        if I::DECODE {
            let c = self.to_caller(name, got as i64)?;
            *v = u32::try_from(c).map_err(|_| BusError::OutOfRange {
                layout: self.layout.name,
                field: name,
                value: c,
                min: 0,
                max: i64::from(u32::MAX),
            })?;
        }
        Ok(())
    }

    fn pixel(&mut self, name: &'static str, v: &mut u16) -> Result<(), BusError> {
        let bits = self.layout.pixel_bits();
        *v = self.uint(name, bits, u64::from(*v))? as u16;
        Ok(())
    }

    fn color(&mut self, name: &'static str, c: &mut Rgb) -> Result<(), BusError> {
        let bits = self.layout.color_bits;
        let mut raw = 0;
        if !I::DECODE {
            raw = match bits {
                8 => u64::from(rgb332_encode(*c).ok_or(BusError::ColorNotRepresentable {
                    layout: self.layout.name,
                    field: name,
                    value: rgb24(*c),
                })?),
                24 => u64::from(rgb24(*c)),
                other => return Err(BusError::BadWidth(other)),
            };
        }
        let got = self.io.bits(name, bits, raw)?;
        if I::DECODE {
            *c = match bits {
                8 => rgb332_decode(got as u8),
                _ => Rgb::new((got >> 16) as u8, (got >> 8) as u8, got as u8),
            };
        }
        Ok(())
    }

    /// A flag for an optional feature: on layouts without the feature the value must be
    /// off (and decodes as off).
    fn feature_flag(
        &mut self,
        present: bool,
        name: &'static str,
        b: &mut bool,
    ) -> Result<(), BusError> {
        if present {
            self.flag(name, b)
        } else if !I::DECODE && *b {
            Err(self.unsupported(name, 1))
        } else {
            *b = false;
            Ok(())
        }
    }

    fn body(&mut self, cmd: &mut RasterCmd) -> Result<(), BusError> {
        match cmd {
            RasterCmd::Clear(c) => self.color("color", c),
            RasterCmd::Line(l) => self.line(l),
            RasterCmd::Triangle(t) => self.triangle(t),
            RasterCmd::Circle(c) => self.circle(c),
            RasterCmd::Fill(f) => self.fill(f),
            RasterCmd::Polygon(p) => self.polygon(p),
            RasterCmd::Bezier(b) => self.bezier(b),
            RasterCmd::Patch(p) => self.patch(p),
        }
    }

    fn line(&mut self, l: &mut Line) -> Result<(), BusError> {
        let style = self.layout.has(FEAT_LINE_STYLE);
        let one_px = 1u32 << self.sub;
        let mut gradient = l.color_to.is_some();
        let mut dda = l.algo == LineAlgo::Dda;
        if style {
            self.flag("gradient", &mut gradient)?;
            self.flag("aa", &mut l.aa)?;
            self.flag("algo", &mut dda)?;
            l.algo = if dda {
                LineAlgo::Dda
            } else {
                LineAlgo::Bresenham
            };
        } else if I::DECODE {
            l.aa = false;
            l.algo = LineAlgo::Bresenham;
            l.width = one_px;
        } else {
            if gradient {
                return Err(self.unsupported("color_to", 1));
            }
            if l.aa {
                return Err(self.unsupported("aa", 1));
            }
            if dda {
                return Err(self.unsupported("algo", 1));
            }
            if l.width > one_px {
                return Err(self.unsupported("width", i64::from(l.width)));
            }
        }
        self.point(("x0", "y0"), &mut l.from)?;
        self.point(("x1", "y1"), &mut l.to)?;
        if style {
            self.length("width", &mut l.width)?;
        }
        self.color("color", &mut l.color)?;
        if gradient {
            let mut c = l.color_to.unwrap_or_default();
            self.color("color_to", &mut c)?;
            l.color_to = Some(c);
        } else {
            l.color_to = None;
        }
        Ok(())
    }

    fn triangle(&mut self, t: &mut Triangle) -> Result<(), BusError> {
        let lay = *self.layout;
        let mut gouraud = matches!(t.shade, Shade::Gouraud(_));
        let mut has_z = t.z.is_some();
        let mut has_w = t.w.is_some();
        let mut has_tex = t.tex.is_some();
        self.feature_flag(lay.has(FEAT_PER_VERTEX_COLOR), "gouraud", &mut gouraud)?;
        self.feature_flag(lay.z_bits > 0, "z", &mut has_z)?;
        self.feature_flag(lay.has(FEAT_W), "w", &mut has_w)?;
        self.feature_flag(lay.has(FEAT_TEXTURE), "tex", &mut has_tex)?;
        self.point(("x0", "y0"), &mut t.v[0])?;
        self.point(("x1", "y1"), &mut t.v[1])?;
        self.point(("x2", "y2"), &mut t.v[2])?;
        if gouraud {
            let mut cs = match t.shade {
                Shade::Gouraud(cs) => cs,
                Shade::Flat(c) => [c; 3],
            };
            self.color("color0", &mut cs[0])?;
            self.color("color1", &mut cs[1])?;
            self.color("color2", &mut cs[2])?;
            t.shade = Shade::Gouraud(cs);
        } else {
            let mut c = match t.shade {
                Shade::Flat(c) => c,
                Shade::Gouraud(cs) => cs[0],
            };
            self.color("color", &mut c)?;
            t.shade = Shade::Flat(c);
        }
        if has_z {
            let mut z = t.z.unwrap_or_default();
            self.u32f("z0", lay.z_bits, &mut z[0])?;
            self.u32f("z1", lay.z_bits, &mut z[1])?;
            self.u32f("z2", lay.z_bits, &mut z[2])?;
            t.z = Some(z);
        } else {
            t.z = None;
        }
        if has_w {
            let mut w = t.w.unwrap_or_default();
            self.u32f("w0", 32, &mut w[0])?;
            self.u32f("w1", 32, &mut w[1])?;
            self.u32f("w2", 32, &mut w[2])?;
            t.w = Some(w);
        } else {
            t.w = None;
        }
        if has_tex {
            let mut tex = t.tex.unwrap_or(TexRef {
                base: 0,
                width_log2: 0,
                height_log2: 0,
                uv: [[0; 2]; 3],
                wrap: Wrap::Repeat,
                filter: Filter::Nearest,
            });
            self.tex(&mut tex)?;
            t.tex = Some(tex);
        } else {
            t.tex = None;
        }
        Ok(())
    }

    fn tex(&mut self, tex: &mut TexRef) -> Result<(), BusError> {
        self.u32f("tex.base", TEX_BASE_BITS, &mut tex.base)?;
        self.u8f("tex.width_log2", 4, &mut tex.width_log2)?;
        self.u8f("tex.height_log2", 4, &mut tex.height_log2)?;
        const UV: [[&str; 2]; 3] = [["u0", "v0"], ["u1", "v1"], ["u2", "v2"]];
        for (uv, names) in tex.uv.iter_mut().zip(UV) {
            self.i32f(names[0], &mut uv[0])?;
            self.i32f(names[1], &mut uv[1])?;
        }
        let mut clamp = tex.wrap == Wrap::Clamp;
        self.flag("tex.clamp", &mut clamp)?;
        tex.wrap = if clamp { Wrap::Clamp } else { Wrap::Repeat };
        let f = match tex.filter {
            Filter::Nearest => 0,
            Filter::Bilinear => 1,
            Filter::Trilinear => 2,
        };
        tex.filter = match self.code("tex.filter", 2, f)? {
            0 => Filter::Nearest,
            1 => Filter::Bilinear,
            2 => Filter::Trilinear,
            v => return Err(self.invalid("tex.filter", v)),
        };
        Ok(())
    }

    fn circle(&mut self, c: &mut Circle) -> Result<(), BusError> {
        self.point(("cx", "cy"), &mut c.center)?;
        self.length("radius", &mut c.radius)?;
        self.flag("fill", &mut c.fill)?;
        self.color("color", &mut c.color)
    }

    fn fill(&mut self, f: &mut SeedFill) -> Result<(), BusError> {
        self.pixel("x", &mut f.seed.x)?;
        self.pixel("y", &mut f.seed.y)?;
        let mut eight = f.connectivity == Connectivity::Eight;
        self.flag("eight_connected", &mut eight)?;
        f.connectivity = if eight {
            Connectivity::Eight
        } else {
            Connectivity::Four
        };
        self.color("color", &mut f.color)
    }

    fn points<const N: usize>(
        &mut self,
        pts: &mut Vec<Point, N>,
        n: usize,
    ) -> Result<(), BusError> {
        if I::DECODE {
            pts.clear();
            for _ in 0..n {
                pts.push(Point::default())
                    .map_err(|_| BusError::BufferTooSmall { capacity: N })?;
            }
        }
        for (p, names) in pts.iter_mut().zip(POINT_NAMES) {
            self.point(names, p)?;
        }
        Ok(())
    }

    fn polygon(&mut self, p: &mut Polygon) -> Result<(), BusError> {
        let max = p.points.capacity() as i64;
        let n = p.points.len() as i64;
        if !I::DECODE {
            self.range("count", n, 3, max)?;
        }
        let n = self.uint("count", 4, (n - 3).max(0) as u64)? as i64 + 3;
        if I::DECODE {
            self.range("count", n, 3, max)?;
        }
        let mut even_odd = p.rule == FillRule::EvenOdd;
        self.flag("even_odd", &mut even_odd)?;
        p.rule = if even_odd {
            FillRule::EvenOdd
        } else {
            FillRule::NonZero
        };
        self.color("color", &mut p.color)?;
        self.points(&mut p.points, n as usize)
    }

    fn bezier(&mut self, b: &mut Bezier) -> Result<(), BusError> {
        let n = b.points.len() as i64;
        if !I::DECODE {
            self.range("points", n, 3, 4)?;
        }
        let mut cubic = n == 4;
        self.flag("cubic", &mut cubic)?;
        self.length("tolerance", &mut b.tolerance)?;
        self.color("color", &mut b.color)?;
        self.points(&mut b.points, if cubic { 4 } else { 3 })
    }

    fn patch(&mut self, p: &mut BezierPatch) -> Result<(), BusError> {
        self.u8f("steps", 8, &mut p.steps)?;
        self.color("color", &mut p.color)?;
        for (pt, names) in p.points.iter_mut().zip(POINT_NAMES) {
            self.point(names, pt)?;
        }
        Ok(())
    }

    /// CB and opcode; returns the kind (read from the opcode when decoding).
    fn header(&mut self, kind: Kind, clear: &mut bool) -> Result<Kind, BusError> {
        self.flag("cb", clear)?;
        if self.layout.opcode_bits == 0 {
            return Ok(kind);
        }
        let op = u64::from(kind.opcode().unwrap_or(0));
        let got = self.code("opcode", self.layout.opcode_bits, op)?;
        if I::DECODE {
            Kind::from_opcode(got)
                .filter(|k| self.layout.supports(*k))
                .ok_or(self.invalid("opcode", got))
        } else {
            Ok(kind)
        }
    }
}

/// Largest [`PackOptions::subpixel_bits`] (and `subpixel_bits` of [`unpack`]): the
/// precision of the caller's values that the packer rescales to and from a layout's, kept
/// low enough that every rescaled coordinate fits an i64. It bounds this conversion only;
/// what a target accepts is [`crate::frame::MAX_SUBPIXEL_BITS`].
pub const MAX_CALLER_SUBPIXEL_BITS: u8 = 24;

fn check(layout: &BusLayout, subpixel_bits: u8) -> Result<(), BusError> {
    layout.validate()?;
    if subpixel_bits > MAX_CALLER_SUBPIXEL_BITS {
        return Err(BusError::OutOfRange {
            layout: layout.name,
            field: "subpixel_bits",
            value: i64::from(subpixel_bits),
            min: 0,
            max: i64::from(MAX_CALLER_SUBPIXEL_BITS),
        });
    }
    Ok(())
}

/// A command of `kind` with every field zero: what decoding fills in.
fn template(kind: Kind) -> RasterCmd {
    let black = Rgb::default();
    let p = Point::default();
    match kind {
        Kind::Line => RasterCmd::Line(Line {
            from: p,
            to: p,
            color: black,
            color_to: None,
            width: 0,
            aa: false,
            algo: LineAlgo::Bresenham,
        }),
        Kind::Triangle => RasterCmd::Triangle(Triangle {
            v: [p; 3],
            shade: Shade::Flat(black),
            z: None,
            w: None,
            tex: None,
        }),
        Kind::Circle => RasterCmd::Circle(Circle {
            center: p,
            radius: 0,
            color: black,
            fill: false,
        }),
        Kind::Fill => RasterCmd::Fill(SeedFill {
            seed: Pixel::default(),
            color: black,
            connectivity: Connectivity::Four,
        }),
        Kind::Polygon => RasterCmd::Polygon(Polygon {
            points: Vec::new(),
            rule: FillRule::NonZero,
            color: black,
        }),
        Kind::Bezier => RasterCmd::Bezier(Bezier {
            points: Vec::new(),
            color: black,
            tolerance: 0,
        }),
        Kind::Patch => RasterCmd::Patch(BezierPatch {
            points: [p; 16],
            steps: 0,
            color: black,
        }),
        Kind::Clear | Kind::Fragment => RasterCmd::Clear(black),
    }
}

fn unsupported(layout: &BusLayout, kind: Kind) -> BusError {
    BusError::UnsupportedCommand {
        layout: layout.name,
        command: kind.name(),
    }
}

/// The SPI address a command of `kind` is written to on `layout`.
pub fn channel(layout: &BusLayout, kind: Kind) -> Result<u8, BusError> {
    if !layout.supports(kind) || kind == Kind::Fragment {
        return Err(unsupported(layout, kind));
    }
    if layout.opcode_bits > 0 {
        return Ok(CHANNEL_STREAM);
    }
    match kind {
        Kind::Line => Ok(ADDR_LINE),
        Kind::Triangle => Ok(ADDR_TRIANGLE),
        Kind::Clear => Ok(ADDR_CLEAR),
        _ => Err(unsupported(layout, kind)),
    }
}

fn kind_of_channel(layout: &BusLayout, ch: u8) -> Result<Option<Kind>, BusError> {
    let unknown = BusError::UnknownChannel {
        layout: layout.name,
        channel: ch,
    };
    if layout.opcode_bits > 0 {
        return if ch == CHANNEL_STREAM {
            Ok(None)
        } else {
            Err(unknown)
        };
    }
    let kind = match ch {
        ADDR_LINE => Kind::Line,
        ADDR_TRIANGLE => Kind::Triangle,
        ADDR_CLEAR => Kind::Clear,
        _ => return Err(unknown),
    };
    if layout.supports(kind) {
        Ok(Some(kind))
    } else {
        Err(unknown)
    }
}

/// Packs one command into `out` and returns the number of records used (the rest of `out`
/// is zeroed). Nothing is truncated: a value that does not fit is an error naming it.
pub fn pack_into(
    layout: &BusLayout,
    cmd: &RasterCmd,
    opts: PackOptions,
    out: &mut [u64],
) -> Result<usize, BusError> {
    check(layout, opts.subpixel_bits)?;
    let kind = Kind::of(cmd);
    if !layout.supports(kind) {
        return Err(unsupported(layout, kind));
    }
    let mut w = Walker {
        io: Enc(BitWriter::new(out, layout.record_bits, 0)?),
        layout,
        sub: opts.subpixel_bits,
    };
    let mut clear = opts.clear || kind == Kind::Clear;
    w.header(kind, &mut clear)?;
    let mut c = cmd.clone();
    w.body(&mut c)?;
    Ok(w.io.0.records_used())
}

/// Packs one command into a new record vector (see [`pack_into`]).
pub fn pack(
    layout: &BusLayout,
    cmd: &RasterCmd,
    opts: PackOptions,
) -> Result<Vec<u64, MAX_RECORDS>, BusError> {
    let mut buf = [0u64; MAX_RECORDS];
    let n = pack_into(layout, cmd, opts, &mut buf)?;
    Vec::from_slice(&buf[..n]).map_err(|_| BusError::BufferTooSmall {
        capacity: MAX_RECORDS,
    })
}

/// Decodes the records of exactly one packet received on `channel`, giving points and
/// lengths in `subpixel_bits` units. Trailing records, non-zero padding, unknown opcodes
/// and enumeration codes are errors.
pub fn unpack(
    layout: &BusLayout,
    channel: u8,
    records: &[u64],
    subpixel_bits: u8,
) -> Result<Decoded, BusError> {
    check(layout, subpixel_bits)?;
    let fixed = kind_of_channel(layout, channel)?;
    let mut w = Walker {
        io: Dec(BitReader::new(records, layout.record_bits, 0)?),
        layout,
        sub: subpixel_bits,
    };
    let mut clear = false;
    let kind = w.header(fixed.unwrap_or(Kind::Clear), &mut clear)?;
    if kind == Kind::Clear && !clear {
        return Err(w.invalid("cb", 0));
    }
    let mut cmd = template(kind);
    w.body(&mut cmd)?;
    let pos = w.io.0.position();
    let rb = usize::from(layout.record_bits);
    let used = pos.div_ceil(rb);
    if used != records.len() {
        return Err(BusError::TrailingRecords {
            used,
            given: records.len(),
        });
    }
    let pad = used * rb - pos;
    if pad > 0 {
        let value = w.io.0.read(pad as u8)?;
        if value != 0 {
            return Err(BusError::NonZeroPadding { bits: pad, value });
        }
    }
    Ok(Decoded { clear, cmd })
}

/// A rasterized pixel, as the raster block hands it to the framebuffer FIFO.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Fragment {
    /// Column, 0 at the left edge.
    pub x: u16,
    /// Row, 0 at the top edge.
    pub y: u16,
    /// Colour written to the framebuffer.
    pub color: Rgb,
}

fn fragment_geometry(layout: &BusLayout) -> (usize, usize) {
    let bits = 2 * usize::from(layout.pixel_bits()) + usize::from(layout.color_bits);
    let rb = usize::from(layout.record_bits);
    let records = bits.div_ceil(rb);
    (records, records * rb - bits)
}

fn walk_fragment<I: Io>(w: &mut Walker<'_, I>, f: &mut Fragment) -> Result<(), BusError> {
    w.pixel("x", &mut f.x)?;
    w.pixel("y", &mut f.y)?;
    w.color("color", &mut f.color)
}

/// Packs a fragment right-aligned (unused top bits, as in the seed's output FIFO).
pub fn pack_fragment(layout: &BusLayout, f: Fragment) -> Result<Vec<u64, 2>, BusError> {
    layout.validate()?;
    let (n, pad) = fragment_geometry(layout);
    let mut buf = [0u64; 2];
    let out = buf
        .get_mut(..n)
        .ok_or(BusError::BufferTooSmall { capacity: 2 })?;
    let mut w = Walker {
        io: Enc(BitWriter::new(out, layout.record_bits, pad)?),
        layout,
        sub: 0,
    };
    let mut f = f;
    walk_fragment(&mut w, &mut f)?;
    Vec::from_slice(&buf[..n]).map_err(|_| BusError::BufferTooSmall { capacity: 2 })
}

/// Decodes a fragment; the unused top bits must be zero.
pub fn unpack_fragment(layout: &BusLayout, records: &[u64]) -> Result<Fragment, BusError> {
    layout.validate()?;
    let (n, pad) = fragment_geometry(layout);
    if records.len() != n {
        return Err(BusError::TrailingRecords {
            used: n,
            given: records.len(),
        });
    }
    let mut r = BitReader::new(records, layout.record_bits, 0)?;
    let top = r.read(pad as u8)?;
    if top != 0 {
        return Err(BusError::NonZeroPadding {
            bits: pad,
            value: top,
        });
    }
    let mut w = Walker {
        io: Dec(r),
        layout,
        sub: 0,
    };
    let mut f = Fragment::default();
    walk_fragment(&mut w, &mut f)?;
    Ok(f)
}

/// The fields of the base form of a `kind` packet on `layout` (every optional flag off;
/// a polygon with 3 vertices, a quadratic Bézier), header included.
pub fn fields(layout: &BusLayout, kind: Kind) -> Result<Vec<Field, MAX_FIELDS>, BusError> {
    layout.validate()?;
    if !layout.supports(kind) {
        return Err(unsupported(layout, kind));
    }
    let mut w = Walker {
        io: Describe(Vec::new()),
        layout,
        sub: layout.subpixel_bits,
    };
    if kind == Kind::Fragment {
        walk_fragment(&mut w, &mut Fragment::default())?;
    } else {
        let mut clear = false;
        w.header(kind, &mut clear)?;
        w.body(&mut template(kind))?;
    }
    Ok(w.io.0)
}

/// How much of its records a packet uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Efficiency {
    /// [`BusLayout::name`], the table's row label.
    pub layout: &'static str,
    /// The command whose base form was measured.
    pub kind: Kind,
    /// Payload bits (header included).
    pub used_bits: u32,
    /// Records occupied.
    pub records: u32,
    /// Bits per record.
    pub record_bits: u32,
}

impl Efficiency {
    /// Used bits ÷ occupied bits.
    pub fn ratio(&self) -> f64 {
        f64::from(self.used_bits) / f64::from(self.records * self.record_bits)
    }

    /// [`Self::ratio`] in per cent.
    pub fn percent(&self) -> f64 {
        self.ratio() * 100.0
    }
}

/// The packing efficiency of the base form of `kind` on `layout` (see [`fields`]).
pub fn efficiency(layout: &BusLayout, kind: Kind) -> Result<Efficiency, BusError> {
    let used: u32 = fields(layout, kind)?
        .iter()
        .map(|f| u32::from(f.bits))
        .sum();
    let rb = u32::from(layout.record_bits);
    Ok(Efficiency {
        layout: layout.name,
        kind,
        used_bits: used,
        records: used.div_ceil(rb),
        record_bits: rb,
    })
}

/// Efficiency of every kind every built-in layout supports, layout by layout.
pub fn efficiency_table() -> Vec<Efficiency, { 3 * 9 }> {
    let mut rows = Vec::new();
    for layout in &LAYOUTS {
        for kind in Kind::ALL {
            if let Ok(e) = efficiency(layout, kind) {
                // Capacity is layouts × kinds, so this cannot fail.
                let _ = rows.push(e);
            }
        }
    }
    rows
}
