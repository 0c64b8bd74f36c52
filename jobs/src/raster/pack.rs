//! A raster job packed for a bus layout exactly as the controller packs it, so a command
//! the target cannot carry is refused before anything is sent, naming its place in the file.

use protocol::bus::{BusLayout, Kind, PackOptions};
use protocol::raster::RasterCmd;

use super::file::RasterJob;

/// The command's `op` as the job file spells it.
pub fn op_name(cmd: &RasterCmd) -> &'static str {
    match cmd {
        RasterCmd::Clear(_) => "clear",
        RasterCmd::Line(_) => "line",
        RasterCmd::Triangle(_) => "triangle",
        RasterCmd::Circle(_) => "circle",
        RasterCmd::Fill(_) => "fill",
        RasterCmd::Polygon(_) => "polygon",
        RasterCmd::Bezier(_) => "bezier",
        RasterCmd::Patch(_) => "patch",
    }
}

/// A command of a job that a bus layout cannot carry, named by its place in the file.
#[derive(Debug, thiserror::Error)]
#[error(
    "{file}: cmd[{index}] ({op}): the target's raster block takes the {layout} layout: {reason}"
)]
pub struct LayoutError {
    /// The job file as named to [`pack_job`].
    pub file: String,
    /// 0-based index of the command in the file.
    pub index: usize,
    /// The command's `op`.
    pub op: &'static str,
    /// The layout's name.
    pub layout: &'static str,
    /// The packer's complaint (part of the message, not a separate cause, so a chain of
    /// causes does not print it twice).
    pub reason: Box<protocol::bus::BusError>,
}

/// One command as the controller pushes it: the SPI address (channel) and the FIFO
/// records.
pub type Packet = (u8, heapless::Vec<u64, { protocol::bus::MAX_RECORDS }>);

/// The job's commands packed for `layout` exactly as the controller packs them (its
/// channel, no CB: a clear is a command of its own), so that a command the layout cannot
/// carry (a circle, a Gouraud triangle or a colour outside RGB332 on the FITkit) is
/// refused before anything is sent, naming it: the controller would refuse it too, but
/// only after the commands before it were drawn. Test vectors use the packets themselves.
pub fn pack_job(
    job: &RasterJob,
    file: &str,
    layout: &'static BusLayout,
) -> Result<Vec<Packet>, LayoutError> {
    let opts = PackOptions {
        subpixel_bits: job.setup.subpixel_bits,
        clear: false,
    };
    job.cmds
        .iter()
        .enumerate()
        .map(|(index, cmd)| {
            protocol::bus::channel(layout, Kind::of(cmd))
                .and_then(|ch| Ok((ch, protocol::bus::pack(layout, cmd, opts)?)))
                .map_err(|reason| LayoutError {
                    file: file.to_string(),
                    index,
                    op: op_name(cmd),
                    layout: layout.name,
                    reason: Box::new(reason),
                })
        })
        .collect()
}
