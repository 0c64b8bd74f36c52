//! The only place an fpgfx wire format is defined.
//!
//! Each wire format has its own module, so that a reader who holds a captured byte string
//! knows where to look. These modules are the crate's surface: everything a caller needs
//! is one level down (`protocol::frame::HostFrame`, `protocol::scene::SceneRegs`), and the
//! root holds only the limits the formats share. Only the register map's word offsets sit
//! one level further, grouped per block (`scene::obj::SHAPE`), because blocks share field
//! names.
//!
//! * [`raster`] — the raster block's vocabulary: the commands of a raster job and the
//!   values they carry, spoken by the messages, the bus packer, the model and the files.
//! * [`frame`] — the messages between the host (`fpgfx`) and the controller firmware,
//!   serialised with postcard. Both ends compare a [`frame::schema_hash`] in the
//!   handshake so that two builds with different message layouts refuse each other
//!   instead of exchanging garbage.
//! * [`link`] — how those messages cross a byte stream (UART, pty, TCP): COBS framing,
//!   CRC-32, sequence numbers, ACK/NAK, a retransmit window and credit-based flow control,
//!   as a sans-I/O state machine that runs unchanged on the MCU and on the host.
//! * [`bus`] — the bit-packed words the controller pushes into the FPGA's input FIFO
//!   (the FITkit raster block and richer layouts), [`fitkit_spi`] — the SPI transactions
//!   that carry them to the FITkit block with its set-up, status and read-back, and
//!   [`scene`] — the ray tracer's
//!   32-bit AXI4-Lite register image, and [`axi_lite`] — where that image and the start
//!   of a frame sit on the block's AXI4-Lite bus.
//! * [`bootloader`] — the STM32 ROM bootloader's UART protocol (ST AN3155) that
//!   `fpgfx flash` speaks to the board and `fpgfx-sim --bootloader` emulates, and
//!   [`msp430_bsl`] — the MSP430's ROM bootstrap loader (TI SLAU319), the same for the
//!   FITkit's MSP430F168 (`fpgfx flash --chip msp430f168`, `fpgfx-sim --bootloader msp430`).
//! * [`fpga_link`] — the same bus operations as messages, for an FPGA reached over a
//!   serial line (the board's second UART when the FPGA is the `fpgfx-sim` emulator):
//!   what `firmware::FpgaLink` sends and `sim_board::FpgaServer` answers.
//! * [`names`] — how the enums above are spelled in files and on the command line
//!   (with the `clap` feature, as the flags' possible values).
//!
//! The crate is `#![no_std]` without `alloc`: everything here must fit a Cortex-M4 with
//! 128 KiB of RAM, so buffers are `heapless` and bounded by the named constants below.
#![no_std]
#![deny(missing_docs)]

pub mod axi_lite;
pub mod bootloader;
pub mod bus;
mod bytes;
pub mod fitkit_spi;
pub mod fpga_link;
pub mod frame;
pub mod link;
pub mod msp430_bsl;
pub mod names;
pub mod raster;
pub mod scene;

/// Version of the host <-> controller protocol. Bump it whenever a change is not purely
/// additive; the handshake reports both sides' values when they differ.
pub const PROTOCOL_VERSION: u16 = 3;

/// Largest postcard-encoded message (one [`frame::HostFrame`] or [`frame::DeviceFrame`])
/// that may travel in one link frame. Sized so that the controller's receive buffer,
/// a few window slots and the read-back buffer fit comfortably in the MCU's RAM, and so
/// that a full frame still takes only ~23 ms at 115 200 baud.
pub const MAX_PAYLOAD: usize = 256;

/// Largest frame side in pixels, for the raster block and the ray tracer alike: the
/// raster block's edge functions are proven exact up to it (sim-target's `raster::tri`),
/// targets report it in [`frame::Caps`], and the host refuses a larger frame before sending it.
/// The FITkit SDRAM row is 512 columns; the extended layouts allow more; the wire's
/// `u16` would carry more still.
pub const MAX_FRAME_SIDE: u32 = 4096;
