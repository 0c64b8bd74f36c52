//! The frame core `rt_cast`: a scene image in through its configuration port, one result
//! per pixel out (the nearest hit's object, distance and normal, and the colour).

use std::ptr::NonNull;

use crate::{ffi, RtlError};

/// One pixel's result as `rt_cast` gives it.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CastPixel {
    /// Column.
    pub x: u16,
    /// Row.
    pub y: u16,
    /// The primary ray hit an object within [bias, max_distance].
    pub hit: bool,
    /// The nearest object's index (meaningful with `hit`).
    pub obj: u8,
    /// Its distance, Q16.16 bits (meaningful with `hit`).
    pub t: i32,
    /// The world-space unit normal facing the ray, Q16.16 bits (0 for a miss).
    pub n: [i32; 3],
    /// The colour, RGB888 (R, G, B).
    pub rgb: [u8; 3],
    /// The colour in ViRAY's 16-bit KCU116 mode: G << 8 | B at even x, G << 8 | R at odd.
    pub kcu116: u16,
}

/// A frame from `rt_cast`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CastFrame {
    /// Every pixel in the order the core gave them (raster order).
    pub pixels: Vec<CastPixel>,
    /// Clock edges from the start pulse to the one after which `done` was high.
    pub cycles: u64,
    /// The core's refusal bits (`rt_cast.v`: value format, samples per pixel, object
    /// count, a shape not built, the frame's geometry, shadows, lights, materials); 0 for
    /// a frame it could render.
    pub err: u8,
}

/// Why a frame did not complete.
#[derive(Debug, thiserror::Error)]
pub enum CastError {
    /// No model.
    #[error(transparent)]
    Rtl(#[from] RtlError),
    /// `done` did not rise within the bound.
    #[error(
        "rt_cast did not raise done within {cycles} cycles (busy {busy}, {pixels} pixels out)"
    )]
    Stuck {
        /// The bound.
        cycles: u64,
        /// `busy` at the end.
        busy: bool,
        /// Pixels received.
        pixels: usize,
    },
    /// A register word's offset is beyond the core's 9-bit configuration address.
    #[error("scene word {0} is beyond the core's configuration address range")]
    Address(usize),
}

/// The Verilated `rt_cast` with every shape built, the default object capacity and one
/// point-light lane.
pub struct Cast {
    model: NonNull<ffi::RtCast>,
    cycle: u64,
}

// SAFETY: the model is owned by this value alone and only used through `&mut self`.
unsafe impl Send for Cast {}

impl Cast {
    /// A fresh model, every register and memory at 0, reset for four cycles.
    pub fn new() -> Result<Self, RtlError> {
        Self::with_x_seed(0)
    }

    /// A fresh model whose registers and memories start at random values drawn from
    /// `seed` (0: at 0), as uninitialised hardware does, then reset for four cycles.
    pub fn with_x_seed(seed: u64) -> Result<Self, RtlError> {
        Ok(Self {
            model: ffi::cast_new(seed)?,
            cycle: 0,
        })
    }

    fn edge(&mut self, cfg: Option<(u16, u32)>, start: bool, hold: bool) -> [u32; 14] {
        let (addr, data) = cfg.unwrap_or_default();
        let inputs = [
            u32::from(cfg.is_some()),
            u32::from(addr),
            data,
            u32::from(start),
            u32::from(hold),
        ];
        self.cycle += 1;
        ffi::cast_cycle(self.model, &inputs)
    }

    /// Writes the scene image `words` (word i at offset i), one word per clock.
    pub fn load(&mut self, words: &[u32]) -> Result<(), CastError> {
        for (i, w) in words.iter().enumerate() {
            let addr = u16::try_from(i)
                .ok()
                .filter(|a| *a < 512)
                .ok_or(CastError::Address(i))?;
            self.edge(Some((addr, *w)), false, false);
        }
        Ok(())
    }

    /// Starts a frame and clocks until `done`, at most `max_cycles` edges; `hold(cycle)`
    /// says on which clock edges (counted from the start pulse) the core is held.
    pub fn render(
        &mut self,
        max_cycles: u64,
        mut hold: impl FnMut(u64) -> bool,
    ) -> Result<CastFrame, CastError> {
        let mut frame = CastFrame::default();
        // a pixel is taken on an edge where pix_valid is high before it and hold is low
        let mut out = self.edge(None, true, false);
        let mut n = 1u64;
        loop {
            if n >= max_cycles {
                return Err(CastError::Stuck {
                    cycles: max_cycles,
                    busy: out[0] != 0,
                    pixels: frame.pixels.len(),
                });
            }
            let held = hold(n);
            if out[3] != 0 && !held {
                frame.pixels.push(CastPixel {
                    x: out[4] as u16,
                    y: out[5] as u16,
                    hit: out[6] != 0,
                    obj: out[7] as u8,
                    t: out[8] as i32,
                    n: [out[9] as i32, out[10] as i32, out[11] as i32],
                    rgb: [(out[12] >> 16) as u8, (out[12] >> 8) as u8, out[12] as u8],
                    kcu116: out[13] as u16,
                });
            }
            out = self.edge(None, false, held);
            n += 1;
            if out[1] != 0 {
                frame.cycles = n;
                frame.err = out[2] as u8;
                return Ok(frame);
            }
        }
    }

    /// Clock edges since reset.
    pub fn cycles(&self) -> u64 {
        self.cycle
    }

    /// Starts a VCD of every signal at `path` from the next clock edge on, closed when the
    /// model is dropped (the replay of a failing case); only with the `trace` feature.
    pub fn trace_to(&mut self, path: &std::path::Path) -> Result<(), RtlError> {
        crate::trace(path, |c| ffi::cast_trace(self.model, c))
    }
}

impl Drop for Cast {
    fn drop(&mut self) {
        ffi::cast_free(self.model);
    }
}
