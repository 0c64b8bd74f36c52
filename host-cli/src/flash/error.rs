//! What can go wrong flashing, with the command, the stage and what the chip sent.

use std::io;
use std::time::Duration;

use super::image::ImageError;
use crate::connect::ConnectError;

/// What can go wrong flashing.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FlashError {
    /// The target named is not a serial port, so no bootloader can be behind it.
    #[error(
        "cannot open serial port {port}: flash needs a serial --port (or FPGFX_PORT) with the \
         board's bootloader behind it; the built-in and TCP targets have none"
    )]
    NotSerial {
        /// The `--port` given, or "(none)".
        port: String,
    },
    /// The serial port could not be opened.
    #[error(transparent)]
    Open(#[from] ConnectError),
    /// Nothing (or nothing sensible) came back to 0x7F.
    #[error(
        "no answer from the bootloader: sent 0x7F {attempts} times{burst} at {baud} baud 8E1, got {got} \
         (is BOOT0 high and the board reset? is this the right port?)"
    )]
    NoSync {
        /// How many 0x7F sync bytes were sent before giving up.
        attempts: u32,
        /// Line rate in baud the sync was tried at.
        baud: u32,
        /// Mentions the flushing burst if one was sent.
        burst: &'static str,
        /// What came back, as hex, or "nothing".
        got: String,
    },
    /// The chip answered NACK.
    #[error("{command}: the chip answered NACK {stage}")]
    Nack {
        /// The command that got it.
        command: &'static str,
        /// At which step.
        stage: String,
    },
    /// The chip answered something that is neither ACK nor NACK.
    #[error("{command}: expected {expected} {stage}, the chip answered {got}")]
    Unexpected {
        /// The AN3155 command that got the answer.
        command: &'static str,
        /// What the protocol says comes.
        expected: &'static str,
        /// At which step.
        stage: String,
        /// What came, as hex.
        got: String,
    },
    /// The chip stopped answering.
    #[error("{command}: no answer {stage} within {timeout:?} (got {got})")]
    Timeout {
        /// The AN3155 command waiting for its answer.
        command: &'static str,
        /// At which step.
        stage: String,
        /// How long we waited.
        timeout: Duration,
        /// Whatever partial answer came, as hex.
        got: String,
    },
    /// Get ID reported another part.
    #[error(
        "chip ID {0:#05x} is not the STM32F405/407's 0x413; refusing to flash it (--force to try anyway)"
    )]
    UnknownChip(u16),
    /// The bootloader lacks a command we need.
    #[error("the bootloader does not offer {0} (its Get answer lists {1})")]
    MissingCommand(&'static str, String),
    /// The image is unusable.
    #[error(transparent)]
    Image(#[from] ImageError),
    /// A block failed every attempt.
    #[error("block at {address:#010x} failed (attempts made: {attempts})")]
    Block {
        /// The block's address.
        address: u32,
        /// Attempts made before giving up ([`FlashOptions::attempts`](super::FlashOptions::attempts)).
        attempts: u32,
        /// The last failure.
        #[source]
        last: Box<FlashError>,
    },
    /// Read-back differs from the image.
    #[error("verify failed at {address:#010x}: wrote {wrote:#04x}, read back {read:#04x}")]
    Verify {
        /// First differing address.
        address: u32,
        /// The byte the image has at `address`.
        wrote: u8,
        /// The byte the chip read back there.
        read: u8,
    },
    /// The port itself failed.
    #[error("the serial port failed (adapter unplugged, or the board lost power?)")]
    Io(#[from] io::Error),
}
