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

mod client;
mod error;
mod image;
mod port;
mod sequence;
#[cfg(test)]
mod test_wire;

pub use client::{ChipInfo, Client, Timeouts};
pub use error::FlashError;
pub use image::{parse_elf, parse_hex, parse_u32, Block, Image, ImageError};
pub use port::{open, BootPort};
pub use sequence::{flash, FlashOptions, Progress, Report, Stage};
