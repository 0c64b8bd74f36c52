//! The FPGA, emulated: a bit-exact golden model of the raster and ray-trace blocks.

pub mod bootloader;
pub mod device;
pub mod fpga_link;
pub mod num;
pub mod raster;
pub mod rt;
pub mod scene_regs;
