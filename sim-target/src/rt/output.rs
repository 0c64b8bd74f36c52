//! Output packing (RGB888 and the KCU116 16-bit mode), read-back reconstruction, and the
//! PFM writer and reader for the AOVs.

use std::io::{self, Write};

/// RGB888 in a 32-bit word per pixel: 0x00RRGGBB.
pub fn pack_rgb888(rgb8: &[u8]) -> Vec<u32> {
    rgb8.chunks_exact(3)
        .map(|p| (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32)
        .collect()
}

/// Inverse of [`pack_rgb888`].
pub fn unpack_rgb888(words: &[u32]) -> Vec<u8> {
    words
        .iter()
        .flat_map(|w| [(w >> 16) as u8, (w >> 8) as u8, *w as u8])
        .collect()
}

/// KCU116 16-bit mode: each pixel keeps G (high byte) and, in alternation along the row,
/// B (even x, first) or R (odd x) in the low byte.
pub fn pack_kcu116(rgb8: &[u8], width: u32) -> Vec<u16> {
    let w = width.max(1) as usize;
    rgb8.chunks_exact(3)
        .enumerate()
        .map(|(i, p)| {
            let other = if (i % w).is_multiple_of(2) {
                p[2]
            } else {
                p[0]
            };
            (p[1] as u16) << 8 | other as u16
        })
        .collect()
}

/// Read-back reconstruction of the KCU116 mode: G is exact; the missing R or B of a pixel
/// is the mean of its row neighbours that carry it (one-dimensional demosaic).
pub fn unpack_kcu116(words: &[u16], width: u32) -> Vec<u8> {
    let w = width.max(1) as usize;
    let mut out = Vec::with_capacity(words.len() * 3);
    for (row_i, row) in words.chunks(w).enumerate() {
        let _ = row_i;
        for x in 0..row.len() {
            let g = (row[x] >> 8) as u8;
            let own = row[x] as u8;
            let neigh = || {
                let mut s = 0u32;
                let mut n = 0u32;
                if x > 0 {
                    s += (row[x - 1] & 0xff) as u32;
                    n += 1;
                }
                if x + 1 < row.len() {
                    s += (row[x + 1] & 0xff) as u32;
                    n += 1;
                }
                (s + n / 2).checked_div(n).map_or(own, |v| v as u8)
            };
            if x.is_multiple_of(2) {
                out.extend([neigh(), g, own]);
            } else {
                out.extend([own, g, neigh()]);
            }
        }
    }
    out
}

/// Write a PFM (little-endian, bottom row first as the format requires). `channels` is 1
/// (depth, "Pf") or 3 (normal, "PF").
pub fn write_pfm(
    mut out: impl Write,
    width: u32,
    height: u32,
    channels: usize,
    data: &[f32],
) -> io::Result<()> {
    let expected = width as usize * height as usize * channels;
    if data.len() != expected || !(channels == 1 || channels == 3) {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("PFM: {} values for {width}x{height}x{channels}", data.len()),
        ));
    }
    let tag = if channels == 3 { "PF" } else { "Pf" };
    write!(out, "{tag}\n{width} {height}\n-1.0\n")?;
    let row = width as usize * channels;
    for r in (0..height as usize).rev() {
        for v in &data[r * row..(r + 1) * row] {
            out.write_all(&v.to_le_bytes())?;
        }
    }
    Ok(())
}

/// A decoded PFM: the layout [`write_pfm`] takes (top row first, `channels` samples per
/// pixel interleaved), whichever byte order and row order the file used.
#[derive(Debug, Clone, PartialEq)]
pub struct Pfm {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// 1 (`Pf`, e.g. depth) or 3 (`PF`, e.g. normals).
    pub channels: usize,
    /// `width · height · channels` samples, top row first.
    pub data: Vec<f32>,
}

/// A file [`read_pfm`] cannot decode.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PfmError {
    /// The first token is not `PF` or `Pf`.
    #[error("not a PFM file: it starts with {0:?}, not \"PF\" or \"Pf\"")]
    Tag(String),
    /// The size or scale line is missing or not a number.
    #[error("PFM header: {0}")]
    Header(String),
    /// More or fewer sample bytes than the header promises.
    #[error("PFM: the header promises {expected} bytes of samples, the file holds {got}")]
    Length {
        /// Bytes `width · height · channels · 4`.
        expected: usize,
        /// Bytes after the header.
        got: usize,
    },
}

/// Reads a PFM file. The header is three whitespace-separated fields after the tag (width,
/// height, scale) and exactly one whitespace byte before the samples; a negative scale
/// means little-endian (what [`write_pfm`] writes), a positive one big-endian (what other
/// tools may write: a testbench's dump must read back too). Rows are stored bottom first.
pub fn read_pfm(bytes: &[u8]) -> Result<Pfm, PfmError> {
    let mut pos = 0;
    let mut token = || -> Option<&str> {
        while bytes.get(pos).is_some_and(u8::is_ascii_whitespace) {
            pos += 1;
        }
        let start = pos;
        while bytes.get(pos).is_some_and(|b| !b.is_ascii_whitespace()) {
            pos += 1;
        }
        // Header bytes beyond ASCII are not a PFM header: reported as what they start.
        std::str::from_utf8(&bytes[start..pos]).ok()
    };
    let tag = token().unwrap_or("");
    let channels = match tag {
        "Pf" => 1,
        "PF" => 3,
        other => return Err(PfmError::Tag(other.chars().take(8).collect())),
    };
    let mut number = |what: &str| -> Result<f64, PfmError> {
        let t = token().unwrap_or("");
        t.parse::<f64>()
            .map_err(|_| PfmError::Header(format!("{what} {t:?} is not a number")))
    };
    let (w, h, scale) = (number("width")?, number("height")?, number("scale")?);
    let side = |v: f64, what: &str| -> Result<u32, PfmError> {
        if v >= 1.0 && v.fract() == 0.0 && v <= f64::from(u32::MAX) {
            Ok(v as u32)
        } else {
            Err(PfmError::Header(format!(
                "{what} {v} is not a positive integer"
            )))
        }
    };
    let (width, height) = (side(w, "width")?, side(h, "height")?);
    if scale == 0.0 || !scale.is_finite() {
        return Err(PfmError::Header(format!(
            "scale {scale} gives no byte order (negative: little-endian, positive: big-endian)"
        )));
    }
    // The single whitespace byte that ends the header.
    let body = bytes.get(pos + 1..).unwrap_or(&[]);
    let row = width as usize * channels;
    let expected = row
        .checked_mul(height as usize)
        .and_then(|n| n.checked_mul(4))
        .unwrap_or(usize::MAX);
    if body.len() != expected {
        return Err(PfmError::Length {
            expected,
            got: body.len(),
        });
    }
    let little = scale < 0.0;
    let sample = |b: &[u8]| {
        let b = [b[0], b[1], b[2], b[3]];
        if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut data = Vec::with_capacity(row * height as usize);
    for r in body.chunks_exact(4 * row).rev() {
        data.extend(r.chunks_exact(4).map(sample));
    }
    Ok(Pfm {
        width,
        height,
        channels,
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pfm_round_trips_through_the_writer() {
        for channels in [1, 3] {
            let mut data: Vec<f32> = (0..3 * 2 * channels)
                .map(|i| i as f32 * 0.5 - 1.0)
                .collect();
            // A depth plane's "no hit".
            data[1] = f32::INFINITY;
            let mut file = Vec::new();
            write_pfm(&mut file, 3, 2, channels, &data).expect("writes");
            let pfm = read_pfm(&file).expect("reads back");
            assert_eq!(
                pfm,
                Pfm {
                    width: 3,
                    height: 2,
                    channels,
                    data
                }
            );
        }
    }

    #[test]
    fn big_endian_and_bottom_row_first() {
        let mut file = b"Pf 1 2 1.0\n".to_vec();
        file.extend(2.0f32.to_be_bytes());
        file.extend(7.0f32.to_be_bytes());
        let pfm = read_pfm(&file).expect("reads");
        assert_eq!(pfm.data, [7.0, 2.0]);
    }

    #[test]
    fn bad_files_say_what_is_wrong() {
        assert_eq!(read_pfm(b"P6\n1 1\n255\n"), Err(PfmError::Tag("P6".into())));
        assert!(
            matches!(read_pfm(b"Pf\nx 1\n-1\n"), Err(PfmError::Header(m)) if m.contains("width"))
        );
        assert!(matches!(
            read_pfm(b"Pf\n0 1\n-1\n"),
            Err(PfmError::Header(_))
        ));
        assert!(
            matches!(read_pfm(b"Pf\n1 1\n0\n"), Err(PfmError::Header(m)) if m.contains("scale"))
        );
        assert_eq!(
            read_pfm(b"Pf\n1 1\n-1\n\0\0"),
            Err(PfmError::Length {
                expected: 4,
                got: 2
            })
        );
        assert!(matches!(read_pfm(b""), Err(PfmError::Tag(_))));
    }
}
