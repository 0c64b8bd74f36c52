//! The `$readmemh` text format of fpgfx's test vectors.
//!
//! One word per line in hexadecimal, fixed width per file, `//` comments, and `@addr`
//! lines (hex word address) as Verilog's `$readmemh` accepts them, so a dump a user's
//! testbench writes with `$writememh` reads back too. A framebuffer file names its size
//! and pixel format in a first-line comment ([`FrameHeader`]), so a reader needs no
//! manifest to interpret it.

use core::fmt::Write as _;
use thiserror::Error;

/// A `$readmemh` file that could not be read, with the line it failed on (1-based).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[non_exhaustive]
pub enum MemhError {
    /// A word that is not hexadecimal, or wider than 64 bits.
    #[error("line {line}: {text:?} is not a hexadecimal word")]
    BadWord {
        /// 1-based line number.
        line: usize,
        /// The offending token.
        text: String,
    },
    /// An `@addr` line that is not a hexadecimal address.
    #[error("line {line}: {text:?} is not an @address")]
    BadAddress {
        /// 1-based line number.
        line: usize,
        /// The offending token.
        text: String,
    },
    /// An `@addr` beyond what the file may hold (a typo would otherwise allocate gigabytes).
    #[error("line {line}: address {addr:#x} is beyond the limit of {limit:#x} words")]
    AddressTooLarge {
        /// 1-based line number.
        line: usize,
        /// The address.
        addr: u64,
        /// The largest address accepted.
        limit: u64,
    },
    /// An `x`/`z` digit: simulation wrote an unknown value.
    #[error("line {line}: {text:?} holds unknown (x/z) bits")]
    Unknown {
        /// 1-based line number.
        line: usize,
        /// The offending token.
        text: String,
    },
    /// A framebuffer file without its `// fpgfx framebuffer WxH FORMAT` header.
    #[error("no `// fpgfx framebuffer WxH FORMAT` header on the first line")]
    NoHeader,
    /// A header whose size or pixel format is unknown.
    #[error("header {0:?}: expected `fpgfx framebuffer WxH rgb332|rgb888`")]
    BadHeader(String),
    /// A framebuffer file with more or fewer pixels than its header says.
    #[error("the header says {expected} pixels, the file holds {got}")]
    WrongLength {
        /// Pixels the header promises.
        expected: usize,
        /// Words in the file.
        got: usize,
    },
    /// A pixel word wider than its format.
    #[error("pixel {index}: {value:#x} does not fit {format}")]
    PixelTooWide {
        /// Row-major index of the pixel.
        index: usize,
        /// The word.
        value: u64,
        /// The format's name.
        format: &'static str,
    },
}

/// Words addressed beyond this are refused: 16 M words covers a 4096 × 4096 frame.
pub const ADDRESS_LIMIT: u64 = 1 << 24;

/// Formats `words` as a `$readmemh` file: the `comments` first (one `// ` line each), then
/// one word per line, `digits` hex digits wide (zero padded), so a Verilog memory of that
/// width loads it without width warnings.
pub fn format(comments: &[&str], words: impl IntoIterator<Item = u64>, digits: usize) -> String {
    let mut out = String::new();
    for c in comments {
        // Writing to a String cannot fail.
        let _ = writeln!(out, "// {c}");
    }
    for w in words {
        let _ = writeln!(out, "{w:0digits$x}");
    }
    out
}

/// A parsed `$readmemh` file: its comments and its words, with `@addr` gaps filled by
/// zero (Verilog leaves them unset; a comparison needs a value).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Memh {
    /// Comment texts without the `//` and surrounding blanks, in file order.
    pub comments: Vec<String>,
    /// The words, by address.
    pub words: Vec<u64>,
}

/// Refuses an address past [`ADDRESS_LIMIT`], whether an `@addr` named it or the words
/// counted up to it.
fn within_limit(line: usize, addr: u64) -> Result<(), MemhError> {
    if addr > ADDRESS_LIMIT {
        return Err(MemhError::AddressTooLarge {
            line,
            addr,
            limit: ADDRESS_LIMIT,
        });
    }
    Ok(())
}

/// Parses `$readmemh` text. Underscores inside words are ignored as Verilog does; `/* */`
/// block comments are not supported (fpgfx never writes them and `$writememh` neither).
pub fn parse(text: &str) -> Result<Memh, MemhError> {
    let mut m = Memh::default();
    let mut addr: u64 = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let (code, comment) = match raw.find("//") {
            Some(p) => (&raw[..p], Some(raw[p + 2..].trim())),
            None => (raw, None),
        };
        if let Some(c) = comment {
            m.comments.push(c.to_string());
        }
        for tok in code.split_whitespace() {
            if let Some(a) = tok.strip_prefix('@') {
                addr = u64::from_str_radix(a, 16).map_err(|_| MemhError::BadAddress {
                    line,
                    text: tok.to_string(),
                })?;
                within_limit(line, addr)?;
                continue;
            }
            let digits: String = tok.chars().filter(|&c| c != '_').collect();
            if digits.chars().any(|c| matches!(c, 'x' | 'X' | 'z' | 'Z')) {
                return Err(MemhError::Unknown {
                    line,
                    text: tok.to_string(),
                });
            }
            let w = u64::from_str_radix(&digits, 16).map_err(|_| MemhError::BadWord {
                line,
                text: tok.to_string(),
            })?;
            within_limit(line, addr)?;
            let a = addr as usize;
            if m.words.len() <= a {
                m.words.resize(a + 1, 0);
            }
            m.words[a] = w;
            addr += 1;
        }
    }
    Ok(m)
}

/// How a framebuffer file's words hold a pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum PixelFormat {
    /// The FITkit's byte: RRRGGGBB.
    Rgb332,
    /// `0xRRGGBB`.
    Rgb888,
}

impl PixelFormat {
    /// The spelling in a header.
    pub fn name(self) -> &'static str {
        match self {
            PixelFormat::Rgb332 => "rgb332",
            PixelFormat::Rgb888 => "rgb888",
        }
    }

    /// Hex digits per word.
    pub fn digits(self) -> usize {
        match self {
            PixelFormat::Rgb332 => 2,
            PixelFormat::Rgb888 => 6,
        }
    }

    /// The word as 8-bit RGB. RGB332 expands by bit replication, the way a VGA DAC
    /// driven from the top bits shows it, so both formats compare on one scale.
    pub fn to_rgb8(self, w: u64) -> [u8; 3] {
        match self {
            PixelFormat::Rgb332 => {
                let (r, g, b) = ((w >> 5) & 7, (w >> 2) & 7, w & 3);
                let r = (r << 5 | r << 2 | r >> 1) as u8;
                let g = (g << 5 | g << 2 | g >> 1) as u8;
                let b = (b * 0x55) as u8;
                [r, g, b]
            }
            PixelFormat::Rgb888 => [(w >> 16) as u8, (w >> 8) as u8, w as u8],
        }
    }

    fn max(self) -> u64 {
        match self {
            PixelFormat::Rgb332 => 0xff,
            PixelFormat::Rgb888 => 0xff_ffff,
        }
    }

    fn parse(s: &str) -> Option<Self> {
        match s {
            "rgb332" => Some(PixelFormat::Rgb332),
            "rgb888" => Some(PixelFormat::Rgb888),
            _ => None,
        }
    }
}

/// The first-line comment of a framebuffer file: `fpgfx framebuffer WxH FORMAT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameHeader {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// How each word holds a pixel.
    pub format: PixelFormat,
}

impl FrameHeader {
    /// The comment text (without `// `).
    pub fn comment(&self) -> String {
        format!(
            "fpgfx framebuffer {}x{} {}",
            self.width,
            self.height,
            self.format.name()
        )
    }

    fn parse(c: &str) -> Result<Self, MemhError> {
        let bad = || MemhError::BadHeader(c.to_string());
        let rest = c
            .strip_prefix("fpgfx framebuffer ")
            .ok_or(MemhError::NoHeader)?;
        let mut it = rest.split_whitespace();
        let size = it.next().ok_or_else(bad)?;
        let format = it.next().and_then(PixelFormat::parse).ok_or_else(bad)?;
        let (w, h) = size.split_once('x').ok_or_else(bad)?;
        let width: u32 = w.parse().map_err(|_| bad())?;
        let height: u32 = h.parse().map_err(|_| bad())?;
        if width == 0 || height == 0 || u64::from(width) * u64::from(height) > ADDRESS_LIMIT {
            return Err(bad());
        }
        Ok(FrameHeader {
            width,
            height,
            format,
        })
    }
}

/// Formats a framebuffer file: the header, then one pixel word per line in row-major order.
pub fn format_frame(header: &FrameHeader, pixels: impl IntoIterator<Item = u64>) -> String {
    format(&[&header.comment()], pixels, header.format.digits())
}

/// Parses a framebuffer file, checking its length and word widths against the header.
pub fn parse_frame(text: &str) -> Result<(FrameHeader, Vec<u64>), MemhError> {
    let m = parse(text)?;
    let first = m.comments.first().ok_or(MemhError::NoHeader)?;
    let header = FrameHeader::parse(first)?;
    let expected = header.width as usize * header.height as usize;
    if m.words.len() != expected {
        return Err(MemhError::WrongLength {
            expected,
            got: m.words.len(),
        });
    }
    if let Some((index, &value)) = m
        .words
        .iter()
        .enumerate()
        .find(|(_, &w)| w > header.format.max())
    {
        return Err(MemhError::PixelTooWide {
            index,
            value,
            format: header.format.name(),
        });
    }
    Ok((header, m.words))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn golden_text() {
        let h = FrameHeader {
            width: 2,
            height: 1,
            format: PixelFormat::Rgb332,
        };
        assert_eq!(
            format_frame(&h, [0xe0, 0x03]),
            "// fpgfx framebuffer 2x1 rgb332\ne0\n03\n"
        );
    }

    #[test]
    fn addresses_underscores_and_comments() {
        let m = parse("// a\n@2 ab_cd // b\n0\n").unwrap();
        assert_eq!(m.comments, ["a", "b"]);
        assert_eq!(m.words, [0, 0, 0xabcd, 0]);
    }

    #[test]
    fn errors_name_the_line() {
        assert_eq!(
            parse("00\n0g\n"),
            Err(MemhError::BadWord {
                line: 2,
                text: "0g".into()
            })
        );
        assert!(matches!(
            parse("xx\n"),
            Err(MemhError::Unknown { line: 1, .. })
        ));
        assert!(matches!(
            parse("@ffffffff\n0\n"),
            Err(MemhError::AddressTooLarge { line: 1, .. })
        ));
        assert_eq!(parse_frame("00\n"), Err(MemhError::NoHeader));
        assert!(matches!(
            parse_frame("// fpgfx framebuffer 2x1 rgb332\n00\n"),
            Err(MemhError::WrongLength {
                expected: 2,
                got: 1
            })
        ));
        assert!(matches!(
            parse_frame("// fpgfx framebuffer 1x1 rgb332\n100\n"),
            Err(MemhError::PixelTooWide { index: 0, .. })
        ));
        assert!(matches!(
            parse_frame("// fpgfx framebuffer 1x1 rgb565\n00\n"),
            Err(MemhError::BadHeader(_))
        ));
    }

    #[test]
    fn rgb332_expands_to_full_scale() {
        assert_eq!(PixelFormat::Rgb332.to_rgb8(0xff), [255, 255, 255]);
        assert_eq!(PixelFormat::Rgb332.to_rgb8(0x00), [0, 0, 0]);
        assert_eq!(PixelFormat::Rgb332.to_rgb8(0xe0), [255, 0, 0]);
    }

    proptest! {
        #[test]
        fn frames_round_trip(w in 1u32..20, h in 1u32..20, rgb888: bool, seed: u64) {
            let format = if rgb888 { PixelFormat::Rgb888 } else { PixelFormat::Rgb332 };
            let header = FrameHeader { width: w, height: h, format };
            let px: Vec<u64> = (0..u64::from(w * h))
                .map(|i| (seed.wrapping_mul(i + 1) >> 7) & format.max())
                .collect();
            let text = format_frame(&header, px.iter().copied());
            prop_assert_eq!(parse_frame(&text), Ok((header, px)));
        }
    }
}
