//! The reliable link: how postcard messages cross a lossy byte stream (UART, pty, TCP).
//!
//! The link is a sans-I/O state machine: it never reads a clock or touches a port. The
//! caller feeds received bytes to [`Link::handle_input`], drains frames to write with
//! [`Link::poll_transmit`], and tells it the time (milliseconds from any origin) on every
//! call, so the same code runs in the firmware's main loop, in the host's async task and in
//! a deterministic test with a simulated clock. It allocates nothing: every buffer is a
//! fixed array sized by the window `WINDOW` and the link's [`Capacity`]: [`Small`]
//! ([`crate::MAX_PAYLOAD`], what every end accepts, an MCU's size) or [`Bulk`] (for ends
//! with memory to spare: a host, the built-in target, a TCP board).
//!
//! # Frame format
//!
//! ```text
//! COBS( header[6] ‖ payload[0..=capacity] ‖ CRC-32(header ‖ payload) as u32 LE ) ‖ 0x00
//! ```
//!
//! COBS removes every zero byte, so `0x00` only ever appears as the delimiter and a receiver
//! that lost bytes resynchronises at the next one. The CRC is CRC-32/ISO-HDLC (the zlib and
//! Ethernet polynomial), so a captured frame can be checked with any standard tool.
//!
//! | byte | field | meaning |
//! |---|---|---|
//! | 0 | kind \| epoch << 4 | [`Kind`] in the low nibble, the sender's reset epoch in the high one |
//! | 1–2 | seq (u16 LE) | Data/Probe: sequence number; Ack: SACK bitmap; Nak: the missing seq; Reset/ResetAck: nonce |
//! | 3–4 | ack (u16 LE) | cumulative ACK: the next sequence number the sender of this frame expects |
//! | 5 | credit | receive slots, counted from `ack`, that the sender of this frame grants its peer |
//!
//! # Reliability
//!
//! Selective repeat: up to `WINDOW` data frames are unacknowledged at once. The receiver
//! buffers out-of-order frames inside its window and delivers strictly in order; it answers
//! every data frame with an ACK whose SACK bitmap names which of the 16 frames after the
//! cumulative point it already holds (so a timeout only resends what is really missing),
//! and sends one NAK per detected gap (repeated at most once per `nak_holdoff_ms`), which
//! triggers an immediate resend. A frame whose ACK never comes is resent after `rto_ms`.
//! Duplicates are acknowledged (the first ACK may have been lost) but delivered once.
//!
//! Flow control is by credit: every frame advertises how many frames, counted from its
//! cumulative ACK, the sender of that frame can still accept (`min(WINDOW, rx_credit)`,
//! where the application sets `rx_credit`, e.g. to its free queue slots). A sender never
//! sends past that point; when it is blocked it sends a Probe every `probe_ms`, which the
//! peer answers with an ACK carrying its current credit, so a lost window update cannot
//! deadlock the pair.
//!
//! A [`Link::reset`] bumps the 4-bit epoch and restarts both ends' sequence numbers at 0;
//! frames of an older epoch still in the channel are counted as stale and ignored.
//!
//! # Driving it
//!
//! ```
//! use protocol::link::{Config, Event, Link, MAX_FRAME};
//!
//! /// Moves every frame `from` wants to send into `to`, collecting delivered payloads.
//! fn pump(from: &mut Link, to: &mut Link, now: u64, got: &mut Vec<Vec<u8>>) {
//!     let mut wire = [0u8; MAX_FRAME];
//!     while let Some(n) = from.poll_transmit(now, &mut wire) {
//!         let mut rest = &wire[..n];
//!         loop {
//!             let (used, event) = to.handle_input(now, rest);
//!             rest = &rest[used..];
//!             match event {
//!                 Some(Event::Data(payload)) => got.push(payload.to_vec()),
//!                 Some(_) => {}
//!                 None => break, // everything consumed
//!             }
//!         }
//!     }
//! }
//!
//! let (mut host, mut device): (Link, Link) = (Link::new(Config::default()), Link::new(Config::default()));
//! let mut got = Vec::new();
//! // No credit has been granted yet: the refused send makes the host probe.
//! assert!(host.send(0, b"hello").is_err());
//! pump(&mut host, &mut device, 0, &mut got); // Probe
//! pump(&mut device, &mut host, 0, &mut got); // Ack granting 8 slots
//! assert_eq!(host.send(1, b"hello"), Ok(0));
//! pump(&mut host, &mut device, 1, &mut got); // Data
//! pump(&mut device, &mut host, 1, &mut got); // Ack
//! assert_eq!(got, [b"hello".to_vec()]);
//! assert_eq!(host.in_flight(), 0);
//! // With nothing in flight there is no timer to serve.
//! assert_eq!(host.next_deadline(), None);
//! ```

use crate::frame::LinkCounters;
use crate::MAX_PAYLOAD;
#[cfg(target_os = "none")]
use crc::{Crc, CRC_32_ISO_HDLC};

/// Bytes of the link header that precedes every payload.
pub const HEADER_LEN: usize = 6;
/// Bytes of the CRC-32 trailer.
pub const CRC_LEN: usize = 4;
/// Largest frame of a [`Small`] link before COBS: header, the largest payload and the CRC.
const MAX_RAW: usize = HEADER_LEN + MAX_PAYLOAD + CRC_LEN;
/// Largest COBS-encoded frame of a [`Small`] link without its delimiter.
const MAX_ENCODED: usize = encoded_len(MAX_PAYLOAD);
/// Worst-case bytes one frame of a [`Small`] link occupies on the wire, including the
/// `0x00` delimiter: the size of the buffer to hand to its [`Link::poll_transmit`] and to
/// [`encode_frame`] for a payload of up to [`MAX_PAYLOAD`] bytes.
pub const MAX_FRAME: usize = MAX_ENCODED + 1;

/// The largest payload of a [`Bulk`] link: 16 KiB, where the per-frame work (a controller
/// poll, an ACK each way, a header, a clock reading) is below a percent of the bytes'
/// own and a frame is still well inside a core's L1/L2 on its way through the copies.
pub const BULK_PAYLOAD: usize = 16 * 1024;

/// COBS-encoded length, without the delimiter, of a frame carrying up to `payload` bytes.
pub const fn encoded_len(payload: usize) -> usize {
    cobs_max_len(HEADER_LEN + payload + CRC_LEN)
}

/// A fixed byte buffer a [`Capacity`] names: any `[u8; N]`.
pub trait Buffer: AsRef<[u8]> + AsMut<[u8]> {
    /// The buffer with every byte zero, a constant so that arrays of slots need no `Copy`.
    const ZERO: Self;
}

impl<const N: usize> Buffer for [u8; N] {
    const ZERO: Self = [0; N];
}

/// How large a [`Link`]'s frames may be: the size of each of its window's slots and of its
/// receive buffer. Both ends of a link must agree on what they send each other; an end
/// never sends a payload longer than its peer accepts, which the application learns from
/// the peer (the hello's [`crate::frame::Caps::link_payload`]) — every end accepts
/// [`MAX_PAYLOAD`].
pub trait Capacity {
    /// The largest payload, in bytes (at most `u16::MAX`).
    const PAYLOAD: usize;
    /// A payload slot: `[u8; PAYLOAD]`.
    type Payload: Buffer;
    /// A frame before COBS, where the encoder gathers header, payload and CRC:
    /// `[u8; HEADER_LEN + PAYLOAD + CRC_LEN]`.
    type Raw: Buffer;
    /// The receive buffer: `[u8; encoded_len(PAYLOAD)]`.
    type Encoded: Buffer;
    /// A buffer that holds any frame this link sends, delimiter included: what
    /// [`Link::poll_transmit`] needs.
    type Frame: Buffer;
}

/// [`MAX_PAYLOAD`]-byte frames: what every end accepts, and what an MCU's RAM affords.
#[derive(Debug, Clone, Copy)]
pub enum Small {}

impl Capacity for Small {
    const PAYLOAD: usize = MAX_PAYLOAD;
    type Payload = [u8; MAX_PAYLOAD];
    type Raw = [u8; MAX_RAW];
    type Encoded = [u8; MAX_ENCODED];
    type Frame = [u8; MAX_FRAME];
}

/// [`BULK_PAYLOAD`]-byte frames, for ends with RAM to spare (a window of 8 holds 256 KiB):
/// a read-back then crosses the link in frames of 16 KiB rather than 256 bytes.
#[derive(Debug, Clone, Copy)]
pub enum Bulk {}

impl Capacity for Bulk {
    const PAYLOAD: usize = BULK_PAYLOAD;
    type Payload = [u8; BULK_PAYLOAD];
    type Raw = [u8; HEADER_LEN + BULK_PAYLOAD + CRC_LEN];
    type Encoded = [u8; encoded_len(BULK_PAYLOAD)];
    type Frame = [u8; encoded_len(BULK_PAYLOAD) + 1];
}

/// On the MCU, where flash is the budget, the 1 KiB byte-wise table; on the MSP430, whose
/// 16-bit address space leaves the firmware short of flash by about that much, no table
/// (bit by bit). All give identical values (`tests/integration/crc.rs` holds the host's
/// to them).
#[cfg(all(target_os = "none", not(target_arch = "msp430")))]
type CrcTable = crc::Table<1>;
#[cfg(all(target_os = "none", target_arch = "msp430"))]
type CrcTable = crc::NoTable;

#[cfg(target_os = "none")]
static TABLE_CRC: Crc<u32, CrcTable> = Crc::<u32, CrcTable>::new(&CRC_32_ISO_HDLC);

/// The link's CRC-32 (ISO-HDLC): every frame's trailer, and the read-back's checksum
/// ([`crate::frame::ReadDone::crc32`]) too, so that a board carries one table, not two.
///
/// On a host it is `crc32fast` (carry-less multiply where the CPU has it, chosen at run
/// time: each read-back byte is checked four times, by the controller's checksum, the
/// link's trailer on both ends and the host's checksum, and a table-driven CRC was a
/// quarter of the built-in target's read-back time); on an MCU the `crc` crate's table
/// sized for the part.
pub static CRC32: Crc32 = Crc32;

/// The type of [`CRC32`]: the same CRC on every target, computed as each target can
/// afford.
#[derive(Debug, Clone, Copy)]
pub struct Crc32;

impl Crc32 {
    /// The CRC of `bytes`.
    pub fn checksum(&self, bytes: &[u8]) -> u32 {
        let mut d = self.digest();
        d.update(bytes);
        d.finalize()
    }

    /// A CRC over bytes that arrive in pieces (a read-back's chunks).
    pub fn digest(&self) -> Crc32Digest {
        #[cfg(not(target_os = "none"))]
        return Crc32Digest(crc32fast::Hasher::new());
        #[cfg(target_os = "none")]
        return Crc32Digest(TABLE_CRC.digest());
    }
}

/// A [`CRC32`] in progress: what [`Crc32::digest`] returns, nameable so that a struct can
/// hold one.
#[derive(Clone)]
pub struct Crc32Digest(
    #[cfg(not(target_os = "none"))] crc32fast::Hasher,
    #[cfg(target_os = "none")] crc::Digest<'static, u32, CrcTable>,
);

impl Crc32Digest {
    /// Adds `bytes` to the checksum.
    pub fn update(&mut self, bytes: &[u8]) {
        self.0.update(bytes);
    }

    /// The CRC of everything added.
    pub fn finalize(self) -> u32 {
        self.0.finalize()
    }
}

/// Why the link refused an operation or a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum LinkError {
    /// A payload longer than the link's [`Capacity::PAYLOAD`] cannot fit a slot.
    #[error("payload of {len} bytes exceeds the maximum of {max}")]
    TooLarge {
        /// The rejected payload length.
        len: usize,
        /// The largest payload the link carries.
        max: usize,
    },
    /// `WINDOW` frames are unacknowledged; retry after ACKs arrive. Nothing was dropped.
    #[error("send window full")]
    WindowFull,
    /// The peer has granted no more receive slots; retry later (the link probes meanwhile).
    #[error("peer granted no credit")]
    NoCredit,
    /// The output buffer cannot hold the encoded frame; [`MAX_FRAME`] always suffices.
    #[error("output buffer too small: need {need} bytes")]
    BufferTooSmall {
        /// Bytes the frame needs.
        need: usize,
    },
    /// COBS decoding failed, the frame was too short or carried an unknown kind.
    #[error("malformed frame")]
    Framing,
    /// The CRC-32 did not match: the frame was corrupted on the way.
    #[error("CRC mismatch")]
    Crc,
}

/// What a frame is for; the low nibble of header byte 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// Carries a payload and a sequence number; must be acknowledged.
    Data = 1,
    /// Cumulative acknowledgement; `seq` holds the SACK bitmap.
    Ack = 2,
    /// Asks for an immediate resend of the frame numbered `seq`.
    Nak = 3,
    /// Sent by a sender the peer has granted no credit; asks for a fresh ACK.
    Probe = 4,
    /// Starts a new epoch; `seq` holds a nonce that the peer echoes.
    Reset = 5,
    /// Confirms a [`Kind::Reset`]; `seq` echoes its nonce.
    ResetAck = 6,
}

impl Kind {
    fn from_nibble(n: u8) -> Option<Self> {
        Some(match n {
            1 => Kind::Data,
            2 => Kind::Ack,
            3 => Kind::Nak,
            4 => Kind::Probe,
            5 => Kind::Reset,
            6 => Kind::ResetAck,
            _ => return None,
        })
    }
}

/// The six header bytes of a link frame, decoded. See the module docs for the layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Header {
    /// What the frame is for.
    pub kind: Kind,
    /// Reset epoch of the sender (0..=15); frames from another epoch are stale.
    pub epoch: u8,
    /// Sequence number, SACK bitmap or nonce, depending on `kind`.
    pub seq: u16,
    /// Next sequence number the sender of this frame expects (cumulative ACK).
    pub ack: u16,
    /// Receive slots, counted from `ack`, granted to the peer.
    pub credit: u8,
}

impl Header {
    /// The wire bytes; the epoch is truncated to its 4 bits.
    pub fn to_bytes(&self) -> [u8; HEADER_LEN] {
        let s = self.seq.to_le_bytes();
        let a = self.ack.to_le_bytes();
        [
            self.kind as u8 | ((self.epoch & 0x0f) << 4),
            s[0],
            s[1],
            a[0],
            a[1],
            self.credit,
        ]
    }

    /// Parses the wire bytes; `None` for an unknown kind.
    pub fn from_bytes(b: &[u8; HEADER_LEN]) -> Option<Self> {
        Some(Header {
            kind: Kind::from_nibble(b[0] & 0x0f)?,
            epoch: b[0] >> 4,
            seq: u16::from_le_bytes([b[1], b[2]]),
            ack: u16::from_le_bytes([b[3], b[4]]),
            credit: b[5],
        })
    }
}

/// Encodes one frame (COBS, CRC and the trailing `0x00`) into `out`; returns its length.
/// Payloads up to [`MAX_PAYLOAD`] bytes, which every end accepts.
///
/// Exposed so that tools and tests can build frames without a [`Link`].
pub fn encode_frame(header: &Header, payload: &[u8], out: &mut [u8]) -> Result<usize, LinkError> {
    encode_frame_in(header, payload, out, &mut [0; MAX_RAW])
}

/// [`encode_frame`] gathering the frame in `raw`, whose length sets the largest payload
/// (a link's [`Capacity::Raw`]).
fn encode_frame_in(
    header: &Header,
    payload: &[u8],
    out: &mut [u8],
    raw: &mut [u8],
) -> Result<usize, LinkError> {
    let max = raw.len() - HEADER_LEN - CRC_LEN;
    if payload.len() > max {
        return Err(LinkError::TooLarge {
            len: payload.len(),
            max,
        });
    }
    let raw_len = HEADER_LEN + payload.len() + CRC_LEN;
    let need = cobs_max_len(raw_len) + 1;
    if out.len() < need {
        return Err(LinkError::BufferTooSmall { need });
    }
    raw[..HEADER_LEN].copy_from_slice(&header.to_bytes());
    raw[HEADER_LEN..HEADER_LEN + payload.len()].copy_from_slice(payload);
    let crc = CRC32.checksum(&raw[..HEADER_LEN + payload.len()]);
    raw[HEADER_LEN + payload.len()..raw_len].copy_from_slice(&crc.to_le_bytes());
    let n = cobs_encode(&raw[..raw_len], out);
    out[n] = 0;
    Ok(n + 1)
}

/// The longest COBS encoding of `len` bytes: one code byte per started 254-byte block.
pub const fn cobs_max_len(len: usize) -> usize {
    len + len / 254 + 1
}

/// COBS (Cheshire and Baker) of `src` into `out` (at least [`cobs_max_len`] long);
/// returns the encoded length. A block at a time: the next zero is found by `memchr`
/// (word- or SIMD-wide) and the block copied whole, where a byte loop cost a read-back
/// ≈ 1.6 ns a byte. The bytes are exactly the `cobs` crate's (a property test holds them).
fn cobs_encode(src: &[u8], out: &mut [u8]) -> usize {
    let mut o = 0;
    let mut i = 0;
    loop {
        let window = &src[i..src.len().min(i + 254)];
        let zero = memchr::memchr(0, window);
        let k = zero.unwrap_or(window.len());
        out[o] = k as u8 + 1;
        out[o + 1..o + 1 + k].copy_from_slice(&window[..k]);
        o += k + 1;
        i += k;
        match zero {
            // the zero is the block's end; the next block starts after it (even if that
            // is the input's end: an empty last block still gets its code)
            Some(_) => {
                i += 1;
                // Zeros right after it (a black span of a frame) each close an empty
                // block: a code 1 apiece, written as one run rather than a block each.
                // Not on the MSP430, whose frames are 256 bytes and whose flash is the
                // budget: the loop does the same a zero at a time.
                #[cfg(not(target_arch = "msp430"))]
                {
                    let z = run_of(&src[i..], 0);
                    out[o..o + z].fill(1);
                    o += z;
                    i += z;
                }
            }
            // a full block with more input behind it: the code 0xFF implies no zero
            None if k == 254 && i < src.len() => {}
            None => return o,
        }
    }
}

/// How many of `bytes` are `b` before the first that is not: 32 at a time (a reduction
/// without an early exit, which vectorises), then byte by byte.
#[cfg(not(target_arch = "msp430"))]
fn run_of(bytes: &[u8], b: u8) -> usize {
    let mut n = 0;
    for c in bytes.chunks_exact(32) {
        if c.iter().fold(0, |acc, &x| acc | (x ^ b)) != 0 {
            break;
        }
        n += 32;
    }
    n + bytes[n..].iter().take_while(|&&x| x == b).count()
}

/// Decodes COBS in place (`buf` holds no zero: the caller checked); returns the decoded
/// length, or None for a block that runs past the end. The inverse of [`cobs_encode`],
/// a block at a time, accepting and refusing what the `cobs` crate does.
fn cobs_decode_in_place(buf: &mut [u8]) -> Option<usize> {
    let (mut r, mut w) = (0, 0);
    while r < buf.len() {
        // Not on the MSP430 (as in the encoder): a code 1 is an empty block below too.
        #[cfg(not(target_arch = "msp430"))]
        if buf[r] == 1 {
            // A run of empty blocks (a run of zeros encoded): one zero each, but for a
            // last block, which ends the frame instead.
            let z = run_of(&buf[r..], 1);
            r += z;
            let zeros = z - usize::from(r == buf.len());
            buf[w..w + zeros].fill(0);
            w += zeros;
            continue;
        }
        let code = usize::from(buf[r]);
        r += 1;
        let n = code.checked_sub(1)?;
        if r + n > buf.len() {
            return None;
        }
        buf.copy_within(r..r + n, w);
        w += n;
        r += n;
        if code < 0xFF && r < buf.len() {
            buf[w] = 0;
            w += 1;
        }
    }
    Some(w)
}

/// Decodes one frame in place: `buf` holds the COBS bytes, with or without the trailing
/// delimiter. Returns the header and the payload (a sub-slice of `buf`). Payloads longer
/// than [`MAX_PAYLOAD`] are refused, as a [`Small`] link refuses them.
pub fn decode_frame(buf: &mut [u8]) -> Result<(Header, &[u8]), LinkError> {
    let (header, len) = decode_in_place(buf, MAX_PAYLOAD)?;
    Ok((header, &buf[HEADER_LEN..HEADER_LEN + len]))
}

/// [`decode_frame`] without the borrow, so the link can copy the payload out of its own
/// receive buffer: returns the header and the payload length (payload at `HEADER_LEN`),
/// refusing payloads longer than `max`.
fn decode_in_place(buf: &mut [u8], max: usize) -> Result<(Header, usize), LinkError> {
    let end = match buf.last() {
        Some(0) => buf.len() - 1,
        _ => buf.len(),
    };
    let encoded = &mut buf[..end];
    // COBS output never contains a zero; one inside means two frames ran together.
    if encoded.is_empty() || memchr::memchr(0, encoded).is_some() {
        return Err(LinkError::Framing);
    }
    let n = cobs_decode_in_place(encoded).ok_or(LinkError::Framing)?;
    if n < HEADER_LEN + CRC_LEN {
        return Err(LinkError::Framing);
    }
    let body = n - CRC_LEN;
    let mut crc = [0u8; CRC_LEN];
    crc.copy_from_slice(&encoded[body..n]);
    if CRC32.checksum(&encoded[..body]) != u32::from_le_bytes(crc) {
        return Err(LinkError::Crc);
    }
    let mut h = [0u8; HEADER_LEN];
    h.copy_from_slice(&encoded[..HEADER_LEN]);
    let header = Header::from_bytes(&h).ok_or(LinkError::Framing)?;
    let len = body - HEADER_LEN;
    if len > max || (len > 0 && header.kind != Kind::Data) {
        return Err(LinkError::Framing);
    }
    Ok((header, len))
}

/// Timing and flow-control parameters. All times are in the caller's milliseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// Resend a data frame (or a Reset) not acknowledged after this long. Must exceed the
    /// time to send a whole window plus the ACK: 8 full frames take ~190 ms at 115 200 baud.
    pub rto_ms: u64,
    /// After a NAK, do not NAK the same missing frame again for this long, so one loss
    /// costs one resend rather than one per later frame that reveals the gap.
    pub nak_holdoff_ms: u64,
    /// How often a sender without credit probes the peer for a window update.
    pub probe_ms: u64,
    /// Frames the application can accept; the link advertises `min(WINDOW, rx_credit)`.
    /// `u8::MAX` means the window is the only limit. Change it with [`Link::set_rx_credit`].
    pub rx_credit: u8,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            rto_ms: 500,
            nak_holdoff_ms: 250,
            probe_ms: 200,
            rx_credit: u8::MAX,
        }
    }
}

/// Something the application must act on, returned by [`Link::handle_input`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event<'a> {
    /// The next payload in order; it borrows the link's buffer until the next call.
    Data(&'a [u8]),
    /// The reset this end started with [`Link::reset`] was confirmed by the peer.
    Synced,
    /// The peer started a new epoch: this end's unacknowledged frames were discarded
    /// (the application must resend what still matters) and sequence numbers restart.
    PeerReset {
        /// Frames this end had queued or in flight that were dropped.
        discarded: u16,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TxState {
    /// Accepted by `send`, not yet on the wire.
    Unsent,
    /// On the wire, waiting for an ACK.
    InFlight,
}

struct TxSlot<C: Capacity> {
    state: TxState,
    /// The receiver holds it (SACK) but has not passed it cumulatively: never resend.
    sacked: bool,
    /// Resend at the next `poll_transmit` (NAK or timeout).
    resend: bool,
    sent_at: u64,
    len: u16,
    buf: C::Payload,
}

impl<C: Capacity> TxSlot<C> {
    const EMPTY: Self = TxSlot {
        state: TxState::Unsent,
        sacked: false,
        resend: false,
        sent_at: 0,
        len: 0,
        buf: C::Payload::ZERO,
    };
}

struct RxSlot<C: Capacity> {
    full: bool,
    seq: u16,
    len: u16,
    buf: C::Payload,
}

impl<C: Capacity> RxSlot<C> {
    const EMPTY: Self = RxSlot {
        full: false,
        seq: 0,
        len: 0,
        buf: C::Payload::ZERO,
    };
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pending {
    Synced,
    PeerReset(u16),
}

/// One end of a reliable link with a window of `WINDOW` frames of up to `C::PAYLOAD`
/// bytes ([`Small`] by default).
///
/// `WINDOW` must be a power of two (so that slot = seq mod WINDOW stays consistent when the
/// u16 sequence number wraps) between 4 and 128 (so that "ahead" and "behind" are never
/// ambiguous and the credit fits a byte); other values fail to compile:
///
/// ```compile_fail,E0080
/// let link = protocol::link::Link::<6>::new(Default::default());
/// ```
pub struct Link<const WINDOW: usize = 8, C: Capacity = Small> {
    config: Config,
    epoch: u8,
    counters: LinkCounters,
    // Transmit side.
    tx: [TxSlot<C>; WINDOW],
    /// Oldest unacknowledged sequence number.
    tx_base: u16,
    /// Sequence number the next `send` gets.
    tx_next: u16,
    /// First sequence number the peer has not granted (its ack + its credit).
    tx_limit: u16,
    /// `send` failed for lack of credit: probe until credit arrives.
    blocked: bool,
    probe_due: bool,
    last_probe: Option<u64>,
    // Receive side.
    rx: [RxSlot<C>; WINDOW],
    /// Next sequence number to deliver.
    rx_next: u16,
    rx_credit: u8,
    ack_due: bool,
    nak_due: Option<u16>,
    /// The last NAK sent: the seq and when.
    last_nak: Option<(u16, u64)>,
    // Byte stream reassembly.
    raw: C::Encoded,
    raw_len: usize,
    /// A frame overflowed `raw`: skip to the next delimiter.
    discarding: bool,
    // Reset handshake.
    /// Our Reset awaiting its ResetAck: nonce and last send time (None: send now).
    reset_pending: Option<(u16, Option<u64>)>,
    /// The peer's Reset we accepted last (epoch, nonce), to recognise its repeats.
    peer_reset: Option<(u8, u16)>,
    reset_ack_due: Option<u16>,
    pending: Option<Pending>,
}

impl<const WINDOW: usize, C: Capacity> Link<WINDOW, C> {
    const WINDOW_OK: () = assert!(
        WINDOW.is_power_of_two() && WINDOW >= 4 && WINDOW <= 128,
        "Link WINDOW must be a power of two in 4..=128"
    );
    // Every end accepts MAX_PAYLOAD; a slot's length is a u16; the buffers are the sizes
    // the capacity promises.
    const CAPACITY_OK: () = assert!(
        C::PAYLOAD >= MAX_PAYLOAD
            && C::PAYLOAD <= u16::MAX as usize
            && core::mem::size_of::<C::Payload>() == C::PAYLOAD
            && core::mem::size_of::<C::Raw>() == HEADER_LEN + C::PAYLOAD + CRC_LEN
            && core::mem::size_of::<C::Encoded>() == encoded_len(C::PAYLOAD)
            && core::mem::size_of::<C::Frame>() == encoded_len(C::PAYLOAD) + 1,
        "Link capacity: PAYLOAD in MAX_PAYLOAD..=65535 and buffers of the sizes it implies"
    );

    /// The largest payload this link carries ([`Capacity::PAYLOAD`]).
    pub const PAYLOAD: usize = C::PAYLOAD;

    /// A link in epoch 0 with sequence numbers at 0 and no credit from the peer yet (the
    /// first `send` makes it probe). Both ends of a fresh connection can start this way;
    /// an end that restarts while its peer keeps running must call [`Link::reset`].
    pub fn new(config: Config) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::WINDOW_OK;
        #[allow(clippy::let_unit_value)]
        let () = Self::CAPACITY_OK;
        Link {
            config,
            epoch: 0,
            counters: LinkCounters::default(),
            tx: [TxSlot::EMPTY; WINDOW],
            tx_base: 0,
            tx_next: 0,
            tx_limit: 0,
            blocked: false,
            probe_due: false,
            last_probe: None,
            rx: [RxSlot::EMPTY; WINDOW],
            rx_next: 0,
            rx_credit: config.rx_credit,
            ack_due: false,
            nak_due: None,
            last_nak: None,
            raw: C::Encoded::ZERO,
            raw_len: 0,
            discarding: false,
            reset_pending: None,
            peer_reset: None,
            reset_ack_due: None,
            pending: None,
        }
    }

    /// Frames queued or in flight, not yet acknowledged.
    pub fn in_flight(&self) -> usize {
        usize::from(self.tx_next.wrapping_sub(self.tx_base))
    }

    fn credit_left(&self) -> bool {
        // tx_next is before tx_limit in modular order.
        let d = self.tx_limit.wrapping_sub(self.tx_next);
        d != 0 && d < 0x8000
    }

    /// Whether [`Link::send`] would accept a frame now.
    pub fn can_send(&self) -> bool {
        self.reset_pending.is_none() && self.in_flight() < WINDOW && self.credit_left()
    }

    /// The counters so far (for [`crate::frame::Stats`]).
    pub fn counters(&self) -> LinkCounters {
        self.counters
    }

    /// The 4-bit epoch this end is in.
    pub fn epoch(&self) -> u8 {
        self.epoch
    }

    fn slot(seq: u16) -> usize {
        usize::from(seq) & (WINDOW - 1)
    }

    /// Queues `payload` for transmission and returns its sequence number. The payload is
    /// copied, so the caller's buffer is free at once. On error nothing was queued: the
    /// caller keeps the payload and retries after more input or a timeout.
    pub fn send(&mut self, now_ms: u64, payload: &[u8]) -> Result<u16, LinkError> {
        if payload.len() > C::PAYLOAD {
            return Err(LinkError::TooLarge {
                len: payload.len(),
                max: C::PAYLOAD,
            });
        }
        let slot = self.claim(now_ms)?;
        slot.len = payload.len() as u16;
        slot.buf.as_mut()[..payload.len()].copy_from_slice(payload);
        Ok(self.commit())
    }

    /// [`Link::send`] of a payload written in place: `fill` gets the next slot's
    /// [`Capacity::PAYLOAD`] bytes and returns how many it wrote, so a large payload (a
    /// read-back chunk) is produced where it is sent from instead of copied there. The
    /// outer error is the link's (nothing was called, nothing queued: retry later); the
    /// inner one is `fill`'s (nothing queued either). A length past the slot is a bug in
    /// `fill`, refused as [`LinkError::TooLarge`].
    pub fn send_with<E>(
        &mut self,
        now_ms: u64,
        fill: impl FnOnce(&mut [u8]) -> Result<usize, E>,
    ) -> Result<Result<u16, E>, LinkError> {
        let slot = self.claim(now_ms)?;
        let len = match fill(slot.buf.as_mut()) {
            Ok(len) => len,
            Err(e) => return Ok(Err(e)),
        };
        if len > C::PAYLOAD {
            return Err(LinkError::TooLarge {
                len,
                max: C::PAYLOAD,
            });
        }
        slot.len = len as u16;
        Ok(Ok(self.commit()))
    }

    /// The slot the next send fills, once window, reset and credit allow one; starts
    /// probing when the peer's credit is what is missing.
    fn claim(&mut self, now_ms: u64) -> Result<&mut TxSlot<C>, LinkError> {
        if self.in_flight() >= WINDOW {
            return Err(LinkError::WindowFull);
        }
        if self.reset_pending.is_some() {
            return Err(LinkError::NoCredit);
        }
        if !self.credit_left() {
            if !self.blocked {
                self.blocked = true;
                self.probe_due = match self.last_probe {
                    None => true,
                    Some(t) => now_ms >= t.saturating_add(self.config.probe_ms),
                };
            }
            return Err(LinkError::NoCredit);
        }
        let slot = &mut self.tx[Self::slot(self.tx_next)];
        slot.state = TxState::Unsent;
        slot.sacked = false;
        slot.resend = false;
        Ok(slot)
    }

    /// Queues the slot [`Link::claim`] gave out; returns its sequence number.
    fn commit(&mut self) -> u16 {
        let seq = self.tx_next;
        self.tx_next = seq.wrapping_add(1);
        seq
    }

    /// Credit this end advertises: free slots from `rx_next`.
    fn advertised(&self) -> u8 {
        // WINDOW <= 128, so the minimum fits a byte.
        self.rx_credit.min(WINDOW as u8)
    }

    /// Sets how many frames the application can accept (e.g. its free queue slots, after
    /// it queued or executed one). Raising it sends a window update at once.
    pub fn set_rx_credit(&mut self, n: u8) {
        let before = self.advertised();
        self.rx_credit = n;
        if self.advertised() > before {
            self.ack_due = true;
        }
    }

    /// Starts a new epoch: discards every queued and in-flight frame of both directions,
    /// restarts sequence numbers at 0 and sends a Reset (repeated every `rto_ms`) until
    /// the peer confirms it, which [`Event::Synced`] reports. `nonce` tells this reset from
    /// older ones (a counter or random value). Returns the number of frames discarded.
    pub fn reset(&mut self, _now_ms: u64, nonce: u16) -> u16 {
        let discarded = self.in_flight() as u16;
        self.clear_state();
        self.epoch = (self.epoch + 1) & 0x0f;
        self.reset_pending = Some((nonce, None));
        self.counters.resets += 1;
        discarded
    }

    fn clear_state(&mut self) {
        self.tx_base = 0;
        self.tx_next = 0;
        self.tx_limit = 0;
        self.blocked = false;
        self.probe_due = false;
        self.last_probe = None;
        for s in self.rx.iter_mut() {
            s.full = false;
        }
        self.rx_next = 0;
        self.ack_due = false;
        self.nak_due = None;
        self.last_nak = None;
        self.reset_pending = None;
        self.reset_ack_due = None;
        self.pending = None;
    }

    /// Feeds received bytes. Returns how many of `bytes` were consumed and, if something
    /// happened, the event. Call it again with the rest (and finally with an empty slice)
    /// until it returns `None`; only then have all bytes been consumed. Delivered payloads
    /// borrow the link's receive buffer, which is why one call yields at most one event.
    pub fn handle_input(&mut self, now_ms: u64, bytes: &[u8]) -> (usize, Option<Event<'_>>) {
        if let Some(p) = self.pending.take() {
            return (0, Some(Self::pending_event(p)));
        }
        let mut used = 0;
        if !self.deliverable() {
            // A run of frame bytes at a time up to the next delimiter (bulk copies, not a
            // byte loop: a read-back streams megabytes through here).
            while used < bytes.len() {
                let rest = &bytes[used..];
                let run = memchr::memchr(0, rest).unwrap_or(rest.len());
                self.push_run(&rest[..run]);
                used += run;
                if run == rest.len() {
                    break;
                }
                used += 1;
                if self.end_of_frame(now_ms) {
                    break;
                }
            }
            if let Some(p) = self.pending.take() {
                return (used, Some(Self::pending_event(p)));
            }
        }
        if self.deliverable() {
            let i = Self::slot(self.rx_next);
            self.rx[i].full = false;
            self.rx_next = self.rx_next.wrapping_add(1);
            self.counters.delivered += 1;
            let slot = &self.rx[i];
            return (
                used,
                Some(Event::Data(&slot.buf.as_ref()[..usize::from(slot.len)])),
            );
        }
        (used, None)
    }

    fn pending_event(p: Pending) -> Event<'static> {
        match p {
            Pending::Synced => Event::Synced,
            Pending::PeerReset(discarded) => Event::PeerReset { discarded },
        }
    }

    fn deliverable(&self) -> bool {
        let s = &self.rx[Self::slot(self.rx_next)];
        s.full && s.seq == self.rx_next
    }

    /// Adds a run of non-zero bytes to the frame being received. More than the largest
    /// encoded frame is an overflow: counted once, and the frame is discarded up to its
    /// delimiter.
    fn push_run(&mut self, run: &[u8]) {
        if run.is_empty() || self.discarding {
            return;
        }
        let end = self.raw_len + run.len();
        match self.raw.as_mut().get_mut(self.raw_len..end) {
            Some(dst) => {
                dst.copy_from_slice(run);
                self.raw_len = end;
            }
            _ => {
                self.counters.overflows += 1;
                self.discarding = true;
                self.raw_len = 0;
            }
        }
    }

    /// The delimiter: decodes the frame received since the last one; returns true when it
    /// produced something to report. Never inlined: in the caller's byte loop it left the
    /// MSP430's 16 registers short, and the spills cost 0.5 KB of its flash.
    #[inline(never)]
    fn end_of_frame(&mut self, now_ms: u64) -> bool {
        let len = core::mem::take(&mut self.raw_len);
        if core::mem::take(&mut self.discarding) || len == 0 {
            return false;
        }
        match decode_in_place(&mut self.raw.as_mut()[..len], C::PAYLOAD) {
            Err(LinkError::Crc) => {
                self.counters.crc_errors += 1;
                false
            }
            Err(_) => {
                self.counters.framing_errors += 1;
                false
            }
            Ok((header, plen)) => self.on_frame(now_ms, header, plen),
        }
    }

    /// Handles a valid frame whose payload sits at `raw[HEADER_LEN..][..plen]`.
    fn on_frame(&mut self, now_ms: u64, h: Header, plen: usize) -> bool {
        match h.kind {
            Kind::Reset => return self.on_reset(h),
            Kind::ResetAck => {
                if let Some((nonce, _)) = self.reset_pending {
                    if h.seq == nonce && h.epoch == self.epoch {
                        self.reset_pending = None;
                        self.tx_limit = h.ack.wrapping_add(u16::from(h.credit));
                        self.pending = Some(Pending::Synced);
                        return true;
                    }
                }
                self.counters.stale += 1;
                return false;
            }
            _ => {}
        }
        if h.epoch != self.epoch {
            self.counters.stale += 1;
            return false;
        }
        self.on_ack(h);
        match h.kind {
            Kind::Data => self.on_data(now_ms, h.seq, plen),
            Kind::Nak => {
                let off = h.seq.wrapping_sub(self.tx_base);
                if usize::from(off) < self.in_flight() {
                    let s = &mut self.tx[Self::slot(h.seq)];
                    if s.state == TxState::InFlight && !s.sacked {
                        s.resend = true;
                    }
                }
            }
            Kind::Probe => self.ack_due = true,
            _ => {}
        }
        self.deliverable()
    }

    /// The cumulative ACK, credit and (for Ack frames) SACK bitmap of any current-epoch frame.
    fn on_ack(&mut self, h: Header) {
        let adv = h.ack.wrapping_sub(self.tx_base);
        if usize::from(adv) > self.in_flight() {
            // Acknowledges frames never sent: corrupted past the CRC or from a confused
            // peer; trusting its credit could overrun the peer.
            return;
        }
        self.tx_base = h.ack;
        self.tx_limit = h.ack.wrapping_add(u16::from(h.credit));
        if self.credit_left() {
            self.blocked = false;
            self.probe_due = false;
        }
        if h.kind == Kind::Ack {
            for i in 0..16u16 {
                if h.seq & (1 << i) == 0 {
                    continue;
                }
                let seq = h.ack.wrapping_add(1 + i);
                if usize::from(seq.wrapping_sub(self.tx_base)) < self.in_flight() {
                    let s = &mut self.tx[Self::slot(seq)];
                    if s.state == TxState::InFlight {
                        s.sacked = true;
                        s.resend = false;
                    }
                }
            }
        }
    }

    fn on_data(&mut self, now_ms: u64, seq: u16, plen: usize) {
        self.ack_due = true;
        let off = seq.wrapping_sub(self.rx_next);
        if off >= 0x8000 {
            // Behind the cumulative point: already delivered.
            self.counters.duplicates += 1;
            return;
        }
        let i = Self::slot(seq);
        if usize::from(off) < WINDOW && self.rx[i].full && self.rx[i].seq == seq {
            self.counters.duplicates += 1;
            return;
        }
        if off >= u16::from(self.advertised()) {
            // Past the credit we granted: refuse it (no ACK for it); the sender resends
            // once a window update lets it.
            self.counters.overflows += 1;
            return;
        }
        let slot = &mut self.rx[i];
        slot.full = true;
        slot.seq = seq;
        slot.len = plen as u16;
        slot.buf.as_mut()[..plen]
            .copy_from_slice(&self.raw.as_ref()[HEADER_LEN..HEADER_LEN + plen]);
        if off > 0 && !self.rx[Self::slot(self.rx_next)].full {
            let missing = self.rx_next;
            let held_off = matches!(self.last_nak,
                Some((s, t)) if s == missing && now_ms < t.saturating_add(self.config.nak_holdoff_ms));
            if !held_off {
                self.nak_due = Some(missing);
                self.last_nak = Some((missing, now_ms));
            }
        }
    }

    fn on_reset(&mut self, h: Header) -> bool {
        if self.peer_reset == Some((h.epoch, h.seq)) {
            // A repeat: our ResetAck was lost. Confirm again if we are still there.
            if self.epoch == h.epoch {
                self.reset_ack_due = Some(h.seq);
            } else {
                self.counters.stale += 1;
            }
            return false;
        }
        if let Some((own, _)) = self.reset_pending {
            // Both ends reset at once: the larger nonce wins, the other end adopts it.
            if own >= h.seq {
                return false;
            }
        }
        let discarded = self.in_flight() as u16;
        self.clear_state();
        self.epoch = h.epoch & 0x0f;
        self.tx_limit = h.ack.wrapping_add(u16::from(h.credit));
        self.peer_reset = Some((self.epoch, h.seq));
        self.reset_ack_due = Some(h.seq);
        self.counters.resets += 1;
        self.pending = Some(Pending::PeerReset(discarded));
        true
    }

    /// Writes the next frame to send into `out` (at least [`Capacity::Frame`]'s size,
    /// [`MAX_FRAME`] for a [`Small`] link) and returns its length, or `None` when nothing
    /// is due (or `out` is too small for the frame that is). Call it until it returns `None` after
    /// every [`Link::send`], [`Link::handle_input`] and [`Link::handle_timeout`].
    pub fn poll_transmit(&mut self, now_ms: u64, out: &mut [u8]) -> Option<usize> {
        let credit = self.advertised();
        let mut header = Header {
            kind: Kind::Ack,
            epoch: self.epoch,
            seq: 0,
            ack: self.rx_next,
            credit,
        };
        if let Some((nonce, sent)) = self.reset_pending {
            if sent.is_none() {
                header.kind = Kind::Reset;
                header.seq = nonce;
                header.ack = 0;
                let n = encode_frame(&header, &[], out).ok()?;
                self.reset_pending = Some((nonce, Some(now_ms)));
                return Some(n);
            }
        }
        if let Some(nonce) = self.reset_ack_due {
            header.kind = Kind::ResetAck;
            header.seq = nonce;
            let n = encode_frame(&header, &[], out).ok()?;
            self.reset_ack_due = None;
            return Some(n);
        }
        if self.reset_pending.is_some() {
            return None;
        }
        if let Some(missing) = self.nak_due {
            header.kind = Kind::Nak;
            header.seq = missing;
            let n = encode_frame(&header, &[], out).ok()?;
            self.nak_due = None;
            self.counters.naks += 1;
            return Some(n);
        }
        if self.ack_due {
            header.seq = self.sack_bitmap();
            let n = encode_frame(&header, &[], out).ok()?;
            self.ack_due = false;
            return Some(n);
        }
        // Resends first (oldest first), then new frames, both in sequence order.
        let mut seq = self.tx_base;
        while seq != self.tx_next {
            let i = Self::slot(seq);
            let s = &self.tx[i];
            let first = s.state == TxState::Unsent;
            if first || s.resend {
                header.kind = Kind::Data;
                header.seq = seq;
                let payload = &s.buf.as_ref()[..usize::from(s.len)];
                let mut raw = C::Raw::ZERO;
                let n = encode_frame_in(&header, payload, out, raw.as_mut()).ok()?;
                let s = &mut self.tx[i];
                s.state = TxState::InFlight;
                s.resend = false;
                s.sent_at = now_ms;
                if first {
                    self.counters.sent += 1;
                } else {
                    self.counters.resent += 1;
                }
                return Some(n);
            }
            seq = seq.wrapping_add(1);
        }
        if self.probe_due {
            header.kind = Kind::Probe;
            header.seq = self.tx_next;
            let n = encode_frame(&header, &[], out).ok()?;
            self.probe_due = false;
            self.last_probe = Some(now_ms);
            return Some(n);
        }
        None
    }

    /// Bit i set: frame `rx_next + 1 + i` is held.
    fn sack_bitmap(&self) -> u16 {
        let mut bits = 0u16;
        for i in 0..16u16.min(WINDOW as u16 - 1) {
            let seq = self.rx_next.wrapping_add(1 + i);
            let s = &self.rx[Self::slot(seq)];
            if s.full && s.seq == seq {
                bits |= 1 << i;
            }
        }
        bits
    }

    /// Fires the timers that are due at `now_ms`: resends of unacknowledged frames, the
    /// Reset repeat and the credit probe. Call it when [`Link::next_deadline`] passes (or
    /// simply every few milliseconds), then drain [`Link::poll_transmit`].
    pub fn handle_timeout(&mut self, now_ms: u64) {
        if let Some((nonce, Some(t))) = self.reset_pending {
            if now_ms >= t.saturating_add(self.config.rto_ms) {
                self.reset_pending = Some((nonce, None));
                self.counters.timeouts += 1;
            }
            return;
        }
        let mut seq = self.tx_base;
        while seq != self.tx_next {
            let s = &mut self.tx[Self::slot(seq)];
            if s.state == TxState::InFlight
                && !s.sacked
                && !s.resend
                && now_ms >= s.sent_at.saturating_add(self.config.rto_ms)
            {
                s.resend = true;
                self.counters.timeouts += 1;
            }
            seq = seq.wrapping_add(1);
        }
        if self.blocked && !self.credit_left() {
            if let Some(t) = self.last_probe {
                if now_ms >= t.saturating_add(self.config.probe_ms) {
                    self.probe_due = true;
                }
            }
        }
    }

    /// The earliest time [`Link::handle_timeout`] has something to do, if any.
    pub fn next_deadline(&self) -> Option<u64> {
        if let Some((_, sent)) = self.reset_pending {
            return sent.map(|t| t.saturating_add(self.config.rto_ms));
        }
        let mut next: Option<u64> = None;
        let mut seq = self.tx_base;
        while seq != self.tx_next {
            let s = &self.tx[Self::slot(seq)];
            if s.state == TxState::InFlight && !s.sacked && !s.resend {
                let t = s.sent_at.saturating_add(self.config.rto_ms);
                next = Some(next.map_or(t, |n| n.min(t)));
            }
            seq = seq.wrapping_add(1);
        }
        if self.blocked && !self.probe_due {
            if let Some(t) = self.last_probe {
                let t = t.saturating_add(self.config.probe_ms);
                next = Some(next.map_or(t, |n| n.min(t)));
            }
        }
        next
    }
}

#[cfg(test)]
mod cobs_codec {
    //! The link's COBS codec against the `cobs` crate, the oracle it replaced on the wire.
    extern crate std;
    use super::{cobs_decode_in_place, cobs_encode, cobs_max_len, MAX_RAW};
    use proptest::prelude::*;
    use std::{vec, vec::Vec};

    /// The `cobs` crate's encoding of `src`.
    fn crate_encoding(src: &[u8]) -> Vec<u8> {
        let mut out = vec![0u8; cobs::max_encoding_length(src.len())];
        let n = cobs::encode(src, &mut out);
        out.truncate(n);
        out
    }

    /// Bytes with zeros at every density and runs around the 254-byte block limit.
    fn bytes() -> impl Strategy<Value = Vec<u8>> {
        prop_oneof![
            proptest::collection::vec(any::<u8>(), 0..=MAX_RAW),
            proptest::collection::vec(prop_oneof![Just(0u8), 1u8..=255], 0..=MAX_RAW),
            (0usize..=MAX_RAW, 240usize..=270, any::<u8>()).prop_map(|(len, run, fill)| {
                let mut v = vec![fill | 1; len];
                for i in (run..len).step_by(run + 1) {
                    v[i] = 0;
                }
                v
            }),
        ]
    }

    #[test]
    fn block_edges_encode_as_the_crate_does() {
        for len in [0, 1, 253, 254, 255, 507, 508, 509, MAX_RAW] {
            for zero_at in [
                None,
                Some(0),
                Some(253),
                Some(254),
                Some(len.saturating_sub(1)),
            ] {
                let mut src = vec![7u8; len];
                if let Some(z) = zero_at.filter(|z| *z < len) {
                    src[z] = 0;
                }
                let mut ours = vec![0u8; cobs_max_len(len)];
                let n = cobs_encode(&src, &mut ours);
                assert_eq!(
                    ours[..n],
                    crate_encoding(&src)[..],
                    "len {len}, zero {zero_at:?}"
                );
            }
        }
    }

    /// Runs of zeros (a frame's black spans) between runs of other bytes, past the
    /// 32-byte steps of `run_of` and the 254-byte blocks.
    fn zero_runs() -> impl Strategy<Value = Vec<u8>> {
        proptest::collection::vec((0usize..600, 0usize..300, 1u8..=255), 0..12).prop_map(|runs| {
            let mut v = Vec::new();
            for (zeros, others, fill) in runs {
                v.resize(v.len() + zeros, 0);
                v.resize(v.len() + others, fill);
            }
            v
        })
    }

    proptest! {
        #[test]
        fn zero_runs_encode_as_the_crate_does_and_decode_back(src in zero_runs()) {
            let mut ours = vec![0u8; cobs_max_len(src.len())];
            let n = cobs_encode(&src, &mut ours);
            prop_assert_eq!(&ours[..n], &crate_encoding(&src)[..]);
            let mut back = ours[..n].to_vec();
            prop_assert_eq!(cobs_decode_in_place(&mut back), Some(src.len()));
            prop_assert_eq!(&back[..src.len()], &src[..]);
        }

        #[test]
        fn runs_of_empty_blocks_decode_as_the_crate_does(
            enc in proptest::collection::vec(prop_oneof![4 => Just(1u8), 1 => 1u8..=255], 1..2000)
        ) {
            let mut ours = enc.clone();
            let mut theirs = enc.clone();
            let a = cobs_decode_in_place(&mut ours);
            prop_assert_eq!(a, cobs::decode_in_place(&mut theirs).ok());
            if let Some(n) = a {
                prop_assert_eq!(&ours[..n], &theirs[..n]);
            }
        }

        #[test]
        fn encoding_is_the_crates_and_decodes_back(src in bytes()) {
            let mut ours = vec![0u8; cobs_max_len(src.len())];
            let n = cobs_encode(&src, &mut ours);
            prop_assert_eq!(&ours[..n], &crate_encoding(&src)[..]);
            prop_assert!(!ours[..n].contains(&0));
            let mut back = ours[..n].to_vec();
            let m = cobs_decode_in_place(&mut back);
            prop_assert_eq!(m, Some(src.len()));
            prop_assert_eq!(&back[..src.len()], &src[..]);
        }

        #[test]
        fn decoding_accepts_and_refuses_as_the_crate_does(
            enc in proptest::collection::vec(1u8..=255, 1..600)
        ) {
            let mut ours = enc.clone();
            let mut theirs = enc.clone();
            let a = cobs_decode_in_place(&mut ours);
            let b = cobs::decode_in_place(&mut theirs).ok();
            prop_assert_eq!(a, b);
            if let Some(n) = a {
                prop_assert_eq!(&ours[..n], &theirs[..n]);
            }
        }
    }
}
