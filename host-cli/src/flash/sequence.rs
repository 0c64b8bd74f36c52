//! The flash sequence: identify the chip, erase what the image touches, write every
//! block with bounded retries, read it all back, jump. It reports how far it got as
//! [`Progress`] and what it did as a [`Report`]; the caller decides what to show.

use std::fmt;
use std::io;
use std::time::{Duration, Instant};

use protocol::bootloader::{self as bl, Command};

use super::{Block, ChipInfo, Client, FlashError, Image};
use crate::session::Transport;

/// A step of [`flash`] that takes long enough to show.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Extended Erase of the image's sectors: one command, seconds on a real part.
    Erase,
    /// Write Memory of every block.
    Write,
    /// Read Memory of every block, compared with the image.
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

/// How [`flash`] tells its caller how far it got (a progress bar, a log, a test). Both
/// methods do nothing by default, and `()` is the caller that wants nothing.
pub trait Progress {
    /// `stage` begins with `total` units to do: sectors for [`Stage::Erase`] (which
    /// then reports no progress until it ends), bytes for write and verify.
    fn stage(&mut self, stage: Stage, total: u64) {
        let _ = (stage, total);
    }

    /// `done` units of the current stage are finished.
    fn advance(&mut self, done: u64) {
        let _ = done;
    }
}

impl Progress for () {}

/// What a flash did, for the summary line and for tests.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// What Get, Get Version and Get ID said about the chip.
    pub chip: ChipInfo,
    /// Flash sectors erased (only those the image touches), by sector number.
    pub sectors: Vec<u16>,
    /// Write Memory blocks written (at most 256 bytes each) and verified.
    pub blocks: usize,
    /// Image bytes written.
    pub bytes: usize,
    /// Block retries that were needed.
    pub retries: u32,
    /// Time to erase, write and verify.
    pub elapsed: Duration,
    /// Whether the read-back ran.
    pub verified: bool,
    /// Where Go jumped, if asked.
    pub jumped: Option<u32>,
}

/// How [`flash`] runs: whether it verifies and jumps, whether it accepts another chip, how
/// often it tries a block.
#[derive(Debug, Clone, Copy)]
pub struct FlashOptions {
    /// Read back and compare.
    pub verify: bool,
    /// Jump to the image start at the end.
    pub go: bool,
    /// Accept a product ID other than 0x413.
    pub force: bool,
    /// Attempts per block.
    pub attempts: u32,
}

/// Erases, writes and verifies `image` through `client`; `progress` is told when each
/// stage begins and after every block.
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
                    Err(e @ (FlashError::Nack { .. } | FlashError::Timeout { .. })) => {
                        last = Some(e)
                    }
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
        sectors,
        blocks: image.blocks.len(),
        bytes: image.len(),
        retries,
        elapsed,
        verified: opts.verify,
        jumped,
    })
}

/// Writes one block with up to `attempts` tries, counting them in `made`; returns the
/// last failure.
fn write_with_retries<T: Transport>(
    client: &mut Client<T>,
    block: &Block,
    attempts: u32,
    made: &mut u32,
) -> Result<(), FlashError> {
    let mut last = None;
    for _ in 0..attempts {
        *made += 1;
        match client.write_block(block.address, &block.data) {
            Ok(()) => return Ok(()),
            Err(e @ (FlashError::Nack { .. } | FlashError::Timeout { .. })) => {
                // A timeout may leave the chip mid-frame; a NACK leaves it idle.
                if matches!(e, FlashError::Timeout { .. }) {
                    client.recover()?;
                }
                // The block may have landed with only the ACK lost, and a plain retry
                // would then be refused as programming unerased flash.
                match client.read_block(block.address, block.data.len()) {
                    Ok(back) if back == block.data => return Ok(()),
                    Ok(_) | Err(FlashError::Nack { .. }) => {}
                    Err(FlashError::Timeout { .. }) => client.recover()?,
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
        c.timeouts.ack = Duration::from_millis(1);
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
        c.timeouts.ack = Duration::from_millis(1);
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
        c.timeouts.ack = Duration::from_millis(1);
        let e = flash(&mut c, &image, OPTS, &mut ()).unwrap_err();
        assert!(matches!(e, FlashError::UnknownChip(0x410)), "{e}");
        assert!(e.to_string().contains("0x410"), "{e}");
    }
}
