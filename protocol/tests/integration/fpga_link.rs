//! The FPGA link's messages: the worst case of each fits a link frame, a golden byte
//! vector pins the encoding, layouts map to ids and back, and no input bytes make the
//! decoder panic.

use heapless::Vec;
use proptest::prelude::*;
use protocol::bus::LayoutId;
use protocol::bus::{EXTENDED, FITKIT, WIDE};
use protocol::fpga_link::{
    Fault, FaultCode, FpgaReply, FpgaRequest, FpgaStatus, Identity, FPGA_SCHEMA_HASH, PUSH_RECORDS,
};
use protocol::frame::{
    decode, encode, Caps, DeviceCounters, FrameDone, PixelFormat, Plane, ReadRequest, Rect,
    READ_CHUNK, REG_WRITE_WORDS, TEXTURE_CHUNK,
};
use protocol::MAX_PAYLOAD;

#[test]
fn worst_cases_fit_a_link_frame() {
    let texels = [0xffu8; TEXTURE_CHUNK];
    let req = ReadRequest {
        plane: Plane::Normal,
        rect: Rect {
            x: u16::MAX,
            y: u16::MAX,
            w: u16::MAX,
            h: u16::MAX,
        },
        format: PixelFormat::NormalF32,
    };
    let requests = [
        FpgaRequest::Push {
            channel: u8::MAX,
            last: true,
            records: Vec::from_slice(&[u64::MAX; PUSH_RECORDS]).expect("cap"),
        },
        FpgaRequest::Regs {
            offset: u16::MAX,
            words: Vec::from_slice(&[u32::MAX; REG_WRITE_WORDS]).expect("cap"),
        },
        FpgaRequest::Texels {
            offset: u32::MAX,
            bytes: &texels,
        },
        FpgaRequest::Read {
            req,
            offset: u32::MAX,
            len: u16::MAX,
        },
    ];
    let mut buf = [0u8; MAX_PAYLOAD];
    for r in &requests {
        let bytes = encode(r, &mut buf).unwrap_or_else(|e| panic!("{r:?}: {e:?}"));
        assert_eq!(&decode::<FpgaRequest<'_>>(bytes).expect("round trip"), r);
    }
    let replies = [
        FpgaReply::Data(Vec::from_slice(&[0xff; READ_CHUNK]).expect("cap")),
        FpgaReply::Counters(DeviceCounters {
            commands: u32::MAX,
            bus_words: u32::MAX,
            fragments: u64::MAX,
            cycles: u64::MAX,
            fifo_stalls: u64::MAX,
            frames: u32::MAX,
            queue_free: u16::MAX,
            saturations: u64::MAX,
        }),
        FpgaReply::Status(FpgaStatus {
            fifo_free: u16::MAX,
            idle: true,
            done: Some(FrameDone {
                frame_id: u32::MAX,
                cycles: u64::MAX,
                work: u64::MAX,
            }),
        }),
        FpgaReply::Identity(Identity {
            schema_hash: u64::MAX,
            caps: Caps {
                texture_words: u32::MAX,
                fifo_depth: u16::MAX,
                ..Default::default()
            },
            layout: LayoutId::Wide,
        }),
        FpgaReply::Fault(Fault {
            request: u32::MAX,
            code: FaultCode::Malformed,
        }),
    ];
    for r in &replies {
        let bytes = encode(r, &mut buf).unwrap_or_else(|e| panic!("{r:?}: {e:?}"));
        assert_eq!(&decode::<FpgaReply>(bytes).expect("round trip"), r);
    }
}

/// The bytes of a push: variant index 3, channel, `last`, record count, varint records.
#[test]
fn push_golden_bytes() {
    let mut buf = [0u8; MAX_PAYLOAD];
    let push = FpgaRequest::Push {
        channel: 0x02,
        last: true,
        records: Vec::from_slice(&[1, 300]).expect("cap"),
    };
    assert_eq!(
        encode(&push, &mut buf).expect("fits"),
        &[3, 0x02, 1, 2, 1, 0xac, 0x02]
    );
    assert_eq!(encode(&FpgaRequest::Status, &mut buf).expect("fits"), &[2]);
}

#[test]
fn layouts_have_ids() {
    for layout in [&FITKIT, &EXTENDED, &WIDE] {
        let id = LayoutId::of(layout).expect("our layouts have ids");
        assert_eq!(id.layout().name, layout.name);
    }
    println!("FPGA schema hash {FPGA_SCHEMA_HASH:#018x}");
}

proptest! {
    #[test]
    fn any_bytes_decode_or_fail_cleanly(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _ = decode::<FpgaRequest<'_>>(&bytes);
        let _ = decode::<FpgaReply>(&bytes);
    }
}
