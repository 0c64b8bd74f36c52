//! The emulated ROM bootloader ([`crate::bootloader`]) served on a pty, what the board
//! does with BOOT0 high, with its flash optionally kept in a file across runs.
//!
//! A pty has no physical parity, so the 8E1 the host asks for is accepted and changes
//! nothing: bytes arrive as sent.

use std::fs::File;
use std::io::{self, Read, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::bootloader::{Bootloader, BootloaderError};
use crate::pty::peer_gone;

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

/// The emulated STM32 in its ROM bootloader, with the file its flash is written through
/// to, if any.
pub struct Chip {
    bootloader: Bootloader,
    image: Option<File>,
}

impl Chip {
    /// A factory-fresh chip (flash erased) whose flash lives only as long as the process.
    pub fn new() -> Self {
        Self {
            bootloader: Bootloader::new(),
            image: None,
        }
    }

    /// A chip whose flash is kept in `path` (`FLASH_SIZE` bytes, created erased if
    /// missing) and updated after every write or erase, so that a later run sees it.
    pub fn with_image(path: &Path) -> Result<Self, BootloaderPtyError> {
        let image = match std::fs::read(path) {
            Ok(image) => image,
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                let erased = vec![0xFF; protocol::bootloader::FLASH_SIZE as usize];
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
        let bootloader =
            Bootloader::with_flash(image).map_err(|source| BootloaderPtyError::Image {
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

impl Default for Chip {
    fn default() -> Self {
        Self::new()
    }
}

/// Serves `chip` on `master`. A host that closes the pty ends its session: tools expect
/// a fresh chip per session (on a board the adapter's DTR usually drives reset), so the
/// chip is reset and the next host starts with 0x7F; flash survives. A Go is handed to
/// `on_go` with its address, and the chip is reset into the bootloader again.
///
/// With `exit_after_writes` (a test aid: a board losing power at a known point) it
/// returns, with the count of Write Memory commands, once that many have succeeded;
/// otherwise only an error ends it.
pub fn serve(
    mut master: serialport::TTYPort,
    chip: Chip,
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
            persist(file, chip.flash(), &dirty)?;
        }
        if !out.is_empty() {
            match master.write_all(&out).and_then(|()| master.flush()) {
                Ok(()) => {}
                Err(e) if peer_gone(&e) => continue,
                Err(e) => return Err(BootloaderPtyError::PtyWrite(e)),
            }
        }
        if let Some(address) = chip.go_address() {
            // The chip would now run user code. We report the jump and behave as if the
            // board were reset into the bootloader again, so the sim keeps serving.
            on_go(address);
            chip.reset();
        }
        let writes = chip.stats().writes;
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
