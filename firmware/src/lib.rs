//! The fpgfx controller: takes frames from the host and feeds the FPGA.
//!
//! The seeds' controllers (the FITkit's MSP430 over SPI, ViRAY's MicroBlaze over
//! AXI4-Lite) are one program here: [`Controller`] runs the host link and a bounded inbox,
//! [`Engine`] turns each request into bus records or register writes for an [`FpgaBus`].
//! The library is `no_std` without alloc so the board binary and the host (built-in mode,
//! `fpgfx-sim`, tests) run the same code.
#![no_std]

pub mod controller;
pub mod engine;
pub mod fpga;
pub mod fpga_link;
mod log;

pub use controller::{Controller, ControllerError};
pub use engine::Engine;
pub use fpga::FpgaBus;
pub use fpga_link::{FpgaLink, FpgaLinkError};
