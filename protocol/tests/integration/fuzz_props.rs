//! Fuzz-style properties that run in CI (cargo-fuzz needs a nightly; these do not): bytes
//! from the wire, random or damaged versions of valid frames, reach the frame decoder,
//! the message decoder, the raster-batch walker and the link receiver, which must give a
//! value or an error and never panic — and must never deliver damaged data as good.
//! The `frame` and `link` modules already feed *random* bytes to `decode` and
//! `Link::handle_input`; these start from *valid* frames and damage them, which reaches
//! the deeper states (a correct COBS structure, a matching CRC, a known variant) that
//! random bytes almost never reach.

use proptest::prelude::*;
use protocol::frame::{decode, raster_commands, HostFrame, RasterBatcher, Request};
use protocol::link::{decode_frame, encode_frame, Config, Event, Header, Kind, Link, MAX_FRAME};
use protocol::raster::{RasterCmd, Rgb};
use protocol::MAX_PAYLOAD;

/// Cases per property: 4 properties × 4000 = 16 000 inputs per `cargo test` run.
const CASES: u32 = 4000;

fn data_header(seq: u16) -> Header {
    Header {
        kind: Kind::Data,
        epoch: 0,
        seq,
        ack: 0,
        credit: 8,
    }
}

/// One damage: flip a bit, overwrite, insert or delete a byte, or cut the tail.
#[derive(Debug, Clone)]
enum Damage {
    Flip(usize, u8),
    Set(usize, u8),
    Insert(usize, u8),
    Delete(usize),
    Cut(usize),
}

fn damage() -> impl Strategy<Value = Damage> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(i, b)| Damage::Flip(i, b)),
        (any::<usize>(), any::<u8>()).prop_map(|(i, v)| Damage::Set(i, v)),
        (any::<usize>(), any::<u8>()).prop_map(|(i, v)| Damage::Insert(i, v)),
        any::<usize>().prop_map(Damage::Delete),
        any::<usize>().prop_map(Damage::Cut),
    ]
}

fn apply(bytes: &mut Vec<u8>, d: &[Damage]) {
    for d in d {
        let n = bytes.len().max(1);
        match *d {
            Damage::Flip(i, b) => {
                if let Some(x) = bytes.get_mut(i % n) {
                    *x ^= 1 << b;
                }
            }
            Damage::Set(i, v) => {
                if let Some(x) = bytes.get_mut(i % n) {
                    *x = v;
                }
            }
            Damage::Insert(i, v) => bytes.insert(i % (bytes.len() + 1), v),
            Damage::Delete(i) => {
                if !bytes.is_empty() {
                    bytes.remove(i % n);
                }
            }
            Damage::Cut(i) => bytes.truncate(i % n),
        }
    }
}

fn raster_cmd() -> impl Strategy<Value = RasterCmd> {
    use protocol::raster::{Circle, Line, LineAlgo, Point, Shade, Triangle};
    let p = || (any::<i32>(), any::<i32>()).prop_map(|(x, y)| Point { x, y });
    prop_oneof![
        (any::<u8>(), any::<u8>(), any::<u8>())
            .prop_map(|(r, g, b)| RasterCmd::Clear(Rgb::new(r, g, b))),
        (p(), p(), any::<u32>(), any::<bool>()).prop_map(|(from, to, width, aa)| RasterCmd::Line(
            Line {
                from,
                to,
                color: Rgb::new(1, 2, 3),
                color_to: None,
                width,
                aa,
                algo: LineAlgo::Dda,
            }
        )),
        (p(), p(), p()).prop_map(|(a, b, c)| RasterCmd::Triangle(Triangle {
            v: [a, b, c],
            shade: Shade::Flat(Rgb::new(9, 8, 7)),
            z: Some([1, 2, 3]),
            w: None,
            tex: None,
        })),
        (p(), any::<u32>(), any::<bool>()).prop_map(|(center, radius, fill)| RasterCmd::Circle(
            Circle {
                center,
                radius,
                color: Rgb::new(0, 0, 0),
                fill,
            }
        )),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: CASES, ..ProptestConfig::default() })]

    /// A damaged frame decodes to an error or (if the damage missed it, e.g. a cut
    /// after the delimiter) to exactly the frame that was sent; any single bit flip
    /// inside the frame is always caught (CRC-32 detects every 1-bit error, and a COBS
    /// code byte hit breaks the structure or the CRC).
    #[test]
    fn damaged_frames_never_decode_to_other_data(
        seq: u16,
        payload in proptest::collection::vec(any::<u8>(), 0..=MAX_PAYLOAD),
        dmg in proptest::collection::vec(damage(), 1..4),
    ) {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_frame(&data_header(seq), &payload, &mut out).expect("encodes");
        let mut bytes = out[..n].to_vec();
        let single_flip = matches!(dmg.as_slice(), [Damage::Flip(i, _)] if i % n < n - 1);
        apply(&mut bytes, &dmg);
        if let Ok((h, p)) = decode_frame(&mut bytes) {
            prop_assert!(!single_flip, "a single bit flip went undetected");
            prop_assert_eq!(h, data_header(seq));
            prop_assert_eq!(p, &payload[..]);
        }
    }

    /// A damaged message payload (a valid `HostFrame::Raster` batch, then damaged) gives
    /// a message or an error; the in-place batch walker gives at most the announced
    /// number of commands plus one error, never a panic or an endless iteration. A
    /// controller's [`Request`] accepts exactly the payloads a `HostFrame` does, and its
    /// checked batch walks to the same commands.
    #[test]
    fn damaged_batches_decode_or_fail(
        cmds in proptest::collection::vec(raster_cmd(), 1..8),
        dmg in proptest::collection::vec(damage(), 0..4),
    ) {
        let mut b = RasterBatcher::new();
        let mut batches = Vec::new();
        for c in &cmds {
            batches.extend(b.push(c).expect("fits"));
        }
        batches.extend(b.finish());
        for batch in batches {
            let mut bytes = batch.as_bytes().to_vec();
            apply(&mut bytes, &dmg);
            let frame = decode::<HostFrame>(&bytes);
            let request = decode::<Request>(&bytes);
            prop_assert_eq!(frame.is_ok(), request.is_ok(), "HostFrame {:?}, Request {:?}", frame, request);
            if let (Ok(HostFrame::Raster(cmds)), Ok(Request::Raster(checked))) = (&frame, &request) {
                prop_assert_eq!(usize::from(checked.count), cmds.len());
                let walked: Result<Vec<RasterCmd>, _> = raster_commands(&bytes).expect("a batch").collect();
                prop_assert_eq!(walked.expect("checked"), cmds.to_vec());
            }
            if let Ok(it) = raster_commands(&bytes) {
                let mut n = 0;
                for c in it {
                    n += 1;
                    prop_assert!(n <= protocol::frame::RASTER_BATCH + 1);
                    if c.is_err() {
                        break;
                    }
                }
            }
        }
    }

    /// Any bytes given straight to the frame decoder (which the link calls once per
    /// delimiter) give a header and payload or an error.
    #[test]
    fn decode_frame_is_total(bytes in proptest::collection::vec(any::<u8>(), 0..(2 * MAX_FRAME))) {
        let mut b = bytes.clone();
        if let Ok((h, p)) = decode_frame(&mut b) {
            prop_assert!(p.len() <= MAX_PAYLOAD);
            prop_assert!(p.is_empty() || h.kind == Kind::Data);
        }
    }

    /// A stream of valid data frames, damaged in flight, reaches a receiving link: it
    /// never panics, and what it delivers is exactly a prefix of what was sent, in order
    /// (a damaged frame is dropped, never delivered altered).
    #[test]
    fn link_delivers_only_what_was_sent(
        payloads in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 1..64), 1..6),
        dmg in proptest::collection::vec(damage(), 0..6),
        chunk in 1usize..300,
    ) {
        let mut wire = Vec::new();
        for (k, p) in payloads.iter().enumerate() {
            let mut out = [0u8; MAX_FRAME];
            let n = encode_frame(&data_header(k as u16), p, &mut out).expect("encodes");
            wire.extend_from_slice(&out[..n]);
        }
        let clean = dmg.is_empty();
        apply(&mut wire, &dmg);
        let mut link: Link = Link::new(Config::default());
        let mut got: Vec<Vec<u8>> = Vec::new();
        for part in wire.chunks(chunk) {
            let mut rest = part;
            let mut spins = 0;
            while !rest.is_empty() {
                let (n, ev) = link.handle_input(0, rest);
                if let Some(Event::Data(d)) = ev {
                    got.push(d.to_vec());
                }
                rest = &rest[n..];
                spins += 1;
                prop_assert!(spins < 10_000, "handle_input makes no progress");
            }
        }
        prop_assert!(got.len() <= payloads.len());
        prop_assert_eq!(&got[..], &payloads[..got.len()]);
        if clean {
            prop_assert_eq!(got.len(), payloads.len(), "an undamaged stream is delivered whole");
        }
    }
}

/// A batch of one command more than [`protocol::frame::RASTER_BATCH`] is refused by a
/// controller's [`Request`] as by a `HostFrame` (whose vector cannot hold it), and a
/// full batch is accepted by both.
#[test]
fn request_refuses_the_batches_host_frame_refuses() {
    let cmd = RasterCmd::Clear(Rgb::new(1, 2, 3));
    let mut one = [0u8; 16];
    let cmd_bytes = postcard::to_slice(&cmd, &mut one)
        .expect("encodes")
        .to_vec();
    for n in [
        protocol::frame::RASTER_BATCH,
        protocol::frame::RASTER_BATCH + 1,
    ] {
        // HostFrame::Raster's variant index, the count, the commands.
        let mut bytes = vec![2u8, n as u8];
        for _ in 0..n {
            bytes.extend_from_slice(&cmd_bytes);
        }
        let full = n == protocol::frame::RASTER_BATCH;
        assert_eq!(decode::<HostFrame>(&bytes).is_ok(), full, "{n} commands");
        match decode::<Request>(&bytes) {
            Ok(Request::Raster(checked)) => {
                assert!(full, "{n} commands accepted");
                assert_eq!(usize::from(checked.count), n);
            }
            Ok(other) => panic!("decoded as {other:?}"),
            Err(_) => assert!(!full, "{n} commands refused"),
        }
    }
}
