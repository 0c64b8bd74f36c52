//! `fpgfx flash`: programs the board's STM32F405 through its ROM bootloader (ST AN3155)
//! over a serial port, the way a user without a debug probe does it.
//!
//! The sequence is the one ST documents and `stm32flash` follows: 0x7F for autobaud, Get
//! / Get Version / Get ID to learn what the chip is, Extended Erase of only the sectors
//! the image touches (erasing a 128 KiB sector takes the real part a second or two, so a
//! 40 KiB image must not cost a mass erase), 256-byte Write Memory blocks, then a
//! read-back of every block. Each block is retried a bounded number of times on NACK or
//! timeout; errors name the command, the stage and the bytes the chip actually sent.
//! Wire encodings come from [`protocol::bootloader`].

use std::collections::BTreeMap;
use std::io;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use protocol::bootloader::{self as bl, Command, ACK, NACK, SYNC};

use crate::session::Transport;

/// Arguments of `fpgfx flash` (the port and baud rate are the tool's global options).
#[derive(Debug, Clone, clap::Args)]
pub struct FlashArgs {
    /// Firmware image: raw .bin (placed at --address), Intel .hex or .elf (PT_LOAD
    /// segments at their physical addresses).
    pub image: PathBuf,
    /// Where a .bin goes; ignored for .hex and .elf, which carry their addresses.
    #[arg(long, default_value = "0x08000000", value_parser = parse_u32)]
    pub address: u32,
    /// Jump to the image's first address (its vector table) when done.
    #[arg(long)]
    pub go: bool,
    /// Skip the read-back comparison.
    #[arg(long)]
    pub no_verify: bool,
    /// Flash a chip whose ID is not the STM32F405's 0x413.
    #[arg(long)]
    pub force: bool,
    /// Attempts per block before giving up.
    #[arg(long, default_value_t = 4)]
    pub retries: u32,
}

/// Parses a decimal or 0x-prefixed hexadecimal address.
pub fn parse_u32(s: &str) -> Result<u32, String> {
    let t = s.trim();
    let r = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(&hex.replace('_', ""), 16),
        None => t.replace('_', "").parse(),
    };
    r.map_err(|_| format!("{s:?} is not a 32-bit address"))
}

/// Why an image file could not be turned into flash blocks.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file could not be read.
    #[error("cannot read {path}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        source: io::Error,
    },
    /// A malformed Intel HEX record.
    #[error("Intel HEX line {line}: {message}")]
    Hex {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A malformed or unsupported ELF file.
    #[error("ELF: {0}")]
    Elf(String),
    /// Nothing to write.
    #[error("the image holds no data")]
    Empty,
    /// Two records or segments write the same byte.
    #[error("the image writes {0:#010x} twice")]
    Overlap(u32),
    /// Part of the image lies outside the F405's flash.
    #[error(
        "the image covers {start:#010x}..{end:#010x}, outside the flash (0x08000000..0x08100000)"
    )]
    OutsideFlash {
        /// First byte.
        start: u32,
        /// One past the last byte.
        end: u64,
    },
}

/// What can go wrong flashing.
#[derive(Debug, thiserror::Error)]
pub enum FlashError {
    /// The serial port could not be opened.
    #[error("cannot open serial port {port}: {why}")]
    Open {
        /// The path given.
        port: String,
        /// What the OS said, with a hint.
        why: String,
    },
    /// Nothing (or nothing sensible) came back to 0x7F.
    #[error(
        "no answer from the bootloader: sent 0x7F {attempts} times{burst} at {baud} baud 8E1, got {got} \
         (is BOOT0 high and the board reset? is this the right port?)"
    )]
    NoSync {
        /// Tries.
        attempts: u32,
        /// The line rate.
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
        /// The command.
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
        /// The command.
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
    /// The fpgfx config file is unreadable.
    #[error("config file: {0}")]
    Config(String),
    /// The image is unusable.
    #[error(transparent)]
    Image(#[from] ImageError),
    /// A block failed every attempt.
    #[error("block at {address:#010x} failed (attempts made: {attempts})")]
    Block {
        /// The block's address.
        address: u32,
        /// Attempts made.
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
        /// Image byte.
        wrote: u8,
        /// Chip byte.
        read: u8,
    },
    /// The port itself failed.
    #[error("the serial port failed (adapter unplugged, or the board lost power?)")]
    Io(#[from] io::Error),
}

fn hex(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "nothing".into();
    }
    let shown: Vec<String> = bytes.iter().take(16).map(|b| format!("{b:02x}")).collect();
    let more = if bytes.len() > 16 { " …" } else { "" };
    format!("[{}{more}]", shown.join(" "))
}

/// One Write Memory: at most 256 bytes, 4-byte aligned start and length, inside one
/// 256-byte-aligned page of flash.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Block {
    /// Where it goes.
    pub address: u32,
    /// What goes there (gaps inside the page are 0xFF, which programs nothing).
    pub data: Vec<u8>,
}

/// A firmware image as the flash will hold it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Blocks in address order.
    pub blocks: Vec<Block>,
}

impl Image {
    /// Builds the blocks from `(address, bytes)` pieces: checks overlap and bounds,
    /// pads to words with 0xFF and cuts at 256-byte boundaries.
    pub fn from_pieces(pieces: &[(u32, Vec<u8>)]) -> Result<Image, ImageError> {
        let mut pages: BTreeMap<u32, ([u8; 256], [bool; 256])> = BTreeMap::new();
        let mut any = false;
        for (start, data) in pieces {
            if data.is_empty() {
                continue;
            }
            any = true;
            let end = u64::from(*start) + data.len() as u64;
            let flash_end = u64::from(bl::FLASH_BASE + bl::FLASH_SIZE);
            if *start < bl::FLASH_BASE || end > flash_end {
                return Err(ImageError::OutsideFlash { start: *start, end });
            }
            for (i, &b) in data.iter().enumerate() {
                let a = start + i as u32;
                let page = pages
                    .entry(a & !0xFF)
                    .or_insert(([0xFF; 256], [false; 256]));
                let o = (a & 0xFF) as usize;
                if page.1[o] {
                    return Err(ImageError::Overlap(a));
                }
                page.0[o] = b;
                page.1[o] = true;
            }
        }
        if !any {
            return Err(ImageError::Empty);
        }
        let blocks = pages
            .into_iter()
            .filter_map(|(base, (bytes, used))| {
                let first = used.iter().position(|&u| u)? & !3;
                let last = used.iter().rposition(|&u| u)?;
                let end = (last + 4) & !3;
                Some(Block {
                    address: base + first as u32,
                    data: bytes[first..end].to_vec(),
                })
            })
            .collect();
        Ok(Image { blocks })
    }

    /// Reads a .bin, .hex or .elf file (by extension; by content when the extension is
    /// something else). `base` places a .bin.
    pub fn load(path: &Path, base: u32) -> Result<Image, ImageError> {
        let bytes = std::fs::read(path).map_err(|source| ImageError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let pieces = match ext.as_str() {
            "hex" | "ihex" | "ihx" => parse_hex(&bytes)?,
            "elf" | "axf" | "out" => parse_elf(&bytes)?,
            "bin" => vec![(base, bytes)],
            _ if bytes.starts_with(b"\x7FELF") => parse_elf(&bytes)?,
            _ if bytes.first() == Some(&b':') => parse_hex(&bytes)?,
            _ => vec![(base, bytes)],
        };
        Image::from_pieces(&pieces)
    }

    /// Bytes the image programs (including word padding).
    pub fn len(&self) -> usize {
        self.blocks.iter().map(|b| b.data.len()).sum()
    }

    /// True if there are no blocks (never, for a loaded image).
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// First address: where the vector table is, and where `--go` jumps.
    pub fn start(&self) -> Option<u32> {
        self.blocks.first().map(|b| b.address)
    }

    /// Indices of the sectors the image touches, ascending, without repeats.
    pub fn sectors(&self) -> Vec<u16> {
        let mut s: Vec<u16> = self
            .blocks
            .iter()
            .filter_map(|b| bl::sectors_touched(b.address, b.data.len() as u32))
            .flat_map(|ss| ss.iter().map(|s| s.index))
            .collect();
        s.sort_unstable();
        s.dedup();
        s
    }
}

/// Intel HEX: data (00), end (01), extended segment (02) and linear (04) address records;
/// start-address records (03, 05) are accepted and ignored (Go uses the image start).
pub fn parse_hex(bytes: &[u8]) -> Result<Vec<(u32, Vec<u8>)>, ImageError> {
    let text = std::str::from_utf8(bytes).map_err(|_| ImageError::Hex {
        line: 1,
        message: "not text".into(),
    })?;
    let mut pieces = Vec::new();
    let mut upper: u32 = 0;
    let mut ended = false;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |message: &str| ImageError::Hex {
            line,
            message: message.to_string(),
        };
        let l = raw.trim();
        if l.is_empty() {
            continue;
        }
        if ended {
            return Err(err("record after the end-of-file record"));
        }
        let body = l
            .strip_prefix(':')
            .ok_or_else(|| err("does not start with ':'"))?;
        if !body.len().is_multiple_of(2) || body.len() < 10 {
            return Err(err("odd or too short record"));
        }
        let rec: Vec<u8> = (0..body.len())
            .step_by(2)
            .map(|j| u8::from_str_radix(&body[j..j + 2], 16))
            .collect::<Result<_, _>>()
            .map_err(|_| err("not hexadecimal"))?;
        let count = usize::from(rec[0]);
        if rec.len() != count + 5 {
            return Err(err("byte count does not match the record length"));
        }
        if rec.iter().fold(0u8, |a, b| a.wrapping_add(*b)) != 0 {
            return Err(err("checksum mismatch"));
        }
        let offset = u32::from(u16::from_be_bytes([rec[1], rec[2]]));
        let data = &rec[4..4 + count];
        match rec[3] {
            0x00 => pieces.push((upper.wrapping_add(offset), data.to_vec())),
            0x01 => ended = true,
            0x02 if count == 2 => upper = u32::from(u16::from_be_bytes([data[0], data[1]])) << 4,
            0x04 if count == 2 => upper = u32::from(u16::from_be_bytes([data[0], data[1]])) << 16,
            0x03 | 0x05 => {}
            t => return Err(err(&format!("unsupported record type {t:02x} or length"))),
        }
    }
    if !ended {
        return Err(ImageError::Hex {
            line: text.lines().count(),
            message: "no end-of-file record (truncated file?)".into(),
        });
    }
    Ok(pieces)
}

/// ELF (32- or 64-bit, either endianness): the file bytes of every PT_LOAD segment at its
/// physical address (LMA), which is where initialised data lives in flash even though it
/// runs from RAM.
pub fn parse_elf(bytes: &[u8]) -> Result<Vec<(u32, Vec<u8>)>, ImageError> {
    use object::read::elf::{FileHeader, ProgramHeader};
    use object::Endianness;

    fn segments<H: FileHeader<Endian = Endianness>>(
        bytes: &[u8],
    ) -> Result<Vec<(u32, Vec<u8>)>, ImageError> {
        let e = |err: object::Error| ImageError::Elf(err.to_string());
        let header = H::parse(bytes).map_err(e)?;
        let endian = header.endian().map_err(e)?;
        let mut out = Vec::new();
        for ph in header.program_headers(endian, bytes).map_err(e)? {
            if ph.p_type(endian) != object::elf::PT_LOAD {
                continue;
            }
            let data = ph
                .data(endian, bytes)
                .map_err(|()| ImageError::Elf("a PT_LOAD segment lies outside the file".into()))?;
            if data.is_empty() {
                continue;
            }
            let paddr: u64 = ph.p_paddr(endian).into();
            let paddr = u32::try_from(paddr)
                .map_err(|_| ImageError::Elf(format!("segment address {paddr:#x} above 4 GiB")))?;
            out.push((paddr, data.to_vec()));
        }
        Ok(out)
    }

    match object::FileKind::parse(bytes) {
        Ok(object::FileKind::Elf32) => segments::<object::elf::FileHeader32<Endianness>>(bytes),
        Ok(object::FileKind::Elf64) => segments::<object::elf::FileHeader64<Endianness>>(bytes),
        _ => Err(ImageError::Elf("not an ELF file".into())),
    }
}

/// A serial port at 8E1, the bootloader's line settings.
pub struct BootPort {
    port: Box<dyn serialport::SerialPort>,
}

impl BootPort {
    /// Opens `path` at `baud`, 8 data bits, even parity, one stop bit, no flow control.
    pub fn open(path: &str, baud: u32) -> Result<Self, FlashError> {
        let port = serialport::new(path, baud)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::Even)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(Duration::from_millis(10))
            .open()
            .map_err(|e| {
                let text = e.to_string();
                let hint = match e.kind() {
                    serialport::ErrorKind::NoDevice => " (no such port: unplugged or mistyped?)",
                    serialport::ErrorKind::Io(io::ErrorKind::NotFound) => {
                        " (no such port: unplugged or mistyped?)"
                    }
                    _ if text.to_ascii_lowercase().contains("busy") => {
                        " (busy: another program has the port open)"
                    }
                    _ => "",
                };
                FlashError::Open {
                    port: path.to_string(),
                    why: format!("{text}{hint}"),
                }
            })?;
        Ok(Self { port })
    }
}

impl Transport for BootPort {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        io::Write::write_all(&mut self.port, bytes)?;
        io::Write::flush(&mut self.port)
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        self.port
            .set_timeout(timeout.max(Duration::from_millis(1)))
            .map_err(io::Error::other)?;
        match io::Read::read(&mut self.port, buf) {
            Ok(n) => Ok(n),
            Err(e) if e.kind() == io::ErrorKind::TimedOut => Ok(0),
            Err(e) => Err(e),
        }
    }
}

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
    port: T,
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

    /// Reads exactly `n` bytes or fails with what arrived.
    fn read_exact(&mut self, n: usize, timeout: Duration) -> Result<Vec<u8>, (Vec<u8>, bool)> {
        let deadline = Instant::now() + timeout;
        let mut got = Vec::with_capacity(n);
        let mut buf = [0u8; 300];
        while got.len() < n {
            let now = Instant::now();
            if now >= deadline {
                return Err((got, true));
            }
            let want = (n - got.len()).min(buf.len());
            match self.port.read(&mut buf[..want], deadline - now) {
                Ok(k) => got.extend_from_slice(&buf[..k]),
                Err(_) => return Err((got, false)),
            }
        }
        Ok(got)
    }

    /// Empties the receive buffer; returns (the first 64 of) what was in it.
    fn drain(&mut self) -> io::Result<Vec<u8>> {
        let mut buf = [0u8; 256];
        let mut seen = Vec::new();
        loop {
            let n = self.port.read(&mut buf, Duration::from_millis(5))?;
            if n == 0 {
                return Ok(seen);
            }
            let room = 64usize.saturating_sub(seen.len());
            seen.extend_from_slice(&buf[..n.min(room)]);
        }
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
        let mut got = Vec::new();
        let mut burst = false;
        for i in 0..attempts {
            if i == 2 {
                self.port.write_all(&[SYNC; 258])?;
                burst = true;
                // Let the burst and its answers cross the line (2 × 258 byte times).
                let line =
                    Duration::from_secs_f64(2.0 * 258.0 * 11.0 / f64::from(self.baud.max(1)));
                std::thread::sleep(line.min(Duration::from_secs(1)) + Duration::from_millis(20));
                let answers = self.drain()?;
                if answers.iter().any(|&b| b != ACK && b != NACK) {
                    got.extend(answers);
                }
            }
            got.extend(self.drain()?);
            self.port.write_all(&[SYNC])?;
            match self.read_exact(1, self.timeouts.sync) {
                Ok(b) if b[0] == ACK || b[0] == NACK => return Ok(()),
                Ok(b) => got.extend(b),
                Err((b, _)) => got.extend(b),
            }
        }
        Err(FlashError::NoSync {
            attempts,
            baud: self.baud,
            burst: if burst {
                " (and one burst of 258 to end a half-received command)"
            } else {
                ""
            },
            got: hex(&got),
        })
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

    /// Go.
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

/// What a flash did, for the summary line and for tests.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// The chip.
    pub chip: ChipInfo,
    /// Sectors erased.
    pub sectors: Vec<u16>,
    /// Blocks written.
    pub blocks: usize,
    /// Bytes written.
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

/// Options of [`flash`].
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

/// Erases, writes and verifies `image` through `client`; `progress` is told about every
/// block (bytes done of total).
pub fn flash<T: Transport>(
    client: &mut Client<T>,
    image: &Image,
    opts: FlashOptions,
    progress: &mut dyn FnMut(&str, u64, u64),
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
    progress("erase", 0, sectors.len() as u64);
    client.erase(&sectors)?;

    let total = image.len() as u64;
    let attempts = opts.attempts.max(1);
    let mut retries = 0;
    let mut done = 0u64;
    progress("write", 0, total);
    for block in &image.blocks {
        let mut made = 0;
        write_with_retries(client, block, attempts, &mut made).map_err(|e| FlashError::Block {
            address: block.address,
            attempts: made,
            last: Box::new(e),
        })?;
        retries += made.saturating_sub(1);
        done += block.data.len() as u64;
        progress("write", done, total);
    }

    if opts.verify {
        let mut checked = 0u64;
        progress("verify", 0, total);
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
            progress("verify", checked, total);
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

/// `fpgfx flash`: the whole command, with a progress bar on stderr (hidden when stderr
/// is not a terminal) and a summary.
pub fn run(port: Option<&str>, baud: Option<u32>, args: &FlashArgs) -> Result<Report, FlashError> {
    let image = Image::load(&args.image, args.address)?;
    // --port/--baud, else the config file `fpgfx ports --help` describes.
    let config = crate::connect::load_config()
        .map_err(|e| FlashError::Config(e.to_string()))?
        .map(|(_, c)| c)
        .unwrap_or_default();
    let port = port.map(str::to_string).or(config.port);
    let baud = baud.or(config.baud).unwrap_or(115_200);
    let port = match port.as_deref() {
        Some(p) if p != "builtin" && !p.starts_with("tcp:") => p.to_string(),
        other => {
            return Err(FlashError::Open {
                port: other.unwrap_or("(none)").to_string(),
                why: "flash needs a serial --port (or FPGFX_PORT) with the board's bootloader \
                      behind it; the built-in and TCP targets have none"
                    .into(),
            })
        }
    };
    let port = port.as_str();
    let mut client = Client::new(BootPort::open(port, baud)?, baud);

    let bar = indicatif::ProgressBar::with_draw_target(
        Some(image.len() as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    let style = indicatif::ProgressStyle::with_template(
        "{msg:>7} [{bar:40}] {bytes}/{total_bytes} {bytes_per_sec}",
    )
    .map(|s| s.progress_chars("=> "))
    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar());
    bar.set_style(style);
    let mut progress = |phase: &str, done: u64, total: u64| {
        if bar.message() != phase {
            bar.set_message(phase.to_string());
            bar.set_length(total);
        }
        bar.set_position(done);
    };
    let result = flash(
        &mut client,
        &image,
        FlashOptions {
            verify: !args.no_verify,
            go: args.go,
            force: args.force,
            attempts: args.retries.max(1),
        },
        &mut progress,
    );
    bar.finish_and_clear();
    let report = result?;
    let secs = report.elapsed.as_secs_f64().max(1e-9);
    eprintln!(
        "chip {:#05x}, bootloader v{}.{}",
        report.chip.pid,
        report.chip.version >> 4,
        report.chip.version & 0xF
    );
    eprintln!(
        "erased sectors {:?}; wrote {} bytes in {} blocks{}; {:.2} s ({:.0} blocks/s){}",
        report.sectors,
        report.bytes,
        report.blocks,
        if report.verified { ", verified" } else { "" },
        secs,
        report.blocks as f64 / secs,
        if report.retries > 0 {
            format!(", {} retries", report.retries)
        } else {
            String::new()
        }
    );
    if let Some(a) = report.jumped {
        eprintln!("jumped to {a:#010x}");
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_board::bootloader::Bootloader;
    use std::collections::VecDeque;

    /// The emulator as an in-process transport, optionally dropping one answer.
    struct Wire {
        chip: Bootloader,
        rx: VecDeque<u8>,
        /// Swallow the answer to the Nth write from the host (1-based), to test retries.
        lose_answer_to_write: Option<usize>,
        writes: usize,
    }

    impl Transport for Wire {
        fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
            self.writes += 1;
            let mut out = Vec::new();
            self.chip.feed(bytes, &mut out);
            if self.lose_answer_to_write != Some(self.writes) {
                self.rx.extend(out);
            }
            Ok(())
        }

        fn read(&mut self, buf: &mut [u8], _timeout: Duration) -> io::Result<usize> {
            let n = buf.len().min(self.rx.len());
            for b in buf.iter_mut().take(n) {
                *b = self.rx.pop_front().unwrap_or(0);
            }
            Ok(n)
        }
    }

    fn wire() -> Wire {
        Wire {
            chip: Bootloader::new(),
            rx: VecDeque::new(),
            lose_answer_to_write: None,
            writes: 0,
        }
    }

    fn client(w: Wire) -> Client<Wire> {
        let mut c = Client::new(w, 115_200);
        c.timeouts.sync = Duration::from_millis(1);
        c.timeouts.ack = Duration::from_millis(1);
        c
    }

    const OPTS: FlashOptions = FlashOptions {
        verify: true,
        go: true,
        force: false,
        attempts: 3,
    };

    fn pattern(n: usize, seed: u32) -> Vec<u8> {
        let mut x = seed.max(1);
        (0..n)
            .map(|_| {
                x ^= x << 13;
                x ^= x >> 17;
                x ^= x << 5;
                x as u8
            })
            .collect()
    }

    #[test]
    fn flashes_and_verifies_against_the_emulator() {
        let data = pattern(40 * 1024 + 3, 7);
        let image = Image::from_pieces(&[(bl::FLASH_BASE, data.clone())]).unwrap();
        assert_eq!(image.sectors(), vec![0, 1, 2]);
        let mut c = client(wire());
        let r = flash(&mut c, &image, OPTS, &mut |_, _, _| {}).unwrap();
        assert_eq!(r.blocks, 161);
        assert_eq!(r.jumped, Some(bl::FLASH_BASE));
        assert_eq!(r.chip.pid, 0x413);
        let flash = c.port.chip.flash();
        assert_eq!(&flash[..data.len()], &data[..]);
        // Word padding is 0xFF, i.e. unprogrammed.
        assert_eq!(&flash[data.len()..data.len() + 1], &[0xFF]);
    }

    #[test]
    fn a_lost_ack_is_recovered_by_read_back() {
        let image = Image::from_pieces(&[(0x0800_4000, pattern(1024, 3))]).unwrap();
        let mut w = wire();
        // Host writes: 7F, Get, GetVersion, GetId, erase cmd, erase list, then per
        // block: cmd, address, data. Lose the ACK to block 2's data.
        w.lose_answer_to_write = Some(6 + 3 + 3);
        let mut c = client(w);
        let r = flash(&mut c, &image, OPTS, &mut |_, _, _| {}).unwrap();
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
        let e = flash(&mut c, &image, OPTS, &mut |_, _, _| {}).unwrap_err();
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
        assert!(flash(&mut c, &image, no_verify, &mut |_, _, _| {}).is_ok());
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
        let e = flash(&mut c, &image, OPTS, &mut |_, _, _| {}).unwrap_err();
        assert!(matches!(e, FlashError::UnknownChip(0x410)), "{e}");
        assert!(e.to_string().contains("0x410"), "{e}");
    }

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

    #[test]
    fn hex_parser() {
        // Extended linear address 0x0800, 4 data bytes at 0x0000, 2 at 0x0010, EOF.
        let text = ":020000040800F2\n:0400000001020304F2\n:02001000AABB89\n:00000001FF\n";
        let pieces = parse_hex(text.as_bytes()).unwrap();
        assert_eq!(
            pieces,
            vec![
                (0x0800_0000, vec![1, 2, 3, 4]),
                (0x0800_0010, vec![0xAA, 0xBB])
            ]
        );
        let image = Image::from_pieces(&pieces).unwrap();
        assert_eq!(
            image.blocks,
            vec![Block {
                address: 0x0800_0000,
                data: [
                    &[1, 2, 3, 4][..],
                    &[0xFF; 12][..],
                    &[0xAA, 0xBB, 0xFF, 0xFF][..]
                ]
                .concat()
            }]
        );
        let bad = ":0400000001020304F3\n:00000001FF\n";
        let e = parse_hex(bad.as_bytes()).unwrap_err();
        assert_eq!(e.to_string(), "Intel HEX line 1: checksum mismatch");
        let e = parse_hex(b":0400000001020304F2\n").unwrap_err();
        assert!(e.to_string().contains("no end-of-file record"), "{e}");
    }

    #[test]
    fn image_bounds_overlap_and_blocks() {
        let e = Image::from_pieces(&[(0x0810_0000 - 2, vec![0; 4])]).unwrap_err();
        assert!(matches!(e, ImageError::OutsideFlash { .. }), "{e}");
        let e = Image::from_pieces(&[(0x2000_0000, vec![0; 4])]).unwrap_err();
        assert!(matches!(e, ImageError::OutsideFlash { .. }), "{e}");
        let e =
            Image::from_pieces(&[(0x0800_0000, vec![0; 8]), (0x0800_0004, vec![1])]).unwrap_err();
        assert!(matches!(e, ImageError::Overlap(0x0800_0004)), "{e}");
        assert!(matches!(
            Image::from_pieces(&[]).unwrap_err(),
            ImageError::Empty
        ));
        // Unaligned start and a block boundary crossing: cut at 0x0800_0100.
        let img = Image::from_pieces(&[(0x0800_00FE, vec![7; 6])]).unwrap();
        assert_eq!(
            img.blocks,
            vec![
                Block {
                    address: 0x0800_00FC,
                    data: vec![0xFF, 0xFF, 7, 7]
                },
                Block {
                    address: 0x0800_0100,
                    data: vec![7, 7, 7, 7]
                }
            ]
        );
        assert_eq!(img.sectors(), vec![0]);
        let img = Image::from_pieces(&[(0x0800_3FFC, vec![1; 8])]).unwrap();
        assert_eq!(img.sectors(), vec![0, 1]);
    }

    #[test]
    fn address_parser() {
        assert_eq!(parse_u32("0x08000000"), Ok(0x0800_0000));
        assert_eq!(parse_u32("0X0800_4000"), Ok(0x0800_4000));
        assert_eq!(parse_u32("134217728"), Ok(0x0800_0000));
        assert!(parse_u32("0x1_0000_0000").is_err());
        assert!(parse_u32("flash").is_err());
    }
}
