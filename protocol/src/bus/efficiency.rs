//! How much of its records each packet uses, per layout and kind.

use super::error::BusError;
use super::layout::{BusLayout, Kind, LAYOUTS};
use super::pack::fields;
use heapless::Vec;

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
