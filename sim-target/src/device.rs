//! The emulated FPGA as the controller sees it: an input FIFO of bus records, the raster
//! block behind it, the ray tracer's register file and texture memory, and read-back.
//!
//! Records are decoded with the same [`protocol::bus`] layout the controller packed them
//! with, so a packing bug shows up as a wrong picture or a decode error here, exactly as it
//! would on a board. Every mode (built-in, `fpgfx-sim`, QEMU) drives this one type.

use std::borrow::Cow;
use std::collections::VecDeque;

use protocol::bus::{quantize_rgb332, rgb332_encode, unpack, BusError, BusLayout, MAX_RECORDS};
use protocol::frame::{
    Block, Caps, FrameDone, Numeric, NumericSet, PixelFormat, Plane, ReadRequest, StartFrame,
};
use protocol::raster::{RasterSetup, Rgb};

use crate::raster::{Raster, RasterError};
use crate::rt::RenderOptions;
use crate::scene_regs::{from_regs, Regs, SceneRegsError};

/// Records in the input FIFO, as the raster model counts them.
const FIFO_RECORDS: usize = crate::raster::FIFO_DEPTH as usize;

/// Packets the model executes per [`Device::wait`]: how far the FPGA gets while the
/// controller waits once. Small, so back-pressure is exercised in every run.
const PACKETS_PER_WAIT: usize = 4;

/// A fault of the emulated FPGA: what a board would flag on its error line.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DeviceError {
    /// A FIFO packet did not decode with the device's layout.
    #[error("input FIFO packet #{packet} on channel {channel:#04x}: {source}")]
    Packet {
        /// Index of the packet since power-on.
        packet: u64,
        /// The bus channel it arrived on (which block it was for).
        channel: u8,
        /// The decoder's complaint.
        source: BusError,
    },
    /// The raster block refused a command.
    #[error("raster command #{packet}: {source}")]
    Raster {
        /// Index of the packet since power-on.
        packet: u64,
        /// The block's complaint.
        source: RasterError,
    },
    /// The raster block was used before its set-up, or set up wrongly.
    #[error("raster set-up: {0}")]
    Setup(RasterError),
    /// A packet larger than the FIFO's free space: the controller ignored FIFO_FREE.
    #[error("input FIFO overrun: {len} records pushed with {free} free")]
    Overrun {
        /// Records in the packet.
        len: usize,
        /// Records the FIFO had free when it arrived.
        free: usize,
    },
    /// Raster records arrived before any set-up.
    #[error("raster packet #{0} before any raster set-up")]
    NoSetup(u64),
    /// A register write past the end of the register file.
    #[error("register write at {offset} of {len} words past the {size}-word register file")]
    Registers {
        /// Index of the first register written.
        offset: u16,
        /// 32-bit words in the write.
        len: usize,
        /// Size of the register file.
        size: usize,
    },
    /// The register file does not describe a scene the ray tracer can render.
    #[error("ray-tracer registers: {0}")]
    Scene(SceneRegsError),
    /// The ray tracer refused the scene.
    #[error("ray tracer: {0}")]
    Render(crate::rt::RtError),
}

/// The emulated FPGA: one per board, driven by the controller through its bus calls
/// (`push_packet`, `write_regs`, `start`, `read`, …) and reset like the real one.
pub struct Device {
    layout: &'static BusLayout,
    fifo: VecDeque<(u8, heapless::Vec<u64, MAX_RECORDS>)>,
    fifo_records: usize,
    packets: u64,
    raster: Option<Raster>,
    setup: Option<RasterSetup>,
    regs: Vec<u32>,
    /// Texture memory, empty until the first write (then [`crate::raster::TEXTURE_WORDS`]
    /// words): power-on memory reads as zero, and most devices never hold a texel, so a
    /// device costs no megabyte to make (the C library, fuzzing and the tests make many).
    texels: Vec<u32>,
    done: VecDeque<FrameDone>,
    frames: u32,
    /// The block whose output read-back shows: the last one started or set up.
    shown: Block,
    rt_frame: Option<crate::rt::Frame>,
    /// The last read-back's bytes: a read is streamed in chunks, each a call to `read`.
    read_cache: Option<(ReadRequest, Vec<u8>)>,
}

impl Device {
    /// A device whose raster block reads `layout` records.
    pub fn new(layout: &'static BusLayout) -> Self {
        Self {
            layout,
            fifo: VecDeque::new(),
            fifo_records: 0,
            packets: 0,
            raster: None,
            setup: None,
            // Power-on register file: the ID words (magic, version) are read-only constants.
            regs: Regs::new().words().collect(),
            texels: Vec::new(),
            done: VecDeque::new(),
            frames: 0,
            shown: Block::Raster,
            rt_frame: None,
            read_cache: None,
        }
    }

    /// What this model can do, for the controller's hello.
    pub fn caps(&self) -> Caps {
        Caps {
            raster: true,
            ray_trace: true,
            numeric: Numeric::ALL
                .iter()
                .fold(NumericSet::default(), |s, &n| s.with(n)),
            pixel_formats: PixelFormat::Rgb888.bit()
                | PixelFormat::Rgb332.bit()
                | PixelFormat::Kcu116.bit()
                | PixelFormat::DepthF32.bit()
                | PixelFormat::NormalF32.bit(),
            max_width: protocol::MAX_FRAME_SIDE as u16,
            max_height: protocol::MAX_FRAME_SIDE as u16,
            max_subpixel_bits: protocol::raster::MAX_SUBPIXEL_BITS,
            queue_depth: 4,
            fifo_depth: FIFO_RECORDS as u16,
            max_objects: 8,
            max_lights: 2,
            texture_words: crate::raster::TEXTURE_WORDS as u32,
            raster_layout: protocol::bus::LayoutId::of(self.layout),
            // The float datapaths take IEEE words; the fixed ones (and f16, an experiment
            // without an HLS port of its own) read the seed's Q16.16.
            float_regs: NumericSet::default().with(Numeric::F32).with(Numeric::F64),
            // the golden model renders everything the register map can express
            rt_build: protocol::frame::RtBuild::FULL,
            link_payload: 0,
        }
    }

    /// The bus layout the raster block decodes.
    pub fn layout(&self) -> &'static BusLayout {
        self.layout
    }

    /// The raster block, once set up.
    pub fn raster(&self) -> Option<&Raster> {
        self.raster.as_ref()
    }

    /// The raster block, mutable, once set up: for callers that instrument the block
    /// between set-up and packets (recording its framebuffer writes for test vectors)
    /// while the packets still go through this device's FIFO and decoder.
    pub fn raster_mut(&mut self) -> Option<&mut Raster> {
        self.raster.as_mut()
    }

    /// FIFO_FREE: records the input FIFO can take.
    pub fn fifo_free(&self) -> usize {
        FIFO_RECORDS - self.fifo_records
    }

    /// Pushes one packet into the input FIFO.
    pub fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), DeviceError> {
        let free = self.fifo_free();
        let packet = heapless::Vec::from_slice(records).map_err(|_| DeviceError::Overrun {
            len: records.len(),
            free,
        })?;
        if records.len() > free {
            return Err(DeviceError::Overrun {
                len: records.len(),
                free,
            });
        }
        self.fifo_records += records.len();
        self.fifo.push_back((channel, packet));
        Ok(())
    }

    /// Lets the FPGA run for a moment: executes a few packets from the FIFO.
    pub fn wait(&mut self) -> Result<(), DeviceError> {
        for _ in 0..PACKETS_PER_WAIT {
            if !self.step()? {
                break;
            }
        }
        Ok(())
    }

    /// Executes one packet; `false` if the FIFO was empty.
    fn step(&mut self) -> Result<bool, DeviceError> {
        let Some((channel, records)) = self.fifo.pop_front() else {
            return Ok(false);
        };
        self.fifo_records -= records.len();
        let packet = self.packets;
        self.packets += 1;
        let (Some(raster), Some(setup)) = (self.raster.as_mut(), self.setup) else {
            return Err(DeviceError::NoSetup(packet));
        };
        let decoded =
            unpack(self.layout, channel, &records, setup.subpixel_bits).map_err(|source| {
                DeviceError::Packet {
                    packet,
                    channel,
                    source,
                }
            })?;
        // CB on a drawing command clears to the set-up's background first (seed 000).
        let cb_draw =
            decoded.clear && !matches!(decoded.cmd, protocol::raster::RasterCmd::Clear(_));
        if cb_draw {
            raster.draw_after_clear(&decoded.cmd)
        } else {
            raster.draw(&decoded.cmd)
        }
        .map_err(|source| DeviceError::Raster { packet, source })?;
        Ok(true)
    }

    /// Runs until the FIFO is empty.
    pub fn drain(&mut self) -> Result<(), DeviceError> {
        while self.step()? {}
        Ok(())
    }

    /// Whether every pushed packet has been executed.
    pub fn idle(&self) -> bool {
        self.fifo.is_empty()
    }

    /// Programs the raster block; earlier packets finish first, as on a board where the
    /// set-up registers are written behind the FIFO.
    pub fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), DeviceError> {
        self.drain()?;
        let mut raster = Raster::new(u32::from(setup.width), u32::from(setup.height), setup)
            .map_err(DeviceError::Setup)?;
        raster
            .write_texture(0, &texels_bytes(&self.texels))
            .map_err(DeviceError::Setup)?;
        self.raster = Some(raster);
        self.setup = Some(*setup);
        self.shown = Block::Raster;
        self.read_cache = None;
        Ok(())
    }

    /// Writes ray-tracer registers.
    pub fn write_regs(&mut self, offset: u16, words: &[u32]) -> Result<(), DeviceError> {
        let start = usize::from(offset);
        let size = self.regs.len();
        let slot = self
            .regs
            .get_mut(start..start + words.len())
            .ok_or(DeviceError::Registers {
                offset,
                len: words.len(),
                size,
            })?;
        slot.copy_from_slice(words);
        Ok(())
    }

    /// The ray tracer's register file.
    pub fn regs(&self) -> &[u32] {
        &self.regs
    }

    /// Writes texture memory (little-endian 32-bit texels), shared by both blocks.
    pub fn write_texels(&mut self, offset: u32, bytes: &[u8]) -> Result<(), DeviceError> {
        let words = crate::raster::TEXTURE_WORDS;
        let start = offset as usize;
        let fits = bytes.len().is_multiple_of(4)
            && start
                .checked_add(bytes.len() / 4)
                .is_some_and(|end| end <= words);
        if !fits {
            // Refused whether or not the raster block is set up: a write that lands
            // nowhere must not pass for one that landed.
            return Err(DeviceError::Setup(RasterError::TextureWrite {
                offset,
                len: bytes.len(),
                words,
            }));
        }
        if let Some(r) = &mut self.raster {
            r.write_texture(offset, bytes).map_err(DeviceError::Setup)?;
        }
        if bytes.is_empty() {
            return Ok(());
        }
        if self.texels.is_empty() {
            self.texels = vec![0; words];
        }
        let slot = &mut self.texels[start..start + bytes.len() / 4];
        for (t, b) in slot.iter_mut().zip(bytes.chunks_exact(4)) {
            *t = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
        }
        Ok(())
    }

    /// Starts a frame. The raster block's "frame" is the commands already queued: it
    /// finishes when they have run.
    pub fn start(&mut self, start: &StartFrame) -> Result<(), DeviceError> {
        match start.block {
            Block::Raster => {
                self.drain()?;
                let (cycles, work) = self
                    .raster
                    .as_ref()
                    .map_or((0, 0), |r| (r.stats().total_cycles(), r.stats().fragments));
                self.frames += 1;
                self.done.push_back(FrameDone {
                    frame_id: start.frame_id,
                    cycles,
                    work,
                });
                Ok(())
            }
            Block::RayTrace => {
                let regs =
                    Regs::from_words(&self.regs).map_err(|e| DeviceError::Scene(e.into()))?;
                let scene = from_regs(&regs).map_err(DeviceError::Scene)?;
                let opts = RenderOptions {
                    numeric: start.numeric,
                    aovs: start.aovs,
                    ..Default::default()
                };
                let frame = crate::rt::render(&scene, &opts).map_err(DeviceError::Render)?;
                self.frames += 1;
                self.done.push_back(FrameDone {
                    frame_id: start.frame_id,
                    cycles: frame.stats.board_cycles,
                    work: frame.stats.rays(),
                });
                self.rt_frame = Some(frame);
                self.shown = Block::RayTrace;
                self.read_cache = None;
                Ok(())
            }
        }
    }

    /// A finished frame, if any.
    pub fn poll_done(&mut self) -> Option<FrameDone> {
        self.done.pop_front()
    }

    /// Bytes a read-back of `req` produces, or `None` if the buffer does not exist.
    pub fn read_len(&self, req: &ReadRequest) -> Option<u32> {
        let (w, h) = self.shown_size()?;
        let r = req.rect;
        let inside = u32::from(r.x) + u32::from(r.w) <= w && u32::from(r.y) + u32::from(r.h) <= h;
        let format_ok = matches!(
            (req.plane, req.format),
            (
                Plane::Color,
                PixelFormat::Rgb888 | PixelFormat::Rgb332 | PixelFormat::Kcu116
            ) | (Plane::Depth, PixelFormat::DepthF32)
        ) || (req.plane, req.format, self.shown)
            == (Plane::Normal, PixelFormat::NormalF32, Block::RayTrace);
        // A ray-traced frame has its depth and normal planes only if its start asked for
        // them (`StartFrame::aovs`); reading absent planes is refused, not zero-filled.
        let plane_exists = match (self.shown, req.plane) {
            (Block::RayTrace, Plane::Depth) => self.rt_frame.as_ref()?.depth.is_some(),
            (Block::RayTrace, Plane::Normal) => self.rt_frame.as_ref()?.normal.is_some(),
            _ => true,
        };
        (inside && format_ok && plane_exists)
            .then(|| r.area() * req.format.bytes_per_pixel() as u32)
    }

    fn shown_size(&self) -> Option<(u32, u32)> {
        match self.shown {
            Block::Raster => self
                .raster
                .as_ref()
                .map(|r| (r.framebuffer().width(), r.framebuffer().height())),
            Block::RayTrace => self.rt_frame.as_ref().map(|f| (f.width, f.height)),
        }
    }

    /// Copies read-back bytes `offset..offset + out.len()` of `req` into `out`; bytes
    /// past the end of the request (a caller bug) read as zero.
    pub fn read(&mut self, req: &ReadRequest, offset: u32, out: &mut [u8]) {
        let copied = if (req.plane, req.format) == (Plane::Color, PixelFormat::Rgb888) {
            // The frame's own bytes, a row span at a time: no copy of the whole plane
            // first (a 1080p read-back spent more time building it than crossing the link).
            self.rgb888_span(req.rect, offset as usize, out)
        } else {
            if self.read_cache.as_ref().map(|(r, _)| r) != Some(req) {
                self.read_cache = self.plane_bytes(req).map(|b| (*req, b));
            }
            self.read_cache.as_ref().map_or(0, |(_, bytes)| {
                let start = (offset as usize).min(bytes.len());
                let end = (start + out.len()).min(bytes.len());
                out[..end - start].copy_from_slice(&bytes[start..end]);
                end - start
            })
        };
        out[copied..].fill(0);
    }

    /// Copies bytes `offset..` of `rect`'s RGB888 read-back (its rows, left to right)
    /// from the shown frame into `out`; returns how many there were.
    fn rgb888_span(&self, rect: protocol::frame::Rect, offset: usize, out: &mut [u8]) -> usize {
        let rgb = match self.shown {
            Block::Raster => self.raster.as_ref().map(|r| r.framebuffer().rgb()),
            Block::RayTrace => self.rt_frame.as_ref().map(|f| &f.rgb8[..]),
        };
        let (Some(rgb), Some((width, _))) = (rgb, self.shown_size()) else {
            return 0;
        };
        let row_bytes = usize::from(rect.w) * 3;
        let mut done = 0;
        while done < out.len() && row_bytes > 0 {
            let at = offset + done;
            let (row, col) = (at / row_bytes, at % row_bytes);
            if row >= usize::from(rect.h) {
                break;
            }
            let y = usize::from(rect.y) + row;
            let start = (y * width as usize + usize::from(rect.x)) * 3 + col;
            let n = (row_bytes - col).min(out.len() - done);
            let Some(src) = rgb.get(start..start + n) else {
                break;
            };
            out[done..done + n].copy_from_slice(src);
            done += n;
        }
        done
    }

    /// The whole read-back of `req` in its pixel format.
    fn plane_bytes(&self, req: &ReadRequest) -> Option<Vec<u8>> {
        let (width, _) = self.shown_size()?;
        let r = req.rect;
        // Only a depth read-back needs the depth plane: the raster's is converted from its
        // Z-buffer on demand, the ray tracer's is borrowed.
        let (rgb, depth, normal): (&[u8], Cow<[f32]>, Option<&[f32]>) = match self.shown {
            Block::Raster => {
                let fb = self.raster.as_ref()?.framebuffer();
                let z = if req.plane == Plane::Depth {
                    fb.depth()
                        .iter()
                        .map(|&z| z as f32 / crate::raster::Z_FAR as f32)
                        .collect()
                } else {
                    Cow::Borrowed(&[][..])
                };
                (fb.rgb(), z, None)
            }
            Block::RayTrace => {
                let f = self.rt_frame.as_ref()?;
                (
                    &f.rgb8,
                    Cow::Borrowed(f.depth.as_deref().unwrap_or_default()),
                    f.normal.as_deref(),
                )
            }
        };
        let pixels = (r.y..r.y + r.h).flat_map(|y| {
            (r.x..r.x + r.w).map(move |x| usize::from(y) * width as usize + usize::from(x))
        });
        let mut out = Vec::with_capacity(r.area() as usize * req.format.bytes_per_pixel());
        match (req.plane, req.format) {
            (Plane::Color, PixelFormat::Rgb888) => {
                for i in pixels {
                    out.extend_from_slice(rgb.get(i * 3..i * 3 + 3)?);
                }
            }
            (Plane::Color, PixelFormat::Rgb332) => {
                for i in pixels {
                    let c = rgb.get(i * 3..i * 3 + 3)?;
                    let q = quantize_rgb332(Rgb::new(c[0], c[1], c[2]));
                    out.push(rgb332_encode(q).unwrap_or(0));
                }
            }
            (Plane::Color, PixelFormat::Kcu116) => {
                // ViRAY's 16-bit mode keeps G and, alternately by column, B or R.
                let mut rect = Vec::with_capacity(r.area() as usize * 3);
                for i in pixels {
                    rect.extend_from_slice(rgb.get(i * 3..i * 3 + 3)?);
                }
                for word in crate::rt::pack_kcu116(&rect, u32::from(r.w)) {
                    out.extend_from_slice(&word.to_be_bytes());
                }
            }
            (Plane::Depth, PixelFormat::DepthF32) => {
                for i in pixels {
                    out.extend_from_slice(&depth.get(i)?.to_le_bytes());
                }
            }
            (Plane::Normal, PixelFormat::NormalF32) => {
                let n = normal?;
                for i in pixels {
                    for v in n.get(i * 3..i * 3 + 3)? {
                        out.extend_from_slice(&v.to_le_bytes());
                    }
                }
            }
            _ => return None,
        }
        Some(out)
    }

    /// Fragments written, FPGA cycles, frames done and the last ray-traced frame's
    /// saturations, for the controller's stats.
    pub fn counters(&self) -> protocol::frame::DeviceCounters {
        let (fragments, cycles) = self
            .raster
            .as_ref()
            .map_or((0, 0), |r| (r.stats().fragments, r.stats().total_cycles()));
        protocol::frame::DeviceCounters {
            fragments,
            cycles,
            frames: self.frames,
            saturations: self.rt_frame.as_ref().map_or(0, |f| f.stats.saturations),
            ..Default::default()
        }
    }

    /// Power-on state (the layout stays: it is the bitstream's).
    pub fn reset(&mut self) {
        *self = Self::new(self.layout);
    }
}

fn texels_bytes(texels: &[u32]) -> Vec<u8> {
    texels.iter().flat_map(|t| t.to_le_bytes()).collect()
}
