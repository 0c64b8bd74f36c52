//! Firmware files (.bin, Intel .hex, .elf) as the Write Memory blocks the flash will hold.

use std::collections::BTreeMap;
use std::io;
use std::path::Path;

use protocol::bootloader as bl;

/// Parses a decimal or 0x-prefixed hexadecimal address.
pub fn parse_u32(s: &str) -> Result<u32, String> {
    let t = s.trim();
    let r = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(&hex.replace('_', ""), 16),
        None => t.replace('_', "").parse(),
    };
    r.map_err(|_| format!("{s:?} is not a 32-bit address"))
}

/// Why an image file could not be turned into flash blocks.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// The file could not be read.
    #[error("cannot read {path}")]
    Read {
        /// The image file, as given.
        path: String,
        /// The underlying error, reported as this one's `source()`.
        source: io::Error,
    },
    /// A malformed Intel HEX record.
    #[error("Intel HEX line {line}: {message}")]
    Hex {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A malformed or unsupported ELF file.
    #[error("ELF: {0}")]
    Elf(String),
    /// Nothing to write.
    #[error("the image holds no data")]
    Empty,
    /// Two records or segments write the same byte.
    #[error("the image writes {0:#010x} twice")]
    Overlap(u32),
    /// Part of the image lies outside the chip's flash.
    #[error("the image covers {start:#x}..{end:#x}, outside the {chip}'s flash ({map})")]
    OutsideFlash {
        /// Address of the piece's first byte.
        start: u32,
        /// One past its last byte.
        end: u64,
        /// The part.
        chip: &'static str,
        /// Its flash regions, for the message.
        map: String,
    },
    /// `--go` or the password needs bytes the image does not hold.
    #[error("the image holds no {what} at {address:#x}..{end:#x}")]
    Missing {
        /// What was looked for ("reset vector").
        what: &'static str,
        /// First address.
        address: u32,
        /// One past the last.
        end: u32,
    },
}

/// Where a chip's images may go and how they are cut into the bootloader's write blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// The part, for messages.
    pub chip: &'static str,
    /// The programmable ranges, `(name, start, end)`.
    pub regions: &'static [(&'static str, u32, u32)],
    /// Blocks never cross a multiple of this; at most the bootloader's block limit.
    pub page: u32,
    /// Word size: block starts and lengths are multiples of it, padded with 0xFF (which
    /// programs nothing).
    pub word: u32,
}

/// The STM32F405: 1 MiB of flash, 256-byte Write Memory blocks of 32-bit words.
pub const STM32F405: Layout = Layout {
    chip: "STM32F405",
    regions: &[("flash", bl::FLASH_BASE, bl::FLASH_BASE + bl::FLASH_SIZE)],
    page: 256,
    word: 4,
};

/// The MSP430F168: information memory and main flash (with the vectors); RX data blocks
/// of 16-bit words, 128 bytes (an information segment; the BSL takes up to 250) so a
/// block never straddles a segment.
pub const MSP430F168: Layout = Layout {
    chip: "MSP430F168",
    regions: &[
        ("information memory", 0x1000, 0x1100),
        ("main flash", 0x4000, 0x1_0000),
    ],
    page: 128,
    word: 2,
};

/// One write: at most a [`Layout::page`] of bytes, word-aligned start and length, inside
/// one page-aligned page of flash.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Block {
    /// Where it goes.
    pub address: u32,
    /// What goes there (gaps inside the page are 0xFF, which programs nothing).
    pub data: Vec<u8>,
}

/// A firmware image as the flash will hold it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Blocks in address order.
    pub blocks: Vec<Block>,
}

impl Image {
    /// The STM32F405's blocks from `(address, bytes)` pieces ([`Image::build`]).
    pub fn from_pieces(pieces: &[(u32, Vec<u8>)]) -> Result<Image, ImageError> {
        Image::build(pieces, &STM32F405)
    }

    /// Builds the blocks from `(address, bytes)` pieces: checks overlap and that each
    /// piece lies in one of the layout's regions, pads to words with 0xFF and cuts at
    /// page boundaries.
    pub fn build(pieces: &[(u32, Vec<u8>)], layout: &Layout) -> Result<Image, ImageError> {
        let page_len = layout.page as usize;
        let word = layout.word as usize;
        let mut pages: BTreeMap<u32, (Vec<u8>, Vec<bool>)> = BTreeMap::new();
        let mut any = false;
        for (start, data) in pieces {
            if data.is_empty() {
                continue;
            }
            any = true;
            let end = u64::from(*start) + data.len() as u64;
            let inside = layout
                .regions
                .iter()
                .any(|&(_, lo, hi)| *start >= lo && end <= u64::from(hi));
            if !inside {
                let map = layout
                    .regions
                    .iter()
                    .map(|(name, lo, hi)| format!("{name} {lo:#x}..{hi:#x}"))
                    .collect::<Vec<_>>()
                    .join(", ");
                return Err(ImageError::OutsideFlash {
                    start: *start,
                    end,
                    chip: layout.chip,
                    map,
                });
            }
            for (i, &b) in data.iter().enumerate() {
                let a = start + i as u32;
                let page = pages
                    .entry(a - a % layout.page)
                    .or_insert_with(|| (vec![0xFF; page_len], vec![false; page_len]));
                let o = (a % layout.page) as usize;
                if page.1[o] {
                    return Err(ImageError::Overlap(a));
                }
                page.0[o] = b;
                page.1[o] = true;
            }
        }
        if !any {
            return Err(ImageError::Empty);
        }
        let blocks = pages
            .into_iter()
            .filter_map(|(base, (bytes, used))| {
                let first = used.iter().position(|&u| u)? / word * word;
                let last = used.iter().rposition(|&u| u)?;
                let end = (last / word + 1) * word;
                Some(Block {
                    address: base + first as u32,
                    data: bytes[first..end].to_vec(),
                })
            })
            .collect();
        Ok(Image { blocks })
    }

    /// The image's bytes at `[address, address + len)` (padding counts as 0xFF), or
    /// `None` if any of them is not in a block.
    pub fn bytes(&self, address: u32, len: u32) -> Option<Vec<u8>> {
        (address..address.checked_add(len)?)
            .map(|a| {
                let b = self
                    .blocks
                    .iter()
                    .find(|b| a >= b.address && a - b.address < b.data.len() as u32)?;
                Some(b.data[(a - b.address) as usize])
            })
            .collect()
    }

    /// Reads a .bin, .hex or .elf file (by extension; by content when the extension is
    /// something else) for the STM32F405 ([`Image::load_for`]).
    pub fn load(path: &Path, base: u32) -> Result<Image, ImageError> {
        Image::load_for(path, base, &STM32F405)
    }

    /// Reads a .bin, .hex or .elf file (by extension; by content when the extension is
    /// something else) for the chip `layout` describes. `base` places a .bin.
    pub fn load_for(path: &Path, base: u32, layout: &Layout) -> Result<Image, ImageError> {
        let bytes = std::fs::read(path).map_err(|source| ImageError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let pieces = match ext.as_str() {
            "hex" | "ihex" | "ihx" => parse_hex(&bytes)?,
            "elf" | "axf" | "out" => parse_elf(&bytes)?,
            "bin" => vec![(base, bytes)],
            _ if bytes.starts_with(b"\x7FELF") => parse_elf(&bytes)?,
            _ if bytes.first() == Some(&b':') => parse_hex(&bytes)?,
            _ => vec![(base, bytes)],
        };
        Image::build(&pieces, layout)
    }

    /// Bytes the image programs (including word padding).
    pub fn len(&self) -> usize {
        self.blocks.iter().map(|b| b.data.len()).sum()
    }

    /// True if there are no blocks (never, for a loaded image).
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// First address: where the vector table is, and where `--go` jumps.
    pub fn start(&self) -> Option<u32> {
        self.blocks.first().map(|b| b.address)
    }

    /// Indices of the sectors the image touches, ascending, without repeats.
    pub fn sectors(&self) -> Vec<u16> {
        let mut s: Vec<u16> = self
            .blocks
            .iter()
            .filter_map(|b| bl::sectors_touched(b.address, b.data.len() as u32))
            .flat_map(|ss| ss.iter().map(|s| s.index))
            .collect();
        s.sort_unstable();
        s.dedup();
        s
    }
}

/// Intel HEX: data (00), end (01), extended segment (02) and linear (04) address records;
/// start-address records (03, 05) are accepted and ignored (Go uses the image start).
pub fn parse_hex(bytes: &[u8]) -> Result<Vec<(u32, Vec<u8>)>, ImageError> {
    let text = std::str::from_utf8(bytes).map_err(|_| ImageError::Hex {
        line: 1,
        message: "not text".into(),
    })?;
    let mut pieces = Vec::new();
    let mut upper: u32 = 0;
    let mut ended = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |message: &str| ImageError::Hex {
            line,
            message: message.to_string(),
        };
        let l = raw.trim();
        if l.is_empty() {
            continue;
        }
        if ended {
            return Err(err("record after the end-of-file record"));
        }
        let body = l
            .strip_prefix(':')
            .ok_or_else(|| err("does not start with ':'"))?;
        if !body.len().is_multiple_of(2) || body.len() < 10 {
            return Err(err("odd or too short record"));
        }
        let rec: Vec<u8> = (0..body.len())
            .step_by(2)
            .map(|j| u8::from_str_radix(&body[j..j + 2], 16))
            .collect::<Result<_, _>>()
            .map_err(|_| err("not hexadecimal"))?;
        let count = usize::from(rec[0]);
        if rec.len() != count + 5 {
            return Err(err("byte count does not match the record length"));
        }
        if rec.iter().fold(0u8, |a, b| a.wrapping_add(*b)) != 0 {
            return Err(err("checksum mismatch"));
        }
        let offset = u32::from(u16::from_be_bytes([rec[1], rec[2]]));
        let data = &rec[4..4 + count];
        match rec[3] {
            0x00 => pieces.push((upper.wrapping_add(offset), data.to_vec())),
            0x01 => ended = true,
            0x02 if count == 2 => upper = u32::from(u16::from_be_bytes([data[0], data[1]])) << 4,
            0x04 if count == 2 => upper = u32::from(u16::from_be_bytes([data[0], data[1]])) << 16,
            0x03 | 0x05 => {}
            t => return Err(err(&format!("unsupported record type {t:02x} or length"))),
        }
    }
    if !ended {
        return Err(ImageError::Hex {
            line: text.lines().count(),
            message: "no end-of-file record (truncated file?)".into(),
        });
    }
    Ok(pieces)
}

/// ELF (32- or 64-bit, either endianness): the file bytes of every PT_LOAD segment at its
/// physical address (LMA), which is where initialised data lives in flash even though it
/// runs from RAM.
pub fn parse_elf(bytes: &[u8]) -> Result<Vec<(u32, Vec<u8>)>, ImageError> {
    use object::read::elf::{FileHeader, ProgramHeader};
    use object::Endianness;

    fn segments<H: FileHeader<Endian = Endianness>>(
        bytes: &[u8],
    ) -> Result<Vec<(u32, Vec<u8>)>, ImageError> {
        let e = |err: object::Error| ImageError::Elf(err.to_string());
        let header = H::parse(bytes).map_err(e)?;
        let endian = header.endian().map_err(e)?;
        let mut out = Vec::new();
        for ph in header.program_headers(endian, bytes).map_err(e)? {
            if ph.p_type(endian) != object::elf::PT_LOAD {
                continue;
            }
            let data = ph
                .data(endian, bytes)
                .map_err(|()| ImageError::Elf("a PT_LOAD segment lies outside the file".into()))?;
            if data.is_empty() {
                continue;
            }
            let paddr: u64 = ph.p_paddr(endian).into();
            let paddr = u32::try_from(paddr)
                .map_err(|_| ImageError::Elf(format!("segment address {paddr:#x} above 4 GiB")))?;
            out.push((paddr, data.to_vec()));
        }
        Ok(out)
    }

    match object::FileKind::parse(bytes) {
        Ok(object::FileKind::Elf32) => segments::<object::elf::FileHeader32<Endianness>>(bytes),
        Ok(object::FileKind::Elf64) => segments::<object::elf::FileHeader64<Endianness>>(bytes),
        _ => Err(ImageError::Elf("not an ELF file".into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex_parser() {
        // Extended linear address 0x0800, 4 data bytes at 0x0000, 2 at 0x0010, EOF.
        let text = ":020000040800F2\n:0400000001020304F2\n:02001000AABB89\n:00000001FF\n";
        let pieces = parse_hex(text.as_bytes()).unwrap();
        assert_eq!(
            pieces,
            vec![
                (0x0800_0000, vec![1, 2, 3, 4]),
                (0x0800_0010, vec![0xAA, 0xBB])
            ]
        );
        let image = Image::from_pieces(&pieces).unwrap();
        assert_eq!(
            image.blocks,
            vec![Block {
                address: 0x0800_0000,
                data: [
                    &[1, 2, 3, 4][..],
                    &[0xFF; 12][..],
                    &[0xAA, 0xBB, 0xFF, 0xFF][..]
                ]
                .concat()
            }]
        );
        let bad = ":0400000001020304F3\n:00000001FF\n";
        let e = parse_hex(bad.as_bytes()).unwrap_err();
        assert_eq!(e.to_string(), "Intel HEX line 1: checksum mismatch");
        let e = parse_hex(b":0400000001020304F2\n").unwrap_err();
        assert!(e.to_string().contains("no end-of-file record"), "{e}");
    }

    #[test]
    fn image_bounds_overlap_and_blocks() {
        let e = Image::from_pieces(&[(0x0810_0000 - 2, vec![0; 4])]).unwrap_err();
        assert!(matches!(e, ImageError::OutsideFlash { .. }), "{e}");
        let e = Image::from_pieces(&[(0x2000_0000, vec![0; 4])]).unwrap_err();
        assert!(matches!(e, ImageError::OutsideFlash { .. }), "{e}");
        let e =
            Image::from_pieces(&[(0x0800_0000, vec![0; 8]), (0x0800_0004, vec![1])]).unwrap_err();
        assert!(matches!(e, ImageError::Overlap(0x0800_0004)), "{e}");
        assert!(matches!(
            Image::from_pieces(&[]).unwrap_err(),
            ImageError::Empty
        ));
        // Unaligned start and a block boundary crossing: cut at 0x0800_0100.
        let img = Image::from_pieces(&[(0x0800_00FE, vec![7; 6])]).unwrap();
        assert_eq!(
            img.blocks,
            vec![
                Block {
                    address: 0x0800_00FC,
                    data: vec![0xFF, 0xFF, 7, 7]
                },
                Block {
                    address: 0x0800_0100,
                    data: vec![7, 7, 7, 7]
                }
            ]
        );
        assert_eq!(img.sectors(), vec![0]);
        let img = Image::from_pieces(&[(0x0800_3FFC, vec![1; 8])]).unwrap();
        assert_eq!(img.sectors(), vec![0, 1]);
    }

    #[test]
    fn msp430_blocks_words_and_bounds() {
        let img = Image::build(&[(0xFFDF, vec![7; 33])], &MSP430F168).unwrap();
        assert_eq!(
            img.blocks,
            vec![Block {
                address: 0xFFDE,
                data: [&[0xFF][..], &[7; 33][..], &[]].concat()
            }]
        );
        assert_eq!(img.bytes(0xFFFE, 2), Some(vec![7, 7]));
        assert_eq!(img.bytes(0xFFDC, 4), None);
        // 300 bytes from 0x4000: cut at 128-byte pages.
        let img = Image::build(&[(0x4000, vec![1; 300])], &MSP430F168).unwrap();
        let cuts: Vec<(u32, usize)> = img
            .blocks
            .iter()
            .map(|b| (b.address, b.data.len()))
            .collect();
        assert_eq!(cuts, [(0x4000, 128), (0x4080, 128), (0x4100, 44)]);
        for bad in [
            (0xFF00u32, 0x101usize),
            (0x3FFE, 4),
            (0x10FE, 4),
            (0x0200, 2),
        ] {
            let e = Image::build(&[(bad.0, vec![0; bad.1])], &MSP430F168).unwrap_err();
            assert!(matches!(e, ImageError::OutsideFlash { .. }), "{e}");
        }
        let e = Image::build(&[(0xFF00, vec![0; 0x101])], &MSP430F168).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the image covers 0xff00..0x10001, outside the MSP430F168's flash \
             (information memory 0x1000..0x1100, main flash 0x4000..0x10000)"
        );
        // The layout agrees with the BSL's own map.
        for (name, lo, hi) in MSP430F168.regions {
            let r = protocol::msp430_bsl::MSP430F168.region(*lo, hi - lo);
            assert_eq!(r.map(|r| r.name), Some(*name));
        }
    }

    #[test]
    fn address_parser() {
        assert_eq!(parse_u32("0x08000000"), Ok(0x0800_0000));
        assert_eq!(parse_u32("0X0800_4000"), Ok(0x0800_4000));
        assert_eq!(parse_u32("134217728"), Ok(0x0800_0000));
        assert!(parse_u32("0x1_0000_0000").is_err());
        assert!(parse_u32("flash").is_err());
    }
}
