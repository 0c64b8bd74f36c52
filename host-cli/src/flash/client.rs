//! An AN3155 conversation with the STM32 ROM bootloader over any [`Transport`]: one
//! method per bootloader command, each failure naming the command, the step and the
//! bytes the chip sent.

use std::io;
use std::time::Duration;

use protocol::bootloader::{self as bl, Command, ACK, NACK, SYNC};

use super::line::{self, hex};
use super::{FlashError, Loader};
use crate::session::Transport;

/// What the chip said about itself.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChipInfo {
    /// Bootloader version from Get (0x31 = v3.1).
    pub version: u8,
    /// Command codes from Get.
    pub commands: Vec<u8>,
    /// Product ID from Get ID.
    pub pid: u16,
}

/// Timeouts, generous enough for a real F405 (a 128 KiB sector erase takes up to ~2 s,
/// mass erase up to ~16 s at 3.3 V, x32 parallelism).
#[derive(Debug, Clone, Copy)]
pub struct Timeouts {
    /// Wait for the answer to each 0x7F.
    pub sync: Duration,
    /// Wait for an ordinary ACK or reply.
    pub ack: Duration,
    /// Extra wait per erased sector.
    pub per_sector: Duration,
}

impl Default for Timeouts {
    fn default() -> Self {
        Self {
            sync: Duration::from_millis(300),
            ack: Duration::from_secs(1),
            per_sector: Duration::from_secs(4),
        }
    }
}

/// An AN3155 conversation over any [`Transport`].
pub struct Client<T> {
    /// The line; the sequence's tests look at the emulator behind it.
    pub(super) port: T,
    /// How long to wait for what.
    pub timeouts: Timeouts,
    /// Line rate, only for messages.
    pub baud: u32,
}

impl<T: Transport> Client<T> {
    /// Wraps an open port.
    pub fn new(port: T, baud: u32) -> Self {
        Self {
            port,
            timeouts: Timeouts::default(),
            baud,
        }
    }

    fn read_exact(&mut self, n: usize, timeout: Duration) -> Result<Vec<u8>, (Vec<u8>, bool)> {
        line::read_exact(&mut self.port, n, timeout)
    }

    fn read_or_fail(
        &mut self,
        n: usize,
        timeout: Duration,
        command: Command,
        stage: &str,
    ) -> Result<Vec<u8>, FlashError> {
        self.read_exact(n, timeout)
            .map_err(|(got, _)| FlashError::Timeout {
                command: command.name(),
                stage: stage.to_string(),
                timeout,
                got: hex(&got),
            })
    }

    fn expect_ack(
        &mut self,
        command: Command,
        stage: &str,
        timeout: Duration,
    ) -> Result<(), FlashError> {
        let b = self.read_or_fail(1, timeout, command, stage)?;
        match b[0] {
            ACK => Ok(()),
            NACK => Err(FlashError::Nack {
                command: command.name(),
                stage: stage.to_string(),
            }),
            _ => {
                // Show a little of what follows too: it often identifies the talker
                // (an application's log line, an echo).
                let mut got = b;
                if let Ok(more) = self.read_exact(15, Duration::from_millis(20)) {
                    got.extend(more);
                }
                Err(FlashError::Unexpected {
                    command: command.name(),
                    expected: "ACK (0x79) or NACK (0x1f)",
                    stage: stage.to_string(),
                    got: hex(&got),
                })
            }
        }
    }

    fn send_command(&mut self, command: Command) -> Result<(), FlashError> {
        self.port.write_all(&bl::command_frame(command))?;
        self.expect_ack(command, "to the command", self.timeouts.ack)
    }

    /// Autobaud: 0x7F until the chip answers. A fresh chip ACKs; one that is already
    /// synced takes 0x7F as a command byte and NACKs the second 0x7F (not its
    /// complement) — both mean it is listening and now idle.
    ///
    /// A chip whose previous host died mid-command sits inside a half-received frame
    /// and swallows single bytes, so after two silent tries one burst of 258 × 0x7F
    /// (longer than any frame: N-1, 256 data bytes, checksum) ends that frame with a
    /// NACK; the bytes after it pair up into further NACKs, and at most two more single
    /// 0x7F then get a NACK from an idle chip.
    pub fn sync(&mut self, attempts: u32) -> Result<(), FlashError> {
        line::sync(
            &mut self.port,
            self.baud,
            &AN3155_SYNC,
            self.timeouts.sync,
            attempts,
        )
    }

    /// Get, Get Version and Get ID.
    pub fn identify(&mut self) -> Result<ChipInfo, FlashError> {
        let ack = self.timeouts.ack;
        self.send_command(Command::Get)?;
        let n = self.read_or_fail(1, ack, Command::Get, "(length)")?[0];
        let body = self.read_or_fail(usize::from(n) + 1, ack, Command::Get, "(command list)")?;
        self.expect_ack(Command::Get, "after the command list", ack)?;
        let (version, commands) = (body[0], body[1..].to_vec());

        self.send_command(Command::GetVersion)?;
        self.read_or_fail(3, ack, Command::GetVersion, "(version)")?;
        self.expect_ack(Command::GetVersion, "after the version", ack)?;

        self.send_command(Command::GetId)?;
        let n = self.read_or_fail(1, ack, Command::GetId, "(length)")?[0];
        let id = self.read_or_fail(usize::from(n) + 1, ack, Command::GetId, "(product ID)")?;
        self.expect_ack(Command::GetId, "after the product ID", ack)?;
        let pid = match id.as_slice() {
            [hi, lo, ..] => u16::from_be_bytes([*hi, *lo]),
            [lo] => u16::from(*lo),
            [] => 0,
        };
        Ok(ChipInfo {
            version,
            commands,
            pid,
        })
    }

    /// Extended Erase of the given sectors.
    pub fn erase(&mut self, sectors: &[u16]) -> Result<(), FlashError> {
        if sectors.is_empty() {
            return Ok(());
        }
        let mut frame = vec![0u8; 3 + 2 * sectors.len()];
        let n = bl::encode_extended_erase(bl::EraseRequest::Pages(sectors), &mut frame)
            .map_err(|e| io::Error::other(e.to_string()))?;
        self.send_command(Command::ExtendedErase)?;
        self.port.write_all(&frame[..n])?;
        let timeout = self.timeouts.ack + self.timeouts.per_sector * sectors.len() as u32;
        self.expect_ack(
            Command::ExtendedErase,
            &format!("to erasing sectors {sectors:?}"),
            timeout,
        )
    }

    /// One Write Memory.
    pub fn write_block(&mut self, address: u32, data: &[u8]) -> Result<(), FlashError> {
        let mut frame = [0u8; bl::MAX_BLOCK + 2];
        let n =
            bl::encode_data_block(data, &mut frame).map_err(|e| io::Error::other(e.to_string()))?;
        self.send_command(Command::WriteMemory)?;
        self.port.write_all(&bl::address_frame(address))?;
        let ack = self.timeouts.ack;
        self.expect_ack(
            Command::WriteMemory,
            &format!("to address {address:#010x}"),
            ack,
        )?;
        self.port.write_all(&frame[..n])?;
        self.expect_ack(
            Command::WriteMemory,
            &format!("to the {} bytes for {address:#010x}", data.len()),
            ack,
        )
    }

    /// One Read Memory of 1..=256 bytes.
    pub fn read_block(&mut self, address: u32, len: usize) -> Result<Vec<u8>, FlashError> {
        let length = bl::read_length_frame(len).map_err(|e| io::Error::other(e.to_string()))?;
        self.send_command(Command::ReadMemory)?;
        self.port.write_all(&bl::address_frame(address))?;
        let ack = self.timeouts.ack;
        let stage = format!("to address {address:#010x}");
        self.expect_ack(Command::ReadMemory, &stage, ack)?;
        self.port.write_all(&length)?;
        self.expect_ack(Command::ReadMemory, &format!("to length {len}"), ack)?;
        self.read_or_fail(
            len,
            ack,
            Command::ReadMemory,
            &format!("(data of {address:#010x})"),
        )
    }

    /// Go: the chip jumps to `address` (the application's vector table) and leaves the
    /// bootloader, so a flashed board runs without a reset.
    pub fn go(&mut self, address: u32) -> Result<(), FlashError> {
        self.send_command(Command::Go)?;
        self.port.write_all(&bl::address_frame(address))?;
        self.expect_ack(
            Command::Go,
            &format!("to address {address:#010x}"),
            self.timeouts.ack,
        )
    }

    /// Brings a chip that may be half-way through a command (a lost byte, a lost
    /// answer) back to its idle command loop: that is what [`Client::sync`] does.
    pub fn recover(&mut self) -> Result<(), FlashError> {
        self.sync(4)
    }
}

/// How AN3155's autobaud is done and recovered: a fresh chip ACKs 0x7F; one that is
/// already synced takes 0x7F as a command byte and NACKs the second 0x7F (not its
/// complement) — both mean it is listening and idle. A burst of 258 × 0x7F is longer than
/// any frame (N-1, 256 data bytes, checksum).
const AN3155_SYNC: line::Sync = line::Sync {
    byte: SYNC,
    answers: &[ACK, NACK],
    burst_byte: SYNC,
    burst: 258,
    burst_answers: &[ACK, NACK],
    burst_note: " (and one burst of 258 to end a half-received command)",
    first_drain: Duration::from_millis(5),
    hint: "is BOOT0 high and the board reset? is this the right port?",
};

impl<T: Transport> Loader for Client<T> {
    fn write_block(&mut self, address: u32, data: &[u8]) -> Result<(), FlashError> {
        Client::write_block(self, address, data)
    }
    fn read_block(&mut self, address: u32, len: usize) -> Result<Vec<u8>, FlashError> {
        Client::read_block(self, address, len)
    }
    fn recover(&mut self) -> Result<(), FlashError> {
        Client::recover(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flash::test_wire::{client, wire};

    #[test]
    fn silence_is_no_sync() {
        struct Deaf;
        impl Transport for Deaf {
            fn write_all(&mut self, _: &[u8]) -> io::Result<()> {
                Ok(())
            }
            fn read(&mut self, _: &mut [u8], _: Duration) -> io::Result<usize> {
                Ok(0)
            }
        }
        let mut c = Client::new(Deaf, 115_200);
        c.timeouts.sync = Duration::from_millis(1);
        let e = c.sync(3).unwrap_err();
        assert_eq!(
            e.to_string(),
            "no answer from the bootloader: sent 0x7F 3 times (and one burst of 258 to end a \
             half-received command) at 115200 baud 8E1, got nothing \
             (is BOOT0 high and the board reset? is this the right port?)"
        );
    }

    /// A host died after sending a Write Memory's address and part of its data: the
    /// chip swallows single 0x7F bytes, and sync must still get it back to idle.
    #[test]
    fn sync_recovers_a_chip_stuck_in_a_half_received_frame() {
        for sent in [0usize, 1, 7, 100, 257] {
            let mut w = wire();
            let mut out = Vec::new();
            w.chip.feed(&[SYNC], &mut out);
            w.chip
                .feed(&bl::command_frame(Command::WriteMemory), &mut out);
            w.chip.feed(&bl::address_frame(bl::FLASH_BASE), &mut out);
            w.chip.feed(&vec![0xFF; sent], &mut out);
            let mut c = client(w);
            c.sync(4)
                .unwrap_or_else(|e| panic!("after {sent} data bytes: {e}"));
            let info = c
                .identify()
                .unwrap_or_else(|e| panic!("after {sent} data bytes: {e}"));
            assert_eq!(info.pid, 0x413);
        }
    }
}
