//! The link's CRC-32 on a host (`crc32fast`) against the table-driven and bit-by-bit CRCs
//! the MCUs compute: one value per byte string, however the bytes arrive.

use crc::{Crc, NoTable, Table, CRC_32_ISO_HDLC};
use proptest::prelude::*;
use protocol::link::CRC32;

static BYTEWISE: Crc<u32, Table<1>> = Crc::<u32, Table<1>>::new(&CRC_32_ISO_HDLC);
static BITWISE: Crc<u32, NoTable> = Crc::<u32, NoTable>::new(&CRC_32_ISO_HDLC);

#[test]
fn the_check_value_of_crc_32_iso_hdlc() {
    assert_eq!(CRC32.checksum(b"123456789"), 0xCBF4_3926);
    assert_eq!(CRC32.checksum(b""), 0);
}

#[test]
fn long_inputs_agree_across_the_fast_paths_block_sizes() {
    // Past the carry-less multiply's 64- and 128-byte blocks, with every tail length.
    let bytes: Vec<u8> = (0..5000u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    for len in (0..300).chain([1023, 1024, 1025, 4096, 5000]) {
        let b = &bytes[..len];
        assert_eq!(CRC32.checksum(b), BYTEWISE.checksum(b), "{len} bytes");
    }
}

proptest! {
    #[test]
    fn host_crc_is_the_mcus_crc_in_any_pieces(
        bytes in proptest::collection::vec(any::<u8>(), 0..2048),
        cuts in proptest::collection::vec(any::<prop::sample::Index>(), 0..6),
    ) {
        let want = BYTEWISE.checksum(&bytes);
        prop_assert_eq!(BITWISE.checksum(&bytes), want);
        prop_assert_eq!(CRC32.checksum(&bytes), want);
        let mut at: Vec<usize> = cuts.iter().map(|c| c.index(bytes.len() + 1)).collect();
        at.sort_unstable();
        let mut d = CRC32.digest();
        let mut from = 0;
        for &to in at.iter().chain([bytes.len()].iter()) {
            d.update(&bytes[from..to]);
            from = to;
        }
        prop_assert_eq!(d.finalize(), want);
    }
}
