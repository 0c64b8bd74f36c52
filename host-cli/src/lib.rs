//! The `fpgfx` tool's library: file formats the user writes, and the pipeline that carries
//! them to a target. The binary (`main.rs`, one file per command in `cmd/`) parses
//! arguments, prints, and reports errors.

pub mod animate;
pub mod bench;
mod builtin;
pub mod connect;
pub mod flash;
pub mod ports;
pub mod raster;
pub mod raster_file;
pub mod render;
pub mod serial;
pub mod session;
pub mod stress;
