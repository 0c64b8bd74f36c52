//! The MSP430 BSL frames (protocol::msp430_bsl) under arbitrary input: encode and decode
//! are inverses, and the checksum catches what an XOR of words can catch.

use proptest::prelude::*;
use protocol::msp430_bsl::*;

fn request() -> impl Strategy<Value = (u8, u16, u16, Vec<u8>)> {
    (
        any::<u8>(),
        any::<u16>(),
        any::<u16>(),
        (0..=MAX_DATA / 2).prop_flat_map(|w| proptest::collection::vec(any::<u8>(), 2 * w)),
    )
}

proptest! {
    #[test]
    fn requests_round_trip((cmd, address, length, data) in request()) {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_request(cmd, address, length, &data, &mut out).unwrap();
        prop_assert_eq!(n, 10 + data.len());
        let head = [out[0], out[1], out[2], out[3]];
        prop_assert_eq!(frame_len(head, 4), Ok(n));
        let r = decode_request(&out[..n]).unwrap();
        prop_assert_eq!(r, Request { command: cmd, address, length, data: &data });
    }

    #[test]
    fn data_frames_round_trip(
        data in (0..=MAX_L / 2).prop_flat_map(|w| proptest::collection::vec(any::<u8>(), 2 * w))
    ) {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_data_frame(&data, &mut out).unwrap();
        prop_assert_eq!(decode_data_frame(&out[..n]), Ok(&data[..]));
    }

    /// Any single corrupted byte (any non-zero XOR pattern at any position) is
    /// refused: a byte changes exactly one half of one checksum word, and header or
    /// length damage is caught before the checksum is even looked at.
    #[test]
    fn one_corrupted_byte_is_always_detected(
        (cmd, address, length, data) in request(),
        at in any::<prop::sample::Index>(),
        flip in 1u8..,
    ) {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_request(cmd, address, length, &data, &mut out).unwrap();
        let i = at.index(n);
        out[i] ^= flip;
        prop_assert!(decode_request(&out[..n]).is_err(), "byte {} ^ {:#04x}", i, flip);
    }

    /// Two corrupted bytes in the same word half pass only if the flips cancel;
    /// different halves or words never cancel to nothing, so only the same-column
    /// case can slip through, which the XOR checksum cannot see by construction.
    #[test]
    fn two_corrupted_bytes_in_different_columns_are_detected(
        data in (2..=MAX_DATA / 2).prop_flat_map(|w| proptest::collection::vec(any::<u8>(), 2 * w)),
        a in any::<prop::sample::Index>(),
        fa in 1u8..,
        fb in 1u8..,
    ) {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_request(0x12, 0x4000, data.len() as u16, &data, &mut out).unwrap();
        // Two data bytes, one at an even and one at an odd offset.
        let i = HEADER_LEN + 2 * a.index(data.len() / 2);
        let j = HEADER_LEN + 2 * ((a.index(data.len() / 2) + 1) % (data.len() / 2)) + 1;
        out[i] ^= fa;
        out[j] ^= fb;
        let caught = matches!(decode_request(&out[..n]), Err(DecodeError::Checksum { .. }));
prop_assert!(caught);
    }
}
