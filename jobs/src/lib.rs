//! What the user writes, and what the host makes of it before anything is sent.
//!
//! A job starts as a file the user wrote and ends as words the controller forwards: this
//! crate is that first step, shared by every tool that reads a job (the `fpgfx` CLI, the
//! test-vector writer, the C library's tests, the fuzz targets) so none of them has to
//! reach into another's code for it.
//!
//! * [`scene`] — the ray tracer's scene file (TOML) into a [`sim_target::rt::Scene`]
//!   ([`scene::parse`]), the scene into its register image ([`scene::to_regs`]), what a
//!   scene demands of a number format's range ([`scene::range`]), and the link bytes its
//!   registers cost ([`scene::scene_wire_cost`]);
//! * [`raster`] — the raster command file (TOML or JSON) into a [`raster::RasterJob`]
//!   with its geometry snapped to the sub-pixel grid ([`raster::parse`]), and the job
//!   packed for a bus layout as the controller packs it ([`raster::pack_job`]).
//!
//! Every error names the file, and the line and key (or command index) where it can.
//! The FPGA model (`sim-target`) does not depend on this crate: it renders register
//! images and FIFO records, never files.
#![warn(missing_docs)]

pub mod raster;
pub mod scene;
