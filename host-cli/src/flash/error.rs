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
    /// Nothing (or nothing sensible) came back to the sync byte.
    #[error(
        "no answer from the bootloader: sent 0x{sync:02X} {attempts} times{burst} at {baud} baud 8E1, got {got} \
         ({hint})"
    )]
    NoSync {
        /// The sync byte: 0x7F (STM32) or 0x80 (MSP430 BSL).
        sync: u8,
        /// How many sync bytes were sent before giving up.
        attempts: u32,
        /// Line rate in baud the sync was tried at.
        baud: u32,
        /// Mentions the flushing burst if one was sent.
        burst: &'static str,
        /// What came back, as hex, or "nothing".
        got: String,
        /// What to check on the board.
        hint: &'static str,
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
    /// The chip's answer frame is damaged (MSP430 BSL data frames carry a checksum).
    #[error("{command} {stage}: the chip's answer is damaged ({error}): {got}")]
    Answer {
        /// The command answered.
        command: &'static str,
        /// At which step.
        stage: String,
        /// What is wrong with the frame.
        error: protocol::msp430_bsl::DecodeError,
        /// The frame, as hex.
        got: String,
    },
    /// The MSP430 BSL refused the password given with `--password`.
    #[error(
        "RX password: the BSL refused the password from {from} (its vectors at \
         0xffe0..=0xffff are not the chip's); nothing was erased or written: flash without \
         --password to mass-erase the chip instead"
    )]
    Password {
        /// The file the password came from.
        from: String,
    },
    /// The MSP430 BSL refused the all-0xFF password right after its own mass erase.
    #[error(
        "RX password: the BSL refused the erased chip's password (32 × 0xff) after Mass \
         erase answered DATA_ACK: the erase did not reach the vectors"
    )]
    ErasedPassword,
    /// TX BSL version reported another part.
    #[error(
        "device ID {id:#06x} (BSL {version}) is not the {expected}'s {expected_id:#06x}; \
         refusing to flash it (--force to try anyway)"
    )]
    UnknownMsp430 {
        /// The device ID the chip reported.
        id: u16,
        /// Its BSL version as text ("1.61").
        version: String,
        /// The part asked for.
        expected: &'static str,
        /// That part's device ID.
        expected_id: u16,
    },
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
