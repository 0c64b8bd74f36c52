//! The FITkit SPI transactions: golden bytes for the documented example, the set-up record's
//! fields, and the status block's encode/decode as inverses that refuse what the block
//! never sends.

use proptest::prelude::*;
use protocol::fitkit_spi::{
    packet, read_header, BlockError, ErrorCode, Setup, SpiFrameError, Status, ADDR_LINE, FLAGS_ALL,
    FLAG_ERROR, FLAG_FIFO_EMPTY, STATUS_BYTES,
};
use protocol::raster::Cull;

/// docs/protocol.md's example: CB = 1, line (1, 2) → (300, 400), colour 0xA9 is records
/// `0x8_0405_2CC8, 0x5_4800_0000` (pinned in `bus.rs`); on SPI that is the address and
/// the 72 record bits.
#[test]
fn the_documented_line_is_nine_payload_bytes() {
    let records = [0x8_0405_2CC8u64, 0x5_4800_0000];
    let mut out = [0u8; 16];
    let n = packet(ADDR_LINE, &records, &mut out).unwrap();
    assert_eq!(
        &out[..n],
        &[0x01, 0x80, 0x40, 0x52, 0xCC, 0x85, 0x48, 0x00, 0x00, 0x00]
    );
}

#[test]
fn one_record_is_five_payload_bytes_and_wide_records_are_refused() {
    let mut out = [0u8; 8];
    assert_eq!(packet(0x03, &[0xF_FFFF_FFFF], &mut out), Ok(6));
    assert_eq!(&out[..6], &[0x03, 0xFF, 0xFF, 0xFF, 0xFF, 0xF0]);
    assert_eq!(
        packet(0x03, &[1 << 36], &mut out),
        Err(SpiFrameError::RecordTooWide {
            index: 0,
            value: 1 << 36
        })
    );
    assert_eq!(
        packet(0x03, &[], &mut out),
        Err(SpiFrameError::PacketLength { records: 0 })
    );
    assert_eq!(
        packet(0x01, &[0, 0], &mut out),
        Err(SpiFrameError::BufferTooSmall {
            needed: 10,
            capacity: 8
        })
    );
}

#[test]
fn setup_record_fields() {
    let s = Setup {
        width: 512,
        height: 1,
        background: 0xA5,
        cull: Cull::CounterClockwise,
    };
    let r = s.record().unwrap();
    assert_eq!(r >> 27, 511);
    assert_eq!(r >> 18 & 0x1FF, 0);
    assert_eq!(r >> 10 & 0xFF, 0xA5);
    assert_eq!(r >> 8 & 3, 2);
    assert_eq!(r & 0xFF, 0);
    assert!(r >> 36 == 0);
    let bad = Setup { width: 0, ..s };
    assert!(matches!(
        bad.record(),
        Err(SpiFrameError::SetupRange { field: "width", .. })
    ));
    let bad = Setup { height: 513, ..s };
    assert!(matches!(
        bad.record(),
        Err(SpiFrameError::SetupRange {
            field: "height",
            ..
        })
    ));
}

#[test]
fn read_header_addresses_a_pixel() {
    assert_eq!(read_header(3, 2).unwrap(), [0x30, 0x00, 0x04, 0x03, 0x00]);
    assert_eq!(
        read_header(511, 511).unwrap(),
        [0x30, 0x03, 0xFF, 0xFF, 0x00]
    );
    assert_eq!(
        read_header(512, 0),
        Err(SpiFrameError::Pixel { x: 512, y: 0 })
    );
}

fn arb_status() -> impl Strategy<Value = Status> {
    (
        0u16..=512,
        any::<u8>(),
        proptest::option::of((1u8..=6, any::<u8>(), any::<u16>())),
        proptest::array::uniform6(any::<u32>()),
        any::<u8>(),
    )
        .prop_map(|(free, flags, err, c, max)| Status {
            free,
            flags: flags & FLAGS_ALL & !FLAG_ERROR,
            error: err.map(|(code, channel, packet)| BlockError {
                code: ErrorCode::from_code(code).unwrap(),
                channel,
                packet,
            }),
            packets: c[0],
            fragments: c[1],
            line_cycles: c[2],
            triangle_cycles: c[3],
            clear_cycles: c[4],
            end_cycle: c[5],
            fifo_max_pairs: max,
        })
}

proptest! {
    #[test]
    fn status_decode_inverts_encode(s in arb_status()) {
        let mut want = s;
        if s.error.is_some() {
            want.flags |= protocol::fitkit_spi::FLAG_ERROR;
        }
        prop_assert_eq!(Status::decode(&s.encode()), Ok(want));
    }
}

#[test]
fn status_from_a_floating_miso_is_refused() {
    let ones = [0xFFu8; STATUS_BYTES];
    assert!(matches!(
        Status::decode(&ones),
        Err(SpiFrameError::Status { byte: 0, .. })
    ));
    let mut b = [0u8; STATUS_BYTES];
    b[3] = 2; // an error code with the error flag clear
    assert!(matches!(
        Status::decode(&b),
        Err(SpiFrameError::Status { byte: 3, .. })
    ));
    b[2] = protocol::fitkit_spi::FLAG_ERROR;
    b[3] = 9;
    assert!(matches!(
        Status::decode(&b),
        Err(SpiFrameError::Status { byte: 3, .. })
    ));
    let zeros = [0u8; STATUS_BYTES];
    assert_eq!(Status::decode(&zeros).map(|s| s.idle()), Ok(true));
}

/// The units a build lacks are flags 4 and 5; bits 6 and 7 stay reserved, so a status
/// with them set is still refused as not the block's.
#[test]
fn status_names_the_units_a_build_lacks() {
    use protocol::fitkit_spi::{FLAG_NO_LINE, FLAG_NO_TRIANGLE};
    let mut b = [0u8; STATUS_BYTES];
    let full = Status::decode(&b).expect("the full block's idle status");
    assert!(full.has_line_unit() && full.has_triangle_unit());
    b[2] = FLAG_NO_TRIANGLE | FLAG_FIFO_EMPTY;
    let lines = Status::decode(&b).expect("a line-only block's status");
    assert!(lines.has_line_unit() && !lines.has_triangle_unit());
    b[2] = FLAG_NO_LINE;
    let tris = Status::decode(&b).expect("a triangle-only block's status");
    assert!(!tris.has_line_unit() && tris.has_triangle_unit());
    for reserved in [1u8 << 6, 1 << 7] {
        b[2] = reserved;
        assert!(
            matches!(
                Status::decode(&b),
                Err(SpiFrameError::Status { byte: 2, .. })
            ),
            "flag {reserved:#04x} is reserved"
        );
    }
}

/// The committed Verilog header, which every RTL module and testbench of the FITkit block
/// includes, is exactly what `write_verilog_header` writes from the Rust map: a number
/// changed on one side only fails here. `FPGFX_BLESS=1` rewrites the file instead.
#[test]
fn fitkit_map_header_matches_the_rust_map() {
    let mut text = String::new();
    protocol::fitkit_spi::write_verilog_header(&mut text).expect("writes to a String");
    super::generated::matches_committed(
        "../hw/fitkit-raster/rtl/fitkit_map.vh",
        &text,
        "protocol::fitkit_spi::MAP",
    );
}

/// Every error code has its macro, every address and status offset is there once, and
/// the sized literals carry the right width.
#[test]
fn fitkit_map_header_names_every_fact_once() {
    let mut text = String::new();
    protocol::fitkit_spi::write_verilog_header(&mut text).expect("writes to a String");
    for e in protocol::fitkit_spi::ErrorCode::ALL {
        let want = format!("`define FITKIT_ERR_{} 3'd{}\n", e.verilog_name(), e.code());
        assert!(text.contains(&want), "missing {want:?}");
    }
    assert!(text.contains("`define FITKIT_ADDR_STATUS 8'h20\n"));
    assert!(text.contains("`define FITKIT_ADDR_RESET 8'h7F\n"));
    assert!(text.contains("`define FITKIT_STATUS_END_CYCLE 27\n"));
    assert!(text.contains("`define FITKIT_RECORD_BITS 36\n"));
    let mut names: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("`define "))
        .map(|l| l.split(' ').next().unwrap_or(l))
        .collect();
    let n = names.len();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), n, "a macro is defined twice");
    assert_eq!(n, protocol::fitkit_spi::MAP.len() + 6 + 1);
}
