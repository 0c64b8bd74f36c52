//! Fragments: what the raster block hands to its framebuffer FIFO, as records.

use super::bits::{BitReader, BitWriter};
use super::error::BusError;
use super::layout::BusLayout;
use super::walk::{Dec, Enc, Io, Walker};
use crate::raster::Rgb;
use heapless::Vec;

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

pub(super) fn fragment_geometry(layout: &BusLayout) -> (usize, usize) {
    let bits = 2 * usize::from(layout.pixel_bits()) + usize::from(layout.color_bits);
    let rb = usize::from(layout.record_bits);
    let records = bits.div_ceil(rb);
    (records, records * rb - bits)
}

pub(super) fn walk_fragment<I: Io>(
    w: &mut Walker<'_, I>,
    f: &mut Fragment,
) -> Result<(), BusError> {
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
