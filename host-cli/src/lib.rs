//! The `fpgfx` tool's library: file formats the user writes, and the pipeline that carries
//! them to a target. The binary (`main.rs`) only parses arguments and reports errors.

pub mod builtin;
pub mod raster;
pub mod raster_file;
pub mod render;
pub mod serial;
pub mod session;
pub mod stress;
