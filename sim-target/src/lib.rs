//! The FPGA, emulated: a bit-exact golden model of the raster and ray-trace blocks, and
//! the device around them that a controller drives.
//!
//! What is where (the whole public surface):
//!
//! * at the root: [`Device`], the FPGA as the controller's bus sees it (FIFO, blocks,
//!   read-back), and its [`DeviceError`];
//! * [`mmio`]: the same device word by word on its AXI4-Lite map, for a soft-core driver
//!   (`RegisterFile`);
//! * [`raster`]: the raster block's golden model (`Raster`, `Framebuffer`, the cycle
//!   model's `Stats`); its stages are namespaces: `aa`, `circle`, `curve`, `line`,
//!   `oracle`, `tex`, `tri`;
//! * [`rt`]: the ray-trace block's golden model (`render` and its `RenderOptions`,
//!   `Frame`, `Plan`, the `Scene` model, `V3`); its stages are namespaces: `cull`,
//!   `shade`, `shapes`, `texture`, and so is `f`, the scene's f64 arithmetic. The
//!   renderer itself is split by stage (plan, prepared scene, kernel, entry points) in
//!   private modules;
//! * [`num`]: the number formats the ray tracer runs in and the approximations (`Scalar`,
//!   `Q16_16`, `SqrtKind`, …); namespaces `composed` (the composed forms of `Scalar`
//!   methods) and `instrumented` (the wrappers that check or count operations);
//! * [`scene_regs`]: a ray-tracer scene from its register image (`from_regs`).
//!
//! Every other module is private; what callers need of it is re-exported where it
//! belongs.
//!
//! This crate is the FPGA and nothing else: the rest of an emulated board (the
//! firmware's controller, the line to the host, the STM32's ROM bootloader) is the
//! `sim-board` crate, because it runs the firmware and the model must not depend on it.
//! So is the FPGA end of the serial FPGA link (`sim_board::FpgaServer`), which serves
//! any of the firmware's FPGA buses, this model or the Verilated RTL.
#![warn(missing_docs)]

mod device;
pub mod mmio;
pub mod num;
pub mod raster;
pub mod rt;
pub mod scene_regs;

pub use device::{Device, DeviceError};
