//! The FPGA, emulated: a bit-exact golden model of the raster and ray-trace blocks, and
//! the device around them that a controller drives.
//!
//! What is where:
//!
//! * at the root: [`Device`], the FPGA as the controller's bus sees it (FIFO, blocks,
//!   read-back);
//! * [`mmio`]: the same device word by word on its AXI4-Lite map, for a soft-core driver;
//! * [`raster`] and [`rt`]: the two blocks' golden models;
//! * [`num`]: the number formats the ray tracer runs in;
//! * [`scene_regs`]: a ray-tracer scene to and from its register image.
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
