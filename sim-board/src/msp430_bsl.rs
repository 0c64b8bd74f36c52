//! The MSP430F168's ROM bootstrap loader (BSL 1.61, TI SLAU319's 1xx/2xx/4xx protocol)
//! as a sans-I/O emulator: bytes in, bytes out, like [`crate::bootloader`] for the STM32.
//! The same model runs behind a pseudo-terminal (`fpgfx-sim --bootloader msp430`),
//! inside host-cli's flash tests and in the unit tests below.
//!
//! It exists so that `fpgfx flash --chip msp430f168` and a third-party BSL client
//! (python-msp430-tools' `msp430-bsl`) can be tested end to end without a FITkit. What it
//! models, and where it knowingly differs from the real part, is listed in
//! `docs/flash.md`; in short:
//!
//! * every command is preceded by SYNC 0x80, answered with DATA_ACK; other bytes while
//!   waiting for SYNC are ignored;
//! * a frame with a bad header, L1 ≠ L2, an odd or oversized length or a wrong checksum
//!   is answered with DATA_NAK, as soon as the fault is known;
//! * all commands but RX password and mass erase are refused until the password (the
//!   vector table at 0xFFE0) is given; a wrong password is NAK'd and erases nothing (as
//!   on the 1xx BSL);
//! * flash programming only clears bits: a write over programmed cells stores the AND of
//!   old and new and is answered DATA_NAK, which is what the real BSL's online
//!   verification (from V1.40) reports;
//! * RX data block, TX data block and erase check must lie in one region of the F168's
//!   map (RAM, information memory, main flash; the boot ROM is readable); peripherals
//!   (0x0000..0x0200) are not modelled and are NAK'd;
//! * Load PC records the address and the chip stops listening until [`Bsl::reset`];
//!   Change baud rate is acknowledged and recorded (a pty has no baud rate);
//! * erase takes no time.

use std::ops::Range;

use protocol::msp430_bsl::{
    self as wire, erase_mode, Chip, Command, Kind, DATA_ACK, DATA_NAK, MAX_DATA, MAX_FRAME,
    MSP430F168, PASSWORD_ADDRESS, PASSWORD_LEN, SYNC,
};

use crate::bootloader::BootloaderError;

/// The 16-bit address space the model keeps (the F168 has nothing above 0xFFFF).
pub const SPACE: usize = 0x1_0000;

/// Where the emulator is.
#[derive(Debug, Clone, PartialEq, Eq)]
enum State {
    /// Waiting for SYNC.
    AwaitSync,
    /// SYNC answered: collecting a frame (its length known after four bytes).
    Frame(Vec<u8>),
    /// Load PC was accepted: user code runs and the BSL no longer listens.
    Jumped,
}

/// Counters a test or the sim can report.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct Stats {
    /// Frames answered DATA_ACK or with a data frame.
    pub commands: u64,
    /// DATA_NAKs sent.
    pub naks: u64,
    /// RX data blocks that were written and verified.
    pub writes: u64,
    /// Mass erases.
    pub mass_erases: u64,
}

/// The emulated MSP430F168 in its ROM BSL.
pub struct Bsl {
    chip: Chip,
    state: State,
    memory: Vec<u8>,
    unlocked: bool,
    go: Option<u16>,
    baud: u32,
    dirty: Vec<Range<u32>>,
    stats: Stats,
    corrupt_answers: bool,
}

impl Default for Bsl {
    fn default() -> Self {
        Self::new()
    }
}

impl Bsl {
    /// A factory-fresh F168: flash erased (so the password is 32 × 0xFF), RAM zero,
    /// locked, waiting for SYNC.
    pub fn new() -> Self {
        let chip = MSP430F168;
        let mut memory = vec![0xFF; SPACE];
        for r in chip.regions {
            if r.kind == Kind::Ram {
                memory[r.start as usize..r.end as usize].fill(0);
            }
        }
        memory[0x0FF0..0x1000].copy_from_slice(&chip.version_bytes());
        Self {
            chip,
            state: State::AwaitSync,
            memory,
            unlocked: false,
            go: None,
            baud: 9600,
            dirty: Vec::new(),
            stats: Stats::default(),
            corrupt_answers: false,
        }
    }

    /// A chip whose flash holds `image` (the 64 KiB address space a previous run saved;
    /// only its flash regions are taken), so a flash interrupted in one process can be
    /// completed by the next.
    pub fn with_memory(image: Vec<u8>) -> Result<Self, BootloaderError> {
        if image.len() != SPACE {
            return Err(BootloaderError::ImageSize {
                expected: SPACE,
                actual: image.len(),
            });
        }
        let mut b = Self::new();
        for r in b.chip.regions {
            if matches!(r.kind, Kind::Flash { .. }) {
                let range = r.start as usize..r.end as usize;
                b.memory[range.clone()].copy_from_slice(&image[range]);
            }
        }
        Ok(b)
    }

    /// A test aid: every data frame leaves with a wrong checksum, as if the line flipped
    /// a bit of each answer, so a client that does not check answers is caught.
    pub fn corrupt_answers(&mut self, on: bool) {
        self.corrupt_answers = on;
    }

    /// The BSL entry sequence again (RST/TEST on a board): locked, waiting for SYNC.
    /// Memory survives.
    pub fn reset(&mut self) {
        self.state = State::AwaitSync;
        self.unlocked = false;
        self.go = None;
        self.baud = 9600;
    }

    /// The 64 KiB address space (flash, RAM, boot ROM; peripherals read 0xFF).
    pub fn memory(&self) -> &[u8] {
        &self.memory
    }

    /// Whether the password has been accepted since the last reset.
    pub fn unlocked(&self) -> bool {
        self.unlocked
    }

    /// Where Load PC jumped, until the next [`Bsl::reset`].
    pub fn go_address(&self) -> Option<u16> {
        self.go
    }

    /// The line rate Change baud rate asked for (9600 after reset).
    pub fn baud(&self) -> u32 {
        self.baud
    }

    /// Counters since creation.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Flash ranges (addresses) changed since the last call, for a caller that persists
    /// the flash.
    pub fn take_dirty(&mut self) -> Vec<Range<u32>> {
        std::mem::take(&mut self.dirty)
    }

    /// Processes bytes from the host and appends the answers to `out`.
    pub fn feed(&mut self, input: &[u8], out: &mut Vec<u8>) {
        for &b in input {
            self.step(b, out);
        }
    }

    fn nak(&mut self, out: &mut Vec<u8>) {
        out.push(DATA_NAK);
        self.stats.naks += 1;
        self.state = State::AwaitSync;
    }

    fn ack(&mut self, out: &mut Vec<u8>) {
        out.push(DATA_ACK);
        self.stats.commands += 1;
    }

    fn step(&mut self, b: u8, out: &mut Vec<u8>) {
        match std::mem::replace(&mut self.state, State::AwaitSync) {
            State::Jumped => self.state = State::Jumped,
            State::AwaitSync => {
                if b == SYNC {
                    out.push(DATA_ACK);
                    self.state = State::Frame(Vec::with_capacity(MAX_FRAME));
                }
            }
            State::Frame(mut buf) => {
                buf.push(b);
                // The header byte is judged at once, the lengths once both are in: the
                // BSL gives up on a frame as soon as it cannot be one.
                if buf.len() == 1 && !(0x80..=0x8F).contains(&b) {
                    return self.nak(out);
                }
                if buf.len() < 4 {
                    self.state = State::Frame(buf);
                    return;
                }
                match wire::frame_len([buf[0], buf[1], buf[2], buf[3]], 4) {
                    Err(_) => self.nak(out),
                    Ok(n) if buf.len() < n => self.state = State::Frame(buf),
                    Ok(_) => self.frame(&buf, out),
                }
            }
        }
    }

    /// A complete frame: checked, then executed.
    fn frame(&mut self, frame: &[u8], out: &mut Vec<u8>) {
        let Ok(req) = wire::decode_request(frame) else {
            return self.nak(out);
        };
        let Some(cmd) = Command::from_code(req.command) else {
            return self.nak(out);
        };
        if cmd.needs_password() && !self.unlocked {
            return self.nak(out);
        }
        let (address, length) = (u32::from(req.address), u32::from(req.length));
        let ok = match cmd {
            Command::RxPassword => {
                let right = req.data.len() == PASSWORD_LEN
                    && *req.data == self.memory[usize::from(PASSWORD_ADDRESS)..];
                self.unlocked |= right;
                right
            }
            Command::MassErase => {
                self.mass_erase();
                true
            }
            Command::RxDataBlock => {
                usize::from(req.length) == req.data.len() && self.write(address, req.data)
            }
            Command::TxDataBlock => match self.readable(address, length) {
                Some(bytes) if req.data.is_empty() => return self.data_frame(&bytes, out),
                _ => false,
            },
            Command::TxBslVersion => {
                let version = self.memory[0x0FF0..0x1000].to_vec();
                return self.data_frame(&version, out);
            }
            Command::EraseSegment => self.erase_segment(address, req.length),
            Command::EraseCheck => match self.chip.region(address, length) {
                Some(_) if length > 0 => self.memory[address as usize..(address + length) as usize]
                    .iter()
                    .all(|&b| b == 0xFF),
                _ => false,
            },
            Command::LoadPc => {
                let runnable = self
                    .chip
                    .region(address, 2)
                    .is_some_and(|r| r.kind != Kind::Rom);
                if runnable && address.is_multiple_of(2) {
                    self.ack(out);
                    self.go = Some(req.address);
                    self.state = State::Jumped;
                    return;
                }
                false
            }
            Command::ChangeBaudRate => {
                // D3 (LL) selects the rate; D1 D2 are the clock settings, not modelled.
                let rate = match req.length & 0xFF {
                    0 => Some(9600),
                    1 => Some(19_200),
                    2 => Some(38_400),
                    _ => None,
                };
                if let Some(rate) = rate {
                    self.baud = rate;
                }
                rate.is_some()
            }
            // BSL 2.12 and up only; the F168's 1.61 does not know it.
            Command::SetMemOffset => false,
        };
        if ok {
            self.ack(out);
        } else {
            self.nak(out);
        }
    }

    /// Answers with a data frame (its checksum spoilt under [`Bsl::corrupt_answers`]).
    fn data_frame(&mut self, data: &[u8], out: &mut Vec<u8>) {
        let mut frame = [0u8; MAX_FRAME];
        match wire::encode_data_frame(data, &mut frame) {
            Ok(n) => {
                if self.corrupt_answers {
                    frame[n - 1] ^= 0x01;
                }
                out.extend_from_slice(&frame[..n]);
                self.stats.commands += 1;
            }
            // Reads are limited to a frame's worth before they get here.
            Err(_) => self.nak(out),
        }
    }

    /// The bytes of `[address, address + len)` if they lie in one region and the read
    /// is word-aligned and fits a data frame.
    fn readable(&self, address: u32, len: u32) -> Option<Vec<u8>> {
        let fits = (2..=MAX_DATA as u32).contains(&len)
            && len.is_multiple_of(2)
            && address.is_multiple_of(2);
        self.chip.region(address, len).filter(|_| fits)?;
        Some(self.memory[address as usize..(address + len) as usize].to_vec())
    }

    /// Programs `data` at `address`: RAM takes it as is, flash only clears bits. False
    /// if the block leaves writable memory, is not word-aligned, or (flash) reads back
    /// other than `data` — the cells are then left holding old AND new, as on the part.
    fn write(&mut self, address: u32, data: &[u8]) -> bool {
        let len = data.len() as u32;
        let aligned = address.is_multiple_of(2) && len.is_multiple_of(2) && len > 0;
        let Some(region) = self.chip.region(address, len).filter(|_| aligned) else {
            return false;
        };
        let target = &mut self.memory[address as usize..(address + len) as usize];
        match region.kind {
            Kind::Rom => false,
            Kind::Ram => {
                target.copy_from_slice(data);
                true
            }
            Kind::Flash { .. } => {
                for (old, new) in target.iter_mut().zip(data) {
                    *old &= new;
                }
                let verified = target == data;
                self.dirty.push(address..address + len);
                if verified {
                    self.stats.writes += 1;
                }
                verified
            }
        }
    }

    /// Erase segment: the segment holding `address` (mode 0xA502), or all of main or
    /// information memory (0xA504); other modes and non-flash addresses are refused.
    fn erase_segment(&mut self, address: u32, mode: u16) -> bool {
        let Some(region) = self.chip.region(address, 1) else {
            return false;
        };
        let Kind::Flash { segment } = region.kind else {
            return false;
        };
        let range = match mode {
            erase_mode::SEGMENT => {
                let start = address - (address - region.start) % segment;
                start..start + segment
            }
            erase_mode::MAIN_OR_INFO => region.start..region.end,
            _ => return false,
        };
        self.erase(range);
        true
    }

    /// Main and information memory, whatever LL LH say (the 1xx ROM BSL ignores them).
    fn mass_erase(&mut self) {
        for r in self.chip.regions {
            if matches!(r.kind, Kind::Flash { .. }) {
                self.erase(r.start..r.end);
            }
        }
        self.stats.mass_erases += 1;
    }

    fn erase(&mut self, range: Range<u32>) {
        self.memory[range.start as usize..range.end as usize].fill(0xFF);
        self.dirty.push(range);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use protocol::msp430_bsl::{decode_data_frame, encode_request, ERASED_PASSWORD};

    fn talk(b: &mut Bsl, bytes: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        b.feed(bytes, &mut out);
        out
    }

    /// SYNC, then the frame; returns the answer after the SYNC's ACK.
    fn command(b: &mut Bsl, cmd: Command, address: u16, length: u16, data: &[u8]) -> Vec<u8> {
        assert_eq!(talk(b, &[SYNC]), [DATA_ACK], "sync before {}", cmd.name());
        let mut frame = [0u8; MAX_FRAME];
        let n = encode_request(cmd.code(), address, length, data, &mut frame).unwrap();
        talk(b, &frame[..n])
    }

    fn write(b: &mut Bsl, address: u16, data: &[u8]) -> Vec<u8> {
        command(b, Command::RxDataBlock, address, data.len() as u16, data)
    }

    fn read(b: &mut Bsl, address: u16, len: u16) -> Vec<u8> {
        let out = command(b, Command::TxDataBlock, address, len, &[]);
        decode_data_frame(&out)
            .unwrap_or_else(|e| panic!("read at {address:#06x}: {e} in {out:02x?}"))
            .to_vec()
    }

    /// Erased and unlocked, as every host starts.
    fn unlocked() -> Bsl {
        let mut b = Bsl::new();
        assert_eq!(
            command(&mut b, Command::MassErase, 0xFFFE, 0xA506, &[]),
            [DATA_ACK]
        );
        assert_eq!(
            command(&mut b, Command::RxPassword, 0, 0, &ERASED_PASSWORD),
            [DATA_ACK]
        );
        b
    }

    #[test]
    fn protected_commands_are_refused_until_the_password() {
        let mut b = Bsl::new();
        for (cmd, len, data) in [
            (Command::RxDataBlock, 2, &[1u8, 2][..]),
            (Command::TxDataBlock, 2, &[][..]),
            (Command::EraseSegment, 0xA502, &[][..]),
            (Command::EraseCheck, 2, &[][..]),
            (Command::LoadPc, 0, &[][..]),
            (Command::TxBslVersion, 0, &[][..]),
            (Command::ChangeBaudRate, 1, &[][..]),
        ] {
            assert_eq!(
                command(&mut b, cmd, 0x4000, len, data),
                [DATA_NAK],
                "{}",
                cmd.name()
            );
        }
        assert_eq!(b.memory()[0x4000], 0xFF);
        assert_eq!(
            command(&mut b, Command::RxPassword, 0, 0, &ERASED_PASSWORD),
            [DATA_ACK]
        );
        assert!(b.unlocked());
        let v = command(&mut b, Command::TxBslVersion, 0, 0, &[]);
        let data = decode_data_frame(&v).unwrap();
        assert_eq!(
            protocol::msp430_bsl::parse_version(data),
            Some((0xF169, 0x0161))
        );
        // A reset (the entry sequence again) locks it.
        b.reset();
        assert_eq!(
            command(&mut b, Command::TxDataBlock, 0x4000, 2, &[]),
            [DATA_NAK]
        );
    }

    #[test]
    fn a_wrong_password_is_refused_and_erases_nothing() {
        let mut b = unlocked();
        let mut vectors = [0u8; 32];
        for (i, v) in vectors.iter_mut().enumerate() {
            *v = 0x40 + i as u8;
        }
        assert_eq!(write(&mut b, 0xFFE0, &vectors), [DATA_ACK]);
        assert_eq!(write(&mut b, 0x4000, &[0x31, 0x40]), [DATA_ACK]);
        b.reset();
        assert_eq!(
            command(&mut b, Command::RxPassword, 0, 0, &ERASED_PASSWORD),
            [DATA_NAK]
        );
        assert!(!b.unlocked());
        assert_eq!(&b.memory()[0x4000..0x4002], &[0x31, 0x40]);
        // Short passwords are wrong too.
        assert_eq!(
            command(&mut b, Command::RxPassword, 0, 0, &vectors[..30]),
            [DATA_NAK]
        );
        assert_eq!(
            command(&mut b, Command::RxPassword, 0, 0, &vectors),
            [DATA_ACK]
        );
        assert_eq!(read(&mut b, 0x4000, 2), [0x31, 0x40]);
    }

    #[test]
    fn mass_erase_resets_the_password_to_all_ones() {
        let mut b = unlocked();
        assert_eq!(write(&mut b, 0xFFE0, &[0x12; 32]), [DATA_ACK]);
        assert_eq!(write(&mut b, 0x1000, &[0x34; 128]), [DATA_ACK]);
        b.reset();
        // Locked, and the old password is unknown to this host: erase.
        assert_eq!(
            command(&mut b, Command::MassErase, 0xFFFE, 0xA506, &[]),
            [DATA_ACK]
        );
        assert!(!b.unlocked());
        assert!(b.memory()[0x4000..].iter().all(|&x| x == 0xFF));
        // Information memory too (MERAS + ERASE on the 1xx).
        assert!(b.memory()[0x1000..0x1100].iter().all(|&x| x == 0xFF));
        assert_eq!(
            command(&mut b, Command::RxPassword, 0, 0, &ERASED_PASSWORD),
            [DATA_ACK]
        );
    }

    #[test]
    fn writing_over_programmed_bits_reads_back_wrong_and_is_naked() {
        let mut b = unlocked();
        assert_eq!(write(&mut b, 0x4000, &[0xF0, 0x0F]), [DATA_ACK]);
        // Programming only clears bits: the same or a subset of bits is fine.
        assert_eq!(write(&mut b, 0x4000, &[0xF0, 0x0F]), [DATA_ACK]);
        assert_eq!(write(&mut b, 0x4000, &[0x30, 0x0F]), [DATA_ACK]);
        // Setting bits again cannot be done: the cells hold old AND new.
        assert_eq!(write(&mut b, 0x4000, &[0x0F, 0xFF]), [DATA_NAK]);
        assert_eq!(read(&mut b, 0x4000, 2), [0x00, 0x0F]);
        // Segment erase brings it back, and only its 512 bytes.
        assert_eq!(write(&mut b, 0x4200, &[0x55, 0x55]), [DATA_ACK]);
        assert_eq!(
            command(&mut b, Command::EraseSegment, 0x41FE, 0xA502, &[]),
            [DATA_ACK]
        );
        assert_eq!(read(&mut b, 0x4000, 2), [0xFF, 0xFF]);
        assert_eq!(read(&mut b, 0x4200, 2), [0x55, 0x55]);
        assert_eq!(
            command(&mut b, Command::EraseCheck, 0x4000, 0x200, &[]),
            [DATA_ACK]
        );
        assert_eq!(
            command(&mut b, Command::EraseCheck, 0x4000, 0x202, &[]),
            [DATA_NAK]
        );
        assert_eq!(write(&mut b, 0x4000, &[0x0F, 0xFF]), [DATA_ACK]);
        // RAM takes anything.
        assert_eq!(write(&mut b, 0x0200, &[1, 2]), [DATA_ACK]);
        assert_eq!(write(&mut b, 0x0200, &[0xFF, 0xFF]), [DATA_ACK]);
        assert_eq!(read(&mut b, 0x0200, 2), [0xFF, 0xFF]);
    }

    #[test]
    fn out_of_map_and_misaligned_accesses_are_naked() {
        let mut b = unlocked();
        for (address, len) in [
            (0xFFFEu16, 4u16), // past the end of flash (the frame's 16-bit address wraps)
            (0x3FFE, 4),       // straddles the gap below main flash
            (0x2000, 2),       // the gap
            (0x10FE, 4),       // past information memory
            (0x09FE, 4),       // past RAM
            (0x0120, 2),       // peripherals (WDTCTL): not modelled
            (0x0C00, 2),       // boot ROM: read-only
            (0x4001, 2),       // odd address
        ] {
            let data = vec![0u8; usize::from(len)];
            assert_eq!(
                write(&mut b, address, &data),
                [DATA_NAK],
                "{address:#06x}+{len}"
            );
        }
        // A length field that disagrees with the data.
        assert_eq!(
            command(&mut b, Command::RxDataBlock, 0x4000, 4, &[0, 0]),
            [DATA_NAK]
        );
        // Reads: out of map, odd, too long for a frame.
        assert_eq!(
            command(&mut b, Command::TxDataBlock, 0x3FFE, 4, &[]),
            [DATA_NAK]
        );
        assert_eq!(
            command(&mut b, Command::TxDataBlock, 0x4000, 3, &[]),
            [DATA_NAK]
        );
        assert_eq!(
            command(&mut b, Command::TxDataBlock, 0x4000, 252, &[]),
            [DATA_NAK]
        );
        assert_eq!(read(&mut b, 0x4000, 250).len(), 250);
        // The boot ROM reads, with the version bytes.
        assert_eq!(&read(&mut b, 0x0FF0, 2), &[0xF1, 0x69]);
        assert!(b.memory()[0x4000..].iter().all(|&x| x == 0xFF));
        // Set mem offset does not exist on BSL 1.61; unknown codes neither.
        assert_eq!(
            command(&mut b, Command::SetMemOffset, 1, 0, &[]),
            [DATA_NAK]
        );
        assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK]);
        let mut frame = [0u8; 16];
        let n = encode_request(0x42, 0, 0, &[], &mut frame).unwrap();
        assert_eq!(talk(&mut b, &frame[..n]), [DATA_NAK]);
    }

    #[test]
    fn bad_frames_are_naked() {
        let mut b = unlocked();
        let mut frame = [0u8; MAX_FRAME];
        let n =
            encode_request(Command::RxDataBlock.code(), 0x4000, 2, &[1, 2], &mut frame).unwrap();
        // A wrong checksum: NAK, nothing written.
        let mut bad = frame;
        bad[n - 1] ^= 0x80;
        assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK]);
        assert_eq!(talk(&mut b, &bad[..n]), [DATA_NAK]);
        assert_eq!(b.memory()[0x4000], 0xFF);
        // A flipped data bit with the checksum left alone: NAK.
        let mut bad = frame;
        bad[8] ^= 0x01;
        assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK]);
        assert_eq!(talk(&mut b, &bad[..n]), [DATA_NAK]);
        // L1 ≠ L2: NAK'd after the fourth byte, the rest is ignored until SYNC.
        let mut bad = frame;
        bad[3] = 8;
        assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK]);
        assert_eq!(talk(&mut b, &bad[..4]), [DATA_NAK]);
        assert!(talk(&mut b, &bad[4..n]).is_empty());
        // Not a header: NAK'd at once.
        assert_eq!(talk(&mut b, &[SYNC, 0x7F]), [DATA_ACK, DATA_NAK]);
        // No SYNC: the frame is ignored (0x80 is the SYNC, answered, then the rest is
        // taken as a frame whose header is the CMD byte 0x12: NAK).
        assert_eq!(talk(&mut b, &frame[..n]), [DATA_ACK, DATA_NAK]);
        // And the good frame still works.
        assert_eq!(write(&mut b, 0x4000, &[1, 2]), [DATA_ACK]);
        assert_eq!(b.stats().writes, 1);
    }

    #[test]
    fn load_pc_leaves_the_bsl_until_reset() {
        let mut b = unlocked();
        assert_eq!(command(&mut b, Command::LoadPc, 0x0C00, 0, &[]), [DATA_NAK]);
        assert_eq!(command(&mut b, Command::LoadPc, 0x4001, 0, &[]), [DATA_NAK]);
        assert_eq!(command(&mut b, Command::LoadPc, 0x4000, 0, &[]), [DATA_ACK]);
        assert_eq!(b.go_address(), Some(0x4000));
        assert!(talk(&mut b, &[SYNC]).is_empty());
        b.reset();
        assert_eq!(b.go_address(), None);
        assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK]);
    }

    #[test]
    fn change_baud_rate_is_recorded() {
        let mut b = unlocked();
        assert_eq!(
            command(&mut b, Command::ChangeBaudRate, 0x87E0, 2, &[]),
            [DATA_ACK]
        );
        assert_eq!(b.baud(), 38_400);
        assert_eq!(
            command(&mut b, Command::ChangeBaudRate, 0, 7, &[]),
            [DATA_NAK]
        );
        b.reset();
        assert_eq!(b.baud(), 9600);
    }

    /// A host that died mid-frame leaves the chip collecting; a burst of 0xFF longer
    /// than any frame ends it with one NAK, and a SYNC is then answered.
    #[test]
    fn a_burst_of_ff_ends_a_half_received_frame() {
        for sent in [0usize, 1, 2, 3, 4, 9, 100, 259] {
            let mut b = unlocked();
            let mut frame = [0u8; MAX_FRAME];
            let n = encode_request(
                Command::RxDataBlock.code(),
                0x4000,
                250,
                &[0; 250],
                &mut frame,
            )
            .unwrap();
            assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK]);
            talk(&mut b, &frame[..sent.min(n)]);
            let answers = talk(&mut b, &[0xFF; MAX_FRAME]);
            assert!(
                answers.iter().all(|&a| a == DATA_NAK) && answers.len() <= 1,
                "after {sent}: {answers:02x?}"
            );
            assert_eq!(talk(&mut b, &[SYNC]), [DATA_ACK], "after {sent}");
        }
    }

    #[test]
    fn memory_survives_a_saved_image() {
        let mut b = unlocked();
        assert_eq!(write(&mut b, 0x4000, &[1, 2, 3, 4]), [DATA_ACK]);
        assert_eq!(write(&mut b, 0x0200, &[9, 9]), [DATA_ACK]);
        let dirty = b.take_dirty();
        assert!(dirty.contains(&(0x4000..0x4004)), "{dirty:?}");
        let again = Bsl::with_memory(b.memory().to_vec()).unwrap();
        assert_eq!(&again.memory()[0x4000..0x4004], &[1, 2, 3, 4]);
        // RAM does not survive; the boot ROM is the chip's own.
        assert_eq!(&again.memory()[0x0200..0x0202], &[0, 0]);
        assert_eq!(&again.memory()[0x0FF0..0x0FF2], &[0xF1, 0x69]);
        assert!(Bsl::with_memory(vec![0; 10]).is_err());
    }

    proptest! {
        /// Any bytes at all: no panic, and only ACK, NAK or data frames come out.
        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..600)) {
            let mut b = unlocked();
            let mut out = Vec::new();
            b.feed(&bytes, &mut out);
        }

        /// Even-aligned writes into erased flash read back.
        #[test]
        fn writes_read_back(
            offset in 0u16..0x5F00,
            data in (1usize..=125).prop_flat_map(|w| proptest::collection::vec(any::<u8>(), 2 * w)),
        ) {
            let mut b = unlocked();
            let address = 0x4000 + 2 * offset;
            prop_assume!(u32::from(address) + data.len() as u32 <= 0x1_0000);
            prop_assert_eq!(write(&mut b, address, &data), vec![DATA_ACK]);
            prop_assert_eq!(read(&mut b, address, data.len() as u16), data);
        }
    }
}
