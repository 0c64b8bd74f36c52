//! A conversation with the MSP430's ROM BSL (TI SLAU319, 1xx/2xx/4xx protocol) over any
//! [`Transport`]: one method per BSL command, each failure naming the command, the
//! address and the bytes the chip sent. Wire encodings come from
//! [`protocol::msp430_bsl`].

use std::io;
use std::time::Duration;

use protocol::msp430_bsl::{self as wire, Command, DATA_ACK, DATA_NAK, MAX_FRAME, SYNC};

use super::line::{self, hex};
use super::{FlashError, Loader};
use crate::session::Transport;

/// What TX BSL version said about the chip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BslInfo {
    /// Device ID (0xF169 for the F16x).
    pub device_id: u16,
    /// BSL version in BCD (0x0161 is 1.61).
    pub version: u16,
}

impl BslInfo {
    /// The version as SLAU319 writes it, "1.61".
    pub fn version_text(&self) -> String {
        format!("{:x}.{:02x}", self.version >> 8, self.version & 0xFF)
    }
}

/// Timeouts, generous enough for a real F168 at 9600 baud (a 250-byte data frame takes
/// 0.3 s on the wire; a mass erase ~0.2 s, which python-msp430-tools allows 6 s for).
#[derive(Debug, Clone, Copy)]
pub struct BslTimeouts {
    /// Wait for DATA_ACK to each SYNC.
    pub sync: Duration,
    /// Wait for the first byte of an answer.
    pub ack: Duration,
    /// Wait for a mass or segment erase.
    pub erase: Duration,
}

impl Default for BslTimeouts {
    fn default() -> Self {
        Self {
            sync: Duration::from_millis(500),
            ack: Duration::from_secs(1),
            erase: Duration::from_secs(6),
        }
    }
}

/// How the BSL is synced and freed: SYNC 0x80 answered DATA_ACK. A chip left inside a
/// frame by a dead host takes single bytes as frame bytes; 260 × 0xFF (longer than the
/// longest frame) ends it: 0xFF is neither a header nor a valid length, and a frame
/// completed by it fails its checksum, each answered by one DATA_NAK; a waiting chip
/// ignores 0xFF. (0x80 itself would not do: it is the header, and would start a frame.)
const BSL_SYNC: line::Sync = line::Sync {
    byte: SYNC,
    answers: &[DATA_ACK],
    burst_byte: 0xFF,
    burst: MAX_FRAME,
    burst_answers: &[DATA_NAK, DATA_ACK],
    burst_note: " (and one burst of 260 × 0xFF to end a half-received frame)",
    first_drain: Duration::ZERO,
    hint: "was the BSL entered with the RST/TEST sequence? is this the right port?",
};

/// A BSL conversation over any [`Transport`].
pub struct BslClient<T> {
    /// The line; tests look at the emulator behind it.
    pub(super) port: T,
    /// How long to wait for what.
    pub timeouts: BslTimeouts,
    /// Line rate, only for messages.
    pub baud: u32,
}

impl<T: Transport> BslClient<T> {
    /// Wraps an open port.
    pub fn new(port: T, baud: u32) -> Self {
        Self {
            port,
            timeouts: BslTimeouts::default(),
            baud,
        }
    }

    /// SYNC until DATA_ACK (see [`BSL_SYNC`] for the rescue of a half-received frame).
    pub fn sync(&mut self, attempts: u32) -> Result<(), FlashError> {
        line::sync(
            &mut self.port,
            self.baud,
            &BSL_SYNC,
            self.timeouts.sync,
            attempts,
        )
    }

    /// SYNC, then the frame; the caller reads the answer.
    fn send(
        &mut self,
        command: Command,
        address: u16,
        length: u16,
        data: &[u8],
    ) -> Result<(), FlashError> {
        self.sync(4)?;
        let mut frame = [0u8; MAX_FRAME];
        let n = wire::encode_request(command.code(), address, length, data, &mut frame)
            .map_err(|e| io::Error::other(e.to_string()))?;
        self.port.write_all(&frame[..n])?;
        Ok(())
    }

    /// One byte within `timeout`, or a timeout naming the command and step.
    fn first_byte(
        &mut self,
        command: Command,
        stage: &str,
        timeout: Duration,
    ) -> Result<u8, FlashError> {
        line::read_exact(&mut self.port, 1, timeout)
            .map(|b| b[0])
            .map_err(|(got, _)| FlashError::Timeout {
                command: command.name(),
                stage: stage.to_string(),
                timeout,
                got: hex(&got),
            })
    }

    /// A command answered DATA_ACK or DATA_NAK.
    fn acked(
        &mut self,
        command: Command,
        address: u16,
        length: u16,
        data: &[u8],
        stage: &str,
        timeout: Duration,
    ) -> Result<(), FlashError> {
        self.send(command, address, length, data)?;
        match self.first_byte(command, stage, timeout)? {
            DATA_ACK => Ok(()),
            DATA_NAK => Err(FlashError::Nack {
                command: command.name(),
                stage: stage.to_string(),
            }),
            other => {
                Err(self.unexpected(command, stage, other, "DATA_ACK (0x90) or DATA_NAK (0xa0)"))
            }
        }
    }

    /// A command answered by a data frame (or DATA_NAK); returns its data.
    fn data_frame(
        &mut self,
        command: Command,
        address: u16,
        length: u16,
        stage: &str,
    ) -> Result<Vec<u8>, FlashError> {
        let ack = self.timeouts.ack;
        self.send(command, address, length, &[])?;
        let first = self.first_byte(command, stage, ack)?;
        match first {
            DATA_NAK => {
                return Err(FlashError::Nack {
                    command: command.name(),
                    stage: stage.to_string(),
                })
            }
            wire::HDR => {}
            other => {
                return Err(self.unexpected(
                    command,
                    stage,
                    other,
                    "a data frame (0x80) or DATA_NAK (0xa0)",
                ))
            }
        }
        let timeout = |this: &Self, bytes: usize| {
            // The answer's bytes at 8E1, on top of the usual wait.
            this.timeouts.ack
                + Duration::from_secs_f64(bytes as f64 * 11.0 / f64::from(this.baud.max(1)))
        };
        let mut frame = vec![first];
        let t = timeout(self, 3);
        let head =
            line::read_exact(&mut self.port, 3, t).map_err(|(got, _)| FlashError::Timeout {
                command: command.name(),
                stage: format!("{stage} (frame header)"),
                timeout: t,
                got: hex(&[&[first][..], &got].concat()),
            })?;
        frame.extend(&head);
        let total = wire::frame_len([frame[0], frame[1], frame[2], frame[3]], 0)
            .map_err(|error| self.damaged(command, stage, error, &frame))?;
        let t = timeout(self, total);
        let rest = line::read_exact(&mut self.port, total - 4, t).map_err(|(got, _)| {
            FlashError::Timeout {
                command: command.name(),
                stage: format!("{stage} (data)"),
                timeout: t,
                got: hex(&[&frame[..], &got].concat()),
            }
        })?;
        frame.extend(rest);
        match wire::decode_data_frame(&frame) {
            Ok(data) => Ok(data.to_vec()),
            Err(error) => Err(self.damaged(command, stage, error, &frame)),
        }
    }

    fn damaged(
        &mut self,
        command: Command,
        stage: &str,
        error: wire::DecodeError,
        frame: &[u8],
    ) -> FlashError {
        // Whatever else is on the line belongs to this broken answer.
        let _ = line::drain(&mut self.port);
        FlashError::Answer {
            command: command.name(),
            stage: stage.to_string(),
            error,
            got: hex(frame),
        }
    }

    fn unexpected(
        &mut self,
        command: Command,
        stage: &str,
        first: u8,
        expected: &'static str,
    ) -> FlashError {
        // A little of what follows often identifies the talker (an echo, a log line).
        let mut got = vec![first];
        if let Ok(more) = line::drain(&mut self.port) {
            got.extend(more);
        }
        FlashError::Unexpected {
            command: command.name(),
            expected,
            stage: stage.to_string(),
            got: hex(&got),
        }
    }

    /// Mass erase: all flash, information memory included; the one erase a locked chip
    /// accepts, after which its password is 32 × 0xFF.
    pub fn mass_erase(&mut self) -> Result<(), FlashError> {
        let erase = self.timeouts.erase;
        self.acked(
            Command::MassErase,
            0xFFFE,
            wire::erase_mode::MASS,
            &[],
            "to erasing all flash",
            erase,
        )
    }

    /// Erase segment: the flash segment holding `address`.
    pub fn erase_segment(&mut self, address: u16) -> Result<(), FlashError> {
        let erase = self.timeouts.erase;
        self.acked(
            Command::EraseSegment,
            address,
            wire::erase_mode::SEGMENT,
            &[],
            &format!("to erasing the segment at {address:#06x}"),
            erase,
        )
    }

    /// RX password: the 32 bytes of the chip's vector table.
    pub fn password(&mut self, password: &[u8; wire::PASSWORD_LEN]) -> Result<(), FlashError> {
        let ack = self.timeouts.ack;
        self.acked(Command::RxPassword, 0, 0, password, "to the password", ack)
    }

    /// TX BSL version: device ID and BSL version.
    pub fn version(&mut self) -> Result<BslInfo, FlashError> {
        let data = self.data_frame(Command::TxBslVersion, 0, 0, "(version)")?;
        let (device_id, version) =
            wire::parse_version(&data).ok_or_else(|| FlashError::Unexpected {
                command: Command::TxBslVersion.name(),
                expected: "16 bytes",
                stage: "(version)".into(),
                got: hex(&data),
            })?;
        Ok(BslInfo { device_id, version })
    }

    /// One RX data block (even address and length, ≤ 250 bytes).
    pub fn write_block(&mut self, address: u32, data: &[u8]) -> Result<(), FlashError> {
        let a = addr16(address)?;
        let ack = self.timeouts.ack
            + Duration::from_secs_f64(data.len() as f64 * 11.0 / f64::from(self.baud.max(1)));
        self.acked(
            Command::RxDataBlock,
            a,
            data.len() as u16,
            data,
            &format!("to the {} bytes for {address:#06x}", data.len()),
            ack,
        )
    }

    /// One TX data block of `len` (even, ≤ 250) bytes.
    pub fn read_block(&mut self, address: u32, len: usize) -> Result<Vec<u8>, FlashError> {
        let a = addr16(address)?;
        let data = self.data_frame(
            Command::TxDataBlock,
            a,
            len as u16,
            &format!("to reading {len} bytes at {address:#06x}"),
        )?;
        if data.len() != len {
            return Err(FlashError::Unexpected {
                command: Command::TxDataBlock.name(),
                expected: "as many bytes as asked for",
                stage: format!("to reading {len} bytes at {address:#06x}"),
                got: format!("{} bytes", data.len()),
            });
        }
        Ok(data)
    }

    /// Load PC: the chip leaves the BSL and runs from `address`.
    pub fn load_pc(&mut self, address: u16) -> Result<(), FlashError> {
        let ack = self.timeouts.ack;
        self.acked(
            Command::LoadPc,
            address,
            0,
            &[],
            &format!("to address {address:#06x}"),
            ack,
        )
    }
}

/// The BSL's addresses are 16 bits (the F168 has nothing above 0xFFFF; a layout keeps
/// images below it, so this only catches a caller's mistake).
fn addr16(address: u32) -> Result<u16, FlashError> {
    u16::try_from(address).map_err(|_| {
        FlashError::Image(super::ImageError::OutsideFlash {
            start: address,
            end: u64::from(address) + 1,
            chip: "MSP430F168",
            map: "the ROM BSL addresses 0x0000..0x10000".into(),
        })
    })
}

impl<T: Transport> Loader for BslClient<T> {
    fn write_block(&mut self, address: u32, data: &[u8]) -> Result<(), FlashError> {
        BslClient::write_block(self, address, data)
    }
    fn read_block(&mut self, address: u32, len: usize) -> Result<Vec<u8>, FlashError> {
        BslClient::read_block(self, address, len)
    }
    fn recover(&mut self) -> Result<(), FlashError> {
        // Every command starts with a sync that frees a half-received frame.
        self.sync(4)
    }
}
