//! `fpgfx flash`: programs the board's STM32F405 through its ROM bootloader (ST AN3155)
//! over a serial port, the way a user without a debug probe does it.
//!
//! The sequence is the one ST documents and `stm32flash` follows: 0x7F for autobaud, Get
//! / Get Version / Get ID to learn what the chip is, Extended Erase of only the sectors
//! the image touches (erasing a 128 KiB sector takes the real part a second or two, so a
//! 40 KiB image must not cost a mass erase), 256-byte Write Memory blocks, then a
//! read-back of every block. Each block is retried a bounded number of times on NACK or
//! timeout; errors name the command, the stage and the bytes the chip actually sent.
//! Wire encodings come from [`protocol::bootloader`].
//!
//! One job per file: `image.rs` turns a .bin/.hex/.elf into an [`Image`], `port.rs` is
//! the 8E1 [`BootPort`], `client.rs` speaks AN3155 over any transport ([`Client`]),
//! `sequence.rs` erases, writes and verifies ([`flash()`]) and reports its [`Progress`].
//! Nothing here prints: `fpgfx flash` draws the progress bar and the summary.
//!
//! The FITkit's MSP430F168 is flashed the same way through its ROM BSL (TI SLAU319):
//! `bsl_client.rs` speaks it ([`BslClient`]) and [`flash_msp430`] mass-erases (the
//! password of a chip is its vector table, unknown until erased), unlocks with 32 × 0xFF,
//! reads the BSL version, then shares the STM32's write/verify/retry loop over
//! [`Loader`]. `line.rs` holds what both clients do on the line alike (reads with
//! deadlines, the sync that rescues a chip left mid-frame).

mod bsl_client;
mod client;
mod error;
mod image;
mod line;
mod port;
mod sequence;
#[cfg(test)]
mod test_wire;

pub use bsl_client::{BslClient, BslInfo, BslTimeouts};
pub use client::{ChipInfo, Client, Timeouts};
pub use error::FlashError;
pub use image::{
    parse_elf, parse_hex, parse_u32, Block, Image, ImageError, Layout, MSP430F168, STM32F405,
};
pub use port::{open, open_bsl, BootPort};
pub use sequence::{
    flash, flash_msp430, password_of, Erased, FlashOptions, Loader, Progress, Report, Stage, Unlock,
};
