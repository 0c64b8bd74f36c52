//! Bit-packed words from the controller into the FPGA raster block's input FIFO.
//!
//! Seed 000 (FITkit, fig. 6.2) packs every value of a command bit after bit into an N-byte
//! array that crosses SPI and lands in a FIFO of 36-bit records (RAMB16_S36_S36, 512
//! deep); the top bit, CB, asks for a framebuffer clear. That layout is [`FITKIT`]. The
//! same generic packer, driven by a [`BusLayout`], also serves [`EXTENDED`] (the same
//! 36-bit FIFO with an opcode, sub-pixel coordinates, RGB888, per-vertex colour, z,
//! perspective w, texture coordinates and every other [`RasterCmd`](crate::raster::RasterCmd)) and [`WIDE`] (64-bit
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

mod bits;
mod color;
mod efficiency;
mod error;
mod fragment;
mod layout;
mod pack;
mod walk;

pub use bits::{BitReader, BitWriter};
pub use color::{quantize_rgb332, rgb332_decode, rgb332_encode};
pub use efficiency::{efficiency, efficiency_table, Efficiency};
pub use error::BusError;
pub use fragment::{pack_fragment, unpack_fragment, Fragment};
pub use layout::{
    BusLayout, Kind, LayoutId, EXTENDED, FEAT_LINE_STYLE, FEAT_PER_VERTEX_COLOR, FEAT_TEXTURE,
    FEAT_W, FITKIT, LAYOUTS, WIDE,
};
pub use pack::{channel, fields, pack, pack_into, unpack, MAX_CALLER_SUBPIXEL_BITS};
pub use walk::{Decoded, Field, PackOptions};

/// Records one packet can occupy in any built-in layout: the worst case is a textured,
/// perspective, z-tested Gouraud triangle or a 16-vertex polygon / Bézier patch on
/// [`EXTENDED`] (about 580 bits in 36-bit records).
pub const MAX_RECORDS: usize = 24;

/// Fields of one packet, for [`fields`]; a Bézier patch has the most (36).
pub const MAX_FIELDS: usize = 48;

/// Bits of a texture base address: the texture memory holds 256 × 256 texels.
pub const TEX_BASE_BITS: u8 = 16;

/// The single address of layouts that carry an opcode in every packet.
pub const CHANNEL_STREAM: u8 = 0x04;
