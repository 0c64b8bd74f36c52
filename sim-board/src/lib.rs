//! The emulated board: the firmware's controller, the FPGA model ([`sim_target`]) and the
//! line between them, with the host's line in front — what `fpgfx` talks to when there
//! is no hardware.
//!
//! The board comes in the shapes a real one is met in:
//!
//! * in this process ([`in_process`]): `fpgfx --port builtin` and the tests, the host
//!   joined to the controller by an in-memory pipe, the FPGA on the controller's bus,
//!   behind the serial FPGA link on a second pipe, or on its AXI4-Lite registers
//!   (`--port builtin:mmio`, the firmware's `MmioBus` on `sim_target::mmio`);
//! * behind a pseudo-terminal ([`pty`]) or TCP ([`board`], the `fpgfx-sim` binary): the
//!   controller on a real byte stream (any [`Pending`] one), optionally slowed to a UART's
//!   rate, so `fpgfx --port` is exercised over a tty;
//! * with the FITkit block's RTL, Verilated, for the FPGA ([`rtl`]): the controller's
//!   SPI driver on the block's pins (`--port rtl`, `fpgfx-sim --fpga rtl`);
//! * with the ray-casting core's RTL, Verilated, for the FPGA ([`rt_rtl`]): the
//!   controller's AXI4-Lite register driver on the core's bus (`--port rtl:rt`,
//!   `fpgfx-sim --fpga rtl:rt`);
//! * the FPGA alone on a serial port ([`FpgaPort`], speaking the serial FPGA link through
//!   [`FpgaServer`]), for a controller elsewhere: the QEMU board's second UART, with the
//!   model or the RTL behind it;
//! * the STM32's ROM bootloader ([`bootloader`], on a pty through [`bootloader_pty`]),
//!   what the chip does with BOOT0 high, for `fpgfx flash`; and the FITkit MSP430F168's
//!   ROM BSL ([`msp430_bsl`], on a pty through the same server), for
//!   `fpgfx flash --chip msp430f168`.
//!
//! The shapes whose entry points are free functions stay modules, named the way callers
//! name them (`board::serve`, `bootloader_pty::serve`, `in_process::sim_target()`,
//! `pty::open`, and `bootloader::Stats` beside [`bootloader::Bootloader`]); the byte-stream
//! plumbing under [`board`] is private, and what a caller needs of it is at the root.
//!
//! It is a crate of its own because it runs the firmware's controller: sim-target is the
//! FPGA and must not depend on the firmware, and the host tool (host-cli) should hold no
//! board plumbing, only its side of the line.

#![warn(missing_docs)]

pub mod board;
pub mod bootloader;
pub mod bootloader_pty;
pub mod in_process;
pub mod msp430_bsl;
pub mod pty;
pub mod rt_rtl;
pub mod rtl;

mod fpga_port;
mod fpga_server;
mod host_link;
mod paced;
mod socket;

pub use fpga_port::{FpgaPort, FpgaPortError};
pub use fpga_server::{FpgaServer, Served};
pub use host_link::Pending;
