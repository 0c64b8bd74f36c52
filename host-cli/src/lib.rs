//! The `fpgfx` tool's library: what carries a job to a target and back, and the jobs of
//! the commands that have more than arguments and printing. The binary (`main.rs`, one
//! file per command in `cmd/`) parses arguments, prints, and reports errors; nothing
//! outside this crate depends on it (what the user writes is the `jobs` crate, test
//! vectors the `vectors` crate, the emulated board `sim-board`).
//!
//! One public module per area, each with its items at its own root (`flash` and `stress`
//! keep their files private behind `pub use`):
//!
//! * the link: [`connect`] picks the target and opens it, [`session`] is the host end of
//!   the link over any [`session::Transport`] (serial ports, TCP, the built-in target);
//!   [`serial_ports`] lists this machine's serial ports;
//! * [`run`]: a job run on a target through a session: a raster job drawn, a scene
//!   ray-traced (only the registers that changed are sent), a scripted animation;
//! * the commands' own jobs: [`sweep`] (`fpgfx bench`: number formats and raster
//!   settings against error and cost), [`stress`], [`flash`]; [`frames`], the image
//!   files the commands write.
#![warn(missing_docs)]

pub mod connect;
pub mod flash;
pub mod frames;
pub mod run;
pub mod serial_ports;
pub mod session;
pub mod stress;
pub mod sweep;

mod builtin;
mod serial;
