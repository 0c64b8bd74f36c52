//! The shape of a bus: record width and the bits each value gets ([`BusLayout`]), the
//! built-in layouts, and the command kinds a layout may carry ([`Kind`]).

use super::error::BusError;
use crate::raster::RasterCmd;

use postcard_schema::Schema;
use serde::{Deserialize, Serialize};

use crate::fitkit_spi;

/// Layout feature: triangles may carry one colour per vertex (Gouraud).
pub const FEAT_PER_VERTEX_COLOR: u16 = 1 << 0;
/// Layout feature: lines carry width, anti-aliasing, algorithm and an end colour.
pub const FEAT_LINE_STYLE: u16 = 1 << 1;
/// Layout feature: triangles may carry clip-space w for perspective-correct interpolation.
pub const FEAT_W: u16 = 1 << 2;
/// Layout feature: triangles may carry a texture reference.
pub const FEAT_TEXTURE: u16 = 1 << 3;

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

pub(super) const ALL_COMMANDS: u16 = (1 << 8) - 1;

/// Seed 000's FITkit bus, exactly as docs/requirements.md §2.1: 9-bit unsigned
/// whole-pixel coordinates, RGB332 colour, CB on top, 36-bit records, no opcode; lines,
/// triangles and a clear.
pub const FITKIT: BusLayout = BusLayout {
    name: "fitkit",
    record_bits: fitkit_spi::RECORD_BITS as u8,
    opcode_bits: 0,
    coord_bits: fitkit_spi::COORD_BITS,
    subpixel_bits: 0,
    signed_coords: false,
    color_bits: fitkit_spi::COLOR_BITS,
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
    /// A rasterized pixel on its way to the framebuffer ([`pack_fragment`](crate::bus::pack_fragment)).
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

    pub(super) fn from_opcode(op: u64) -> Option<Kind> {
        Kind::ALL
            .iter()
            .copied()
            .find(|k| k.opcode().map(u64::from) == Some(op))
    }
}

/// Which bus layout the FPGA's input FIFO decodes. A number rather than the
/// layout itself because both ends have the layouts compiled in; the wire only selects one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Schema)]
pub enum LayoutId {
    /// [`FITKIT`].
    Fitkit,
    /// [`EXTENDED`].
    Extended,
    /// [`WIDE`].
    Wide,
}

impl LayoutId {
    /// Every layout this crate defines, in declaration order: the numbering of the C
    /// library's `FPGFX_LAYOUT_*` codes and of raster test vectors' set-up words.
    pub const ALL: [LayoutId; 3] = [LayoutId::Fitkit, LayoutId::Extended, LayoutId::Wide];

    /// The layout this id names.
    pub fn layout(self) -> &'static BusLayout {
        match self {
            LayoutId::Fitkit => &FITKIT,
            LayoutId::Extended => &EXTENDED,
            LayoutId::Wide => &WIDE,
        }
    }

    /// The id of one of this crate's layouts (compared by name, since layouts are consts
    /// and have no stable address), or `None` for a layout defined elsewhere.
    pub fn of(layout: &BusLayout) -> Option<Self> {
        LayoutId::ALL
            .into_iter()
            .find(|id| id.layout().name == layout.name)
    }
}
