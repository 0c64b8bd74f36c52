//! `fpgfx raster`: a parsed command file through a [`Session`] to an image.

use protocol::frame::{
    Block, HostFrame, Numeric, PixelFormat, Plane, RasterBatcher, ReadRequest, Rect, StartFrame,
    Stats,
};

use crate::session::{Phase, Session, SessionError, Transport};
use jobs::raster::{op_name, pack_job, RasterJob};

/// What a raster run produced.
#[derive(Debug)]
pub struct RasterOutput {
    /// The framebuffer, RGB888 row-major.
    pub image: image::RgbImage,
    /// Both ends' counters after the frame.
    pub stats: Stats,
    /// Sending the commands: from the set-up to the target's confirmation that every
    /// command was executed.
    pub send: Phase,
    /// Reading the framebuffer back.
    pub read_back: Phase,
}

/// Draws `job` on the target behind `session` (already handshaken) and reads the frame
/// back. A refusal names the command's index in the file.
pub fn run<T: Transport>(
    session: &mut Session<T>,
    job: &RasterJob,
    file: &str,
) -> Result<RasterOutput, SessionError> {
    if let Some(peer) = session.peer() {
        let caps = peer.caps;
        if !caps.raster {
            return Err(SessionError::Unsupported(format!(
                "the target ({}) has no raster block",
                peer.ident
            )));
        }
        if job.setup.width > caps.max_width || job.setup.height > caps.max_height {
            return Err(SessionError::Unsupported(format!(
                "{file}: size {}×{} exceeds the target's {}×{}",
                job.setup.width, job.setup.height, caps.max_width, caps.max_height
            )));
        }
        if let Some(id) = caps.raster_layout {
            pack_job(job, file, id.layout())
                .map_err(|e| SessionError::Unsupported(e.to_string()))?;
        }
    }
    let started = std::time::Instant::now();
    let payload_before = session.traffic().payload_sent;
    session.send(
        &HostFrame::RasterSetup(job.setup),
        Box::new(|_| "the raster setup (size, sub-pixel bits, AA)".into()),
    )?;
    let mut batcher = RasterBatcher::new();
    // File indices and names of the commands in the pending batch.
    let mut pending: Vec<(usize, &'static str)> = Vec::new();
    let file_name = file.to_string();
    let describe = move |cmds: Vec<(usize, &'static str)>| {
        let file = file_name.clone();
        Box::new(move |i: u32| match cmds.get(i as usize) {
            Some((index, op)) => format!("{file}: cmd[{index}] ({op})"),
            None => format!("{file}: a raster batch (entry {i})"),
        }) as crate::session::Describe
    };
    for (index, cmd) in job.cmds.iter().enumerate() {
        let closed = batcher.push(cmd).map_err(|e| {
            SessionError::Unexpected(format!("{file}: cmd[{index}] ({}): {e}", op_name(cmd)))
        })?;
        if let Some(batch) = closed {
            // The command just pushed opened the next batch.
            session.send_encoded(batch.as_bytes(), describe(std::mem::take(&mut pending)))?;
        }
        pending.push((index, op_name(cmd)));
    }
    if let Some(batch) = batcher.finish() {
        session.send_encoded(batch.as_bytes(), describe(std::mem::take(&mut pending)))?;
    }
    session.send(
        &HostFrame::Start(StartFrame {
            frame_id: 1,
            block: Block::Raster,
            numeric: Numeric::F64,
            auto_restart: false,
            aovs: false,
        }),
        Box::new(|_| "start of the raster frame".into()),
    )?;
    session.sync()?;
    let send = Phase {
        payload_bytes: session.traffic().payload_sent - payload_before,
        time: started.elapsed(),
    };
    let started = std::time::Instant::now();
    let (w, h) = (job.setup.width, job.setup.height);
    let data = session.read_back(ReadRequest {
        plane: Plane::Color,
        rect: Rect { x: 0, y: 0, w, h },
        format: PixelFormat::Rgb888,
    })?;
    let read_back = Phase {
        payload_bytes: data.len() as u64,
        time: started.elapsed(),
    };
    let image = image::RgbImage::from_raw(u32::from(w), u32::from(h), data)
        .ok_or_else(|| SessionError::ReadBack("read-back size does not match the frame".into()))?;
    let stats = session.stats()?;
    Ok(RasterOutput {
        image,
        stats,
        send,
        read_back,
    })
}
