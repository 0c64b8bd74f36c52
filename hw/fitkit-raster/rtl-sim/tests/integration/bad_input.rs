//! Bad packets: each is refused whole (the frame stays the model's, which never saw it)
//! and latches the block's sticky error with its code, address and packet index.

use protocol::fitkit_spi::ADDR_CLEAR;
use protocol::fitkit_spi::{self as wire, BlockError, ErrorCode};
use protocol::raster::{Cull, Rgb};

use crate::cases;
use crate::harness::{self, Pair};

/// A block with its set-up (packet 0) and one good line (packet 1) done.
fn primed() -> Pair {
    let mut pair = Pair::new(harness::setup(16, 16, Rgb::new(0, 0, 0), Cull::None));
    pair.step(
        "prime",
        &cases::line((0, 0), (15, 9), Rgb::new(255, 255, 255)),
        false,
    );
    pair
}

/// Sends `bytes` raw and checks the error the block latched.
fn refused(bytes: &[u8], code: ErrorCode, channel: u8) {
    let mut pair = primed();
    pair.wait_fifo_free();
    pair.write_raw(bytes);
    let s = pair.finish();
    assert_eq!(
        s.error,
        Some(BlockError {
            code,
            channel,
            packet: 2
        }),
        "{bytes:02x?}: {s:?}"
    );
    assert_eq!(s.flags & wire::FLAG_ERROR, wire::FLAG_ERROR);
    pair.assert_frames_equal(&format!("after the refused {bytes:02x?}"));
}

/// A good line packet's bytes, address first.
fn line_bytes() -> Vec<u8> {
    let cmd = cases::line((3, 3), (12, 5), Rgb::new(255, 0, 0));
    let records =
        protocol::bus::pack(&protocol::bus::FITKIT, &cmd, Default::default()).expect("packs");
    let mut buf = [0u8; 1 + wire::MAX_PACKET_BYTES];
    let n = wire::packet(wire::ADDR_LINE, &records, &mut buf).expect("frames");
    buf[..n].to_vec()
}

#[test]
fn short_and_long_packets_are_length_errors() {
    let good = line_bytes();
    refused(&good[..good.len() - 1], ErrorCode::Length, wire::ADDR_LINE);
    let mut long = good.clone();
    long.push(0);
    refused(&long, ErrorCode::Length, wire::ADDR_LINE);
}

#[test]
fn non_zero_padding_is_refused() {
    // A line's 45 bits in 72: the last byte's low bits are padding.
    let mut bad = line_bytes();
    *bad.last_mut().expect("payload") |= 1;
    refused(&bad, ErrorCode::Padding, wire::ADDR_LINE);
}

#[test]
fn a_clear_without_cb_is_refused() {
    // CB col in one record: CB is the record's top bit.
    let record = u64::from(0xE3u8) << 27;
    let mut buf = [0u8; 1 + wire::MAX_PACKET_BYTES];
    let n = wire::packet(ADDR_CLEAR, &[record], &mut buf).expect("frames");
    refused(&buf[..n], ErrorCode::ClearWithoutCb, ADDR_CLEAR);
}

#[test]
fn an_unknown_address_is_refused() {
    let mut bad = line_bytes();
    bad[0] = 0x05;
    refused(&bad, ErrorCode::UnknownAddress, 0x05);
}

#[test]
fn ignoring_fifo_free_overruns() {
    let mut pair = Pair::new(harness::setup(512, 512, Rgb::new(0, 0, 0), Cull::None));
    // Keep the triangle unit busy so the FIFO only fills.
    pair.send(
        &cases::triangle([(0, 0), (511, 0), (0, 511)], Rgb::new(0, 0, 255)),
        false,
    );
    let line = line_bytes();
    // 256 two-record packets fill 512 records; the next has no room.
    for _ in 0..=256 {
        pair.write_raw(&line);
    }
    let s = pair.status();
    let e = s.error.expect("overrun latched");
    assert_eq!(
        (e.code, e.channel),
        (ErrorCode::Overrun, wire::ADDR_LINE),
        "{s:?}"
    );
    // Packets 0 and 1 are the set-up and the triangle, whose records left the FIFO when
    // the unit started it; 256 lines fit the 512 records, the 257th is the first refused.
    assert_eq!(e.packet, 2 + 256, "{s:?}");
}
