//! `fpgfx render`: a ray-tracer scene through a [`Session`] to an image.
//!
//! The scene is written into the ray tracer's register image (protocol::scene) and only
//! the registers that differ from the target's current image are sent, exactly as
//! ViRAY's MicroBlaze driver updates its AXI registers between frames.

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

use protocol::frame::{
    Block, DeviceFrame, HostFrame, Numeric, PixelFormat, Plane, ReadRequest, Rect, StartFrame,
    Stats,
};

use protocol::scene::{diff, ValueFormat};
use sim_target::rt::Scene;
use sim_target::scene_regs::{Regs, SceneRegsError};

use crate::session::{Phase, Session, SessionError, Transport};

/// How the colour buffer is read back.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Packing {
    /// Three bytes per pixel.
    Rgb888,
    /// ViRAY's KCU116 16-bit mode (G plus alternately B or R), reconstructed on the host.
    Kcu116,
}

protocol::named! {
    Packing, what = "packing", ignore_case = false, values = [Packing::Rgb888, Packing::Kcu116],
    { Rgb888 => ["rgb888"], Kcu116 => ["kcu116"] }
}

/// What to fetch besides the colour buffer.
#[derive(Debug, Clone, Copy, Default)]
pub struct Aovs {
    /// Distance to the first hit per pixel.
    pub depth: bool,
    /// World-space normal per pixel.
    pub normal: bool,
}

/// An AOV the target can send besides the colour buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Aov {
    /// Distance to the first hit, one channel.
    Depth,
    /// World-space normal, three channels.
    Normal,
}

impl fmt::Display for Aov {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Aov::Depth => "depth",
            Aov::Normal => "normal",
        })
    }
}

/// `--aov depth=d.pfm,normal=n.pfm`: which AOVs to read back, and the PFM file each one
/// goes to, in the order given.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AovFiles(pub Vec<(Aov, PathBuf)>);

/// What is wrong with an `--aov` list; the item is quoted as given.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AovSpecError {
    /// An item without `=`.
    #[error("{0:?}: expected NAME=FILE.pfm")]
    NoFile(String),
    /// A name that is no AOV.
    #[error("{0:?}: expected depth or normal")]
    UnknownAov(String),
}

/// Why an AOV file was not written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AovWriteError {
    /// The frame lacks an AOV that was asked for.
    #[error("the target sent no {0} AOV")]
    Missing(Aov),
    /// The file cannot be created.
    #[error("cannot create {}", .path.display())]
    Create {
        /// The AOV file named by `--aov`.
        path: PathBuf,
        /// The underlying error, reported as this one's `source()`.
        source: std::io::Error,
    },
    /// Writing it failed.
    #[error("cannot write {}", .path.display())]
    Write {
        /// The AOV file named by `--aov`.
        path: PathBuf,
        /// The underlying error, reported as this one's `source()`.
        source: std::io::Error,
    },
}

impl FromStr for AovFiles {
    type Err = AovSpecError;

    fn from_str(spec: &str) -> Result<Self, Self::Err> {
        spec.split(',')
            .map(|item| {
                let (kind, path) = item
                    .split_once('=')
                    .ok_or_else(|| AovSpecError::NoFile(item.to_string()))?;
                let aov = match kind {
                    "depth" => Aov::Depth,
                    "normal" => Aov::Normal,
                    other => return Err(AovSpecError::UnknownAov(other.to_string())),
                };
                Ok((aov, PathBuf::from(path)))
            })
            .collect::<Result<_, _>>()
            .map(AovFiles)
    }
}

impl AovFiles {
    /// The AOVs to ask the target for.
    pub fn aovs(&self) -> Aovs {
        Aovs {
            depth: self.0.iter().any(|(a, _)| *a == Aov::Depth),
            normal: self.0.iter().any(|(a, _)| *a == Aov::Normal),
        }
    }

    /// Writes each AOV of `out` to its file as PFM, in the order given.
    pub fn write(&self, out: &RenderOutput) -> Result<(), AovWriteError> {
        for (aov, path) in &self.0 {
            let (data, channels) = match aov {
                Aov::Depth => (out.depth.as_deref(), 1),
                Aov::Normal => (out.normal.as_deref(), 3),
            };
            let data = data.ok_or(AovWriteError::Missing(*aov))?;
            let file = std::fs::File::create(path).map_err(|source| AovWriteError::Create {
                path: path.clone(),
                source,
            })?;
            sim_target::rt::write_pfm(
                std::io::BufWriter::new(file),
                out.image.width(),
                out.image.height(),
                channels,
                data,
            )
            .map_err(|source| AovWriteError::Write {
                path: path.clone(),
                source,
            })?;
        }
        Ok(())
    }
}

/// A rendered frame as read back.
#[derive(Debug)]
pub struct RenderOutput {
    /// The colour image, RGB888 as the target packed it.
    pub image: image::RgbImage,
    /// Depth AOV, one f32 per pixel.
    pub depth: Option<Vec<f32>>,
    /// Normal AOV, three f32 per pixel.
    pub normal: Option<Vec<f32>>,
    /// Board-time estimate in FPGA cycles and rays traced, from the target.
    pub cycles: u64,
    /// Rays the target traced for the frame (the board's own count).
    pub rays: u64,
    /// Both ends' counters.
    pub stats: Stats,
    /// The changed register words and the start command, until the last was sent.
    pub send: Phase,
    /// From the start command to the target's "done": the target's compute time (plus one
    /// small message each way), which is what its Mrays/s should be measured by — a
    /// 1080p read-back over a link can take longer than the render itself.
    pub render: std::time::Duration,
    /// Every plane read back: its pixel bytes and the time from request to the last chunk.
    pub read_back: Phase,
}

/// Writes `scene` into the register image the connected target wants for a frame in
/// `numeric`: binary32 reals where its caps list the format as a float datapath, Q16.16
/// otherwise (and before a handshake, when the target is unknown). The one place the host
/// decides the image's value format, so render and animate cannot disagree; also where a
/// scene asking for more than the target's ray tracer builds (`Caps::rt_build`) is
/// refused, naming the field, before anything is sent.
pub fn scene_regs<T: Transport>(
    session: &Session<T>,
    scene: &Scene,
    numeric: Numeric,
) -> Result<Regs, SceneRegsError> {
    if let Some(p) = session.peer() {
        jobs::scene::check_build(scene, &p.caps.rt_build)?;
    }
    let format = session.peer().map_or(ValueFormat::Q16_16, |p| {
        ValueFormat::for_caps(&p.caps, numeric)
    });
    jobs::scene::to_regs_as(scene, format)
}

/// Keeps the register image the target holds, so each frame sends only the difference.
pub struct Renderer {
    current: Regs,
    frame_id: u32,
}

impl Default for Renderer {
    fn default() -> Self {
        Self::new()
    }
}

impl Renderer {
    /// A renderer for a target at power-on (all registers at their reset values).
    pub fn new() -> Self {
        Self {
            current: Regs::new(),
            frame_id: 0,
        }
    }

    /// Sends the changed registers of `regs`, renders in `numeric` and reads the frame
    /// back. Returns the frame and the number of register words sent.
    pub fn frame<T: Transport>(
        &mut self,
        session: &mut Session<T>,
        regs: &Regs,
        numeric: Numeric,
        packing: Packing,
        aovs: Aovs,
    ) -> Result<(RenderOutput, usize), SessionError> {
        if let Some(peer) = session.peer() {
            let caps = peer.caps;
            if !caps.ray_trace {
                return Err(SessionError::Unsupported(format!(
                    "the target ({}) has no ray-trace block",
                    peer.ident
                )));
            }
            if !caps.numeric.contains(numeric) {
                return Err(SessionError::Unsupported(format!(
                    "the target ({}) cannot compute in {numeric:?}",
                    peer.ident
                )));
            }
        }
        let started = std::time::Instant::now();
        let payload_before = session.traffic().payload_sent;
        let mut words = 0;
        for w in diff(&self.current, regs) {
            words += w.words.len();
            let offset = w.offset;
            session.send(
                &HostFrame::Regs(w),
                Box::new(move |_| format!("the register write at offset {offset}")),
            )?;
        }
        self.current = regs.clone();
        self.frame_id = self.frame_id.wrapping_add(1);
        let id = self.frame_id;
        session.send(
            &HostFrame::Start(StartFrame {
                frame_id: id,
                block: Block::RayTrace,
                numeric,
                auto_restart: false,
                aovs: aovs.depth || aovs.normal,
            }),
            Box::new(|_| "the start of the frame".into()),
        )?;
        let send = Phase {
            payload_bytes: session.traffic().payload_sent - payload_before,
            time: started.elapsed(),
        };
        let started = std::time::Instant::now();
        let done = loop {
            match session.recv()? {
                DeviceFrame::Done(d) if d.frame_id == id => break d,
                DeviceFrame::Done(_) | DeviceFrame::Synced(_) => {}
                other => {
                    return Err(SessionError::Unexpected(format!(
                        "{other:?} while waiting for frame {id}"
                    )))
                }
            }
        };
        let render_time = started.elapsed();
        let started = std::time::Instant::now();
        let render = regs.render();
        let (w, h) = (render.width as u16, render.height as u16);
        let rect = Rect { x: 0, y: 0, w, h };
        let mut read_bytes = 0u64;
        let mut read = |session: &mut Session<T>, plane, format| {
            let data = session.read_back(ReadRequest {
                plane,
                rect,
                format,
            })?;
            read_bytes += data.len() as u64;
            Ok::<_, SessionError>(data)
        };
        let image = match packing {
            Packing::Rgb888 => read(session, Plane::Color, PixelFormat::Rgb888)?,
            Packing::Kcu116 => {
                let data = read(session, Plane::Color, PixelFormat::Kcu116)?;
                let words: Vec<u16> = data
                    .chunks_exact(2)
                    .map(|b| u16::from_be_bytes([b[0], b[1]]))
                    .collect();
                sim_target::rt::unpack_kcu116(&words, u32::from(w))
            }
        };
        let image = image::RgbImage::from_raw(u32::from(w), u32::from(h), image)
            .ok_or_else(|| SessionError::ReadBack("colour read-back size".into()))?;
        let floats = |bytes: Vec<u8>| -> Vec<f32> {
            bytes
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                .collect()
        };
        let depth = if aovs.depth {
            Some(floats(read(session, Plane::Depth, PixelFormat::DepthF32)?))
        } else {
            None
        };
        let normal = if aovs.normal {
            Some(floats(read(
                session,
                Plane::Normal,
                PixelFormat::NormalF32,
            )?))
        } else {
            None
        };
        let read_back = Phase {
            payload_bytes: read_bytes,
            time: started.elapsed(),
        };
        let stats = session.stats()?;
        Ok((
            RenderOutput {
                image,
                depth,
                normal,
                cycles: done.cycles,
                rays: done.work,
                stats,
                send,
                render: render_time,
                read_back,
            },
            words,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aov_lists_parse_in_order_and_name_the_bad_item() {
        let files: AovFiles = "normal=n.pfm,depth=d.pfm".parse().unwrap();
        assert_eq!(
            files.0,
            [
                (Aov::Normal, PathBuf::from("n.pfm")),
                (Aov::Depth, PathBuf::from("d.pfm"))
            ]
        );
        let aovs = files.aovs();
        assert!(aovs.depth && aovs.normal);
        let e = "depth=d.pfm,d.pfm".parse::<AovFiles>().unwrap_err();
        assert_eq!(e.to_string(), "\"d.pfm\": expected NAME=FILE.pfm");
        let e = "albedo=a.pfm".parse::<AovFiles>().unwrap_err();
        assert_eq!(e.to_string(), "\"albedo\": expected depth or normal");
    }

    #[test]
    fn packings_are_spelled_as_the_flag_takes_them() {
        for p in <Packing as protocol::names::Named>::VALUES {
            assert_eq!(p.to_string().parse::<Packing>(), Ok(*p));
        }
        let e = "rgb565".parse::<Packing>().unwrap_err();
        assert_eq!(e.to_string(), "unknown packing (expected rgb888, kcu116)");
    }
}
