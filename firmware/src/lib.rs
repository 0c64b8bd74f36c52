//! The fpgfx controller: takes frames from the host and feeds the FPGA.
//!
//! The seeds' controllers (the FITkit's MSP430 over SPI, ViRAY's MicroBlaze over
//! AXI4-Lite) are one program here: [`Controller`] runs the host link and a bounded inbox,
//! [`Engine`] turns each request into bus records or register writes for an [`FpgaBus`].
//! The library is `no_std` without alloc so the board binaries and the host (built-in mode,
//! `fpgfx-sim`, tests) run the same code.
//!
//! Everything a caller needs is at the crate root; the modules are private, except
//! `board` (with the `board-stm32` or `board-riscv` feature): the part the board
//! binaries share, public because those binaries are its only callers.
//! [`FpgaLink`] is the [`FpgaBus`] of a board whose FPGA sits behind a second UART;
//! [`FitkitSpi`] is the FITkit raster block's, on any embedded-hal 1.0 SPI device.
//! [`MmioBus`] is a soft core's beside the FPGA's blocks, on their AXI4-Lite registers.
//! [`Canvas`] puts embedded-graphics on any of them, a command per primitive.
#![no_std]
#![warn(missing_docs)]

#[cfg(feature = "board-common")]
pub mod board;
mod canvas;
mod controller;
mod engine;
mod fitkit_spi;
mod fpga;
mod fpga_link;
mod log;
mod mmio;

pub use canvas::{Accelerated, Canvas, CanvasCounters, CanvasError};
pub use controller::{Controller, ControllerError, INBOX, SHADOW, WINDOW};
pub use engine::Engine;
pub use fitkit_spi::{FitkitSpi, FitkitSpiError};
pub use fpga::FpgaBus;
pub use fpga_link::{Clock, FpgaLink, FpgaLinkError};
pub use mmio::{Accesses, MmioBus, MmioError, Registers, VolatileRegisters, DEFAULT_POLL_LIMIT};
