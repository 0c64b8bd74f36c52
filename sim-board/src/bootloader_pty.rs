//! An emulated ROM bootloader served on a pty, with its flash optionally kept in a file
//! across runs: the STM32's ([`crate::bootloader`], what the board does with BOOT0 high)
//! or the MSP430's BSL ([`crate::msp430_bsl`], what the FITkit's controller does after
//! the entry sequence on RST/TEST). Both are sans-I/O models behind [`RomLoader`], so the
//! serving, the persistence and the test aids below are written once.
//!
//! A pty has no physical parity and no modem lines, so the 8E1 the host asks for is
//! accepted and changes nothing (bytes arrive as sent), and the MSP430's entry sequence
//! cannot arrive: the chip is taken to be in its BSL from the start, and a host closing
//! the pty counts as the next entry sequence (see [`serve`]).

use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::bootloader::{Bootloader, BootloaderError};
use crate::msp430_bsl::Bsl;
use crate::pty::peer_gone;

/// A ROM bootloader model the pty can serve: bytes in, bytes out, and a flash that can be
/// saved to a file and loaded again.
pub trait RomLoader: Sized {
    /// Bytes of the saved image: what [`RomLoader::image`] returns.
    const IMAGE_SIZE: usize;
    /// A factory-fresh chip, flash erased.
    fn erased() -> Self;
    /// A chip whose flash holds a saved image.
    fn from_image(image: Vec<u8>) -> Result<Self, BootloaderError>;
    /// Processes the host's bytes, appending the answers to `out`.
    fn feed(&mut self, input: &[u8], out: &mut Vec<u8>);
    /// The board reset into the bootloader again (by the host's DTR/RTS on real wiring).
    fn reset(&mut self);
    /// What is saved: [`RomLoader::IMAGE_SIZE`] bytes.
    fn image(&self) -> &[u8];
    /// Ranges of [`RomLoader::image`] changed since the last call.
    fn take_dirty(&mut self) -> Vec<Range<u32>>;
    /// Where the chip jumped to user code, if it did since the last reset.
    fn jumped(&self) -> Option<u32>;
    /// Successful flash writes so far (the `exit_after_writes` count).
    fn writes(&self) -> u64;
}

impl RomLoader for Bootloader {
    const IMAGE_SIZE: usize = protocol::bootloader::FLASH_SIZE as usize;
    fn erased() -> Self {
        Bootloader::new()
    }
    fn from_image(image: Vec<u8>) -> Result<Self, BootloaderError> {
        Bootloader::with_flash(image)
    }
    fn feed(&mut self, input: &[u8], out: &mut Vec<u8>) {
        Bootloader::feed(self, input, out)
    }
    fn reset(&mut self) {
        Bootloader::reset(self)
    }
    fn image(&self) -> &[u8] {
        self.flash()
    }
    fn take_dirty(&mut self) -> Vec<Range<u32>> {
        Bootloader::take_dirty(self)
    }
    fn jumped(&self) -> Option<u32> {
        self.go_address()
    }
    fn writes(&self) -> u64 {
        self.stats().writes
    }
}

impl RomLoader for Bsl {
    const IMAGE_SIZE: usize = crate::msp430_bsl::SPACE;
    fn erased() -> Self {
        Bsl::new()
    }
    fn from_image(image: Vec<u8>) -> Result<Self, BootloaderError> {
        Bsl::with_memory(image)
    }
    fn feed(&mut self, input: &[u8], out: &mut Vec<u8>) {
        Bsl::feed(self, input, out)
    }
    fn reset(&mut self) {
        Bsl::reset(self)
    }
    fn image(&self) -> &[u8] {
        self.memory()
    }
    fn take_dirty(&mut self) -> Vec<Range<u32>> {
        Bsl::take_dirty(self)
    }
    fn jumped(&self) -> Option<u32> {
        self.go_address().map(u32::from)
    }
    fn writes(&self) -> u64 {
        self.stats().writes
    }
}

/// Why the bootloader stopped serving, or could not start.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BootloaderPtyError {
    /// A missing flash image could not be created erased.
    #[error("cannot create {}", .path.display())]
    CreateImage {
        /// The flash image file (the chip's flash, persisted between runs).
        path: PathBuf,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// The flash image could not be read.
    #[error("cannot read {}", .path.display())]
    ReadImage {
        /// The flash image file (the chip's flash, persisted between runs).
        path: PathBuf,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// The flash image is not a flash's worth of bytes.
    #[error("flash image {}", .path.display())]
    Image {
        /// The flash image file (the chip's flash, persisted between runs).
        path: PathBuf,
        /// What is wrong with it.
        #[source]
        source: BootloaderError,
    },
    /// The flash image could not be opened for the write-through.
    #[error("cannot open {}", .path.display())]
    OpenImage {
        /// The flash image file (the chip's flash, persisted between runs).
        path: PathBuf,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// Writing flash changes through to the image failed (seeking or writing).
    #[error(transparent)]
    Persist(#[from] io::Error),
    /// Flushing the image after a write failed.
    #[error("flash image")]
    FlushImage(#[source] io::Error),
    /// The pty refused a read timeout.
    #[error("pty timeout")]
    Timeout(#[source] serialport::Error),
    /// Reading the pty failed other than by the host closing it.
    #[error("pty read")]
    PtyRead(#[source] io::Error),
    /// Writing the pty failed other than by the host closing it.
    #[error("pty write")]
    PtyWrite(#[source] io::Error),
}

/// An emulated chip in its ROM bootloader, with the file its flash is written through
/// to, if any.
pub struct Chip<B> {
    bootloader: B,
    image: Option<File>,
}

impl<B: RomLoader> Chip<B> {
    /// A factory-fresh chip (flash erased) whose flash lives only as long as the process.
    pub fn new() -> Self {
        Self {
            bootloader: B::erased(),
            image: None,
        }
    }

    /// The model itself, e.g. to set a test aid before serving.
    pub fn model(&mut self) -> &mut B {
        &mut self.bootloader
    }

    /// A chip whose flash is kept in `path` (`B::IMAGE_SIZE` bytes, created erased if
    /// missing) and updated after every write or erase, so that a later run sees it.
    pub fn with_image(path: &Path) -> Result<Self, BootloaderPtyError> {
        let image = match std::fs::read(path) {
            Ok(image) => image,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                let erased = vec![0xFF; B::IMAGE_SIZE];
                std::fs::write(path, &erased).map_err(|source| {
                    BootloaderPtyError::CreateImage {
                        path: path.to_path_buf(),
                        source,
                    }
                })?;
                erased
            }
            Err(source) => {
                return Err(BootloaderPtyError::ReadImage {
                    path: path.to_path_buf(),
                    source,
                })
            }
        };
        let bootloader = B::from_image(image).map_err(|source| BootloaderPtyError::Image {
            path: path.to_path_buf(),
            source,
        })?;
        let file = std::fs::OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|source| BootloaderPtyError::OpenImage {
                path: path.to_path_buf(),
                source,
            })?;
        Ok(Self {
            bootloader,
            image: Some(file),
        })
    }
}

impl<B: RomLoader> Default for Chip<B> {
    fn default() -> Self {
        Self::new()
    }
}

/// Serves `chip` on `master`. A host that closes the pty ends its session: tools expect
/// a fresh chip per session (on a board the adapter's DTR and RTS usually drive reset and
/// the MSP430's TEST pin), so the chip is reset and the next host starts with its sync
/// byte; flash survives. A jump to user code (STM32 Go, MSP430 Load PC) is handed to
/// `on_go` with its address, and the chip is reset into the bootloader again.
///
/// With `exit_after_writes` (a test aid: a board losing power at a known point) it
/// returns, with the count of flash writes, once that many have succeeded; otherwise
/// only an error ends it.
pub fn serve<B: RomLoader>(
    mut master: serialport::TTYPort,
    chip: Chip<B>,
    exit_after_writes: Option<u64>,
    mut on_go: impl FnMut(u32),
) -> Result<u64, BootloaderPtyError> {
    let Chip {
        bootloader: mut chip,
        image: mut flash_file,
    } = chip;
    serialport::SerialPort::set_timeout(&mut master, Duration::from_millis(5))
        .map_err(BootloaderPtyError::Timeout)?;
    let mut buf = [0u8; 1024];
    let mut out = Vec::new();
    let mut host_present = false;
    loop {
        let n = match master.read(&mut buf) {
            Ok(n) => n,
            Err(e) if e.kind() == io::ErrorKind::TimedOut => 0,
            Err(e) if peer_gone(&e) => {
                if host_present {
                    chip.reset();
                    host_present = false;
                }
                std::thread::sleep(Duration::from_millis(2));
                continue;
            }
            Err(e) => return Err(BootloaderPtyError::PtyRead(e)),
        };
        if n == 0 {
            continue;
        }
        host_present = true;
        out.clear();
        chip.feed(&buf[..n], &mut out);
        let dirty = chip.take_dirty();
        if let Some(file) = flash_file.as_mut() {
            persist(file, chip.image(), &dirty)?;
        }
        if !out.is_empty() {
            match master.write_all(&out).and_then(|()| master.flush()) {
                Ok(()) => {}
                Err(e) if peer_gone(&e) => continue,
                Err(e) => return Err(BootloaderPtyError::PtyWrite(e)),
            }
        }
        if let Some(address) = chip.jumped() {
            // The chip would now run user code. We report the jump and behave as if the
            // board were reset into the bootloader again, so the sim keeps serving.
            on_go(address);
            chip.reset();
        }
        let writes = chip.writes();
        if exit_after_writes.is_some_and(|n| writes >= n) {
            return Ok(writes);
        }
    }
}

/// Writes the changed flash ranges through to the image file.
fn persist(file: &mut File, flash: &[u8], dirty: &[Range<u32>]) -> Result<(), BootloaderPtyError> {
    for r in dirty {
        file.seek(SeekFrom::Start(u64::from(r.start)))?;
        file.write_all(&flash[r.start as usize..r.end as usize])?;
    }
    if !dirty.is_empty() {
        file.flush().map_err(BootloaderPtyError::FlushImage)?;
    }
    Ok(())
}
