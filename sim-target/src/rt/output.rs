//! Output packing (RGB888 and the KCU116 16-bit mode), read-back reconstruction and the
//! PFM writer for the AOVs.

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

