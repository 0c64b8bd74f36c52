//! The MSP430's ROM bootstrap loader (BSL) of the 1xx/2xx/4xx families, TI SLAU319
//! ("MSP430 Programming With the Bootloader", the chapter on the 1xx, 2xx and 4xx
//! protocol) and SLAA089, as far as the FITkit's MSP430F168 (BSL 1.6x) speaks it.
//!
//! The FITkit's controller is programmed without a JTAG adapter through this ROM code:
//! `fpgfx flash --chip msp430f168` (the host) and the emulator in `sim-board` (the chip)
//! both build and check these frames, so the encoding lives here, once. Like the rest of
//! the crate it is `no_std` and allocation-free: encoders write into caller buffers and
//! decoders borrow from the received bytes.
//!
//! Wire rules, all from SLAU319 / SLAA089:
//! * 9600 baud, 8E1. Before every command the host sends [`SYNC`] (0x80) and the chip
//!   answers [`DATA_ACK`] (0x90);
//! * a command is one frame: `HDR CMD L1 L2 AL AH LL LH D1…Dn CKL CKH`, HDR 0x80
//!   (0x80..=0x8F accepted), `L1 = L2 = 4 + n` even and at most [`MAX_L`], the address
//!   and the length (or erase mode) little-endian ([`encode_request`], [`decode_request`]);
//! * the checksum is the XOR of the frame's 16-bit little-endian words (every byte before
//!   CKL), inverted ([`checksum`]);
//! * the chip answers [`DATA_ACK`] or [`DATA_NAK`], except TX data block and TX BSL
//!   version, which are answered by a data frame `80 xx n n D1…Dn CKL CKH`
//!   ([`encode_data_frame`], [`decode_data_frame`]) — or by DATA_NAK when refused;
//! * every command but RX password and mass erase is refused until the password, the 32
//!   bytes of the interrupt vector table at 0xFFE0..=0xFFFF, has been received.

/// The synchronisation byte the host sends before every frame.
pub const SYNC: u8 = 0x80;
/// The first byte of every frame (SLAA089 allows 0x80..=0x8F; hosts send 0x80).
pub const HDR: u8 = 0x80;
/// "Frame received and command executed."
pub const DATA_ACK: u8 = 0x90;
/// "Refused": bad frame or checksum, locked or unknown command, or the command failed
/// (e.g. the online verification of a write over unerased flash).
pub const DATA_NAK: u8 = 0xA0;

/// The largest L1 (= L2): the length byte counts AL..Dn, must be even and below 255.
pub const MAX_L: usize = 254;
/// The most data bytes one RX or TX data block carries (SLAA089: "250 max").
pub const MAX_DATA: usize = 250;
/// Header bytes before the data (HDR CMD L1 L2 AL AH LL LH).
pub const HEADER_LEN: usize = 8;
/// The largest frame on the wire: header, [`MAX_DATA`] bytes, checksum.
pub const MAX_FRAME: usize = 4 + MAX_L + 2;

/// Where the password lives: the interrupt vector table.
pub const PASSWORD_ADDRESS: u16 = 0xFFE0;
/// Password length: 16 vectors.
pub const PASSWORD_LEN: usize = 32;
/// The reset vector, which a `--go` loads into the PC.
pub const RESET_VECTOR: u16 = 0xFFFE;
/// The password of a mass-erased chip: all vectors 0xFFFF.
pub const ERASED_PASSWORD: [u8; PASSWORD_LEN] = [0xFF; PASSWORD_LEN];

/// The erase-mode words of Erase segment (LL LH), as written to FCTL1 with its key.
pub mod erase_mode {
    /// Erase the segment holding the address.
    pub const SEGMENT: u16 = 0xA502;
    /// Erase the main memory (address in main flash) or the information memory (address
    /// in it).
    pub const MAIN_OR_INFO: u16 = 0xA504;
    /// Mass erase: main and information memory (what hosts put in Mass erase's LL LH;
    /// the 1xx ROM BSL ignores the fields).
    pub const MASS: u16 = 0xA506;
}

/// BSL command codes (the CMD byte).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Command {
    /// The 32-byte password; unlocks the protected commands.
    RxPassword = 0x10,
    /// Host → chip: write up to 250 bytes to RAM, flash or peripherals.
    RxDataBlock = 0x12,
    /// Chip → host: read up to 250 bytes.
    TxDataBlock = 0x14,
    /// Erase one segment, or main or information memory.
    EraseSegment = 0x16,
    /// Erase all flash; the one erase a locked chip accepts.
    MassErase = 0x18,
    /// Leave the BSL and run from an address.
    LoadPc = 0x1A,
    /// Whether a range reads as 0xFF.
    EraseCheck = 0x1C,
    /// The 16 bytes of boot ROM at 0x0FF0: device ID and BSL version.
    TxBslVersion = 0x1E,
    /// Switch the line to 19 200 or 38 400 baud.
    ChangeBaudRate = 0x20,
    /// Upper address bits for parts above 64 KiB (BSL 2.12 and up; not the F168's).
    SetMemOffset = 0x21,
}

impl Command {
    /// Every command this module knows, in code order.
    pub const ALL: [Command; 10] = [
        Command::RxPassword,
        Command::RxDataBlock,
        Command::TxDataBlock,
        Command::EraseSegment,
        Command::MassErase,
        Command::LoadPc,
        Command::EraseCheck,
        Command::TxBslVersion,
        Command::ChangeBaudRate,
        Command::SetMemOffset,
    ];

    /// The byte on the wire.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The command with this code, if the 1xx/2xx/4xx BSL defines one.
    pub fn from_code(code: u8) -> Option<Command> {
        Command::ALL.iter().copied().find(|c| c.code() == code)
    }

    /// The name SLAU319 uses, for error messages ("RX data block: DATA_NAK …").
    pub const fn name(self) -> &'static str {
        match self {
            Command::RxPassword => "RX password",
            Command::RxDataBlock => "RX data block",
            Command::TxDataBlock => "TX data block",
            Command::EraseSegment => "Erase segment",
            Command::MassErase => "Mass erase",
            Command::LoadPc => "Load PC",
            Command::EraseCheck => "Erase check",
            Command::TxBslVersion => "TX BSL version",
            Command::ChangeBaudRate => "Change baud rate",
            Command::SetMemOffset => "Set mem offset",
        }
    }

    /// Whether a locked chip refuses it: all but RX password and mass erase, which is
    /// how a chip whose password nobody knows can still be reused (erased).
    pub const fn needs_password(self) -> bool {
        !matches!(self, Command::RxPassword | Command::MassErase)
    }
}

/// What cannot be encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EncodeError {
    /// The BSL counts in words: data must have an even length of at most 250 bytes.
    #[error("a BSL frame carries an even number of data bytes up to 250, not {0}")]
    DataLength(usize),
    /// The output buffer cannot hold the frame.
    #[error("output buffer too small: {needed} bytes needed")]
    BufferTooSmall {
        /// Bytes the frame needs.
        needed: usize,
    },
}

/// What is wrong with a received frame; the chip answers each with DATA_NAK, the host
/// reports it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum DecodeError {
    /// The first byte is not a header (0x80..=0x8F).
    #[error("frame header {0:#04x} is not 0x80..=0x8f")]
    Header(u8),
    /// L1 and L2 differ, which is how the BSL protects its length byte.
    #[error("length bytes differ: L1 {l1:#04x}, L2 {l2:#04x}")]
    LengthMismatch {
        /// First length byte.
        l1: u8,
        /// Second length byte.
        l2: u8,
    },
    /// L1 is odd, above 254, or (for a command) below the four address/length bytes.
    #[error("length byte {0:#04x} is odd, above 254 or too short for the frame kind")]
    Length(u8),
    /// Fewer or more bytes than L1 announces.
    #[error("the frame is {got} bytes, its length bytes announce {expected}")]
    Size {
        /// Bytes the length byte implies (header, body, checksum).
        expected: usize,
        /// Bytes given.
        got: usize,
    },
    /// The checksum does not match the bytes.
    #[error("checksum {got:#06x} received, the bytes give {expected:#06x}")]
    Checksum {
        /// What the bytes before the checksum give.
        expected: u16,
        /// What the frame carries.
        got: u16,
    },
}

/// The BSL checksum of `bytes`: the XOR of their 16-bit little-endian words, inverted.
/// Frames always have an even length; a trailing odd byte counts as a low byte.
pub fn checksum(bytes: &[u8]) -> u16 {
    let xor = bytes.chunks(2).fold(0u16, |acc, w| {
        acc ^ u16::from_le_bytes([w[0], w.get(1).copied().unwrap_or(0)])
    });
    !xor
}

/// A command frame's contents, borrowed from the received bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Request<'a> {
    /// The CMD byte (not necessarily a known [`Command`]: an unknown one is NAK'd).
    pub command: u8,
    /// AL AH: block start, erase address or jump address.
    pub address: u16,
    /// LL LH: data length, length to read or check, erase mode, baud settings.
    pub length: u16,
    /// D1…Dn.
    pub data: &'a [u8],
}

/// The frame length the four first bytes (HDR CMD L1 L2) announce, checksum included,
/// so that a receiver knows how many bytes to collect; `min_l` is the least L1 the
/// frame kind allows (4 for commands, 0 for data frames).
pub fn frame_len(head: [u8; 4], min_l: usize) -> Result<usize, DecodeError> {
    let [hdr, _, l1, l2] = head;
    if !(0x80..=0x8F).contains(&hdr) {
        return Err(DecodeError::Header(hdr));
    }
    if l1 != l2 {
        return Err(DecodeError::LengthMismatch { l1, l2 });
    }
    let l = usize::from(l1);
    if !l.is_multiple_of(2) || l > MAX_L || l < min_l {
        return Err(DecodeError::Length(l1));
    }
    Ok(4 + l + 2)
}

/// Encodes a command frame into `out`; returns the number of bytes used
/// (`8 + data.len() + 2`).
pub fn encode_request(
    command: u8,
    address: u16,
    length: u16,
    data: &[u8],
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    if !data.len().is_multiple_of(2) || data.len() > MAX_DATA {
        return Err(EncodeError::DataLength(data.len()));
    }
    let needed = HEADER_LEN + data.len() + 2;
    let frame = out
        .get_mut(..needed)
        .ok_or(EncodeError::BufferTooSmall { needed })?;
    let l = (4 + data.len()) as u8;
    let [al, ah] = address.to_le_bytes();
    let [ll, lh] = length.to_le_bytes();
    frame[..HEADER_LEN].copy_from_slice(&[HDR, command, l, l, al, ah, ll, lh]);
    frame[HEADER_LEN..needed - 2].copy_from_slice(data);
    let ck = checksum(&frame[..needed - 2]);
    frame[needed - 2..].copy_from_slice(&ck.to_le_bytes());
    Ok(needed)
}

/// Checks a whole command frame (header, lengths, size, checksum) and returns its parts.
pub fn decode_request(frame: &[u8]) -> Result<Request<'_>, DecodeError> {
    let body = check_frame(frame, 4)?;
    Ok(Request {
        command: frame[1],
        address: u16::from_le_bytes([body[0], body[1]]),
        length: u16::from_le_bytes([body[2], body[3]]),
        data: &body[4..],
    })
}

/// Encodes the chip's data frame (the answer to TX data block and TX BSL version):
/// `80 00 n n D1…Dn CKL CKH`; returns the number of bytes used.
pub fn encode_data_frame(data: &[u8], out: &mut [u8]) -> Result<usize, EncodeError> {
    if !data.len().is_multiple_of(2) || data.len() > MAX_L {
        return Err(EncodeError::DataLength(data.len()));
    }
    let needed = 4 + data.len() + 2;
    let frame = out
        .get_mut(..needed)
        .ok_or(EncodeError::BufferTooSmall { needed })?;
    let n = data.len() as u8;
    frame[..4].copy_from_slice(&[HDR, 0x00, n, n]);
    frame[4..needed - 2].copy_from_slice(data);
    let ck = checksum(&frame[..needed - 2]);
    frame[needed - 2..].copy_from_slice(&ck.to_le_bytes());
    Ok(needed)
}

/// Checks a whole data frame and returns its data.
pub fn decode_data_frame(frame: &[u8]) -> Result<&[u8], DecodeError> {
    check_frame(frame, 0)
}

/// Header, lengths, size and checksum of a frame; returns what follows L2.
fn check_frame(frame: &[u8], min_l: usize) -> Result<&[u8], DecodeError> {
    let head: [u8; 4] = match frame.get(..4) {
        Some(h) => [h[0], h[1], h[2], h[3]],
        None => {
            return Err(DecodeError::Size {
                expected: 4 + min_l + 2,
                got: frame.len(),
            })
        }
    };
    let expected = frame_len(head, min_l)?;
    if frame.len() != expected {
        return Err(DecodeError::Size {
            expected,
            got: frame.len(),
        });
    }
    let (bytes, ck) = frame.split_at(expected - 2);
    let got = u16::from_le_bytes([ck[0], ck[1]]);
    let want = checksum(bytes);
    if got != want {
        return Err(DecodeError::Checksum {
            expected: want,
            got,
        });
    }
    Ok(&bytes[4..])
}

/// One kind of memory in a chip's map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Static RAM: written as given.
    Ram,
    /// Flash: programming only clears bits; erased in segments of `segment` bytes.
    Flash {
        /// Erase unit in bytes.
        segment: u32,
    },
    /// The boot ROM (the BSL itself and its identification bytes): read-only.
    Rom,
}

/// One region of a chip's memory map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Region {
    /// Its name in messages ("main flash").
    pub name: &'static str,
    /// First address.
    pub start: u32,
    /// One past the last address.
    pub end: u32,
    /// What it is.
    pub kind: Kind,
}

impl Region {
    /// Whether `[address, address + len)` lies inside.
    pub fn contains(&self, address: u32, len: u32) -> bool {
        let end = u64::from(address) + u64::from(len);
        address >= self.start && end <= u64::from(self.end)
    }
}

/// A part the BSL runs on: how it identifies itself and what its memory looks like.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Chip {
    /// The part's name ("MSP430F168").
    pub name: &'static str,
    /// Device ID at 0x0FF0..=0x0FF1 (high byte first), as TX BSL version reports it.
    pub device_id: u16,
    /// BSL version at 0x0FFA..=0x0FFB in BCD (0x0161 is 1.61).
    pub bsl_version: u16,
    /// The regions the BSL reaches (peripherals at 0x0000..0x0200 are left out: the
    /// emulator does not model them).
    pub regions: &'static [Region],
}

/// The MSP430F168 (the FITkit's controller): 2 KiB RAM, 256 B information memory in two
/// 128-byte segments, 48 KiB main flash in 512-byte segments ending in the vector table,
/// the boot ROM with the BSL at 0x0C00.
///
/// BSL 1.61 is what the F16x family's ROM is assumed to carry (SLAU319's device/version
/// table lists 1.60 and 1.61 for the F15x/F16x/F161x parts); it is above 1.10, so hosts
/// apply no patch, and below 2.12, so there is no Set mem offset.
pub const MSP430F168: Chip = Chip {
    name: "MSP430F168",
    device_id: 0xF169,
    bsl_version: 0x0161,
    regions: &[
        Region {
            name: "RAM",
            start: 0x0200,
            end: 0x0A00,
            kind: Kind::Ram,
        },
        Region {
            name: "boot ROM",
            start: 0x0C00,
            end: 0x1000,
            kind: Kind::Rom,
        },
        Region {
            name: "information memory",
            start: 0x1000,
            end: 0x1100,
            kind: Kind::Flash { segment: 128 },
        },
        Region {
            name: "main flash",
            start: 0x4000,
            end: 0x1_0000,
            kind: Kind::Flash { segment: 512 },
        },
    ],
};

impl Chip {
    /// The region holding all of `[address, address + len)`, if one does.
    pub fn region(&self, address: u32, len: u32) -> Option<&'static Region> {
        self.regions.iter().find(|r| r.contains(address, len))
    }

    /// The 16 bytes of boot ROM at 0x0FF0 that TX BSL version returns: the device ID
    /// (high byte first) at 0x0FF0, the BSL version (BCD, high byte first) at 0x0FFA,
    /// the rest as the emulator fills it (0xFF).
    pub fn version_bytes(&self) -> [u8; 16] {
        let mut v = [0xFF; 16];
        v[..2].copy_from_slice(&self.device_id.to_be_bytes());
        v[10..12].copy_from_slice(&self.bsl_version.to_be_bytes());
        v
    }
}

/// Device ID and BSL version from the 16 bytes TX BSL version returns, `None` if fewer
/// came.
pub fn parse_version(bytes: &[u8]) -> Option<(u16, u16)> {
    let id = u16::from_be_bytes([*bytes.first()?, *bytes.get(1)?]);
    let version = u16::from_be_bytes([*bytes.get(10)?, *bytes.get(11)?]);
    Some((id, version))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// SLAA089's worked example: read 14 bytes at 0x0FF0, and the chip's answer.
    #[test]
    fn slaa089_example() {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_request(Command::TxDataBlock.code(), 0x0FF0, 0x000E, &[], &mut out).unwrap();
        assert_eq!(
            &out[..n],
            &[0x80, 0x14, 0x04, 0x04, 0xF0, 0x0F, 0x0E, 0x00, 0x85, 0xE0]
        );
        let answer = [
            0x80, 0x00, 0x0E, 0x0E, 0xF2, 0x13, 0x40, 0x40, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
            0x02, 0x01, 0x01, 0x01, 0xC0, 0xA2,
        ];
        let data = decode_data_frame(&answer).unwrap();
        assert_eq!(data, &answer[4..18]);
        let mut again = [0u8; MAX_FRAME];
        let n = encode_data_frame(data, &mut again).unwrap();
        assert_eq!(&again[..n], &answer);
        assert_eq!(
            parse_version(&MSP430F168.version_bytes()),
            Some((0xF169, 0x0161))
        );
    }

    /// The mass-erase and password frames python-msp430-tools and mspdebug send.
    #[test]
    fn mass_erase_and_password_frames() {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_request(
            Command::MassErase.code(),
            0xFFFE,
            erase_mode::MASS,
            &[],
            &mut out,
        )
        .unwrap();
        // Words 1880 0404 FFFE A506: XOR = 0x467C, inverted 0xB983 (python-msp430-tools
        // sends the same bytes).
        assert_eq!(
            &out[..n],
            &[0x80, 0x18, 0x04, 0x04, 0xFE, 0xFF, 0x06, 0xA5, 0x83, 0xB9]
        );
        let n =
            encode_request(Command::RxPassword.code(), 0, 0, &ERASED_PASSWORD, &mut out).unwrap();
        assert_eq!(n, 42);
        assert_eq!(&out[..4], &[0x80, 0x10, 0x24, 0x24]);
        let r = decode_request(&out[..n]).unwrap();
        assert_eq!(r.data, &ERASED_PASSWORD);
    }

    #[test]
    fn limits_and_errors() {
        let mut out = [0u8; MAX_FRAME];
        assert_eq!(
            encode_request(0x12, 0, 3, &[1, 2, 3], &mut out),
            Err(EncodeError::DataLength(3))
        );
        assert_eq!(
            encode_request(0x12, 0, 252, &[0; 252], &mut out),
            Err(EncodeError::DataLength(252))
        );
        assert_eq!(encode_request(0x12, 0, 250, &[0; 250], &mut out), Ok(260));
        assert_eq!(
            encode_request(0x12, 0, 2, &[0; 2], &mut out[..11]),
            Err(EncodeError::BufferTooSmall { needed: 12 })
        );
        assert_eq!(
            frame_len([0x7F, 0x12, 4, 4], 4),
            Err(DecodeError::Header(0x7F))
        );
        assert_eq!(
            frame_len([0x80, 0x12, 4, 6], 4),
            Err(DecodeError::LengthMismatch { l1: 4, l2: 6 })
        );
        assert_eq!(
            frame_len([0x80, 0x12, 5, 5], 4),
            Err(DecodeError::Length(5))
        );
        assert_eq!(
            frame_len([0x80, 0x12, 0xFF, 0xFF], 4),
            Err(DecodeError::Length(0xFF))
        );
        assert_eq!(
            frame_len([0x80, 0x12, 2, 2], 4),
            Err(DecodeError::Length(2))
        );
        assert_eq!(frame_len([0x8F, 0x12, 254, 254], 4), Ok(260));
        assert_eq!(frame_len([0x80, 0x00, 0, 0], 0), Ok(6));
        let n = encode_request(0x1A, 0x4000, 0, &[], &mut out).unwrap();
        assert!(matches!(
            decode_request(&out[..n - 1]),
            Err(DecodeError::Size {
                expected: 10,
                got: 9
            })
        ));
    }

    #[test]
    fn memory_map() {
        let m = MSP430F168;
        assert_eq!(m.region(0x4000, 0xC000).map(|r| r.name), Some("main flash"));
        assert_eq!(m.region(0xFFE0, 32).map(|r| r.name), Some("main flash"));
        assert_eq!(m.region(0xFFFE, 4), None);
        assert_eq!(
            m.region(0x1000, 256).map(|r| r.name),
            Some("information memory")
        );
        assert_eq!(m.region(0x10FE, 4), None);
        assert_eq!(m.region(0x0200, 0x800).map(|r| r.name), Some("RAM"));
        assert_eq!(m.region(0x0A00, 2), None);
        assert_eq!(m.region(0x3FFE, 2), None);
        assert_eq!(m.region(0x0120, 2), None);
    }
}
