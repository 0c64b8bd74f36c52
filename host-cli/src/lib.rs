//! The `fpgfx` tool's library: file formats the user writes, and the pipeline that carries
//! them to a target. The binary (`main.rs`, one file per command in `cmd/`) parses
//! arguments, prints, and reports errors.
//!
//! One public module per area, each with its items at its own root (`flash` and `stress`
//! keep their files private behind `pub use`):
//!
//! * the link: [`connect`] picks the target and opens it, [`session`] is the host end of
//!   the link over any [`session::Transport`] (serial ports, TCP, the built-in target);
//!   [`ports`] lists this machine's serial ports;
//! * the files the user writes: [`raster_file`] (raster commands) and, through
//!   `jobs::scene`, ray-tracer scenes;
//! * one module per command that has a library side: [`raster`], [`render`],
//!   [`animate`], [`bench`](mod@bench), [`stress`], [`flash`], [`vectors`].
#![warn(missing_docs)]

pub mod animate;
pub mod bench;
pub mod connect;
pub mod flash;
pub mod frames;
pub mod ports;
pub mod raster;
pub mod render;
pub mod session;
pub mod stress;

mod builtin;
mod serial;
