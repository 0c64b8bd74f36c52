//! Any bytes through the message decoder, the in-place raster-batch walker and the link's
//! frame decoder (COBS + CRC). Beyond "never panics":
//! - a decoded message re-encodes to canonical bytes that decode to the same message,
//!   are never longer than the input, and equal the input when they are as long (postcard
//!   accepts over-long varints, which is the only freedom the wire format has);
//! - the in-place walker (`raster_commands`, what the controller uses) and the full
//!   decoder agree on every raster batch, and the batcher rebuilds the canonical bytes;
//! - a link frame that decodes re-encodes to exactly the input (COBS and the CRC leave no
//!   freedom), and any header + payload survives `encode_frame` → `decode_frame`;
//! - the host's chunk reader (`chunk_view`, any length) and the full decoder agree on
//!   every chunk a `ReadChunk` can hold, and a chunk it reads re-encodes through
//!   `chunk_header` to canonical bytes.
#![no_main]
use std::fmt::Debug;

use libfuzzer_sys::fuzz_target;
use protocol::frame::{
    chunk_header, chunk_view, decode, encode, raster_commands, DeviceFrame, HostFrame,
    RasterBatcher, READ_CHUNK,
};
use protocol::link::{decode_frame, encode_frame, Header, Kind, LinkError, HEADER_LEN, MAX_FRAME};
use protocol::raster::RasterCmd;
use protocol::MAX_PAYLOAD;
use serde::{de::DeserializeOwned, Serialize};

/// Decodes `data` as a `T`; if it decodes, checks the canonical re-encoding and returns it.
fn round_trip<T>(data: &[u8]) -> Option<(T, Vec<u8>)>
where
    T: Serialize + DeserializeOwned + PartialEq + Debug,
{
    let msg = decode::<T>(data).ok()?;
    if data.len() > MAX_PAYLOAD {
        // Beyond what the link can deliver; only "no panic" applies.
        return None;
    }
    let mut buf = [0u8; MAX_PAYLOAD];
    let canon = encode(&msg, &mut buf)
        .unwrap_or_else(|e| panic!("{msg:?} decoded from {data:02x?} does not re-encode: {e}"))
        .to_vec();
    assert!(
        canon.len() <= data.len(),
        "canonical {canon:02x?} longer than input {data:02x?}"
    );
    if canon.len() == data.len() {
        assert_eq!(canon, data, "same length, different bytes for {msg:?}");
    }
    assert_eq!(
        decode::<T>(&canon).as_ref(),
        Ok(&msg),
        "canonical bytes decode differently"
    );
    Some((msg, canon))
}

fn check_payload(data: &[u8]) {
    let host = round_trip::<HostFrame>(data);
    let device = round_trip::<DeviceFrame>(data);

    // The chunk reader and the full decoder agree where both can read.
    match (chunk_view(data), &device) {
        (Some(Ok((offset, bytes))), _) => {
            if bytes.len() <= READ_CHUNK && data.len() <= MAX_PAYLOAD {
                match decode::<DeviceFrame>(data) {
                    Ok(DeviceFrame::Chunk(c)) => {
                        assert_eq!((c.offset, c.data.as_slice()), (offset, bytes));
                    }
                    other => panic!("chunk_view read {offset} {bytes:02x?}, decoder {other:?}"),
                }
            }
            let (head, n) = chunk_header(offset, bytes.len() as u32);
            let canon = [&head[..n], bytes].concat();
            assert!(canon.len() <= data.len(), "canonical chunk longer than {data:02x?}");
            assert_eq!(chunk_view(&canon), Some(Ok((offset, bytes))));
        }
        (Some(Err(_)), Some((DeviceFrame::Chunk(c), _))) => {
            panic!("chunk_view refused {data:02x?}, the decoder read {c:?}")
        }
        (None, Some((DeviceFrame::Chunk(c), _))) => {
            panic!("chunk_view missed {data:02x?}, the decoder read {c:?}")
        }
        _ => {}
    }

    // The walker and the full decoder agree.
    if let Ok(it) = raster_commands(data) {
        let walked: Result<Vec<RasterCmd>, _> = it.collect();
        if let Ok(cmds) = walked {
            match decode::<HostFrame>(data) {
                Ok(HostFrame::Raster(v)) => assert_eq!(v.as_slice(), cmds.as_slice()),
                other => panic!("walker read {cmds:?}, decoder {other:?}"),
            }
        }
    }
    if let Some((HostFrame::Raster(v), canon)) = host {
        if data.len() >= 2 && data[0] == 2 && usize::from(data[1]) == v.len() {
            let walked: Vec<RasterCmd> = raster_commands(data)
                .expect("walker accepts what the decoder accepts")
                .collect::<Result<_, _>>()
                .expect("walker decodes every command the decoder does");
            assert_eq!(v.as_slice(), walked.as_slice());
        }
        // The batcher packs the same commands into the canonical bytes, in one batch.
        if !v.is_empty() {
            let mut b = RasterBatcher::new();
            for c in &v {
                assert_eq!(b.push(c).map(|o| o.is_some()), Ok(false), "{v:?} split");
            }
            let batch = b.finish().expect("a pending batch");
            assert_eq!(batch.as_bytes(), canon.as_slice());
        }
    }
}

fuzz_target!(|data: &[u8]| {
    check_payload(data);

    // The bytes as a wire frame.
    let mut buf = data.to_vec();
    if let Ok((header, payload)) = decode_frame(&mut buf) {
        let payload = payload.to_vec();
        let mut out = [0u8; MAX_FRAME];
        let n = encode_frame(&header, &payload, &mut out).expect("a decoded frame re-encodes");
        let mut want = data.to_vec();
        if want.last() != Some(&0) {
            want.push(0);
        }
        assert_eq!(
            &out[..n],
            want.as_slice(),
            "frame encoding is not canonical"
        );
        check_payload(&payload);
    }

    // The bytes as header + payload, framed and unframed.
    if data.len() >= HEADER_LEN {
        let mut h = [0u8; HEADER_LEN];
        h.copy_from_slice(&data[..HEADER_LEN]);
        if let Some(header) = Header::from_bytes(&h) {
            assert_eq!(header.to_bytes(), h);
            let payload = &data[HEADER_LEN..];
            let mut out = [0u8; MAX_FRAME];
            match encode_frame(&header, payload, &mut out) {
                Ok(n) => {
                    assert_eq!(out[n - 1], 0);
                    assert!(!out[..n - 1].contains(&0), "delimiter inside a frame");
                    let got = decode_frame(&mut out[..n]);
                    if payload.is_empty() || header.kind == Kind::Data {
                        let (h2, p2) = got.expect("an encoded frame decodes");
                        assert_eq!(h2, header);
                        assert_eq!(p2, payload);
                    } else {
                        assert_eq!(got.err(), Some(LinkError::Framing));
                    }
                }
                Err(e) => {
                    assert_eq!(e, LinkError::TooLarge { len: payload.len(), max: MAX_PAYLOAD });
                    assert!(payload.len() > MAX_PAYLOAD);
                }
            }
        }
    }
});
