//! The STM32F405's ROM bootloader (system memory, protocol v3.1, ST AN3155) as a sans-I/O
//! emulator: bytes in, bytes out. The caller owns the port and the clock, so the same
//! model runs behind a pseudo-terminal ([`crate::bootloader_pty`], `fpgfx-sim
//! --bootloader`), inside host-cli's flash tests and in the unit tests below.
//!
//! It exists so that `fpgfx flash` and third-party tools (`stm32flash`) can be tested end
//! to end without a board. What it models, and where it knowingly differs from the real
//! part, is listed in `docs/flash.md`; in short:
//!
//! * autobaud: bytes before the first 0x7F are ignored (the real part cannot even frame
//!   them before it knows the baud rate); 0x7F is answered with ACK;
//! * Get lists exactly what the F405's v3.1 lists (0x00 0x01 0x02 0x11 0x21 0x31 0x44
//!   0x63 0x73 0x82 0x92); Erase 0x43 is *not* listed and gets NACK, like on the F4;
//! * Write Protect (0x63) and Readout Protect (0x82) are listed but refused with NACK
//!   (a protected emulated part would only get in the way of tests); Write Unprotect
//!   and Readout Unprotect (which mass-erases) are implemented and end, like on the real
//!   part, with a system reset, after which the host must send 0x7F again;
//! * flash is 1 MiB of 0xFF in the F405's sectors; erase is instantaneous; a Write Memory
//!   that would program a word that is not erased is refused with NACK *as a whole*
//!   (the real part would have programmed the words before the faulty one);
//! * system memory and the OTP area read as 0xFF (the ROM code itself is not ours to
//!   ship); the option bytes read as a factory-fresh F405's;
//! * Go only records the address (the emulator then ignores the line, as the real chip
//!   would be running user code) until [`Bootloader::reset`].

use std::ops::Range;

use protocol::bootloader::{
    self as bl, erase_code, Command, EraseHeader, ACK, F405_BOOTLOADER_VERSION, F405_COMMANDS,
    F405_PID, F405_SECTORS, NACK, SYNC,
};

/// Factory option bytes at 0x1FFF_C000: USER 0xEC (software watchdog, no reset on
/// stop/standby, BOR off), RDP 0xAA (level 0: no read-out protection), nWRP all ones
/// (no sector write-protected). RM0090 §3.7.
const OPTION_BYTES: [u8; bl::OPTION_BYTES_SIZE as usize] = [
    0xEC, 0xAA, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, //
    0xFF, 0x0F, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
];

/// Why a flash image could not be loaded into the model.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum BootloaderError {
    /// A saved flash image must be exactly the flash's size.
    #[error("a flash image must be {expected} bytes, this one is {actual}")]
    ImageSize {
        /// `FLASH_SIZE`.
        expected: usize,
        /// What was given.
        actual: usize,
    },
}

/// Where the emulator is in a command.
#[derive(Debug, Clone, PartialEq, Eq)]
enum State {
    /// After reset: waiting for the 0x7F that sets the baud rate.
    AwaitSync,
    /// Waiting for a command byte.
    Idle,
    /// Got a command byte, waiting for its complement.
    Command(u8),
    /// Collecting a 5-byte address frame for `cmd`.
    Address {
        cmd: Command,
        buf: [u8; 5],
        len: usize,
    },
    /// Read Memory: collecting N-1 and its complement.
    ReadLength { address: u32, first: Option<u8> },
    /// Write Memory: collecting N-1, N bytes and the checksum.
    WriteData { address: u32, buf: Vec<u8> },
    /// Extended Erase: collecting the 16-bit count or special code.
    EraseHeader { first: Option<u8> },
    /// Extended Erase with a special code: waiting for its checksum.
    EraseSpecial { code: u16 },
    /// Extended Erase by pages: collecting page numbers and the checksum.
    ErasePages {
        /// Page bytes still to come (the checksum comes after them).
        remaining: u32,
        xor: u8,
        high: Option<u8>,
        /// Bit i set: sector i is to be erased (a sector listed twice is erased once).
        pages: u16,
        valid: bool,
    },
    /// Go was accepted: the chip runs user code and no longer listens.
    Jumped,
}

/// Counters a test or the sim can report.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Stats {
    /// Commands answered with ACK (complement checked).
    pub commands: u64,
    /// NACKs sent.
    pub nacks: u64,
    /// Write Memory commands that programmed memory.
    pub writes: u64,
    /// Sectors erased (mass erase counts all twelve).
    pub sectors_erased: u64,
}

/// The emulated STM32F405 in bootloader mode.
pub struct Bootloader {
    state: State,
    flash: Vec<u8>,
    ram: Vec<u8>,
    go: Option<u32>,
    dirty: Vec<Range<u32>>,
    stats: Stats,
}

impl Default for Bootloader {
    fn default() -> Self {
        Self::new()
    }
}

impl Bootloader {
    /// A part fresh from the factory: flash erased, RAM zero, waiting for 0x7F.
    pub fn new() -> Self {
        Self {
            state: State::AwaitSync,
            flash: vec![0xFF; bl::FLASH_SIZE as usize],
            ram: vec![0; bl::RAM_SIZE as usize],
            go: None,
            dirty: Vec::new(),
            stats: Stats::default(),
        }
    }

    /// A part whose flash holds `image` (a previous run's saved flash), so that a flash
    /// interrupted in one process can be completed by the next.
    pub fn with_flash(image: Vec<u8>) -> Result<Self, BootloaderError> {
        if image.len() != bl::FLASH_SIZE as usize {
            return Err(BootloaderError::ImageSize {
                expected: bl::FLASH_SIZE as usize,
                actual: image.len(),
            });
        }
        Ok(Self {
            flash: image,
            ..Self::new()
        })
    }

    /// System reset with BOOT0 high: the bootloader starts over and waits for 0x7F.
    /// Memory survives (flash by nature, RAM because the emulator does not scramble it).
    pub fn reset(&mut self) {
        self.state = State::AwaitSync;
        self.go = None;
    }

    /// True once 0x7F has been answered and no reset happened since.
    pub fn synced(&self) -> bool {
        self.state != State::AwaitSync
    }

    /// The whole main flash, from 0x0800_0000.
    pub fn flash(&self) -> &[u8] {
        &self.flash
    }

    /// The address Go jumped to, until the next [`Bootloader::reset`].
    pub fn go_address(&self) -> Option<u32> {
        self.go
    }

    /// Counters since creation.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Flash ranges (offsets from 0x0800_0000) changed since the last call, so a caller
    /// that persists the flash writes only what changed.
    pub fn take_dirty(&mut self) -> Vec<Range<u32>> {
        std::mem::take(&mut self.dirty)
    }

    /// Processes bytes from the host and appends the answers to `out`.
    pub fn feed(&mut self, input: &[u8], out: &mut Vec<u8>) {
        for &b in input {
            self.step(b, out);
        }
    }

    fn nack(&mut self, out: &mut Vec<u8>) {
        out.push(NACK);
        self.stats.nacks += 1;
        self.state = State::Idle;
    }

    fn step(&mut self, b: u8, out: &mut Vec<u8>) {
        let state = std::mem::replace(&mut self.state, State::Idle);
        match state {
            State::AwaitSync => {
                if b == SYNC {
                    out.push(ACK);
                    self.state = State::Idle;
                } else {
                    self.state = State::AwaitSync;
                }
            }
            State::Jumped => self.state = State::Jumped,
            State::Idle => self.state = State::Command(b),
            State::Command(code) => {
                if !bl::is_command_pair(code, b) {
                    return self.nack(out);
                }
                match Command::from_code(code) {
                    Some(cmd) if F405_COMMANDS.contains(&cmd) => self.command(cmd, out),
                    _ => self.nack(out),
                }
            }
            State::Address { cmd, mut buf, len } => {
                buf[len] = b;
                if len + 1 < buf.len() {
                    self.state = State::Address {
                        cmd,
                        buf,
                        len: len + 1,
                    };
                    return;
                }
                match bl::parse_address_frame(&buf) {
                    Some(address) => self.address(cmd, address, out),
                    None => self.nack(out),
                }
            }
            State::ReadLength { address, first } => match first {
                None => {
                    self.state = State::ReadLength {
                        address,
                        first: Some(b),
                    }
                }
                Some(n) => {
                    let len = usize::from(n) + 1;
                    if n ^ b != 0xFF {
                        return self.nack(out);
                    }
                    match self.readable(address, len) {
                        Some(bytes) => {
                            out.push(ACK);
                            out.extend_from_slice(&bytes);
                            self.stats.commands += 1;
                        }
                        None => self.nack(out),
                    }
                }
            },
            State::WriteData { address, mut buf } => {
                buf.push(b);
                // buf = N-1, N bytes, checksum.
                if buf.len() < usize::from(buf[0]) + 3 {
                    self.state = State::WriteData { address, buf };
                    return;
                }
                let (body, checksum) = buf.split_at(buf.len() - 1);
                if bl::xor(body) != checksum[0] {
                    return self.nack(out);
                }
                if self.write(address, &body[1..]) {
                    out.push(ACK);
                    self.stats.writes += 1;
                } else {
                    self.nack(out);
                }
            }
            State::EraseHeader { first } => match first {
                None => self.state = State::EraseHeader { first: Some(b) },
                Some(hi) => {
                    let n = u16::from_be_bytes([hi, b]);
                    self.state = match EraseHeader::decode(n) {
                        EraseHeader::Pages(count) => State::ErasePages {
                            remaining: 2 * count,
                            xor: hi ^ b,
                            high: None,
                            pages: 0,
                            valid: true,
                        },
                        _ => State::EraseSpecial { code: n },
                    };
                }
            },
            State::EraseSpecial { code } => {
                let [hi, lo] = code.to_be_bytes();
                // Only mass erase exists on the single-bank F405; bank erases and the
                // reserved codes are refused.
                if hi ^ lo == b && code == erase_code::MASS {
                    self.mass_erase();
                    out.push(ACK);
                } else {
                    self.nack(out);
                }
            }
            State::ErasePages {
                remaining,
                xor,
                high,
                mut pages,
                mut valid,
            } => {
                if remaining == 0 {
                    if xor != b || !valid {
                        return self.nack(out);
                    }
                    for i in 0..F405_SECTORS.len() {
                        if pages & (1 << i) != 0 {
                            self.erase_sector(i);
                        }
                    }
                    out.push(ACK);
                    return;
                }
                let high = match high {
                    None => Some(b),
                    Some(hi) => {
                        let page = u16::from_be_bytes([hi, b]);
                        if usize::from(page) < F405_SECTORS.len() {
                            pages |= 1 << page;
                        } else {
                            valid = false;
                        }
                        None
                    }
                };
                self.state = State::ErasePages {
                    remaining: remaining - 1,
                    xor: xor ^ b,
                    high,
                    pages,
                    valid,
                };
            }
        }
    }

    fn command(&mut self, cmd: Command, out: &mut Vec<u8>) {
        self.stats.commands += 1;
        out.push(ACK);
        match cmd {
            Command::Get => {
                out.push(F405_COMMANDS.len() as u8);
                out.push(F405_BOOTLOADER_VERSION);
                out.extend(F405_COMMANDS.iter().map(|c| c.code()));
                out.push(ACK);
            }
            Command::GetVersion => {
                // The F4 sends two zero "option bytes" for compatibility (AN3155).
                out.extend_from_slice(&[F405_BOOTLOADER_VERSION, 0x00, 0x00, ACK]);
            }
            Command::GetId => {
                let [hi, lo] = F405_PID.to_be_bytes();
                out.extend_from_slice(&[0x01, hi, lo, ACK]);
            }
            Command::ReadMemory | Command::Go | Command::WriteMemory => {
                self.state = State::Address {
                    cmd,
                    buf: [0; 5],
                    len: 0,
                };
            }
            Command::ExtendedErase => self.state = State::EraseHeader { first: None },
            Command::WriteUnprotect => {
                // Nothing is protected; the real part answers a second ACK and resets.
                out.push(ACK);
                self.reset();
            }
            Command::ReadoutUnprotect => {
                self.mass_erase();
                out.push(ACK);
                self.reset();
            }
            Command::WriteProtect | Command::ReadoutProtect | Command::Erase => {
                // Undo the ACK pushed above: these are refused outright.
                out.pop();
                self.stats.commands -= 1;
                self.nack(out);
            }
        }
    }

    fn address(&mut self, cmd: Command, address: u32, out: &mut Vec<u8>) {
        let ok = match cmd {
            Command::ReadMemory => self.readable(address, 1).is_some(),
            Command::WriteMemory => address.is_multiple_of(4) && self.writable(address, 4),
            // Go only makes sense into code: flash or RAM.
            Command::Go => {
                in_region(address, 1, bl::FLASH_BASE, bl::FLASH_SIZE)
                    || in_region(address, 1, bl::RAM_BASE, bl::RAM_SIZE)
            }
            _ => false,
        };
        if !ok {
            return self.nack(out);
        }
        out.push(ACK);
        self.state = match cmd {
            Command::ReadMemory => State::ReadLength {
                address,
                first: None,
            },
            Command::WriteMemory => State::WriteData {
                address,
                buf: Vec::with_capacity(bl::MAX_BLOCK + 2),
            },
            _ => {
                self.go = Some(address);
                State::Jumped
            }
        };
    }

    /// The bytes at `[address, address + len)` if they lie in one readable region.
    fn readable(&self, address: u32, len: usize) -> Option<Vec<u8>> {
        let len32 = u32::try_from(len).ok()?;
        let slice = |mem: &[u8], base: u32| {
            let off = (address - base) as usize;
            mem[off..off + len].to_vec()
        };
        if in_region(address, len32, bl::FLASH_BASE, bl::FLASH_SIZE) {
            Some(slice(&self.flash, bl::FLASH_BASE))
        } else if in_region(address, len32, bl::RAM_BASE, bl::RAM_SIZE) {
            Some(slice(&self.ram, bl::RAM_BASE))
        } else if in_region(address, len32, bl::OPTION_BYTES_BASE, bl::OPTION_BYTES_SIZE) {
            Some(slice(&OPTION_BYTES, bl::OPTION_BYTES_BASE))
        } else if in_region(
            address,
            len32,
            bl::SYSTEM_MEMORY_BASE,
            bl::SYSTEM_MEMORY_SIZE + bl::OTP_SIZE,
        ) {
            Some(vec![0xFF; len])
        } else {
            None
        }
    }

    fn writable(&self, address: u32, len: u32) -> bool {
        in_region(address, len, bl::FLASH_BASE, bl::FLASH_SIZE)
            || in_region(
                address,
                len,
                bl::RAM_BOOTLOADER_END,
                bl::RAM_BASE + bl::RAM_SIZE - bl::RAM_BOOTLOADER_END,
            )
    }

    /// Programs `data` at `address`; false (nothing written) if the block is misaligned,
    /// leaves writable memory, or would program a flash word that is not erased.
    fn write(&mut self, address: u32, data: &[u8]) -> bool {
        let Ok(len) = u32::try_from(data.len()) else {
            return false;
        };
        if !bl::is_write_aligned(address, data.len()) || !self.writable(address, len) {
            return false;
        }
        if in_region(address, len, bl::FLASH_BASE, bl::FLASH_SIZE) {
            let off = (address - bl::FLASH_BASE) as usize;
            let target = &mut self.flash[off..off + data.len()];
            // NOR flash programs 1 → 0 only. A word that is not erased cannot take new
            // data (the F4 reports a programming error); writing all-ones is a no-op.
            let clash = target
                .chunks_exact(4)
                .zip(data.chunks_exact(4))
                .any(|(old, new)| old != [0xFF; 4] && new != [0xFF; 4]);
            if clash {
                return false;
            }
            for (old, new) in target.chunks_exact_mut(4).zip(data.chunks_exact(4)) {
                if new != [0xFF; 4] {
                    old.copy_from_slice(new);
                }
            }
            let start = address - bl::FLASH_BASE;
            self.dirty.push(start..start + len);
        } else {
            let off = (address - bl::RAM_BASE) as usize;
            self.ram[off..off + data.len()].copy_from_slice(data);
        }
        true
    }

    fn erase_sector(&mut self, index: usize) {
        if let Some(s) = F405_SECTORS.get(index) {
            let start = s.start - bl::FLASH_BASE;
            self.flash[start as usize..(start + s.size) as usize].fill(0xFF);
            self.dirty.push(start..start + s.size);
            self.stats.sectors_erased += 1;
        }
    }

    fn mass_erase(&mut self) {
        for i in 0..F405_SECTORS.len() {
            self.erase_sector(i);
        }
    }
}

/// True if `[address, address + len)` lies inside `[base, base + size)`.
fn in_region(address: u32, len: u32, base: u32, size: u32) -> bool {
    let (a, l, b, s) = (
        u64::from(address),
        u64::from(len),
        u64::from(base),
        u64::from(size),
    );
    a >= b && a + l <= b + s
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn synced() -> Bootloader {
        let mut b = Bootloader::new();
        assert_eq!(talk(&mut b, &[SYNC]), [ACK]);
        b
    }

    fn talk(b: &mut Bootloader, bytes: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        b.feed(bytes, &mut out);
        out
    }

    fn cmd(c: Command) -> [u8; 2] {
        bl::command_frame(c)
    }

    fn read(b: &mut Bootloader, address: u32, len: usize) -> Vec<u8> {
        let mut out = talk(b, &cmd(Command::ReadMemory));
        out.extend(talk(b, &bl::address_frame(address)));
        out.extend(talk(b, &bl::read_length_frame(len).unwrap()));
        assert_eq!(&out[..3], &[ACK, ACK, ACK], "read at {address:#x}");
        out[3..].to_vec()
    }

    /// The whole Write Memory exchange; returns the last answer byte.
    fn write(b: &mut Bootloader, address: u32, data: &[u8]) -> u8 {
        assert_eq!(talk(b, &cmd(Command::WriteMemory)), [ACK]);
        let a = talk(b, &bl::address_frame(address));
        if a != [ACK] {
            return a[0];
        }
        let mut frame = [0u8; 258];
        let n = bl::encode_data_block(data, &mut frame).unwrap();
        let out = talk(b, &frame[..n]);
        assert_eq!(out.len(), 1);
        out[0]
    }

    fn erase(b: &mut Bootloader, req: bl::EraseRequest) -> Vec<u8> {
        let mut frame = [0u8; 64];
        let n = bl::encode_extended_erase(req, &mut frame).unwrap();
        let mut out = talk(b, &cmd(Command::ExtendedErase));
        out.extend(talk(b, &frame[..n]));
        out
    }

    #[test]
    fn autobaud_ignores_noise_then_acks_0x7f() {
        let mut b = Bootloader::new();
        assert!(talk(&mut b, &[0x00, 0x55, 0xFF]).is_empty());
        assert!(!b.synced());
        assert_eq!(talk(&mut b, &[SYNC]), [ACK]);
        assert!(b.synced());
        // A second 0x7F is the start of a command, and 0x7F 0x7F is not a valid pair:
        // exactly what stm32flash relies on to detect an already-synced chip.
        assert!(talk(&mut b, &[SYNC]).is_empty());
        assert_eq!(talk(&mut b, &[SYNC]), [NACK]);
    }

    #[test]
    fn get_lists_the_f405_commands() {
        let mut b = synced();
        assert_eq!(
            talk(&mut b, &cmd(Command::Get)),
            [
                ACK, 0x0B, 0x31, 0x00, 0x01, 0x02, 0x11, 0x21, 0x31, 0x44, 0x63, 0x73, 0x82, 0x92,
                ACK
            ]
        );
    }

    #[test]
    fn get_version_and_id() {
        let mut b = synced();
        assert_eq!(
            talk(&mut b, &cmd(Command::GetVersion)),
            [ACK, 0x31, 0x00, 0x00, ACK]
        );
        assert_eq!(
            talk(&mut b, &cmd(Command::GetId)),
            [ACK, 0x01, 0x04, 0x13, ACK]
        );
    }

    #[test]
    fn bad_complement_and_unsupported_commands_get_nack() {
        let mut b = synced();
        assert_eq!(talk(&mut b, &[0x00, 0x00]), [NACK]);
        assert_eq!(talk(&mut b, &cmd(Command::Erase)), [NACK]);
        assert_eq!(talk(&mut b, &cmd(Command::WriteProtect)), [NACK]);
        assert_eq!(talk(&mut b, &cmd(Command::ReadoutProtect)), [NACK]);
        assert_eq!(talk(&mut b, &[0xFF, 0x00]), [NACK]);
        assert_eq!(talk(&mut b, &[0xA1, 0x5E]), [NACK]);
        // Still in step after all that.
        assert_eq!(talk(&mut b, &cmd(Command::GetId))[..1], [ACK]);
    }

    #[test]
    fn read_memory_regions() {
        let mut b = synced();
        assert_eq!(read(&mut b, bl::FLASH_BASE, 256), vec![0xFF; 256]);
        assert_eq!(read(&mut b, 0x080F_FFFC, 4), vec![0xFF; 4]);
        assert_eq!(read(&mut b, bl::RAM_BASE, 8), vec![0; 8]);
        assert_eq!(read(&mut b, bl::OPTION_BYTES_BASE, 16), OPTION_BYTES);
        assert_eq!(read(&mut b, bl::SYSTEM_MEMORY_BASE, 4), vec![0xFF; 4]);
    }

    #[test]
    fn read_memory_refusals() {
        let mut b = synced();
        // Unmapped address: NACK after the address.
        assert_eq!(talk(&mut b, &cmd(Command::ReadMemory)), [ACK]);
        assert_eq!(talk(&mut b, &bl::address_frame(0x0810_0000)), [NACK]);
        // Bad address checksum.
        assert_eq!(talk(&mut b, &cmd(Command::ReadMemory)), [ACK]);
        assert_eq!(talk(&mut b, &[0x08, 0, 0, 0, 0x00]), [NACK]);
        // Length complement wrong.
        assert_eq!(talk(&mut b, &cmd(Command::ReadMemory)), [ACK]);
        assert_eq!(talk(&mut b, &bl::address_frame(bl::FLASH_BASE)), [ACK]);
        assert_eq!(talk(&mut b, &[0xFF, 0xFF]), [NACK]);
        // Runs past the end of flash.
        assert_eq!(talk(&mut b, &cmd(Command::ReadMemory)), [ACK]);
        assert_eq!(talk(&mut b, &bl::address_frame(0x080F_FF04)), [ACK]);
        assert_eq!(talk(&mut b, &[0xFF, 0x00]), [NACK]);
        // Exactly up to the end is fine.
        assert_eq!(read(&mut b, 0x080F_FF00, 256), vec![0xFF; 256]);
    }

    #[test]
    fn write_then_read_back() {
        let mut b = synced();
        let data: Vec<u8> = (0..=255u8).collect();
        assert_eq!(write(&mut b, 0x0800_0100, &data), ACK);
        assert_eq!(read(&mut b, 0x0800_0100, 256), data);
        assert_eq!(b.flash()[0x100..0x200], data[..]);
        assert_eq!(b.take_dirty(), vec![0x100..0x200]);
        assert_eq!(b.stats().writes, 1);
        // RAM above the bootloader's own 12 KiB.
        assert_eq!(write(&mut b, 0x2000_3000, &[1, 2, 3, 4]), ACK);
        assert_eq!(read(&mut b, 0x2000_3000, 4), [1, 2, 3, 4]);
    }

    #[test]
    fn write_refusals() {
        let mut b = synced();
        // Misaligned address: NACK after the address.
        assert_eq!(write(&mut b, 0x0800_0002, &[0; 4]), NACK);
        // Length not a multiple of 4: NACK after the data.
        assert_eq!(write(&mut b, 0x0800_0000, &[0; 6]), NACK);
        // Outside flash and RAM, and the bootloader's RAM.
        assert_eq!(write(&mut b, 0x0810_0000, &[0; 4]), NACK);
        assert_eq!(write(&mut b, 0x2000_0000, &[0; 4]), NACK);
        assert_eq!(write(&mut b, bl::OPTION_BYTES_BASE, &[0; 4]), NACK);
        // Runs past the end of flash.
        assert_eq!(write(&mut b, 0x080F_FFF0, &[0; 32]), NACK);
        // Bad data checksum.
        assert_eq!(talk(&mut b, &cmd(Command::WriteMemory)), [ACK]);
        assert_eq!(talk(&mut b, &bl::address_frame(bl::FLASH_BASE)), [ACK]);
        assert_eq!(talk(&mut b, &[0x03, 1, 2, 3, 4, 0x00]), [NACK]);
        assert_eq!(b.flash()[..4], [0xFF; 4]);
        assert_eq!(b.stats().writes, 0);
    }

    #[test]
    fn programming_unerased_flash_is_refused_whole() {
        let mut b = synced();
        assert_eq!(
            write(&mut b, bl::FLASH_BASE + 8, &[0x12, 0x34, 0x56, 0x78]),
            ACK
        );
        // The block overlaps the programmed word: refused, and nothing of it lands.
        let block = [0xA5; 16];
        assert_eq!(write(&mut b, bl::FLASH_BASE, &block), NACK);
        assert_eq!(
            read(&mut b, bl::FLASH_BASE, 16),
            [
                0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x12, 0x34, 0x56, 0x78, 0xFF, 0xFF,
                0xFF, 0xFF
            ]
        );
        // All-ones over it programs nothing, so it is allowed (tools pad with 0xFF).
        assert_eq!(write(&mut b, bl::FLASH_BASE + 8, &[0xFF; 4]), ACK);
        // After erasing sector 0 the same block goes in.
        assert_eq!(erase(&mut b, bl::EraseRequest::Pages(&[0])), [ACK, ACK]);
        assert_eq!(write(&mut b, bl::FLASH_BASE, &block), ACK);
        assert_eq!(read(&mut b, bl::FLASH_BASE, 16), block);
    }

    #[test]
    fn extended_erase_by_sector() {
        let mut b = synced();
        for s in [0u16, 4, 5, 11] {
            let a = F405_SECTORS[usize::from(s)].start;
            assert_eq!(write(&mut b, a, &[0; 8]), ACK);
        }
        let _ = b.take_dirty();
        assert_eq!(erase(&mut b, bl::EraseRequest::Pages(&[4, 11])), [ACK, ACK]);
        assert_eq!(read(&mut b, F405_SECTORS[0].start, 4), [0; 4]);
        assert_eq!(read(&mut b, F405_SECTORS[4].start, 4), [0xFF; 4]);
        assert_eq!(read(&mut b, F405_SECTORS[5].start, 4), [0; 4]);
        assert_eq!(read(&mut b, F405_SECTORS[11].start, 4), [0xFF; 4]);
        assert_eq!(
            b.take_dirty(),
            vec![0x1_0000..0x2_0000, 0xE_0000..0x10_0000]
        );
    }

    #[test]
    fn a_sector_listed_many_times_is_erased_once() {
        let mut b = synced();
        assert_eq!(write(&mut b, F405_SECTORS[3].start, &[0; 4]), ACK);
        let list = [3u16; 100];
        let mut frame = [0u8; 256];
        let n = bl::encode_extended_erase(bl::EraseRequest::Pages(&list), &mut frame).unwrap();
        assert_eq!(talk(&mut b, &cmd(Command::ExtendedErase)), [ACK]);
        assert_eq!(talk(&mut b, &frame[..n]), [ACK]);
        assert_eq!(read(&mut b, F405_SECTORS[3].start, 4), [0xFF; 4]);
        assert_eq!(b.stats().sectors_erased, 1);
    }

    #[test]
    fn extended_erase_refusals() {
        let mut b = synced();
        assert_eq!(write(&mut b, bl::FLASH_BASE, &[0; 4]), ACK);
        // Sector 12 does not exist: the whole command is refused.
        assert_eq!(
            erase(&mut b, bl::EraseRequest::Pages(&[0, 12])),
            [ACK, NACK]
        );
        // Bad checksum.
        assert_eq!(talk(&mut b, &cmd(Command::ExtendedErase)), [ACK]);
        assert_eq!(talk(&mut b, &[0x00, 0x00, 0x00, 0x00, 0x01]), [NACK]);
        // Bank erases: the F405 has one bank.
        assert_eq!(erase(&mut b, bl::EraseRequest::Bank1), [ACK, NACK]);
        assert_eq!(erase(&mut b, bl::EraseRequest::Bank2), [ACK, NACK]);
        // Mass erase with a wrong checksum.
        assert_eq!(talk(&mut b, &cmd(Command::ExtendedErase)), [ACK]);
        assert_eq!(talk(&mut b, &[0xFF, 0xFF, 0x01]), [NACK]);
        // Reserved code.
        assert_eq!(talk(&mut b, &cmd(Command::ExtendedErase)), [ACK]);
        assert_eq!(talk(&mut b, &[0xFF, 0xF0, 0x0F]), [NACK]);
        assert_eq!(read(&mut b, bl::FLASH_BASE, 4), [0; 4]);
    }

    #[test]
    fn mass_erase() {
        let mut b = synced();
        assert_eq!(write(&mut b, bl::FLASH_BASE, &[0; 4]), ACK);
        assert_eq!(write(&mut b, 0x080F_FFFC, &[0; 4]), ACK);
        assert_eq!(erase(&mut b, bl::EraseRequest::Mass), [ACK, ACK]);
        assert!(b.flash().iter().all(|&x| x == 0xFF));
        assert_eq!(b.stats().sectors_erased, 12);
    }

    #[test]
    fn go_records_the_address_and_stops_listening() {
        let mut b = synced();
        assert_eq!(talk(&mut b, &cmd(Command::Go)), [ACK]);
        assert_eq!(talk(&mut b, &bl::address_frame(0x0900_0000)), [NACK]);
        assert_eq!(talk(&mut b, &cmd(Command::Go)), [ACK]);
        assert_eq!(talk(&mut b, &bl::address_frame(bl::FLASH_BASE)), [ACK]);
        assert_eq!(b.go_address(), Some(bl::FLASH_BASE));
        assert!(talk(&mut b, &cmd(Command::Get)).is_empty());
        assert!(talk(&mut b, &[SYNC]).is_empty());
        b.reset();
        assert_eq!(b.go_address(), None);
        assert_eq!(talk(&mut b, &[SYNC]), [ACK]);
    }

    #[test]
    fn unprotect_commands_reset_the_chip() {
        let mut b = synced();
        assert_eq!(talk(&mut b, &cmd(Command::WriteUnprotect)), [ACK, ACK]);
        assert!(!b.synced());
        assert_eq!(talk(&mut b, &[SYNC]), [ACK]);
        assert_eq!(write(&mut b, bl::FLASH_BASE, &[0; 4]), ACK);
        assert_eq!(talk(&mut b, &cmd(Command::ReadoutUnprotect)), [ACK, ACK]);
        assert!(!b.synced());
        assert!(b.flash().iter().all(|&x| x == 0xFF));
    }

    #[test]
    fn saved_flash_must_have_the_flash_size() {
        assert_eq!(
            Bootloader::with_flash(vec![0; 10]).err(),
            Some(BootloaderError::ImageSize {
                expected: 1 << 20,
                actual: 10
            })
        );
        let mut image = vec![0xFF; 1 << 20];
        image[0] = 0x42;
        let mut b = Bootloader::with_flash(image).unwrap();
        assert_eq!(talk(&mut b, &[SYNC]), [ACK]);
        assert_eq!(read(&mut b, bl::FLASH_BASE, 4), [0x42, 0xFF, 0xFF, 0xFF]);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Whatever arrives on the line, the emulator answers without panicking, and a
        /// reset brings it back to a working chip.
        #[test]
        fn arbitrary_bytes_never_panic(
            chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..300), 0..8),
            synced_first in any::<bool>(),
        ) {
            let mut b = Bootloader::new();
            let mut out = Vec::new();
            if synced_first {
                b.feed(&[SYNC], &mut out);
            }
            for c in &chunks {
                b.feed(c, &mut out);
            }
            b.reset();
            out.clear();
            b.feed(&[SYNC], &mut out);
            prop_assert_eq!(out, vec![ACK]);
        }

        /// Blocks written into erased flash at any aligned place read back as written.
        #[test]
        fn aligned_writes_read_back(
            word in 0u32..(bl::FLASH_SIZE / 4 - 64),
            data in proptest::collection::vec(any::<u8>(), 1..=64usize),
        ) {
            let mut b = synced();
            let mut data = data;
            data.resize(data.len().div_ceil(4) * 4, 0);
            let address = bl::FLASH_BASE + word * 4;
            prop_assert_eq!(write(&mut b, address, &data), ACK);
            prop_assert_eq!(read(&mut b, address, data.len()), data);
        }
    }
}
