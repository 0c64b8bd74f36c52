//! The framebuffer: RGB888 colour, an optional 24-bit depth plane and write counters.

use protocol::raster::Rgb;

/// Depth value of a cleared z-buffer ("far"): the largest unorm24.
pub const Z_FAR: u32 = (1 << 24) - 1;

/// One write to the colour plane, in the order the model made it: what a hardware
/// block's memory port would issue, so test vectors can hold a design to the model's
/// write stream and not only to its final frame ([`Framebuffer::record_writes`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FbWrite {
    /// The whole frame set to one colour, row by row from the top, left to right: the
    /// clear unit's order, kept as one entry rather than width × height of them.
    Clear(Rgb),
    /// One pixel, with the colour it holds after the write (a blend's result).
    Pixel {
        /// Column.
        x: u32,
        /// Row.
        y: u32,
        /// The colour written.
        color: Rgb,
    },
}

/// Colour plane (RGB888, row-major, no padding) plus depth and bookkeeping.
///
/// The write counters exist for the watertightness tests: a mesh drawn with the top-left
/// rule must write every covered pixel exactly once, so `overdraw` must stay zero.
#[derive(Debug, Clone)]
pub struct Framebuffer {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
    depth: Vec<u32>,
    writes: Option<Vec<u8>>,
    log: Option<Vec<FbWrite>>,
    fragments: u64,
    overdraw: u64,
    pat: [u8; PAT_BYTES],
    pat_color: Option<Rgb>,
}

/// Bytes of the cached span pattern (256 RGB888 pixels: most triangle spans in one copy,
/// and cheap to rebuild when the colour changes).
const PAT_BYTES: usize = 3 * 256;

/// Copies the start of the span pattern `pat` over `rgb[at..at + n]`. One memcpy per 256
/// pixels from a cached pattern row, since per-pixel 3-byte stores cost more than the
/// copy; but a memcpy call dominates the spans of slivers and triangle tips, so up to 32
/// bytes (10 pixels) are two overlapping fixed-size copies instead (the pattern is the
/// same at every offset, so the overlap writes the same bytes twice). Spans of up to five
/// pixels, a sliver's every row, vary in width from row to row, where the choice between
/// copy sizes was a mispredicted branch per row: they are one 16-byte read-modify-write
/// that keeps the bytes past the span (the plane is ours alone, nobody sees the rewrite).
#[inline(always)]
fn copy_pattern(rgb: &mut [u8], at: usize, n: usize, pat: &[u8; PAT_BYTES]) {
    const W: usize = 16;
    /// `KEEP[n]`: the bytes of a 16-byte word past its first `n` (a load, where a
    /// 128-bit shift by a variable count is a dozen instructions).
    const KEEP: [u128; W] = {
        let mut k = [0; W];
        let mut n = 0;
        while n < W {
            k[n] = !((1u128 << (8 * n)) - 1);
            n += 1;
        }
        k
    };
    if n < W {
        if let Some(Ok(word)) = rgb.get_mut(at..at + W).map(<&mut [u8; W]>::try_from) {
            let mut p = [0; W];
            p.copy_from_slice(&pat[..W]);
            let keep = KEEP[n];
            let old = u128::from_le_bytes(*word);
            *word = ((old & keep) | (u128::from_le_bytes(p) & !keep)).to_le_bytes();
            return;
        }
    }
    let dst = &mut rgb[at..at + n];
    macro_rules! two {
        ($k:literal) => {{
            dst[..$k].copy_from_slice(&pat[..$k]);
            dst[n - $k..].copy_from_slice(&pat[n - $k..n]);
        }};
    }
    match n {
        0 => {}
        1 => dst[0] = pat[0],
        2..=3 => two!(2),
        4..=7 => two!(4),
        8..=15 => two!(8),
        16..=32 => two!(16),
        _ => {
            for ch in dst.chunks_mut(PAT_BYTES) {
                ch.copy_from_slice(&pat[..ch.len()]);
            }
        }
    }
}

impl Framebuffer {
    /// A framebuffer cleared to `background`, depth cleared to far.
    pub fn new(width: u32, height: u32, background: Rgb) -> Self {
        let n = width as usize * height as usize;
        let mut fb = Self {
            width,
            height,
            rgb: vec![0; n * 3],
            depth: vec![Z_FAR; n],
            writes: None,
            log: None,
            fragments: 0,
            overdraw: 0,
            pat: [0; PAT_BYTES],
            pat_color: None,
        };
        fb.clear(background);
        fb
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// RGB bytes, row-major, 3 bytes per pixel.
    pub fn rgb(&self) -> &[u8] {
        &self.rgb
    }

    /// Depth plane (unorm24 in u32), row-major.
    pub fn depth(&self) -> &[u32] {
        &self.depth
    }

    /// Colour of one pixel; `None` outside the framebuffer.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Rgb> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let o = (y as usize * self.width as usize + x as usize) * 3;
        Some(Rgb::new(self.rgb[o], self.rgb[o + 1], self.rgb[o + 2]))
    }

    /// Fragments written since creation.
    pub fn fragments(&self) -> u64 {
        self.fragments
    }

    /// Writes to pixels already written since the last clear (only counted while write
    /// tracking is on).
    pub fn overdraw(&self) -> u64 {
        self.overdraw
    }

    /// Per-pixel write counts since the last clear (saturating at 255), if tracked.
    pub fn write_counts(&self) -> Option<&[u8]> {
        self.writes.as_deref()
    }

    /// Turns per-pixel write tracking on or off. Off by default because it costs a
    /// byte per fragment in the hot loop.
    pub fn track_writes(&mut self, on: bool) {
        self.writes = on.then(|| vec![0; self.width as usize * self.height as usize]);
        self.overdraw = 0;
    }

    /// Starts (or, with `false`, stops and drops) a log of every colour write in order,
    /// which [`Self::take_writes`] hands over. Off by default: it costs an entry per
    /// fragment, and only test-vector generation needs the order.
    pub fn record_writes(&mut self, on: bool) {
        self.log = on.then(Vec::new);
    }

    /// The writes logged since recording started or since the last call; recording
    /// continues. Empty when recording is off.
    pub fn take_writes(&mut self) -> Vec<FbWrite> {
        self.log.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Clears colour, depth and write counts.
    pub fn clear(&mut self, c: Rgb) {
        if let Some(log) = &mut self.log {
            log.push(FbWrite::Clear(c));
        }
        for px in self.rgb.chunks_exact_mut(3) {
            px[0] = c.r;
            px[1] = c.g;
            px[2] = c.b;
        }
        self.depth.fill(Z_FAR);
        if let Some(w) = &mut self.writes {
            w.fill(0);
        }
        self.overdraw = 0;
    }

    /// Books `n` pixels from `idx` just written: fragments, write counts and, when
    /// recording, the log (read back from the plane, so every writer is logged alike).
    #[inline]
    fn count(&mut self, idx: usize, n: usize) {
        self.fragments += n as u64;
        if let Some(log) = &mut self.log {
            let w = self.width as usize;
            for i in idx..idx + n {
                let o = 3 * i;
                log.push(FbWrite::Pixel {
                    x: (i % w) as u32,
                    y: (i / w) as u32,
                    color: Rgb::new(self.rgb[o], self.rgb[o + 1], self.rgb[o + 2]),
                });
            }
        }
        if let Some(w) = &mut self.writes {
            for c in &mut w[idx..idx + n] {
                if *c > 0 {
                    self.overdraw += 1;
                }
                *c = c.saturating_add(1);
            }
        }
    }

    /// Writes one pixel; coordinates outside are ignored (callers clip, this is a guard).
    #[inline]
    pub fn put(&mut self, x: u32, y: u32, c: Rgb) {
        if x >= self.width || y >= self.height {
            return;
        }
        let idx = y as usize * self.width as usize + x as usize;
        let o = idx * 3;
        self.rgb[o] = c.r;
        self.rgb[o + 1] = c.g;
        self.rgb[o + 2] = c.b;
        self.count(idx, 1);
    }

    /// Blends `c` over the pixel with weight `k / n` (AA coverage), rounding to nearest.
    pub fn blend(&mut self, x: u32, y: u32, c: Rgb, k: u32, n: u32) {
        if x >= self.width || y >= self.height || k == 0 || n == 0 {
            return;
        }
        let k = k.min(n);
        let idx = y as usize * self.width as usize + x as usize;
        let o = idx * 3;
        let mix = |s: u8, d: u8| ((s as u32 * k + d as u32 * (n - k) + n / 2) / n) as u8;
        self.rgb[o] = mix(c.r, self.rgb[o]);
        self.rgb[o + 1] = mix(c.g, self.rgb[o + 1]);
        self.rgb[o + 2] = mix(c.b, self.rgb[o + 2]);
        self.count(idx, 1);
    }

    /// Fills pixels `x0..x1` of row `y` with one colour: the flat-shaded fast path, a
    /// slice write with no per-pixel test.
    #[inline]
    pub fn fill_span(&mut self, y: u32, x0: u32, x1: u32, c: Rgb) {
        self.fill_spans(y, &[(x0, x1)], c);
    }

    /// Fills the runs `spans[k] = (x0, x1)` of the rows `y + k` with one colour (empty runs
    /// skipped, pixels outside the frame ignored): a triangle's band of rows in one call,
    /// so that the pattern check and the bookkeeping's branches are paid once per band.
    pub fn fill_spans(&mut self, y: u32, spans: &[(u32, u32)], c: Rgb) {
        if self.pat_color != Some(c) {
            for px in self.pat.chunks_exact_mut(3) {
                px.copy_from_slice(&[c.r, c.g, c.b]);
            }
            self.pat_color = Some(c);
        }
        let (w, tracking) = (self.width, self.tracking());
        // Rows below the frame are ignored.
        let rows = spans.len().min(self.height.saturating_sub(y) as usize);
        for (row, &(x0, x1)) in (y as usize * w as usize..)
            .step_by(w as usize)
            .zip(&spans[..rows])
        {
            let x1 = x1.min(w);
            if x0 >= x1 {
                continue;
            }
            let idx = row + x0 as usize;
            let n = (x1 - x0) as usize;
            copy_pattern(&mut self.rgb, idx * 3, n * 3, &self.pat);
            if tracking {
                self.count(idx, n);
            } else {
                self.fragments += n as u64;
            }
        }
    }

    /// Whether writes are counted per pixel or recorded: fast paths that write the plane
    /// directly must then go through `put`.
    pub fn tracking(&self) -> bool {
        self.writes.is_some() || self.log.is_some()
    }

    /// Raw RGB bytes for the fast line path, which counts its fragments itself.
    pub(crate) fn raw_rgb_mut(&mut self) -> &mut [u8] {
        &mut self.rgb
    }

    /// Adds fragments written through [`Self::raw_rgb_mut`].
    pub(crate) fn add_fragments(&mut self, n: u64) {
        self.fragments += n;
    }

    /// Depth test "less" and write: returns whether the fragment passed.
    #[inline]
    pub fn depth_test(&mut self, x: u32, y: u32, z: u32) -> bool {
        if x >= self.width || y >= self.height {
            return false;
        }
        let idx = y as usize * self.width as usize + x as usize;
        if z < self.depth[idx] {
            self.depth[idx] = z;
            true
        } else {
            false
        }
    }
}
