//! A job run on a target through a [`Session`](crate::session::Session): what `fpgfx
//! raster`, `render` and `animate` do between opening the target and writing files.
//! The job itself (parsed, snapped, compiled to registers) comes from the `jobs` crate;
//! here it crosses the link and the frame comes back.
//!
//! * [`raster`] — a raster job drawn and its framebuffer read back;
//! * [`render`] — a scene ray-traced, sending only the register words that changed since
//!   the target's last frame ([`render::Renderer`]), with depth and normal planes on
//!   request;
//! * [`animate`] — a Rhai script that makes each frame's scene or raster job.

pub mod animate;
pub mod raster;
pub mod render;
