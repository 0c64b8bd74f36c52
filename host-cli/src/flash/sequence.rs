//! The flash sequences: identify the chip, erase, write every block with bounded retries,
//! read it all back, jump. The STM32 ([`flash`]) and the MSP430 ([`flash_msp430`]) differ
//! in how they identify, unlock and erase; writing, verifying, retrying and reporting
//! progress are one implementation over [`Loader`]. Each reports how far it got as
//! [`Progress`] and what it did as a [`Report`]; the caller decides what to show.

use std::fmt;
use std::io;
use std::time::{Duration, Instant};

use protocol::bootloader::{self as bl, Command};
use protocol::msp430_bsl::{self as bsl, PASSWORD_ADDRESS, PASSWORD_LEN, RESET_VECTOR};

use super::{Block, BslClient, BslInfo, ChipInfo, Client, FlashError, Image, ImageError};
use crate::session::Transport;

/// A step of a flash that takes long enough to show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Erasing what the image needs: one command (or one per segment), seconds on a real
    /// part.
    Erase,
    /// Writing every block.
    Write,
    /// Reading every block back, compared with the image.
    Verify,
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Stage::Erase => "erase",
            Stage::Write => "write",
            Stage::Verify => "verify",
        })
    }
}

/// How a flash tells its caller how far it got (a progress bar, a log, a test). Both
/// methods do nothing by default, and `()` is the caller that wants nothing.
pub trait Progress {
    /// `stage` begins with `total` units to do: erase commands for [`Stage::Erase`]
    /// (which then reports no progress until it ends), bytes for write and verify.
    fn stage(&mut self, stage: Stage, total: u64) {
        let _ = (stage, total);
    }

    /// `done` units of the current stage are finished.
    fn advance(&mut self, done: u64) {
        let _ = done;
    }
}

impl Progress for () {}

/// What a bootloader client must do for the shared write/verify loop.
pub trait Loader {
    /// Writes one block (a NACK or timeout is retried by the caller).
    fn write_block(&mut self, address: u32, data: &[u8]) -> Result<(), FlashError>;
    /// Reads one block back.
    fn read_block(&mut self, address: u32, len: usize) -> Result<Vec<u8>, FlashError>;
    /// Brings a chip that may be half-way through a command back to listening.
    fn recover(&mut self) -> Result<(), FlashError>;
}

/// What was erased.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Erased {
    /// STM32 sectors by number: only those the image touches.
    Sectors(Vec<u16>),
    /// All flash (MSP430 mass erase: the password is unknown until then).
    Mass,
    /// MSP430 segments by start address (with `--password`: the chip was unlocked, so
    /// only what the image touches).
    Segments(Vec<u32>),
}

impl fmt::Display for Erased {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Erased::Sectors(s) => write!(f, "erased sectors {s:?}"),
            Erased::Mass => f.write_str("mass-erased"),
            Erased::Segments(s) => {
                let list: Vec<String> = s.iter().map(|a| format!("{a:#06x}")).collect();
                write!(f, "erased segments [{}]", list.join(", "))
            }
        }
    }
}

/// What a flash did, for the summary line and for tests; `C` is what the chip said about
/// itself ([`ChipInfo`] for the STM32, [`BslInfo`] for the MSP430).
#[derive(Debug, Clone, PartialEq)]
pub struct Report<C = ChipInfo> {
    /// What the chip said about itself.
    pub chip: C,
    /// What was erased.
    pub erased: Erased,
    /// Blocks written and verified.
    pub blocks: usize,
    /// Image bytes written.
    pub bytes: usize,
    /// Block retries that were needed.
    pub retries: u32,
    /// Time to erase, write and verify.
    pub elapsed: Duration,
    /// Whether the read-back ran.
    pub verified: bool,
    /// Where the chip was sent to run, if asked.
    pub jumped: Option<u32>,
}

/// How a flash runs: whether it verifies and jumps, whether it accepts another chip, how
/// often it tries a block.
#[derive(Debug, Clone, Copy)]
pub struct FlashOptions {
    /// Read back and compare.
    pub verify: bool,
    /// Jump to the image at the end.
    pub go: bool,
    /// Accept another chip than the one asked for.
    pub force: bool,
    /// Attempts per block.
    pub attempts: u32,
}

/// Erases, writes and verifies `image` through `client` (STM32, AN3155); `progress` is
/// told when each stage begins and after every block.
pub fn flash<T: Transport>(
    client: &mut Client<T>,
    image: &Image,
    opts: FlashOptions,
    progress: &mut dyn Progress,
) -> Result<Report, FlashError> {
    client.sync(4)?;
    let chip = client.identify()?;
    if chip.pid != bl::F405_PID && !opts.force {
        return Err(FlashError::UnknownChip(chip.pid));
    }
    let listed = || {
        chip.commands
            .iter()
            .map(|c| format!("{c:#04x}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut needed = vec![Command::ExtendedErase, Command::WriteMemory];
    if opts.verify {
        needed.push(Command::ReadMemory);
    }
    if opts.go {
        needed.push(Command::Go);
    }
    for c in needed {
        if !chip.commands.contains(&c.code()) {
            return Err(FlashError::MissingCommand(c.name(), listed()));
        }
    }

    let started = Instant::now();
    let sectors = image.sectors();
    progress.stage(Stage::Erase, sectors.len() as u64);
    client.erase(&sectors)?;
    let retries = write_and_verify(client, image, opts, progress)?;
    let elapsed = started.elapsed();

    let jumped = match (opts.go, image.start()) {
        (true, Some(a)) => {
            client.go(a)?;
            Some(a)
        }
        _ => None,
    };
    Ok(Report {
        chip,
        erased: Erased::Sectors(sectors),
        blocks: image.blocks.len(),
        bytes: image.len(),
        retries,
        elapsed,
        verified: opts.verify,
        jumped,
    })
}

/// Where the MSP430 flash gets its password from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Unlock {
    /// Mass-erase first (a locked chip accepts that), then give the erased chip's
    /// password, 32 × 0xFF: works whatever the chip held.
    MassErase,
    /// The chip's current vector table (from a file, named in errors), which keeps
    /// everything the image does not touch; only the touched segments are erased.
    Password {
        /// The 32 bytes at 0xFFE0..=0xFFFF.
        vectors: [u8; PASSWORD_LEN],
        /// Where they came from.
        from: String,
    },
}

/// Unlocks, erases, writes and verifies `image` through the MSP430's ROM BSL; `--go`
/// loads the PC with the image's reset vector. `expected` is the part asked for
/// (`--chip`), whose device ID TX BSL version must report unless `opts.force`.
pub fn flash_msp430<T: Transport>(
    client: &mut BslClient<T>,
    image: &Image,
    expected: &bsl::Chip,
    unlock: &Unlock,
    opts: FlashOptions,
    progress: &mut dyn Progress,
) -> Result<Report<BslInfo>, FlashError> {
    let go = if opts.go {
        let v = image
            .bytes(u32::from(RESET_VECTOR), 2)
            .ok_or(ImageError::Missing {
                what: "reset vector (needed by --go)",
                address: u32::from(RESET_VECTOR),
                end: 0x1_0000,
            })?;
        Some(u16::from_le_bytes([v[0], v[1]]))
    } else {
        None
    };
    let started = Instant::now();
    // No sync of its own: every command below begins with one, and a second SYNC in a
    // row would be taken by the BSL as the header of a frame.
    let erased = match unlock {
        Unlock::MassErase => {
            progress.stage(Stage::Erase, 1);
            client.mass_erase()?;
            client
                .password(&bsl::ERASED_PASSWORD)
                .map_err(|e| match e {
                    FlashError::Nack { .. } => FlashError::ErasedPassword,
                    e => e,
                })?;
            Erased::Mass
        }
        Unlock::Password { vectors, from } => {
            client.password(vectors).map_err(|e| match e {
                FlashError::Nack { .. } => FlashError::Password { from: from.clone() },
                e => e,
            })?;
            Erased::Segments(Vec::new())
        }
    };
    let chip = client.version()?;
    if chip.device_id != expected.device_id && !opts.force {
        return Err(FlashError::UnknownMsp430 {
            id: chip.device_id,
            version: chip.version_text(),
            expected: expected.name,
            expected_id: expected.device_id,
        });
    }
    let erased = match erased {
        Erased::Segments(_) => {
            let segments = segments_touched(image, expected);
            progress.stage(Stage::Erase, segments.len() as u64);
            for (i, &s) in segments.iter().enumerate() {
                client.erase_segment(s as u16)?;
                progress.advance(i as u64 + 1);
            }
            Erased::Segments(segments)
        }
        other => other,
    };
    let retries = write_and_verify(client, image, opts, progress)?;
    let elapsed = started.elapsed();
    if let Some(pc) = go {
        client.load_pc(pc)?;
    }
    Ok(Report {
        chip,
        erased,
        blocks: image.blocks.len(),
        bytes: image.len(),
        retries,
        elapsed,
        verified: opts.verify,
        jumped: go.map(u32::from),
    })
}

/// The 32 bytes of the vector table in `image`, for `--password`.
pub fn password_of(image: &Image) -> Result<[u8; PASSWORD_LEN], ImageError> {
    let v = image
        .bytes(u32::from(PASSWORD_ADDRESS), PASSWORD_LEN as u32)
        .ok_or(ImageError::Missing {
            what: "vector table (the BSL password)",
            address: u32::from(PASSWORD_ADDRESS),
            end: 0x1_0000,
        })?;
    let mut out = [0u8; PASSWORD_LEN];
    out.copy_from_slice(&v);
    Ok(out)
}

/// Start addresses of the flash segments `image`'s blocks touch, ascending.
fn segments_touched(image: &Image, chip: &bsl::Chip) -> Vec<u32> {
    let mut out: Vec<u32> = Vec::new();
    for b in &image.blocks {
        for a in [b.address, b.address + b.data.len() as u32 - 1] {
            if let Some(r) = chip.region(a, 1) {
                if let bsl::Kind::Flash { segment } = r.kind {
                    out.push(a - (a - r.start) % segment);
                }
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Writes every block with retries, then reads every block back and compares (if
/// `opts.verify`); returns the retries needed. Shared by both chips.
fn write_and_verify<L: Loader>(
    client: &mut L,
    image: &Image,
    opts: FlashOptions,
    progress: &mut dyn Progress,
) -> Result<u32, FlashError> {
    let total = image.len() as u64;
    let attempts = opts.attempts.max(1);
    let mut retries = 0;
    let mut done = 0u64;
    progress.stage(Stage::Write, total);
    for block in &image.blocks {
        let mut made = 0;
        write_with_retries(client, block, attempts, &mut made).map_err(|e| FlashError::Block {
            address: block.address,
            attempts: made,
            last: Box::new(e),
        })?;
        retries += made.saturating_sub(1);
        done += block.data.len() as u64;
        progress.advance(done);
    }

    if opts.verify {
        let mut checked = 0u64;
        progress.stage(Stage::Verify, total);
        for block in &image.blocks {
            let mut back = None;
            let mut last = None;
            for attempt in 0..attempts {
                if attempt > 0 {
                    retries += 1;
                    client.recover()?;
                }
                match client.read_block(block.address, block.data.len()) {
                    Ok(b) => {
                        back = Some(b);
                        break;
                    }
                    Err(e) if retryable(&e) => last = Some(e),
                    Err(e) => return Err(e),
                }
            }
            let back = back.ok_or_else(|| FlashError::Block {
                address: block.address,
                attempts,
                last: Box::new(last.unwrap_or(FlashError::Io(io::ErrorKind::TimedOut.into()))),
            })?;
            if let Some(i) = back.iter().zip(&block.data).position(|(r, w)| r != w) {
                return Err(FlashError::Verify {
                    address: block.address + i as u32,
                    wrote: block.data[i],
                    read: back[i],
                });
            }
            checked += block.data.len() as u64;
            progress.advance(checked);
        }
    }
    Ok(retries)
}

/// Failures another attempt may cure: a refusal, silence, a damaged answer. (A port
/// error or a wrong chip is not retried.)
fn retryable(e: &FlashError) -> bool {
    matches!(
        e,
        FlashError::Nack { .. } | FlashError::Timeout { .. } | FlashError::Answer { .. }
    )
}

/// Writes one block with up to `attempts` tries, counting them in `made`; returns the
/// last failure.
fn write_with_retries<L: Loader>(
    client: &mut L,
    block: &Block,
    attempts: u32,
    made: &mut u32,
) -> Result<(), FlashError> {
    let mut last = None;
    for _ in 0..attempts {
        *made += 1;
        match client.write_block(block.address, &block.data) {
            Ok(()) => return Ok(()),
            Err(e) if retryable(&e) => {
                // A timeout may leave the chip mid-frame; a NACK leaves it idle.
                if !matches!(e, FlashError::Nack { .. }) {
                    client.recover()?;
                }
                // The block may have landed with only the ACK lost, and a plain retry
                // would then be refused as programming unerased flash.
                match client.read_block(block.address, block.data.len()) {
                    Ok(back) if back == block.data => return Ok(()),
                    Ok(_) | Err(FlashError::Nack { .. }) => {}
                    Err(e) if retryable(&e) => client.recover()?,
                    Err(other) => return Err(other),
                }
                last = Some(e);
            }
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or(FlashError::Io(io::ErrorKind::TimedOut.into())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flash::test_wire::{client, pattern, wire, Wire};
    use protocol::bootloader::ACK;

    const OPTS: FlashOptions = FlashOptions {
        verify: true,
        go: true,
        force: false,
        attempts: 3,
    };

    #[test]
    fn flashes_and_verifies_against_the_emulator() {
        let data = pattern(40 * 1024 + 3, 7);
        let image = Image::from_pieces(&[(bl::FLASH_BASE, data.clone())]).unwrap();
        assert_eq!(image.sectors(), vec![0, 1, 2]);
        let mut c = client(wire());
        let r = flash(&mut c, &image, OPTS, &mut ()).unwrap();
        assert_eq!(r.blocks, 161);
        assert_eq!(r.jumped, Some(bl::FLASH_BASE));
        assert_eq!(r.chip.pid, 0x413);
        let flash = c.port.chip.flash();
        assert_eq!(&flash[..data.len()], &data[..]);
        // Word padding is 0xFF, i.e. unprogrammed.
        assert_eq!(&flash[data.len()..data.len() + 1], &[0xFF]);
    }

    /// What a progress bar is drawn from, in order, for a two-block image.
    #[test]
    fn progress_reports_each_stage_and_every_block() {
        #[derive(Default)]
        struct Log(Vec<(Option<Stage>, u64)>);
        impl Progress for Log {
            fn stage(&mut self, stage: Stage, total: u64) {
                self.0.push((Some(stage), total));
            }
            fn advance(&mut self, done: u64) {
                self.0.push((None, done));
            }
        }
        let image = Image::from_pieces(&[(bl::FLASH_BASE, pattern(300, 1))]).unwrap();
        let mut log = Log::default();
        flash(&mut client(wire()), &image, OPTS, &mut log).unwrap();
        assert_eq!(
            log.0,
            [
                (Some(Stage::Erase), 1),
                (Some(Stage::Write), 300),
                (None, 256),
                (None, 300),
                (Some(Stage::Verify), 300),
                (None, 256),
                (None, 300),
            ]
        );
    }

    #[test]
    fn a_lost_ack_is_recovered_by_read_back() {
        let image = Image::from_pieces(&[(0x0800_4000, pattern(1024, 3))]).unwrap();
        let mut w = wire();
        // Host writes: 7F, Get, GetVersion, GetId, erase cmd, erase list, then per
        // block: cmd, address, data. Lose the ACK to block 2's data.
        w.lose_answer_to_write = Some(6 + 3 + 3);
        let mut c = client(w);
        let r = flash(&mut c, &image, OPTS, &mut ()).unwrap();
        assert!(r.retries == 0 || r.retries == 1, "{r:?}");
        assert_eq!(&c.port.chip.flash()[0x4000..0x4400], &pattern(1024, 3)[..]);
    }

    /// A line that flips one bit of the second full data block on its way (and fixes the
    /// checksum so the chip accepts it): the read-back must name the exact address.
    #[test]
    fn verify_reports_the_first_differing_address() {
        struct Flip(Wire, usize);
        impl Transport for Flip {
            fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
                if bytes.len() == 258 {
                    self.1 += 1;
                    if self.1 == 2 {
                        let mut b = bytes.to_vec();
                        b[1 + 9] ^= 0x04;
                        b[257] ^= 0x04;
                        return self.0.write_all(&b);
                    }
                }
                self.0.write_all(bytes)
            }
            fn read(&mut self, buf: &mut [u8], t: Duration) -> io::Result<usize> {
                self.0.read(buf, t)
            }
        }
        let data = pattern(1024, 5);
        let image = Image::from_pieces(&[(bl::FLASH_BASE, data.clone())]).unwrap();
        let mut c = Client::new(Flip(wire(), 0), 115_200);
        c.timeouts.ack = Duration::from_millis(20);
        let e = flash(&mut c, &image, OPTS, &mut ()).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "verify failed at 0x08000109: wrote {:#04x}, read back {:#04x}",
                data[0x109],
                data[0x109] ^ 0x04
            )
        );
        // --no-verify does not notice.
        let mut c = Client::new(Flip(wire(), 0), 115_200);
        c.timeouts.ack = Duration::from_millis(20);
        let no_verify = FlashOptions {
            verify: false,
            ..OPTS
        };
        assert!(flash(&mut c, &image, no_verify, &mut ()).is_ok());
    }

    #[test]
    fn unknown_chip_is_refused() {
        // A chip that answers like an F405 but with another ID: patch the wire.
        struct Other(Wire);
        impl Transport for Other {
            fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
                let before = self.0.rx.len();
                self.0.write_all(bytes)?;
                if bytes == bl::command_frame(Command::GetId) {
                    let ans: Vec<u8> = self.0.rx.drain(before..).collect();
                    assert_eq!(ans, [ACK, 1, 0x04, 0x13, ACK]);
                    self.0.rx.extend([ACK, 1, 0x04, 0x10, ACK]);
                }
                Ok(())
            }
            fn read(&mut self, buf: &mut [u8], t: Duration) -> io::Result<usize> {
                self.0.read(buf, t)
            }
        }
        let image = Image::from_pieces(&[(bl::FLASH_BASE, vec![1, 2, 3, 4])]).unwrap();
        let mut c = Client::new(Other(wire()), 115_200);
        c.timeouts.ack = Duration::from_millis(20);
        let e = flash(&mut c, &image, OPTS, &mut ()).unwrap_err();
        assert!(matches!(e, FlashError::UnknownChip(0x410)), "{e}");
        assert!(e.to_string().contains("0x410"), "{e}");
    }
}

#[cfg(test)]
mod msp430_tests {
    use super::*;
    use crate::flash::test_wire::{bsl_client, pattern, wire_to, Wire};
    use crate::flash::MSP430F168;
    use sim_board::msp430_bsl::Bsl;

    const OPTS: FlashOptions = FlashOptions {
        verify: true,
        go: true,
        force: false,
        attempts: 3,
    };

    /// Code at 0x4000 and a vector table whose reset vector is 0x4000.
    fn firmware(len: usize, seed: u32) -> (Image, Vec<u8>, Vec<u8>) {
        let code = pattern(len, seed);
        let mut vectors = pattern(32, seed + 1);
        vectors[30..].copy_from_slice(&0x4000u16.to_le_bytes());
        let image = Image::build(
            &[(0x4000, code.clone()), (0xFFE0, vectors.clone())],
            &MSP430F168,
        )
        .unwrap();
        (image, code, vectors)
    }

    fn flash_on(
        w: &mut Option<Wire<Bsl>>,
        image: &Image,
        unlock: &Unlock,
        progress: &mut dyn Progress,
    ) -> Result<Report<BslInfo>, FlashError> {
        let mut c = bsl_client(w.take().unwrap());
        let r = flash_msp430(&mut c, image, &bsl::MSP430F168, unlock, OPTS, progress);
        *w = Some(c.port);
        r
    }

    /// A chip already holding other firmware (so its password is unknown): mass erase,
    /// the erased password, version, 128-byte blocks, read-back, Load PC.
    #[test]
    fn msp430_flashes_verifies_and_jumps() {
        let (old, _, _) = firmware(500, 40);
        let mut w = Some(wire_to(Bsl::new()));
        flash_on(&mut w, &old, &Unlock::MassErase, &mut ()).unwrap();
        let mut chip = w.take().unwrap().chip;
        chip.reset();
        let mut w = Some(wire_to(chip));

        #[derive(Default)]
        struct Log(Vec<(Option<Stage>, u64)>);
        impl Progress for Log {
            fn stage(&mut self, stage: Stage, total: u64) {
                self.0.push((Some(stage), total));
            }
            fn advance(&mut self, done: u64) {
                self.0.push((None, done));
            }
        }
        let (image, code, vectors) = firmware(200, 7);
        let mut log = Log::default();
        let r = flash_on(&mut w, &image, &Unlock::MassErase, &mut log).unwrap();
        assert_eq!(
            r.chip,
            BslInfo {
                device_id: 0xF169,
                version: 0x0161
            }
        );
        assert_eq!(r.chip.version_text(), "1.61");
        assert_eq!(r.erased, Erased::Mass);
        assert_eq!((r.blocks, r.bytes, r.retries), (3, 232, 0));
        assert_eq!(r.jumped, Some(0x4000));
        let chip = &w.as_ref().unwrap().chip;
        assert_eq!(chip.go_address(), Some(0x4000));
        assert_eq!(&chip.memory()[0x4000..0x4000 + 200], &code[..]);
        // The old firmware's tail is gone: mass erase.
        assert!(chip.memory()[0x4000 + 200..0xFFE0]
            .iter()
            .all(|&b| b == 0xFF));
        assert_eq!(&chip.memory()[0xFFE0..], &vectors[..]);
        assert_eq!(
            log.0,
            [
                (Some(Stage::Erase), 1),
                (Some(Stage::Write), 232),
                (None, 128),
                (None, 200),
                (None, 232),
                (Some(Stage::Verify), 232),
                (None, 128),
                (None, 200),
                (None, 232),
            ]
        );
    }

    /// With the right password only the touched segments are erased; with a wrong one
    /// the BSL refuses, nothing changes, and a plain run (mass erase) then succeeds.
    #[test]
    fn msp430_password_keeps_the_rest_and_a_wrong_one_changes_nothing() {
        let (old, old_code, old_vectors) = firmware(2000, 1);
        let mut w = Some(wire_to(Bsl::new()));
        flash_on(&mut w, &old, &Unlock::MassErase, &mut ()).unwrap();
        let mut info = w.take().unwrap();
        info.chip.reset();
        let mut w = Some(info);

        let (new, new_code, new_vectors) = firmware(100, 2);
        let wrong = Unlock::Password {
            vectors: password_of(&new).unwrap(),
            from: "new.hex".into(),
        };
        let before = w.as_ref().unwrap().chip.memory().to_vec();
        let e = flash_on(&mut w, &new, &wrong, &mut ()).unwrap_err();
        assert!(matches!(e, FlashError::Password { .. }), "{e}");
        assert!(
            e.to_string().contains("refused the password from new.hex"),
            "{e}"
        );
        assert_eq!(w.as_ref().unwrap().chip.memory(), &before[..]);

        let right = Unlock::Password {
            vectors: password_of(&old).unwrap(),
            from: "old.hex".into(),
        };
        let r = flash_on(&mut w, &new, &right, &mut ()).unwrap();
        assert_eq!(r.erased, Erased::Segments(vec![0x4000, 0xFE00]));
        assert_eq!(r.erased.to_string(), "erased segments [0x4000, 0xfe00]");
        let mem = w.as_ref().unwrap().chip.memory().to_vec();
        assert_eq!(&mem[0x4000..0x4064], &new_code[..]);
        // The old code past the first segment is kept.
        assert_eq!(&mem[0x4200..0x4000 + 2000], &old_code[0x200..]);
        assert_eq!(&mem[0xFFE0..], &new_vectors[..]);
        assert_ne!(old_vectors, new_vectors);
    }

    /// A line that damages the chip's data frames: one damaged read is retried; a line
    /// that damages all of them fails naming the block, and the same chip on a clean
    /// line is then flashed.
    #[test]
    fn msp430_damaged_answers_are_retried_then_reported() {
        struct Damage(Wire<Bsl>, u32);
        impl Transport for Damage {
            fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
                let before = self.0.rx.len();
                self.0.write_all(bytes)?;
                // A data frame answering TX data block (CMD 0x14).
                if bytes.get(1) == Some(&0x14) && self.1 > 0 && self.0.rx.len() > before + 4 {
                    self.1 -= 1;
                    let last = self.0.rx.len() - 1;
                    self.0.rx[last] ^= 0x01;
                }
                Ok(())
            }
            fn read(&mut self, buf: &mut [u8], t: Duration) -> io::Result<usize> {
                self.0.read(buf, t)
            }
        }
        let (image, code, _) = firmware(300, 3);
        let fast = |d: Damage| {
            let mut c = BslClient::new(d, 115_200);
            c.timeouts.sync = Duration::from_millis(20);
            c.timeouts.ack = Duration::from_millis(20);
            c
        };
        let mut c = fast(Damage(wire_to(Bsl::new()), 1));
        let r = flash_msp430(
            &mut c,
            &image,
            &bsl::MSP430F168,
            &Unlock::MassErase,
            OPTS,
            &mut (),
        )
        .unwrap();
        assert_eq!(r.retries, 1);

        let mut c = fast(Damage(wire_to(Bsl::new()), u32::MAX));
        let e = flash_msp430(
            &mut c,
            &image,
            &bsl::MSP430F168,
            &Unlock::MassErase,
            OPTS,
            &mut (),
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                FlashError::Block {
                    address: 0x4000,
                    attempts: 3,
                    ..
                }
            ),
            "{e}"
        );
        let cause = match &e {
            FlashError::Block { last, .. } => last.to_string(),
            _ => unreachable!(),
        };
        assert!(
            cause.starts_with(
                "TX data block to reading 128 bytes at 0x4000: the chip's answer is damaged \
                 (checksum"
            ),
            "{cause}"
        );
        let mut chip = c.port.0.chip;
        chip.reset();
        let mut w = Some(wire_to(chip));
        flash_on(&mut w, &image, &Unlock::MassErase, &mut ()).unwrap();
        assert_eq!(&w.unwrap().chip.memory()[0x4000..0x4000 + 300], &code[..]);
    }

    /// The chip goes silent in the middle of the image (a board losing power, a cable
    /// pulled): the error names the block and the command; answering again, the same
    /// chip is flashed by the same call.
    #[test]
    fn msp430_a_chip_that_stops_answering_is_named_and_recovered() {
        struct Mute(Wire<Bsl>, usize);
        impl Transport for Mute {
            fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
                if self.1 == 0 {
                    return Ok(());
                }
                self.1 -= 1;
                self.0.write_all(bytes)
            }
            fn read(&mut self, buf: &mut [u8], t: Duration) -> io::Result<usize> {
                self.0.read(buf, t)
            }
        }
        let (image, code, _) = firmware(1000, 5);
        // Writes: sync + frame per command: erase, password, version, then three blocks
        // (2 each) and the fourth block's SYNC; its frame is lost.
        let mut c = BslClient::new(Mute(wire_to(Bsl::new()), 6 + 6 + 1), 115_200);
        c.timeouts.sync = Duration::from_millis(20);
        c.timeouts.ack = Duration::from_millis(20);
        let e = flash_msp430(
            &mut c,
            &image,
            &bsl::MSP430F168,
            &Unlock::MassErase,
            OPTS,
            &mut (),
        )
        .unwrap_err();
        let FlashError::Block { address, last, .. } = &e else {
            panic!("{e}");
        };
        assert_eq!(*address, 0x4180, "{e}");
        // The block's SYNC went unanswered, and so did the rescue burst's.
        assert!(
            last.to_string().starts_with(
                "no answer from the bootloader: sent 0x80 4 times (and one burst of 260 × \
                 0xFF to end a half-received frame) at 115200 baud 8E1, got nothing"
            ),
            "{last}"
        );
        // The chip was left after a SYNC with its frame never sent; power back (no
        // reset: the same session), the next run gets through.
        let chip = c.port.0.chip;
        let mut w = Some(wire_to(chip));
        flash_on(&mut w, &image, &Unlock::MassErase, &mut ()).unwrap();
        assert_eq!(&w.unwrap().chip.memory()[0x4000..0x4000 + 1000], &code[..]);
    }

    /// A host that died half-way through an RX data block leaves the chip collecting a
    /// frame: the next run's sync frees it with its burst.
    #[test]
    fn msp430_a_chip_left_mid_frame_is_freed() {
        for sent in [0usize, 3, 50] {
            let mut chip = Bsl::new();
            let mut out = Vec::new();
            chip.feed(&[bsl::SYNC], &mut out);
            let mut frame = [0u8; bsl::MAX_FRAME];
            let n = bsl::encode_request(0x12, 0x4000, 128, &[0; 128], &mut frame).unwrap();
            chip.feed(&frame[..sent.min(n)], &mut out);
            let (image, code, _) = firmware(64, 9);
            let mut w = Some(wire_to(chip));
            flash_on(&mut w, &image, &Unlock::MassErase, &mut ())
                .unwrap_or_else(|e| panic!("after {sent} bytes: {e}"));
            assert_eq!(&w.unwrap().chip.memory()[0x4000..0x4040], &code[..]);
        }
    }

    #[test]
    fn msp430_go_needs_a_reset_vector() {
        let image = Image::build(&[(0x4000, vec![1, 2])], &MSP430F168).unwrap();
        let mut w = Some(wire_to(Bsl::new()));
        let e = flash_on(&mut w, &image, &Unlock::MassErase, &mut ()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "the image holds no reset vector (needed by --go) at 0xfffe..0x10000"
        );
        // Nothing was sent.
        assert_eq!(w.unwrap().writes, 0);
    }
}
