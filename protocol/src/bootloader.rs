//! The STM32 system-memory (ROM) bootloader's UART protocol, ST application note AN3155,
//! as far as the STM32F405 (bootloader v3.1) speaks it.
//!
//! Flashing a board needs no debug probe: with BOOT0 high the chip starts its ROM
//! bootloader, which takes commands over USART1 at 8E1. `fpgfx flash` (the host) and the
//! emulator in `sim-board` (the board) both build and check these byte strings, so the
//! encoding lives here, once. Everything is `no_std` and allocation-free: encoders write
//! into fixed arrays or caller buffers.
//!
//! Wire rules, all from AN3155:
//! * the host opens with [`SYNC`] (0x7F) so the chip can measure the baud rate; the chip
//!   answers [`ACK`];
//! * every command is its code followed by the code's complement ([`command_frame`]);
//! * addresses are four bytes, most significant first, followed by the XOR of the four
//!   ([`address_frame`]);
//! * data blocks are `N-1`, the bytes, then the XOR of `N-1` and all bytes
//!   ([`encode_data_block`]);
//! * a read length is `N-1` followed by its complement ([`read_length_frame`]);
//! * Extended Erase takes a 16-bit count-minus-one or a special code, 16-bit page
//!   numbers, and the XOR of everything ([`encode_extended_erase`]).

/// The autobaud byte the host sends first; also what an out-of-sync host re-sends.
pub const SYNC: u8 = 0x7F;
/// "Accepted" / "done".
pub const ACK: u8 = 0x79;
/// "Refused": bad complement or checksum, address out of range, command not supported,
/// or a flash programming error.
pub const NACK: u8 = 0x1F;

/// Product ID the STM32F405/407/415/417 report to Get ID (DBGMCU_IDCODE.DEV_ID).
pub const F405_PID: u16 = 0x0413;
/// Bootloader protocol version of the STM32F405's system memory (v3.1), as Get and Get
/// Version report it.
pub const F405_BOOTLOADER_VERSION: u8 = 0x31;

/// The largest block one Read Memory or Write Memory moves (N-1 is one byte).
pub const MAX_BLOCK: usize = 256;

/// Start of the main flash on the STM32F4.
pub const FLASH_BASE: u32 = 0x0800_0000;
/// Main flash size of the STM32F405xG (the reference board's part).
pub const FLASH_SIZE: u32 = 1024 * 1024;
/// Start of SRAM1+SRAM2 (contiguous on the F405).
pub const RAM_BASE: u32 = 0x2000_0000;
/// SRAM1 + SRAM2 (the 64 KiB CCM is not reachable by the bootloader).
pub const RAM_SIZE: u32 = 128 * 1024;
/// The bootloader keeps its own variables and stack in the first 12 KiB of RAM
/// (AN2606); writes there are refused, which is why tools load code at 0x2000_3000.
pub const RAM_BOOTLOADER_END: u32 = 0x2000_3000;
/// Start of system memory, where the ROM bootloader itself lives.
pub const SYSTEM_MEMORY_BASE: u32 = 0x1FFF_0000;
/// Size of system memory (30 KiB).
pub const SYSTEM_MEMORY_SIZE: u32 = 0x7800;
/// Start of the one-time-programmable area (512 bytes + 16 lock bytes).
pub const OTP_BASE: u32 = 0x1FFF_7800;
/// Size of the OTP area including its lock bytes.
pub const OTP_SIZE: u32 = 0x210;
/// Start of the user option bytes (RDP, USER, nWRP).
pub const OPTION_BYTES_BASE: u32 = 0x1FFF_C000;
/// Size of the option-byte area.
pub const OPTION_BYTES_SIZE: u32 = 16;

/// Bootloader command codes. The chip only accepts a code followed by its complement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum Command {
    /// Bootloader version and the list of supported commands.
    Get = 0x00,
    /// Bootloader version and two (legacy, zero on the F4) option bytes.
    GetVersion = 0x01,
    /// The product ID ([`F405_PID`] on the reference board), to check the chip before
    /// writing to it.
    GetId = 0x02,
    /// Up to 256 bytes from any readable address.
    ReadMemory = 0x11,
    /// Jump to user code.
    Go = 0x21,
    /// Up to 256 bytes into flash or RAM.
    WriteMemory = 0x31,
    /// Legacy one-byte-page erase; not supported by the F4's bootloader.
    Erase = 0x43,
    /// Erase by 16-bit page (on the F4: sector) numbers, or mass erase.
    ExtendedErase = 0x44,
    /// Write-protect sectors.
    WriteProtect = 0x63,
    /// Remove write protection from all sectors (then the chip resets).
    WriteUnprotect = 0x73,
    /// Enable read-out protection (then the chip resets).
    ReadoutProtect = 0x82,
    /// Disable read-out protection: mass-erases the flash (then the chip resets).
    ReadoutUnprotect = 0x92,
}

impl Command {
    /// Every command this module knows, in code order.
    pub const ALL: [Command; 12] = [
        Command::Get,
        Command::GetVersion,
        Command::GetId,
        Command::ReadMemory,
        Command::Go,
        Command::WriteMemory,
        Command::Erase,
        Command::ExtendedErase,
        Command::WriteProtect,
        Command::WriteUnprotect,
        Command::ReadoutProtect,
        Command::ReadoutUnprotect,
    ];

    /// The byte on the wire.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The command with this code, if it is one of AN3155's UART commands.
    pub fn from_code(code: u8) -> Option<Command> {
        Command::ALL.iter().copied().find(|c| c.code() == code)
    }

    /// The name AN3155 uses, for error messages ("NACK to Write Memory").
    pub const fn name(self) -> &'static str {
        match self {
            Command::Get => "Get",
            Command::GetVersion => "Get Version",
            Command::GetId => "Get ID",
            Command::ReadMemory => "Read Memory",
            Command::Go => "Go",
            Command::WriteMemory => "Write Memory",
            Command::Erase => "Erase",
            Command::ExtendedErase => "Extended Erase",
            Command::WriteProtect => "Write Protect",
            Command::WriteUnprotect => "Write Unprotect",
            Command::ReadoutProtect => "Readout Protect",
            Command::ReadoutUnprotect => "Readout Unprotect",
        }
    }
}

/// The commands the STM32F405's bootloader v3.1 lists in its answer to Get, in the order
/// it lists them. Note 0x44 and not 0x43: the F4 only has Extended Erase.
pub const F405_COMMANDS: [Command; 11] = [
    Command::Get,
    Command::GetVersion,
    Command::GetId,
    Command::ReadMemory,
    Command::Go,
    Command::WriteMemory,
    Command::ExtendedErase,
    Command::WriteProtect,
    Command::WriteUnprotect,
    Command::ReadoutProtect,
    Command::ReadoutUnprotect,
];

/// What can be wrong with something to encode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum EncodeError {
    /// Blocks carry 1..=256 bytes (the length travels as N-1 in one byte).
    #[error("a block carries 1..=256 bytes, not {0}")]
    BlockLength(usize),
    /// Extended Erase takes 1..=0xFFF0 page numbers (larger counts are special codes).
    #[error("an erase list holds 1..=65520 pages, not {0}")]
    PageCount(usize),
    /// The output buffer cannot hold the encoding.
    #[error("output buffer too small: {needed} bytes needed")]
    BufferTooSmall {
        /// Bytes the encoding needs.
        needed: usize,
    },
}

/// XOR of all bytes: the checksum of every AN3155 frame except the command byte.
pub fn xor(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |a, b| a ^ b)
}

/// A command as sent: code, complement.
pub const fn command_frame(command: Command) -> [u8; 2] {
    [command.code(), !command.code()]
}

/// True if `second` is the complement of `first`, which is all the chip checks before
/// acting on a command byte.
pub const fn is_command_pair(first: u8, second: u8) -> bool {
    first ^ second == 0xFF
}

/// An address as sent: four bytes MSB first, then their XOR.
pub fn address_frame(address: u32) -> [u8; 5] {
    let b = address.to_be_bytes();
    [b[0], b[1], b[2], b[3], xor(&b)]
}

/// The address in a received address frame, or `None` if its checksum is wrong.
pub fn parse_address_frame(frame: &[u8; 5]) -> Option<u32> {
    (xor(&frame[..4]) == frame[4])
        .then(|| u32::from_be_bytes([frame[0], frame[1], frame[2], frame[3]]))
}

/// The length frame of Read Memory: `len - 1` and its complement.
pub fn read_length_frame(len: usize) -> Result<[u8; 2], EncodeError> {
    if !(1..=MAX_BLOCK).contains(&len) {
        return Err(EncodeError::BlockLength(len));
    }
    let n = (len - 1) as u8;
    Ok([n, !n])
}

/// Encodes a Write Memory data block (`N-1`, data, XOR of both) into `out`; returns the
/// number of bytes used (`data.len() + 2`). Alignment is the caller's business: the chip
/// wants a length that is a multiple of four (see [`is_write_aligned`]).
pub fn encode_data_block(data: &[u8], out: &mut [u8]) -> Result<usize, EncodeError> {
    if !(1..=MAX_BLOCK).contains(&data.len()) {
        return Err(EncodeError::BlockLength(data.len()));
    }
    let needed = data.len() + 2;
    if out.len() < needed {
        return Err(EncodeError::BufferTooSmall { needed });
    }
    let n = (data.len() - 1) as u8;
    out[0] = n;
    out[1..=data.len()].copy_from_slice(data);
    out[data.len() + 1] = n ^ xor(data);
    Ok(needed)
}

/// True if a Write Memory of `len` bytes at `address` has the alignment the F4's
/// bootloader accepts: address and length multiples of four (it programs 32-bit words).
pub const fn is_write_aligned(address: u32, len: usize) -> bool {
    address.is_multiple_of(4) && len.is_multiple_of(4) && len > 0 && len <= MAX_BLOCK
}

/// What an Extended Erase asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EraseRequest<'a> {
    /// Erase the whole flash (special code 0xFFFF).
    Mass,
    /// Erase bank 1 (special code 0xFFFE; only dual-bank parts).
    Bank1,
    /// Erase bank 2 (special code 0xFFFD; only dual-bank parts).
    Bank2,
    /// Erase these pages (on the F4: sector indices).
    Pages(&'a [u16]),
}

/// Special "count" values of Extended Erase.
pub mod erase_code {
    /// [`super::EraseRequest::Mass`]: the whole flash.
    pub const MASS: u16 = 0xFFFF;
    /// [`super::EraseRequest::Bank1`]; dual-bank parts only.
    pub const BANK1: u16 = 0xFFFE;
    /// [`super::EraseRequest::Bank2`]; dual-bank parts only.
    pub const BANK2: u16 = 0xFFFD;
    /// Codes 0xFFF0..=0xFFFC are reserved by AN3155; the chip refuses them.
    pub const RESERVED_FIRST: u16 = 0xFFF0;
}

/// How the two bytes after the Extended Erase command read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EraseHeader {
    /// Mass erase; one checksum byte follows.
    Mass,
    /// Bank 1 erase; one checksum byte follows.
    Bank1,
    /// Bank 2 erase; one checksum byte follows.
    Bank2,
    /// A reserved code; one checksum byte follows and the chip refuses it.
    Reserved(u16),
    /// This many page numbers (two bytes each) and a checksum follow.
    Pages(u32),
}

impl EraseHeader {
    /// Decodes the 16-bit value after the command.
    pub fn decode(n: u16) -> EraseHeader {
        match n {
            erase_code::MASS => EraseHeader::Mass,
            erase_code::BANK1 => EraseHeader::Bank1,
            erase_code::BANK2 => EraseHeader::Bank2,
            n if n >= erase_code::RESERVED_FIRST => EraseHeader::Reserved(n),
            n => EraseHeader::Pages(u32::from(n) + 1),
        }
    }
}

/// Encodes the part of an Extended Erase that follows the command's ACK into `out`;
/// returns the number of bytes used. Special codes are followed by their own XOR (AN3155:
/// mass erase is `FF FF 00`); page lists are `N-1` (two bytes), the pages (two bytes each,
/// MSB first) and the XOR of all of them.
pub fn encode_extended_erase(
    request: EraseRequest<'_>,
    out: &mut [u8],
) -> Result<usize, EncodeError> {
    let mut put = |bytes: &[u8]| -> Result<usize, EncodeError> {
        let needed = bytes.len();
        out.get_mut(..needed)
            .ok_or(EncodeError::BufferTooSmall { needed })?
            .copy_from_slice(bytes);
        Ok(needed)
    };
    let special = |code: u16| {
        let b = code.to_be_bytes();
        [b[0], b[1], b[0] ^ b[1]]
    };
    match request {
        EraseRequest::Mass => put(&special(erase_code::MASS)),
        EraseRequest::Bank1 => put(&special(erase_code::BANK1)),
        EraseRequest::Bank2 => put(&special(erase_code::BANK2)),
        EraseRequest::Pages(pages) => {
            if pages.is_empty() || pages.len() > usize::from(erase_code::RESERVED_FIRST) {
                return Err(EncodeError::PageCount(pages.len()));
            }
            let needed = 2 + 2 * pages.len() + 1;
            if out.len() < needed {
                return Err(EncodeError::BufferTooSmall { needed });
            }
            let n = ((pages.len() - 1) as u16).to_be_bytes();
            out[..2].copy_from_slice(&n);
            for (i, p) in pages.iter().enumerate() {
                out[2 + 2 * i..4 + 2 * i].copy_from_slice(&p.to_be_bytes());
            }
            out[needed - 1] = xor(&out[..needed - 1]);
            Ok(needed)
        }
    }
}

/// One erase unit of the STM32F405's flash. The F4 erases by sector, and its bootloader
/// takes sector indices where AN3155 says "page numbers".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Sector {
    /// Index as Extended Erase takes it.
    pub index: u16,
    /// Address of the sector's first byte in the memory map.
    pub start: u32,
    /// Size in bytes.
    pub size: u32,
}

impl Sector {
    /// One past the last address.
    pub const fn end(&self) -> u32 {
        self.start + self.size
    }
}

const fn f405_sectors() -> [Sector; 12] {
    let mut s = [Sector {
        index: 0,
        start: 0,
        size: 0,
    }; 12];
    let mut i = 0;
    let mut start = FLASH_BASE;
    while i < 12 {
        let size = if i < 4 {
            16 * 1024
        } else if i == 4 {
            64 * 1024
        } else {
            128 * 1024
        };
        s[i] = Sector {
            index: i as u16,
            start,
            size,
        };
        start += size;
        i += 1;
    }
    s
}

/// The STM32F405xG's flash sectors (RM0090 table 5): 4 × 16 KiB, 1 × 64 KiB, 7 × 128 KiB.
pub const F405_SECTORS: [Sector; 12] = f405_sectors();

/// The sector holding `address`, if it is in main flash.
pub fn sector_of(address: u32) -> Option<Sector> {
    F405_SECTORS
        .iter()
        .copied()
        .find(|s| (s.start..s.end()).contains(&address))
}

/// The sectors an image occupying `[start, start + len)` touches, in order; empty if
/// `len` is 0. `None` if any byte of it lies outside main flash.
pub fn sectors_touched(start: u32, len: u32) -> Option<&'static [Sector]> {
    if len == 0 {
        return Some(&[]);
    }
    let last = start.checked_add(len - 1)?;
    let (first, last) = (sector_of(start)?, sector_of(last)?);
    F405_SECTORS.get(usize::from(first.index)..=usize::from(last.index))
}

#[cfg(test)]
mod tests {
    use super::*;

    // Command bytes and complements as AN3155's command tables list them.
    #[test]
    fn command_frames_match_an3155() {
        let golden: [(Command, [u8; 2]); 12] = [
            (Command::Get, [0x00, 0xFF]),
            (Command::GetVersion, [0x01, 0xFE]),
            (Command::GetId, [0x02, 0xFD]),
            (Command::ReadMemory, [0x11, 0xEE]),
            (Command::Go, [0x21, 0xDE]),
            (Command::WriteMemory, [0x31, 0xCE]),
            (Command::Erase, [0x43, 0xBC]),
            (Command::ExtendedErase, [0x44, 0xBB]),
            (Command::WriteProtect, [0x63, 0x9C]),
            (Command::WriteUnprotect, [0x73, 0x8C]),
            (Command::ReadoutProtect, [0x82, 0x7D]),
            (Command::ReadoutUnprotect, [0x92, 0x6D]),
        ];
        for (c, bytes) in golden {
            assert_eq!(command_frame(c), bytes, "{}", c.name());
            assert!(is_command_pair(bytes[0], bytes[1]));
            assert_eq!(Command::from_code(bytes[0]), Some(c));
        }
        assert!(!is_command_pair(0x7F, 0x7F));
        assert_eq!(Command::from_code(0x7F), None);
    }

    #[test]
    fn address_frame_golden() {
        // Go to the start of flash: 08 00 00 00, checksum 08.
        assert_eq!(address_frame(0x0800_0000), [0x08, 0x00, 0x00, 0x00, 0x08]);
        // Option bytes: 1F FF C0 00, checksum 1F^FF^C0 = 0x20.
        assert_eq!(address_frame(0x1FFF_C000), [0x1F, 0xFF, 0xC0, 0x00, 0x20]);
        assert_eq!(address_frame(0x2000_3000), [0x20, 0x00, 0x30, 0x00, 0x10]);
        assert_eq!(
            parse_address_frame(&[0x08, 0x00, 0x00, 0x00, 0x08]),
            Some(0x0800_0000)
        );
        assert_eq!(parse_address_frame(&[0x08, 0x00, 0x00, 0x00, 0x09]), None);
    }

    #[test]
    fn read_length_golden() {
        assert_eq!(read_length_frame(256), Ok([0xFF, 0x00]));
        assert_eq!(read_length_frame(1), Ok([0x00, 0xFF]));
        assert_eq!(read_length_frame(4), Ok([0x03, 0xFC]));
        assert_eq!(read_length_frame(0), Err(EncodeError::BlockLength(0)));
        assert_eq!(read_length_frame(257), Err(EncodeError::BlockLength(257)));
    }

    #[test]
    fn data_block_golden() {
        let mut out = [0u8; 260];
        let n = encode_data_block(&[0x11, 0x22, 0x33, 0x44], &mut out).unwrap();
        // N-1 = 3; checksum 03^11^22^33^44 = 0x47.
        assert_eq!(&out[..n], &[0x03, 0x11, 0x22, 0x33, 0x44, 0x47]);
        let full = [0xFFu8; 256];
        let n = encode_data_block(&full, &mut out).unwrap();
        assert_eq!(n, 258);
        // 0xFF ^ (256 × 0xFF cancel out) = 0xFF.
        assert_eq!((out[0], out[257]), (0xFF, 0xFF));
        assert_eq!(
            encode_data_block(&[], &mut out),
            Err(EncodeError::BlockLength(0))
        );
        assert_eq!(
            encode_data_block(&[1, 2, 3, 4], &mut out[..5]),
            Err(EncodeError::BufferTooSmall { needed: 6 })
        );
    }

    #[test]
    fn extended_erase_golden() {
        let mut out = [0u8; 64];
        let n = encode_extended_erase(EraseRequest::Mass, &mut out).unwrap();
        assert_eq!(&out[..n], &[0xFF, 0xFF, 0x00]);
        let n = encode_extended_erase(EraseRequest::Bank1, &mut out).unwrap();
        assert_eq!(&out[..n], &[0xFF, 0xFE, 0x01]);
        let n = encode_extended_erase(EraseRequest::Bank2, &mut out).unwrap();
        assert_eq!(&out[..n], &[0xFF, 0xFD, 0x02]);
        // Sectors 0, 1, 2: N-1 = 00 02, pages 00 00 / 00 01 / 00 02, XOR = 01.
        let n = encode_extended_erase(EraseRequest::Pages(&[0, 1, 2]), &mut out).unwrap();
        assert_eq!(
            &out[..n],
            &[0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x00, 0x02, 0x01]
        );
        // One sector, 11: 00 00 00 0B 0B.
        let n = encode_extended_erase(EraseRequest::Pages(&[11]), &mut out).unwrap();
        assert_eq!(&out[..n], &[0x00, 0x00, 0x00, 0x0B, 0x0B]);
        assert_eq!(
            encode_extended_erase(EraseRequest::Pages(&[]), &mut out),
            Err(EncodeError::PageCount(0))
        );
        assert_eq!(
            encode_extended_erase(EraseRequest::Pages(&[0; 40]), &mut out),
            Err(EncodeError::BufferTooSmall { needed: 83 })
        );
        assert_eq!(EraseHeader::decode(0xFFFF), EraseHeader::Mass);
        assert_eq!(EraseHeader::decode(0xFFFE), EraseHeader::Bank1);
        assert_eq!(EraseHeader::decode(0xFFFD), EraseHeader::Bank2);
        assert_eq!(EraseHeader::decode(0xFFF0), EraseHeader::Reserved(0xFFF0));
        assert_eq!(EraseHeader::decode(0xFFEF), EraseHeader::Pages(0xFFF0));
        assert_eq!(EraseHeader::decode(0), EraseHeader::Pages(1));
    }

    #[test]
    fn f405_sector_table() {
        let starts: [u32; 12] = [
            0x0800_0000,
            0x0800_4000,
            0x0800_8000,
            0x0800_C000,
            0x0801_0000,
            0x0802_0000,
            0x0804_0000,
            0x0806_0000,
            0x0808_0000,
            0x080A_0000,
            0x080C_0000,
            0x080E_0000,
        ];
        for (s, start) in F405_SECTORS.iter().zip(starts) {
            assert_eq!(s.start, start, "sector {}", s.index);
        }
        assert_eq!(F405_SECTORS[11].end(), FLASH_BASE + FLASH_SIZE);
        assert_eq!(sector_of(0x0800_0000).map(|s| s.index), Some(0));
        assert_eq!(sector_of(0x0800_3FFF).map(|s| s.index), Some(0));
        assert_eq!(sector_of(0x0800_4000).map(|s| s.index), Some(1));
        assert_eq!(sector_of(0x0801_FFFF).map(|s| s.index), Some(4));
        assert_eq!(sector_of(0x080F_FFFF).map(|s| s.index), Some(11));
        assert_eq!(sector_of(0x0810_0000), None);
        assert_eq!(sector_of(0x07FF_FFFF), None);
    }

    #[test]
    fn sectors_touched_by_images() {
        let idx = |start, len| {
            sectors_touched(start, len).map(|it| {
                it.iter()
                    .map(|s| s.index)
                    .collect::<heapless::Vec<u16, 12>>()
            })
        };
        // 40 KiB at the start: sectors 0..=2.
        assert_eq!(idx(FLASH_BASE, 40 * 1024).unwrap().as_slice(), &[0, 1, 2]);
        // Exactly 16 KiB: sector 0 only.
        assert_eq!(idx(FLASH_BASE, 16 * 1024).unwrap().as_slice(), &[0]);
        assert_eq!(idx(0x0801_FFFC, 8).unwrap().as_slice(), &[4, 5]);
        assert!(idx(FLASH_BASE, 0).unwrap().is_empty());
        assert!(idx(0x080F_FFFF, 2).is_none());
        assert!(idx(0xFFFF_FFFF, 2).is_none());
        assert_eq!(idx(FLASH_BASE, FLASH_SIZE).unwrap().len(), 12);
    }

    #[test]
    fn write_alignment() {
        assert!(is_write_aligned(0x0800_0000, 256));
        assert!(is_write_aligned(0x0800_0004, 4));
        assert!(!is_write_aligned(0x0800_0002, 4));
        assert!(!is_write_aligned(0x0800_0000, 6));
        assert!(!is_write_aligned(0x0800_0000, 0));
        assert!(!is_write_aligned(0x0800_0000, 260));
    }
}
