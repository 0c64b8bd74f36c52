//! The link layer: golden frames, round-trip and robustness properties, and whole-link
//! simulations over a lossy channel with a simulated clock (no real time is involved).

use std::collections::VecDeque;

use proptest::prelude::*;
use protocol::link::{
    decode_frame, encode_frame, encoded_len, Bulk, Capacity, Config, Event, Header, Kind, Link,
    LinkError, Small, BULK_PAYLOAD, CRC_LEN, HEADER_LEN, MAX_FRAME,
};
use protocol::MAX_PAYLOAD;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

// ---------------------------------------------------------------------------------------
// Golden vectors. CRC-32/ISO-HDLC and COBS computed by hand (independently of the crate):
// the raw frame is header ‖ payload ‖ crc LE, then every zero is replaced by the distance
// to the next zero (or to the end), prefixed by the distance to the first one.
// ---------------------------------------------------------------------------------------

fn h(kind: Kind, epoch: u8, seq: u16, ack: u16, credit: u8) -> Header {
    Header {
        kind,
        epoch,
        seq,
        ack,
        credit,
    }
}

#[allow(clippy::type_complexity)]
fn golden() -> Vec<(Header, &'static [u8], &'static [u8])> {
    vec![
        // raw 01 01 00 00 00 08 | 01 00 02 | crc 0x17a02387
        (
            h(Kind::Data, 0, 1, 0, 8),
            &[0x01, 0x00, 0x02],
            &[
                0x03, 0x01, 0x01, 0x01, 0x01, 0x03, 0x08, 0x01, 0x06, 0x02, 0x87, 0x23, 0xa0, 0x17,
                0x00,
            ],
        ),
        // raw 12 05 00 34 12 04 | crc 0x6bc774c5 (SACK bitmap 0b101, epoch 1)
        (
            h(Kind::Ack, 1, 0x0005, 0x1234, 4),
            &[],
            &[
                0x03, 0x12, 0x05, 0x08, 0x34, 0x12, 0x04, 0xc5, 0x74, 0xc7, 0x6b, 0x00,
            ],
        ),
        // raw 03 07 00 07 00 08 | crc 0x8ee291aa
        (
            h(Kind::Nak, 0, 7, 7, 8),
            &[],
            &[
                0x03, 0x03, 0x07, 0x02, 0x07, 0x06, 0x08, 0xaa, 0x91, 0xe2, 0x8e, 0x00,
            ],
        ),
        // raw 24 ff ff 00 01 00 | crc 0x208516bf (zero credit, epoch 2)
        (
            h(Kind::Probe, 2, 0xffff, 0x0100, 0),
            &[],
            &[
                0x04, 0x24, 0xff, 0xff, 0x02, 0x01, 0x05, 0xbf, 0x16, 0x85, 0x20, 0x00,
            ],
        ),
        // raw 35 ef be 00 00 08 | crc 0xbc87d628 (nonce 0xbeef, epoch 3)
        (
            h(Kind::Reset, 3, 0xbeef, 0, 8),
            &[],
            &[
                0x04, 0x35, 0xef, 0xbe, 0x01, 0x06, 0x08, 0x28, 0xd6, 0x87, 0xbc, 0x00,
            ],
        ),
        // raw 36 ef be 00 00 02 | crc 0xdac64d98
        (
            h(Kind::ResetAck, 3, 0xbeef, 0, 2),
            &[],
            &[
                0x04, 0x36, 0xef, 0xbe, 0x01, 0x06, 0x02, 0x98, 0x4d, 0xc6, 0xda, 0x00,
            ],
        ),
    ]
}

#[test]
fn golden_frames_encode() {
    for (header, payload, wire) in golden() {
        let mut out = [0u8; MAX_FRAME];
        let n = encode_frame(&header, payload, &mut out).expect("encode");
        assert_eq!(&out[..n], wire, "{header:?}");
    }
}

#[test]
fn golden_frames_decode() {
    for (header, payload, wire) in golden() {
        let mut buf = wire.to_vec();
        let (hd, p) = decode_frame(&mut buf).expect("decode");
        assert_eq!((hd, p), (header, payload));
        // Without the delimiter too.
        let mut buf = wire[..wire.len() - 1].to_vec();
        assert_eq!(decode_frame(&mut buf).expect("decode").0, header);
    }
}

#[test]
fn frame_limits() {
    // 6 + 256 + 4 = 266 bytes, +2 COBS overhead bytes, +1 delimiter.
    assert_eq!(MAX_FRAME, 269);
    assert_eq!((HEADER_LEN, CRC_LEN), (6, 4));
    let mut out = [0u8; MAX_FRAME];
    let header = h(Kind::Data, 15, 0xffff, 0xffff, 0xff);
    let n = encode_frame(&header, &[0xff; MAX_PAYLOAD], &mut out).expect("fits");
    assert!(n <= MAX_FRAME);
    assert_eq!(
        encode_frame(&header, &[0; MAX_PAYLOAD + 1], &mut out),
        Err(LinkError::TooLarge { len: 257, max: 256 })
    );
    let mut small = [0u8; 11];
    assert!(matches!(
        encode_frame(&h(Kind::Ack, 0, 0, 0, 0), &[], &mut small),
        Err(LinkError::BufferTooSmall { .. })
    ));
}

#[test]
fn malformed_frames_are_classified() {
    let (_, _, wire) = golden().remove(0);
    // A flipped payload bit is a CRC error.
    let mut bad = wire.to_vec();
    bad[9] ^= 0x10;
    assert_eq!(decode_frame(&mut bad), Err(LinkError::Crc));
    // Too short to hold a header and a CRC.
    assert_eq!(
        decode_frame(&mut [0x03, 0x01, 0x02, 0x00]),
        Err(LinkError::Framing)
    );
    // A zero inside the encoded bytes: two frames ran together.
    let mut two = wire[..5].to_vec();
    two.push(0);
    two.extend_from_slice(wire);
    assert_eq!(decode_frame(&mut two), Err(LinkError::Framing));
    // Kind 7 with a valid CRC.
    let mut unknown = raw_frame(&[0x07, 0, 0, 0, 0, 0]);
    assert_eq!(decode_frame(&mut unknown), Err(LinkError::Framing));
    // A payload on a control frame: an Ack carrying one byte.
    let mut ack_with_payload = raw_frame(&[0x02, 0, 0, 0, 0, 0, 0x42]);
    assert_eq!(decode_frame(&mut ack_with_payload), Err(LinkError::Framing));
    // The same body as Data is fine.
    let mut data = raw_frame(&[0x01, 0, 0, 0, 0, 0, 0x42]);
    assert_eq!(
        decode_frame(&mut data),
        Ok((h(Kind::Data, 0, 0, 0, 0), &[0x42u8][..]))
    );
}

/// A frame built by the test's own CRC and COBS from header and payload bytes.
fn raw_frame(body: &[u8]) -> Vec<u8> {
    let mut raw = body.to_vec();
    raw.extend_from_slice(&crc32(body).to_le_bytes());
    cobs_encode(&raw)
}

/// Bitwise CRC-32/ISO-HDLC, independent of the `crc` crate the link uses.
fn crc32(data: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in data {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xedb8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// Straightforward COBS with the delimiter, independent of the `cobs` crate.
fn cobs_encode(raw: &[u8]) -> Vec<u8> {
    let mut out = vec![0];
    let mut code_at = 0;
    let mut code = 1u8;
    for (i, &b) in raw.iter().enumerate() {
        if b == 0 {
            out[code_at] = code;
            code_at = out.len();
            out.push(0);
            code = 1;
        } else {
            out.push(b);
            code += 1;
            // A full 254-byte block that ends the data opens no empty block after it
            // (the `cobs` crate's encoding, which the link uses; a trailing 0x01 code
            // would decode the same, but the wire bytes would differ).
            if code == 0xff && i + 1 < raw.len() {
                out[code_at] = code;
                code_at = out.len();
                out.push(0);
                code = 1;
            }
        }
    }
    out[code_at] = code;
    out.push(0);
    out
}

#[test]
fn reference_crc_and_cobs_agree_with_the_golden_vectors() {
    // Guards the helpers used by the tests above.
    assert_eq!(crc32(b"123456789"), 0xcbf4_3926);
    for (header, payload, wire) in golden() {
        let mut raw = header.to_bytes().to_vec();
        raw.extend_from_slice(payload);
        let c = crc32(&raw);
        raw.extend_from_slice(&c.to_le_bytes());
        assert_eq!(cobs_encode(&raw), wire);
    }
}

fn any_kind() -> impl Strategy<Value = Kind> {
    prop_oneof![
        Just(Kind::Data),
        Just(Kind::Ack),
        Just(Kind::Nak),
        Just(Kind::Probe),
        Just(Kind::Reset),
        Just(Kind::ResetAck),
    ]
}

proptest! {
    #[test]
    fn frames_round_trip(
        kind in any_kind(),
        epoch in 0u8..16,
        seq: u16,
        ack: u16,
        credit: u8,
        data in proptest::collection::vec(any::<u8>(), 0..=MAX_PAYLOAD),
    ) {
        let header = h(kind, epoch, seq, ack, credit);
        let payload: &[u8] = if kind == Kind::Data { &data } else { &[] };
        let mut out = [0u8; MAX_FRAME];
        let n = encode_frame(&header, payload, &mut out).expect("encode");
        prop_assert!(n <= MAX_FRAME);
        prop_assert_eq!(out[n - 1], 0);
        prop_assert!(!out[..n - 1].contains(&0));
        // The independent reference produces the same bytes.
        let mut raw = header.to_bytes().to_vec();
        raw.extend_from_slice(payload);
        let c = crc32(&raw);
        raw.extend_from_slice(&c.to_le_bytes());
        prop_assert_eq!(&cobs_encode(&raw)[..], &out[..n]);
        let (hd, p) = decode_frame(&mut out[..n]).expect("decode");
        prop_assert_eq!(hd, header);
        prop_assert_eq!(p, payload);
    }

    #[test]
    fn arbitrary_bytes_never_panic_or_deliver(
        bytes in proptest::collection::vec(any::<u8>(), 0..3000),
        chunk in 1usize..400,
        zeros in proptest::collection::vec(0usize..3000, 0..20),
    ) {
        let mut bytes = bytes;
        // Sprinkle delimiters so that many short "frames" reach the decoder.
        for z in zeros {
            if z < bytes.len() {
                bytes[z] = 0;
            }
        }
        let mut link: Link = Link::new(Config::default());
        for part in bytes.chunks(chunk) {
            let (n, ev) = link.handle_input(0, part);
            prop_assert!(ev.is_none());
            prop_assert_eq!(n, part.len());
        }
        prop_assert_eq!(link.handle_input(0, &[]), (0, None));
        prop_assert_eq!(link.counters().delivered, 0);
        let mut out = [0u8; MAX_FRAME];
        let mut frames = 0;
        while link.poll_transmit(1, &mut out).is_some() {
            frames += 1;
            prop_assert!(frames < 10);
        }
        link.handle_timeout(10_000);
    }
}

// ---------------------------------------------------------------------------------------
// Whole-link simulation.
// ---------------------------------------------------------------------------------------

fn splitmix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// Payload number `i` of stream `stream`: its length (1..=max) and every byte follow from
/// the index, so the receiver can check integrity without a copy of what was sent.
fn payload(stream: u64, i: u64, max: usize, out: &mut Vec<u8>) {
    let r = splitmix(stream << 40 | i);
    let len = 1 + (r % max as u64) as usize;
    out.clear();
    let mut x = r;
    for j in 0..len {
        if j % 8 == 0 {
            x = splitmix(r ^ j as u64);
        }
        out.push((x >> (8 * (j % 8))) as u8);
    }
}

#[derive(Clone, Copy)]
struct Loss {
    corrupt_byte: f64,
    drop: f64,
    duplicate: f64,
    reorder: f64,
}

const CLEAN: Loss = Loss {
    corrupt_byte: 0.0,
    drop: 0.0,
    duplicate: 0.0,
    reorder: 0.0,
};

/// One direction of the wire: frame-level drop, duplicate and reorder (a held frame goes
/// out after the next one), then independent byte corruption of every copy.
struct Channel {
    loss: Loss,
    queue: VecDeque<Vec<u8>>,
    held: Option<Vec<u8>>,
    /// Drop everything (to simulate a cut wire).
    cut: bool,
}

impl Channel {
    fn new(loss: Loss) -> Self {
        Channel {
            loss,
            queue: VecDeque::new(),
            held: None,
            cut: false,
        }
    }

    fn push(&mut self, rng: &mut SmallRng, frame: &[u8]) {
        let l = self.loss;
        if self.cut || rng.gen_bool(l.drop) {
            return;
        }
        let copies = if rng.gen_bool(l.duplicate) { 2 } else { 1 };
        let reorder = self.held.is_none() && rng.gen_bool(l.reorder);
        for k in 0..copies {
            let mut f = frame.to_vec();
            if l.corrupt_byte > 0.0 {
                for b in f.iter_mut() {
                    if rng.gen_bool(l.corrupt_byte) {
                        *b ^= rng.gen_range(1..=255u8);
                    }
                }
            }
            if reorder && k == 0 {
                self.held = Some(f);
            } else {
                self.queue.push_back(f);
                if let Some(h) = self.held.take() {
                    self.queue.push_back(h);
                }
            }
        }
    }

    fn flush_held(&mut self) {
        if let Some(h) = self.held.take() {
            self.queue.push_back(h);
        }
    }

    fn take_bytes(&mut self) -> Vec<u8> {
        let mut v = Vec::new();
        for f in self.queue.drain(..) {
            v.extend_from_slice(&f);
        }
        v
    }
}

struct End<const W: usize, C: Capacity = Small> {
    link: Box<Link<W, C>>,
    /// Frames to send in total and the next to hand to `send`.
    total: u64,
    next_send: u64,
    /// Next frame expected by this end's receiver.
    next_recv: u64,
    stream_out: u64,
    stream_in: u64,
    max_len: usize,
    /// Events other than data, in order.
    events: Vec<String>,
    /// Application queue model: capacity (None: consumes at once) and current fill.
    app_queue: Option<(u8, u8)>,
    max_in_flight: usize,
    /// Check delivered payloads against the stream (off while a reset flushes old data).
    checking: bool,
    scratch: Vec<u8>,
    expected: Vec<u8>,
}

impl<const W: usize, C: Capacity> End<W, C> {
    fn new(config: Config, total: u64, stream_out: u64, stream_in: u64, max_len: usize) -> Self {
        End {
            link: Box::new(Link::new(config)),
            total,
            next_send: 0,
            next_recv: 0,
            stream_out,
            stream_in,
            max_len,
            events: Vec::new(),
            app_queue: None,
            max_in_flight: 0,
            checking: true,
            scratch: Vec::new(),
            expected: Vec::new(),
        }
    }

    fn send_all(&mut self, now: u64) -> bool {
        let mut any = false;
        while self.next_send < self.total {
            payload(
                self.stream_out,
                self.next_send,
                self.max_len,
                &mut self.scratch,
            );
            match self.link.send(now, &self.scratch) {
                Ok(seq) => {
                    assert_eq!(u64::from(seq), self.next_send % 65536, "sequence numbers");
                    self.next_send += 1;
                    any = true;
                }
                Err(LinkError::WindowFull | LinkError::NoCredit) => break,
                Err(e) => panic!("send: {e}"),
            }
        }
        self.max_in_flight = self.max_in_flight.max(self.link.in_flight());
        any
    }

    fn transmit(&mut self, now: u64, rng: &mut SmallRng, ch: &mut Channel) -> bool {
        let mut out = vec![0u8; encoded_len(C::PAYLOAD) + 1];
        let mut any = false;
        while let Some(n) = self.link.poll_transmit(now, &mut out) {
            ch.push(rng, &out[..n]);
            any = true;
        }
        any
    }

    /// Feeds `bytes` in random chunks, checking every delivered payload.
    fn receive(&mut self, now: u64, rng: &mut SmallRng, bytes: &[u8]) {
        let mut rest = bytes;
        loop {
            let take = if rest.is_empty() {
                0
            } else {
                rng.gen_range(1..=rest.len().min(400))
            };
            let (mut chunk, tail) = rest.split_at(take);
            rest = tail;
            loop {
                let (n, ev) = self.link.handle_input(now, chunk);
                chunk = &chunk[n..];
                match ev {
                    None => {
                        assert!(chunk.is_empty(), "None before all bytes were consumed");
                        break;
                    }
                    Some(Event::Data(_)) if !self.checking => {}
                    Some(Event::Data(p)) => {
                        payload(
                            self.stream_in,
                            self.next_recv,
                            self.max_len,
                            &mut self.expected,
                        );
                        assert!(
                            p == &self.expected[..],
                            "frame {} corrupted or out of order",
                            self.next_recv
                        );
                        self.next_recv += 1;
                        if let Some((cap, fill)) = self.app_queue.as_mut() {
                            *fill += 1;
                            assert!(*fill <= *cap, "application queue overrun");
                            let free = *cap - *fill;
                            self.link.set_rx_credit(free);
                        }
                    }
                    Some(Event::Synced) => self.events.push("synced".into()),
                    Some(Event::PeerReset { discarded }) => {
                        self.events.push(format!("peer-reset {discarded}"))
                    }
                }
            }
            if rest.is_empty() {
                break;
            }
        }
    }

    /// The application executes one queued command and frees its slot.
    fn drain_app_queue(&mut self) {
        if let Some((cap, fill)) = self.app_queue.as_mut() {
            if *fill > 0 {
                *fill -= 1;
                let free = *cap - *fill;
                self.link.set_rx_credit(free);
            }
        }
    }

    fn done(&self, peer_total: u64) -> bool {
        self.next_send == self.total && self.link.in_flight() == 0 && self.next_recv == peer_total
    }
}

struct Sim<const W: usize, C: Capacity = Small> {
    now: u64,
    rng: SmallRng,
    a: End<W, C>,
    b: End<W, C>,
    ab: Channel,
    ba: Channel,
}

impl<const W: usize, C: Capacity> Sim<W, C> {
    fn new(seed: u64, loss: Loss, config: Config, a_total: u64, b_total: u64, max: usize) -> Self {
        Sim {
            now: 0,
            rng: SmallRng::seed_from_u64(seed),
            a: End::new(config, a_total, 1, 2, max),
            b: End::new(config, b_total, 2, 1, max),
            ab: Channel::new(loss),
            ba: Channel::new(loss),
        }
    }

    /// One millisecond of simulated time: both ends send, the wire carries what they
    /// wrote, both ends receive, timers fire. When nothing moved, the clock jumps to the
    /// next deadline. Returns false when the links are idle with no deadline.
    fn step(&mut self) -> bool {
        let now = self.now;
        let mut moved = self.a.send_all(now) | self.b.send_all(now);
        moved |= self.a.transmit(now, &mut self.rng, &mut self.ab);
        moved |= self.b.transmit(now, &mut self.rng, &mut self.ba);
        let to_b = self.ab.take_bytes();
        let to_a = self.ba.take_bytes();
        moved |= !to_a.is_empty() || !to_b.is_empty();
        self.b.receive(now, &mut self.rng, &to_b);
        self.a.receive(now, &mut self.rng, &to_a);
        self.a.drain_app_queue();
        self.b.drain_app_queue();
        self.now += 1;
        if !moved {
            if self.ab.held.is_some() || self.ba.held.is_some() {
                self.ab.flush_held();
                self.ba.flush_held();
            } else {
                let next = [self.a.link.next_deadline(), self.b.link.next_deadline()]
                    .into_iter()
                    .flatten()
                    .min();
                match next {
                    Some(t) => self.now = self.now.max(t),
                    None => return false,
                }
            }
        }
        self.a.link.handle_timeout(self.now);
        self.b.link.handle_timeout(self.now);
        true
    }

    fn run_to_completion(&mut self, max_ms: u64) {
        while !(self.a.done(self.b.total) && self.b.done(self.a.total)) {
            assert!(self.now < max_ms, "no progress by t = {} ms", self.now);
            self.step();
        }
    }
}

fn show(name: &str, c: protocol::frame::LinkCounters) {
    eprintln!(
        "{name}: sent {} resent {} delivered {} crc_errors {} framing_errors {} duplicates {} \
         overflows {} naks {} timeouts {} stale {} resets {}",
        c.sent,
        c.resent,
        c.delivered,
        c.crc_errors,
        c.framing_errors,
        c.duplicates,
        c.overflows,
        c.naks,
        c.timeouts,
        c.stale,
        c.resets
    );
}

/// Runs `n` frames each way, of up to `max` bytes, across `loss` and checks that every one
/// arrived exactly once, in order and intact (checked in `End::receive`) and that the
/// channel really damaged frames (resends, CRC errors and duplicates on both ends).
fn cross_lossy<const W: usize, C: Capacity>(
    seed: u64,
    loss: Loss,
    n: u64,
    max: usize,
) -> Sim<W, C> {
    let mut sim: Sim<W, C> = Sim::new(seed, loss, Config::default(), n, n, max);
    sim.run_to_completion(u64::MAX / 2);
    let (a, b) = (sim.a.link.counters(), sim.b.link.counters());
    show("A", a);
    show("B", b);
    eprintln!("simulated time {} ms", sim.now);
    assert_eq!((sim.a.next_recv, sim.b.next_recv), (n, n));
    assert_eq!((a.delivered, b.delivered), (n as u32, n as u32));
    assert_eq!((a.sent, b.sent), (n as u32, n as u32));
    for c in [a, b] {
        assert!(c.resent > 0 && c.crc_errors > 0 && c.duplicates > 0);
        assert_eq!(c.stale, 0);
    }
    sim
}

/// docs/requirements.md §7.1: 100 000 frames each way cross a channel that corrupts 1 % of
/// bytes and drops, duplicates and reorders 1 % of frames; every frame must arrive exactly
/// once, in order and intact. The sequence numbers wrap on the way.
#[test]
fn lossy_channel_delivers_everything_exactly_once_in_order() {
    let loss = Loss {
        corrupt_byte: 0.01,
        drop: 0.01,
        duplicate: 0.01,
        reorder: 0.01,
    };
    let sim: Sim<8> = cross_lossy(0x5eed_f9f8, loss, 100_000, MAX_PAYLOAD);
    // Every kind of damage was seen and handled.
    for c in [sim.a.link.counters(), sim.b.link.counters()] {
        assert!(c.naks > 0);
    }
    assert!(sim.a.max_in_flight <= 8 && sim.b.max_in_flight <= 8);
}

#[test]
fn clean_channel_needs_no_resends() {
    let mut sim: Sim<8> = Sim::new(1, CLEAN, Config::default(), 2_000, 500, 64);
    sim.run_to_completion(1_000_000);
    for c in [sim.a.link.counters(), sim.b.link.counters()] {
        assert_eq!((c.resent, c.timeouts, c.naks, c.crc_errors), (0, 0, 0, 0));
        assert_eq!(c.duplicates, 0);
    }
    assert_eq!(sim.b.link.counters().delivered, 2_000);
    assert_eq!(sim.a.link.counters().delivered, 500);
}

#[test]
fn sequence_numbers_wrap_past_65535() {
    // 70 000 small frames: seq goes 65534, 65535, 0, 1, ... (`End::send_all` checks that
    // each seq is the frame index mod 65536), with some loss around the wrap too.
    let loss = Loss {
        corrupt_byte: 0.0,
        drop: 0.02,
        duplicate: 0.02,
        reorder: 0.02,
    };
    let mut sim: Sim<16> = Sim::new(7, loss, Config::default(), 70_000, 0, 4);
    sim.run_to_completion(u64::MAX / 2);
    assert_eq!(sim.b.next_recv, 70_000);
    assert!(sim.a.link.counters().resent > 0);
}

#[test]
fn window_is_never_exceeded() {
    let loss = Loss {
        corrupt_byte: 0.001,
        drop: 0.05,
        duplicate: 0.05,
        reorder: 0.05,
    };
    let mut sim: Sim<4> = Sim::new(3, loss, Config::default(), 3_000, 3_000, 32);
    let mut max = 0;
    while !(sim.a.done(3_000) && sim.b.done(3_000)) {
        assert!(sim.now < 10_000_000);
        sim.step();
        max = max.max(sim.a.max_in_flight).max(sim.b.max_in_flight);
    }
    assert_eq!(max, 4, "the window of 4 is used but never exceeded");
}

#[test]
fn zero_credit_blocks_then_restored_credit_delivers_everything() {
    let mut sim: Sim<8> = Sim::new(4, CLEAN, Config::default(), 40, 0, 16);
    sim.b.link.set_rx_credit(0);
    for _ in 0..2_000 {
        sim.step();
    }
    // Blocked: nothing sent, nothing delivered, but the sender kept probing.
    assert_eq!(sim.a.next_send, 0);
    assert_eq!(sim.b.next_recv, 0);
    assert_eq!(sim.a.link.counters().sent, 0);
    assert!(!sim.a.link.can_send());
    assert!(
        sim.a.link.next_deadline().is_some(),
        "a blocked sender keeps a probe timer"
    );
    // The application now has a queue of 3 slots that it drains one per millisecond:
    // the sender may never have more than 3 frames outstanding beyond what was executed.
    sim.b.app_queue = Some((3, 0));
    sim.b.link.set_rx_credit(3);
    let mut max = 0;
    while !sim.a.done(0) || sim.b.next_recv < 40 {
        assert!(sim.now < 1_000_000, "stuck");
        sim.step();
        max = max.max(sim.a.link.in_flight());
    }
    assert!(max <= 3, "in flight {max} > credit 3");
    assert_eq!(sim.b.next_recv, 40);
    assert_eq!(sim.b.link.counters().overflows, 0);
}

#[test]
fn lost_window_update_is_recovered_by_probing() {
    let mut sim: Sim<8> = Sim::new(5, CLEAN, Config::default(), 10, 0, 16);
    sim.b.link.set_rx_credit(0);
    for _ in 0..10 {
        sim.step();
    }
    // The window update is lost on the wire; the next probe fetches it again.
    sim.ba.cut = true;
    sim.b.link.set_rx_credit(8);
    sim.step();
    sim.ba.cut = false;
    sim.run_to_completion(1_000_000);
    assert_eq!(sim.b.next_recv, 10);
}

fn frames_of(link: &mut Link, now: u64) -> Vec<Vec<u8>> {
    let mut out = [0u8; MAX_FRAME];
    let mut v = Vec::new();
    while let Some(n) = link.poll_transmit(now, &mut out) {
        v.push(out[..n].to_vec());
    }
    v
}

fn headers(frames: &[Vec<u8>]) -> Vec<Header> {
    frames
        .iter()
        .map(|f| decode_frame(&mut f.clone()).expect("own frame").0)
        .collect()
}

fn feed(link: &mut Link, now: u64, bytes: &[u8]) -> Vec<Vec<u8>> {
    let mut got = Vec::new();
    let mut rest = bytes;
    loop {
        let (n, ev) = link.handle_input(now, rest);
        rest = &rest[n..];
        match ev {
            None => return got,
            Some(Event::Data(p)) => got.push(p.to_vec()),
            Some(e) => panic!("unexpected {e:?}"),
        }
    }
}

/// Two fresh links with credit exchanged (the first send probes).
fn pair() -> (Link, Link) {
    let mut a: Link = Link::new(Config::default());
    let mut b: Link = Link::new(Config::default());
    assert_eq!(a.send(0, b"x"), Err(LinkError::NoCredit));
    let probe = frames_of(&mut a, 0);
    assert_eq!(headers(&probe)[0].kind, Kind::Probe);
    feed(&mut b, 0, &probe.concat());
    let ack = frames_of(&mut b, 0);
    assert_eq!(
        headers(&ack),
        vec![h(Kind::Ack, 0, 0, 0, 8)],
        "the probe is answered with the receiver's credit"
    );
    feed(&mut a, 0, &ack.concat());
    assert!(a.can_send());
    (a, b)
}

/// The receiver takes runs of frame bytes at once: the largest encoded frame still fits,
/// one byte more is one overflow however the bytes are split, and the frame after it
/// arrives.
#[test]
fn an_overlong_frame_is_one_overflow_and_the_next_frame_arrives() {
    let longest = MAX_FRAME - 1;
    for (len, overflows) in [(longest, 0), (longest + 1, 1), (3 * longest + 5, 1)] {
        for chunk in [1, 7, longest, usize::MAX] {
            let (mut a, mut b) = pair();
            let mut bytes = vec![0x55u8; len];
            bytes.push(0);
            a.send(1, b"after").expect("send");
            bytes.extend(frames_of(&mut a, 1).concat());
            let mut got = Vec::new();
            for part in bytes.chunks(chunk.min(bytes.len())) {
                got.extend(feed(&mut b, 1, part));
            }
            let c = b.counters();
            let at = format!("{len} bytes in chunks of {chunk}");
            assert_eq!(c.overflows, overflows, "{at}");
            assert_eq!(c.crc_errors + c.framing_errors, 1 - overflows, "{at}");
            assert_eq!(got, vec![b"after".to_vec()], "{at}");
        }
    }
}

#[test]
fn duplicates_are_acknowledged_but_delivered_once() {
    let (mut a, mut b) = pair();
    a.send(1, b"hello").expect("send");
    let data = frames_of(&mut a, 1).concat();
    assert_eq!(feed(&mut b, 1, &data), vec![b"hello".to_vec()]);
    assert_eq!(
        headers(&frames_of(&mut b, 1)),
        vec![h(Kind::Ack, 0, 0, 1, 8)]
    );
    assert_eq!(feed(&mut b, 2, &data), Vec::<Vec<u8>>::new());
    assert_eq!(
        headers(&frames_of(&mut b, 2)),
        vec![h(Kind::Ack, 0, 0, 1, 8)]
    );
    assert_eq!(b.counters().duplicates, 1);
    assert_eq!(b.counters().delivered, 1);
}

#[test]
fn one_gap_gives_one_nak_and_an_immediate_resend() {
    let (mut a, mut b) = pair();
    for i in 0..5u8 {
        a.send(1, &[i]).expect("send");
    }
    let frames = frames_of(&mut a, 1);
    assert_eq!(frames.len(), 5);
    // Frame 1 is lost; 2, 3, 4 each reveal the gap.
    let mut got = feed(&mut b, 1, &frames[0]);
    let mut replies = frames_of(&mut b, 1);
    for f in &frames[2..] {
        got.extend(feed(&mut b, 2, f));
        replies.extend(frames_of(&mut b, 2));
    }
    assert_eq!(got, vec![vec![0u8]]);
    let naks: Vec<_> = headers(&replies)
        .into_iter()
        .filter(|h| h.kind == Kind::Nak)
        .collect();
    assert_eq!(naks, vec![h(Kind::Nak, 0, 1, 1, 8)]);
    assert_eq!(b.counters().naks, 1);
    // The last ACK SACKs frames 2, 3 and 4 (bits 0..=2 after the cumulative point 1).
    assert_eq!(
        *headers(&replies).last().expect("ack"),
        h(Kind::Ack, 0, 0b111, 1, 8)
    );
    feed(&mut a, 3, &replies.concat());
    let resend = frames_of(&mut a, 3);
    assert_eq!(headers(&resend), vec![h(Kind::Data, 0, 1, 0, 8)]);
    assert_eq!(a.counters().resent, 1);
    assert_eq!(a.counters().timeouts, 0);
    assert_eq!(
        feed(&mut b, 3, &resend.concat()),
        vec![vec![1u8], vec![2], vec![3], vec![4]]
    );
    feed(&mut a, 4, &frames_of(&mut b, 3).concat());
    assert_eq!(a.in_flight(), 0);
    // SACKed frames are not resent when the timer fires.
    a.handle_timeout(10_000);
    assert!(frames_of(&mut a, 10_000).is_empty());
}

#[test]
fn timeout_resends_and_deadline_is_reported() {
    let (mut a, mut b) = pair();
    a.send(100, b"lost").expect("send");
    assert_eq!(frames_of(&mut a, 100).len(), 1);
    let rto = Config::default().rto_ms;
    assert_eq!(a.next_deadline(), Some(100 + rto));
    a.handle_timeout(100 + rto - 1);
    assert!(frames_of(&mut a, 100 + rto - 1).is_empty());
    a.handle_timeout(100 + rto);
    let again = frames_of(&mut a, 100 + rto);
    assert_eq!(headers(&again), vec![h(Kind::Data, 0, 0, 0, 8)]);
    assert_eq!((a.counters().timeouts, a.counters().resent), (1, 1));
    assert_eq!(feed(&mut b, 700, &again.concat()), vec![b"lost".to_vec()]);
    feed(&mut a, 700, &frames_of(&mut b, 700).concat());
    assert_eq!(a.next_deadline(), None);
}

#[test]
fn send_errors_never_drop() {
    let (mut a, _b) = pair();
    assert_eq!(
        a.send(0, &[0; MAX_PAYLOAD + 1]),
        Err(LinkError::TooLarge { len: 257, max: 256 })
    );
    for i in 0..8u16 {
        assert_eq!(a.send(0, &[1]), Ok(i));
    }
    assert_eq!(a.in_flight(), 8);
    assert_eq!(a.send(0, &[1]), Err(LinkError::WindowFull));
    assert_eq!(frames_of(&mut a, 0).len(), 8);
    assert_eq!(a.counters().sent, 8);
}

#[test]
fn garbage_crc_errors_and_overflow_resynchronise() {
    let (mut a, mut b) = pair();
    a.send(1, b"one").expect("send");
    a.send(1, b"two").expect("send");
    let frames = frames_of(&mut a, 1);
    let mut corrupted = frames[0].clone();
    corrupted[7] ^= 0x01;
    let mut stream = corrupted;
    stream.extend(std::iter::repeat_n(0x55u8, 1000)); // no delimiter: overflows the buffer
    stream.push(0);
    stream.extend_from_slice(&frames[0]);
    stream.extend_from_slice(&frames[1]);
    assert_eq!(
        feed(&mut b, 2, &stream),
        vec![b"one".to_vec(), b"two".to_vec()]
    );
    let c = b.counters();
    assert_eq!((c.crc_errors, c.overflows, c.delivered), (1, 1, 2));
}

#[test]
fn reset_resynchronises_and_stale_frames_are_ignored() {
    let (mut a, mut b) = pair();
    // a's probe carried a's credit too, so b may send at once.
    assert_eq!(b.send(0, b"b0"), Ok(0));
    feed(&mut a, 0, &frames_of(&mut b, 0).concat());
    feed(&mut b, 0, &frames_of(&mut a, 0).concat());
    // a has 3 frames in flight, b has 2; all of them are lost.
    for i in 0..3u8 {
        a.send(1, &[i]).expect("send a");
    }
    let old = frames_of(&mut a, 1);
    for i in 0..2u8 {
        b.send(1, &[i]).expect("send b");
    }
    frames_of(&mut b, 1);
    assert_eq!(a.reset(2, 0x1234), 3);
    assert_eq!(a.epoch(), 1);
    assert_eq!(
        a.send(2, b"x"),
        Err(LinkError::NoCredit),
        "no sending until synced"
    );
    let reset = frames_of(&mut a, 2);
    assert_eq!(headers(&reset), vec![h(Kind::Reset, 1, 0x1234, 0, 8)]);
    // The Reset is lost once: it is repeated after the timeout.
    a.handle_timeout(2 + Config::default().rto_ms);
    let reset = frames_of(&mut a, 600);
    assert_eq!(headers(&reset), vec![h(Kind::Reset, 1, 0x1234, 0, 8)]);
    let (n, ev) = b.handle_input(600, &reset.concat());
    assert_eq!(n, reset.concat().len());
    assert_eq!(ev, Some(Event::PeerReset { discarded: 2 }));
    assert_eq!(b.handle_input(600, &[]), (0, None));
    assert_eq!(b.epoch(), 1);
    let reply = frames_of(&mut b, 600);
    assert_eq!(headers(&reply), vec![h(Kind::ResetAck, 1, 0x1234, 0, 8)]);
    let (_, ev) = a.handle_input(601, &reply.concat());
    assert_eq!(ev, Some(Event::Synced));
    assert_eq!(a.handle_input(601, &[]), (0, None));
    // Sequence numbers restart at 0 in the new epoch, on both sides.
    assert_eq!(a.send(602, b"new"), Ok(0));
    assert_eq!(b.send(602, b"new-b"), Ok(0));
    // A frame of the old epoch arriving late is counted and ignored.
    assert_eq!(feed(&mut b, 603, &old[0]), Vec::<Vec<u8>>::new());
    assert_eq!(b.counters().stale, 1);
    assert_eq!(
        feed(&mut b, 603, &frames_of(&mut a, 603).concat()),
        vec![b"new".to_vec()]
    );
    assert_eq!(
        feed(&mut a, 604, &frames_of(&mut b, 604).concat()),
        vec![b"new-b".to_vec()]
    );
    // A repeated Reset (our ResetAck lost) is confirmed again without a second reset.
    let (_, ev) = b.handle_input(605, &reset.concat());
    assert_eq!(ev, None);
    assert_eq!(
        headers(&frames_of(&mut b, 605))[0],
        h(Kind::ResetAck, 1, 0x1234, 1, 8)
    );
    assert_eq!((a.counters().resets, b.counters().resets), (1, 1));
}

#[test]
fn reset_under_loss_then_streaming_continues() {
    let loss = Loss {
        corrupt_byte: 0.005,
        drop: 0.05,
        duplicate: 0.02,
        reorder: 0.02,
    };
    let mut sim: Sim<8> = Sim::new(11, loss, Config::default(), 300, 300, 64);
    for _ in 0..200 {
        sim.step();
    }
    // Restart both streams after the reset: each side resends from scratch.
    let discarded = sim.a.link.reset(sim.now, 0xabcd);
    assert!(discarded <= 8);
    let mut synced = false;
    let mut peer_reset = false;
    sim.a.next_send = sim.a.total; // stop A's stream while resynchronising
    sim.b.next_send = sim.b.total;
    sim.a.checking = false;
    sim.b.checking = false;
    while !(synced && peer_reset) {
        assert!(sim.now < 1_000_000);
        sim.step();
        synced |= sim.a.events.iter().any(|e| e == "synced");
        peer_reset |= sim.b.events.iter().any(|e| e.starts_with("peer-reset"));
    }
    // Both ends are in the new epoch with nothing in flight: restart both streams.
    assert_eq!((sim.a.link.in_flight(), sim.b.link.in_flight()), (0, 0));
    for end in [&mut sim.a, &mut sim.b] {
        end.checking = true;
        end.next_send = 0;
        end.next_recv = 0;
    }
    sim.run_to_completion(10_000_000);
    assert_eq!((sim.a.next_recv, sim.b.next_recv), (300, 300));
}

#[test]
fn simultaneous_resets_converge_on_the_larger_nonce() {
    let mut sim: Sim<8> = Sim::new(12, CLEAN, Config::default(), 20, 20, 16);
    sim.run_to_completion(1_000_000);
    sim.a.link.reset(sim.now, 5);
    sim.b.link.reset(sim.now, 9);
    sim.b.link.reset(sim.now, 9); // epoch 2 on b, 1 on a
    for _ in 0..50 {
        sim.step();
    }
    // b's reset (nonce 9) wins: a adopts b's epoch, b gets its confirmation.
    assert_eq!(sim.a.events, vec!["peer-reset 0".to_string()]);
    assert_eq!(sim.b.events, vec!["synced".to_string()]);
    assert_eq!((sim.a.link.epoch(), sim.b.link.epoch()), (2, 2));
    for end in [&mut sim.a, &mut sim.b] {
        end.next_send = 0;
        end.next_recv = 0;
    }
    sim.run_to_completion(2_000_000);
    assert_eq!((sim.a.next_recv, sim.b.next_recv), (20, 20));
}

#[test]
fn largest_window_works() {
    let loss = Loss {
        corrupt_byte: 0.001,
        drop: 0.02,
        duplicate: 0.02,
        reorder: 0.02,
    };
    let mut sim: Sim<128> = Sim::new(13, loss, Config::default(), 5_000, 5_000, 64);
    sim.run_to_completion(u64::MAX / 2);
    assert!(sim.a.max_in_flight > 16, "a large window is actually used");
    assert!(sim.a.max_in_flight <= 128);
}

#[test]
fn link_fits_the_mcu_budget() {
    // Two windows of 256-byte slots plus the receive buffer: ~4.6 KiB of the MCU's 128 KiB.
    let size = core::mem::size_of::<Link<8>>();
    eprintln!("size_of::<Link<8>>() = {size}");
    assert!(size < 5 * 1024, "{size}");
}

#[test]
fn changing_credit_under_loss_never_overruns_the_application() {
    let loss = Loss {
        corrupt_byte: 0.002,
        drop: 0.03,
        duplicate: 0.03,
        reorder: 0.03,
    };
    let mut sim: Sim<8> = Sim::new(21, loss, Config::default(), 3_000, 1_000, 48);
    // b's application queue holds 3 commands and executes one per millisecond;
    // `End::receive` asserts it is never overrun.
    sim.b.app_queue = Some((3, 0));
    sim.b.link.set_rx_credit(3);
    sim.run_to_completion(u64::MAX / 2);
    assert_eq!((sim.a.next_recv, sim.b.next_recv), (1_000, 3_000));
}

/// The lossy channel of `lossy_channel_delivers_everything_exactly_once_in_order` with
/// links of bulk frames (payloads up to 16 KiB, so bytes are corrupted 500 times less
/// often for frames to get through at all): every one still arrives exactly once, in
/// order and intact.
#[test]
fn bulk_frames_cross_a_lossy_channel_exactly_once_in_order() {
    let loss = Loss {
        corrupt_byte: 0.000_02,
        drop: 0.01,
        duplicate: 0.01,
        reorder: 0.01,
    };
    let _: Sim<8, Bulk> = cross_lossy(0xb01c, loss, 1_500, BULK_PAYLOAD);
}

#[test]
fn a_link_refuses_what_its_capacity_cannot_hold_and_says_its_maximum() {
    let mut small: Link = Link::new(Config::default());
    let mut bulk: Box<Link<8, Bulk>> = Box::new(Link::new(Config::default()));
    assert_eq!(
        small.send(0, &[0; MAX_PAYLOAD + 1]),
        Err(LinkError::TooLarge { len: 257, max: 256 })
    );
    assert_eq!(
        bulk.send(0, &[0; BULK_PAYLOAD + 1]),
        Err(LinkError::TooLarge {
            len: BULK_PAYLOAD + 1,
            max: BULK_PAYLOAD
        })
    );
    assert_eq!(
        LinkError::TooLarge {
            len: 20_000,
            max: BULK_PAYLOAD
        }
        .to_string(),
        "payload of 20000 bytes exceeds the maximum of 16384"
    );
    // A bulk frame reaching a board-sized receiver is one overflow, not a crash or a
    // delivery: the sender must size its payloads for the peer.
    let mut wire = vec![0u8; encoded_len(BULK_PAYLOAD) + 1];
    let mut big: Box<Link<8, Bulk>> = Box::new(Link::new(Config::default()));
    let _ = big.send(0, &[1; 1000]);
    // Credit first, so the frame goes out: the Probe answered by the small end.
    let mut to_small = Vec::new();
    while let Some(n) = big.poll_transmit(0, &mut wire) {
        to_small.extend_from_slice(&wire[..n]);
    }
    let _ = feed(&mut small, 0, &to_small);
    let mut to_big = [0u8; MAX_FRAME];
    while let Some(n) = small.poll_transmit(0, &mut to_big) {
        let _ = feed_any(&mut big, 0, &to_big[..n]);
    }
    assert!(big.send(1, &[1; 1000]).is_ok());
    let mut frames = Vec::new();
    while let Some(n) = big.poll_transmit(1, &mut wire) {
        frames.extend_from_slice(&wire[..n]);
    }
    let before = small.counters().overflows;
    assert!(feed(&mut small, 1, &frames).is_empty(), "nothing delivered");
    assert_eq!(small.counters().overflows, before + 1);
}

/// Feeds bytes to a link of any capacity, collecting what it delivers.
fn feed_any<const W: usize, C: Capacity>(
    link: &mut Link<W, C>,
    now: u64,
    bytes: &[u8],
) -> Vec<Vec<u8>> {
    let mut got = Vec::new();
    let mut rest = bytes;
    loop {
        let (used, event) = link.handle_input(now, rest);
        rest = &rest[used..];
        match event {
            Some(Event::Data(p)) => got.push(p.to_vec()),
            Some(_) => {}
            None if rest.is_empty() => return got,
            None => {}
        }
    }
}

#[test]
fn send_with_writes_the_payload_in_place_and_queues_nothing_on_its_error() {
    let (mut a, mut b) = pair();
    let r: Result<Result<u16, &str>, LinkError> = a.send_with(0, |slot| {
        assert_eq!(slot.len(), MAX_PAYLOAD);
        slot[..3].copy_from_slice(b"abc");
        Ok(3)
    });
    assert_eq!(r, Ok(Ok(0)));
    let r: Result<Result<u16, &str>, LinkError> = a.send_with(0, |_| Err("no data"));
    assert_eq!(r, Ok(Err("no data")));
    assert_eq!(a.in_flight(), 1, "the failed fill queued nothing");
    // A length past the slot is refused, not sent.
    let r: Result<Result<u16, ()>, LinkError> = a.send_with(0, |_| Ok(MAX_PAYLOAD + 1));
    assert_eq!(r, Err(LinkError::TooLarge { len: 257, max: 256 }));
    assert_eq!(a.in_flight(), 1);
    let frames = frames_of(&mut a, 0);
    let got: Vec<Vec<u8>> = frames.iter().flat_map(|f| feed(&mut b, 0, f)).collect();
    assert_eq!(got, [b"abc".to_vec()]);
}
