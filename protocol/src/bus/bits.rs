//! Bit strings across fixed-width records: the writer the packer fills and the reader
//! the unpacker drains, MSB first.

use super::error::BusError;

pub(super) const fn mask(width: u32) -> u64 {
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
