//! The raster command file as the user writes it (TOML or JSON), and the job it becomes:
//! a set-up and commands with geometry already snapped to the sub-pixel grid, then packed
//! for the target's bus layout.

mod file;
mod pack;

pub use file::{parse, parse_color, RasterFileError, RasterJob, GUARD_BAND};
pub use pack::{op_name, pack_job, LayoutError, Packet};
