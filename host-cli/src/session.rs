//! The host end of the link: one [`Session`] per target, over any byte [`Transport`]
//! (the built-in in-process target, a pseudo-terminal, a USB UART).
//!
//! Everything above this module speaks [`HostFrame`] / [`DeviceFrame`]; everything
//! below is bytes. Errors the target reports are mapped back to what the user asked for
//! (each request is remembered by its link sequence number with a description, e.g.
//! `cmd[12] (triangle)`), so a refusal says which line of which file caused it.

use std::collections::{HashMap, VecDeque};
use std::io;
use std::time::{Duration, Instant};

use protocol::frame::{
    chunk_view, decode, encode, Caps, DeviceFrame, ErrorReport, Hello, HostFrame, ReadRequest,
};
use protocol::link::{Buffer, Bulk, Capacity, Crc32Digest, Event, Link, LinkError};
use protocol::MAX_PAYLOAD;

/// Application bytes moved in one direction and how long it took, for throughput figures
/// (a link's speed, apart from the time the target spends computing).
#[derive(Debug, Clone, Copy, Default)]
pub struct Phase {
    /// Encoded messages (host → target) or pixel bytes (target → host).
    pub payload_bytes: u64,
    /// Wall time the phase took, the divisor of its throughput.
    pub time: Duration,
}

impl Phase {
    /// Payload bytes per second.
    pub fn rate(&self) -> f64 {
        self.payload_bytes as f64 / self.time.as_secs_f64().max(1e-9)
    }
}

/// A byte pipe to a target.
pub trait Transport {
    /// Writes all of `bytes`.
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()>;
    /// Reads what has arrived, waiting at most `timeout` for the first byte; `Ok(0)`
    /// means nothing came.
    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize>;
}

/// What can go wrong talking to a target.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// The transport's read or write failed (port unplugged, peer closed, OS error).
    #[error("the transport failed")]
    Io(#[from] io::Error),
    /// No progress for too long.
    #[error("the target did not answer within {0:?} (is the port right and the board running?)")]
    Timeout(Duration),
    /// Nothing usable came back to the handshake: says what was sent and what, if
    /// anything, arrived, which tells a dead line from a wrong baud rate or another
    /// program on the port.
    #[error(
        "no answer to the handshake within {waited:?}: sent {sent} bytes (link reset + hello), \
         received {received} bytes{sample}"
    )]
    NoAnswer {
        /// How long we waited.
        waited: Duration,
        /// Bytes written to the transport for the handshake.
        sent: u64,
        /// Bytes that came back, usable or not.
        received: u64,
        /// The first bytes read, in hex, with a diagnosis, or empty.
        sample: String,
    },
    /// The target stopped answering in the middle of a job.
    #[error("the target stopped answering {during} ({progress}); no byte for {waited:?}")]
    Stalled {
        /// What the session was doing, as a phrase for the message ("in a read-back").
        during: &'static str,
        /// How far it got.
        progress: String,
        /// How long we waited.
        waited: Duration,
    },
    /// The handshake failed; the message names both sides' versions.
    #[error("handshake with {peer:?} failed")]
    Handshake {
        /// The target's identification.
        peer: String,
        /// Which values differ.
        source: protocol::frame::HandshakeError,
    },
    /// The target refused a request.
    #[error("the target refused {what}: {code:?} (at index {index})")]
    Refused {
        /// The request, as the caller described it.
        what: String,
        /// The target's reason.
        code: protocol::frame::ErrorCode,
        /// Where inside the request.
        index: u32,
    },
    /// A message from the target did not decode.
    #[error("malformed answer from the target: {0}")]
    Malformed(protocol::frame::CodecError),
    /// A message that cannot be sent (a bug in the caller: batches are sized to fit).
    #[error("request does not fit in a frame: {0}")]
    Encode(protocol::frame::CodecError),
    /// An answer that makes no sense at this point.
    #[error("unexpected answer from the target: {0}")]
    Unexpected(String),
    /// The job needs what the target's `Caps` say it does not have; refused before
    /// anything is sent. The text names the target and, for a command, its place in the
    /// file.
    #[error("{0}")]
    Unsupported(String),
    /// A read-back whose length or CRC does not match what the target announced.
    #[error("read-back corrupt: {0}")]
    ReadBack(String),
}

/// Describes a request for error messages: called with the index the target reports.
pub type Describe = Box<dyn Fn(u32) -> String>;

/// The host's link: it accepts [`Bulk`] frames (and says so in its hello), so a target
/// that can send them reads back in 16 KiB chunks; it sends [`MAX_PAYLOAD`]-byte ones,
/// which every target accepts.
type HostLink = Link<8, Bulk>;

/// Bytes taken from the transport at a time: several bulk frames.
const READ_BUF: usize = 64 * 1024;

/// A read-back being received: chunks go straight here from the link's buffer (a bulk
/// chunk is larger than a [`DeviceFrame`] holds), checked for order and length on the way.
struct ReadSink {
    data: Vec<u8>,
    expected: usize,
    crc: Crc32Digest,
    /// The first thing wrong with the chunks; the rest is ignored and this reported.
    error: Option<String>,
}

impl ReadSink {
    fn take(&mut self, offset: u32, bytes: &[u8]) {
        if self.error.is_some() {
            return;
        }
        if offset as usize != self.data.len() {
            self.error = Some(format!(
                "chunk at offset {offset} where {} was expected",
                self.data.len()
            ));
        } else if self.data.len() + bytes.len() > self.expected {
            self.error = Some(format!(
                "chunk of {} bytes at offset {offset} runs past the {} bytes requested",
                bytes.len(),
                self.expected
            ));
        } else {
            self.data.extend_from_slice(bytes);
            // The checksum grows with the chunks, while each is still in cache.
            self.crc.update(bytes);
        }
    }
}

/// The host end of one connection.
pub struct Session<T: Transport> {
    transport: T,
    /// Boxed: a window of bulk frames each way is 280 KiB.
    link: Box<HostLink>,
    /// Where frames to send are encoded, and where transport bytes are read to.
    out: Box<<Bulk as Capacity>::Frame>,
    input: Box<[u8; READ_BUF]>,
    epoch: Instant,
    requests: HashMap<u16, Describe>,
    inbox: VecDeque<DeviceFrame>,
    reading: Option<ReadSink>,
    /// Give up when nothing moves for this long.
    pub timeout: Duration,
    next_token: u32,
    peer: Option<Hello>,
    traffic: Traffic,
}

/// Bytes that crossed the transport, for throughput figures and error messages.
#[derive(Debug, Clone, Default)]
pub struct Traffic {
    /// Bytes written to the transport, framing included.
    pub sent: u64,
    /// Bytes read from the transport, framing and noise included.
    pub received: u64,
    /// Encoded request payload bytes the link accepted (what an application sent).
    pub payload_sent: u64,
    /// The first bytes read, for diagnosing a silent or garbled line.
    pub first: Vec<u8>,
}

impl<T: Transport> Session<T> {
    /// A session over `transport`; call [`Session::handshake`] next.
    pub fn new(transport: T) -> Self {
        Self {
            transport,
            link: Box::new(Link::new(Default::default())),
            out: Box::new(Buffer::ZERO),
            input: Box::new([0; READ_BUF]),
            epoch: Instant::now(),
            requests: HashMap::new(),
            inbox: VecDeque::new(),
            reading: None,
            timeout: Duration::from_secs(10),
            next_token: 1,
            peer: None,
            traffic: Traffic::default(),
        }
    }

    fn now(&self) -> u64 {
        self.epoch.elapsed().as_millis() as u64
    }

    /// The transport, e.g. to read the built-in target's model directly in tests.
    pub fn transport(&mut self) -> &mut T {
        &mut self.transport
    }

    /// The target's hello, once the handshake is done.
    pub fn peer(&self) -> Option<&Hello> {
        self.peer.as_ref()
    }

    /// Bytes moved so far.
    pub fn traffic(&self) -> &Traffic {
        &self.traffic
    }

    /// This end's link counters.
    pub fn link_counters(&self) -> protocol::frame::LinkCounters {
        self.link.counters()
    }

    /// Moves bytes both ways once, waiting at most `wait` for input.
    fn pump(&mut self, wait: Duration) -> Result<(), SessionError> {
        let now = self.now();
        self.link.handle_timeout(now);
        self.transmit(now)?;
        let n = self.transport.read(&mut self.input[..], wait)?;
        self.traffic.received += n as u64;
        let room = 32usize.saturating_sub(self.traffic.first.len()).min(n);
        self.traffic.first.extend_from_slice(&self.input[..room]);
        let now = self.now();
        let mut at = 0;
        loop {
            let (used, event) = self.link.handle_input(now, &self.input[at..n]);
            at += used;
            match event {
                Some(Event::Data(payload)) => match chunk_view(payload) {
                    Some(Ok((offset, bytes))) => match &mut self.reading {
                        Some(sink) => sink.take(offset, bytes),
                        None => {
                            return Err(SessionError::Unexpected(format!(
                                "a read-back chunk (offset {offset}, {} bytes) outside a read-back",
                                bytes.len()
                            )))
                        }
                    },
                    Some(Err(e)) => return Err(SessionError::Malformed(e)),
                    None => {
                        let frame =
                            decode::<DeviceFrame>(payload).map_err(SessionError::Malformed)?;
                        self.inbox.push_back(frame);
                    }
                },
                Some(Event::PeerReset { .. }) => {
                    return Err(SessionError::Unexpected(
                        "the target restarted its link mid-session".into(),
                    ))
                }
                Some(Event::Synced) => {}
                None if at == n => break,
                None => {}
            }
        }
        let now = self.now();
        self.transmit(now)
    }

    /// Writes every frame the link has due.
    fn transmit(&mut self, now: u64) -> Result<(), SessionError> {
        while let Some(n) = self.link.poll_transmit(now, self.out.as_mut()) {
            self.transport.write_all(&self.out[..n])?;
            self.traffic.sent += n as u64;
        }
        Ok(())
    }

    /// Sends one request, waiting for window and credit; `describe` names it (given the
    /// index inside it) if the target refuses it later.
    pub fn send(&mut self, frame: &HostFrame, describe: Describe) -> Result<u16, SessionError> {
        let mut buf = [0u8; MAX_PAYLOAD];
        let bytes = encode(frame, &mut buf).map_err(SessionError::Encode)?;
        self.send_encoded(bytes, describe)
    }

    /// [`Session::send`] for a message already encoded (a [`protocol::frame::RasterBatch`]).
    pub fn send_encoded(&mut self, bytes: &[u8], describe: Describe) -> Result<u16, SessionError> {
        let start = Instant::now();
        loop {
            match self.link.send(self.now(), bytes) {
                Ok(seq) => {
                    self.requests.insert(seq, describe);
                    self.traffic.payload_sent += bytes.len() as u64;
                    return Ok(seq);
                }
                Err(LinkError::WindowFull) | Err(LinkError::NoCredit) => {
                    if start.elapsed() > self.timeout {
                        return Err(SessionError::Timeout(self.timeout));
                    }
                    self.pump(Duration::from_millis(1))?;
                    // Errors may arrive while we wait: report them at once rather than
                    // after the whole job.
                    self.take_error()?;
                }
                Err(e) => return Err(SessionError::Unexpected(e.to_string())),
            }
        }
    }

    fn take_error(&mut self) -> Result<(), SessionError> {
        if let Some(pos) = self
            .inbox
            .iter()
            .position(|f| matches!(f, DeviceFrame::Error(_)))
        {
            if let Some(DeviceFrame::Error(report)) = self.inbox.remove(pos) {
                return Err(self.refused(report));
            }
        }
        Ok(())
    }

    fn refused(&self, r: ErrorReport) -> SessionError {
        let what = self
            .requests
            .get(&r.seq)
            .map(|d| d(r.index))
            .unwrap_or_else(|| format!("request #{}", r.seq));
        SessionError::Refused {
            what,
            code: r.code,
            index: r.index,
        }
    }

    /// The next answer, or a timeout; error answers become [`SessionError::Refused`].
    pub fn recv(&mut self) -> Result<DeviceFrame, SessionError> {
        let start = Instant::now();
        loop {
            if let Some(f) = self.inbox.pop_front() {
                return match f {
                    DeviceFrame::Error(r) => Err(self.refused(r)),
                    other => Ok(other),
                };
            }
            if start.elapsed() > self.timeout {
                return Err(SessionError::Timeout(self.timeout));
            }
            self.pump(Duration::from_millis(5))?;
        }
    }

    /// Exchanges hellos; a version or schema mismatch is an error naming both sides.
    pub fn handshake(&mut self) -> Result<Hello, SessionError> {
        // A board keeps running between host sessions, its link in the middle of the
        // previous session's sequence numbers: start a new epoch so both ends resync. The
        // nonce only has to differ from the last session's.
        let nonce = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(1, |d| d.subsec_nanos() as u16 | 1);
        self.link.reset(self.now(), nonce);
        let caps = Caps {
            link_payload: HostLink::PAYLOAD as u32,
            ..Caps::default()
        };
        let ours = Hello::new(caps, concat!("fpgfx ", env!("CARGO_PKG_VERSION")));
        let start = Instant::now();
        // The hello waits for the reset to be confirmed: silence shows up here first.
        match self.send(&HostFrame::Hello(ours), Box::new(|_| "the hello".into())) {
            Err(SessionError::Timeout(_)) => return Err(self.no_answer(start.elapsed())),
            other => other?,
        };
        // The target answers with its own hello even when it refuses ours, so the error
        // can name both sides; check it before looking at a refusal.
        loop {
            let pos = self
                .inbox
                .iter()
                .position(|f| matches!(f, DeviceFrame::Hello(_)));
            if let Some(DeviceFrame::Hello(peer)) = pos.and_then(|p| self.inbox.remove(p)) {
                peer.check().map_err(|source| SessionError::Handshake {
                    peer: peer.ident.to_string(),
                    source,
                })?;
                self.take_error()?;
                self.peer = Some(peer.clone());
                return Ok(peer);
            }
            if start.elapsed() > self.timeout {
                return Err(self.no_answer(start.elapsed()));
            }
            self.pump(Duration::from_millis(5))?;
        }
    }

    fn no_answer(&self, waited: Duration) -> SessionError {
        let t = &self.traffic;
        let sample = if t.first.is_empty() {
            String::new()
        } else {
            let hex: Vec<String> = t.first.iter().map(|b| format!("{b:02x}")).collect();
            let c = self.link.counters();
            let why = if c.crc_errors + c.framing_errors > 0 {
                format!(
                    "; {} frames failed their CRC and {} did not decode: a wrong baud rate or \
                     another protocol on the port",
                    c.crc_errors, c.framing_errors
                )
            } else {
                "; no complete frame: is this an fpgfx controller?".to_string()
            };
            format!(", starting {}{why}", hex.join(" "))
        };
        SessionError::NoAnswer {
            waited,
            sent: t.sent,
            received: t.received,
            sample,
        }
    }

    /// Waits until everything sent so far has been executed by the target.
    pub fn sync(&mut self) -> Result<(), SessionError> {
        let token = self.next_token;
        self.next_token = self.next_token.wrapping_add(1);
        self.send(&HostFrame::Sync(token), Box::new(|_| "sync".into()))?;
        loop {
            match self.recv()? {
                DeviceFrame::Synced(t) if t == token => return Ok(()),
                DeviceFrame::Synced(_) | DeviceFrame::Done(_) => {}
                other => {
                    return Err(SessionError::Unexpected(format!(
                        "{other:?} while waiting for sync"
                    )))
                }
            }
        }
    }

    /// Reads back a buffer rectangle, checking order, length and CRC.
    pub fn read_back(&mut self, req: ReadRequest) -> Result<Vec<u8>, SessionError> {
        self.send(
            &HostFrame::Read(req),
            Box::new(move |_| format!("read-back of {req:?}")),
        )?;
        let expected = req.rect.area() as usize * req.format.bytes_per_pixel();
        self.reading = Some(ReadSink {
            data: Vec::with_capacity(expected),
            expected,
            crc: protocol::link::CRC32.digest(),
            error: None,
        });
        let done = self.read_done();
        // Whatever happened, chunks from now on belong to no read-back.
        let sink = self.reading.take();
        let (done, sink) = match (done?, sink) {
            (done, Some(sink)) => (done, sink),
            (_, None) => return Err(SessionError::Unexpected("read-back lost its sink".into())),
        };
        if let Some(e) = sink.error {
            return Err(SessionError::ReadBack(e));
        }
        let received = sink.data.len();
        if done.len as usize != received || received != expected {
            return Err(SessionError::ReadBack(format!(
                "{received} bytes received, the target announced {}, the request needs {expected}",
                done.len
            )));
        }
        let crc = sink.crc.finalize();
        if done.crc32 != crc {
            return Err(SessionError::ReadBack(format!(
                "CRC-32 {crc:#010x} of the received bytes, the target announced {:#010x}",
                done.crc32
            )));
        }
        Ok(sink.data)
    }

    /// Waits for the end of a read-back whose chunks [`Session::pump`] collects; a stall
    /// is [`Session::timeout`] without a new chunk or answer.
    fn read_done(&mut self) -> Result<protocol::frame::ReadDone, SessionError> {
        let received = |s: &Self| s.reading.as_ref().map_or(0, |r| r.data.len());
        let (mut since, mut got) = (Instant::now(), received(self));
        loop {
            if let Some(f) = self.inbox.pop_front() {
                since = Instant::now();
                match f {
                    DeviceFrame::ReadDone(done) => return Ok(done),
                    DeviceFrame::Error(r) => return Err(self.refused(r)),
                    DeviceFrame::Done(_) => continue,
                    other => {
                        return Err(SessionError::Unexpected(format!(
                            "{other:?} during a read-back"
                        )))
                    }
                }
            }
            if received(self) != got {
                (since, got) = (Instant::now(), received(self));
            } else if since.elapsed() > self.timeout {
                let expected = self.reading.as_ref().map_or(0, |r| r.expected);
                return Err(SessionError::Stalled {
                    during: "in a read-back",
                    progress: format!("{got} of {expected} bytes received"),
                    waited: since.elapsed(),
                });
            }
            self.pump(Duration::from_millis(5))?;
        }
    }

    /// Asks for both ends' statistics.
    pub fn stats(&mut self) -> Result<protocol::frame::Stats, SessionError> {
        self.send(&HostFrame::GetStats, Box::new(|_| "stats".into()))?;
        loop {
            match self.recv()? {
                DeviceFrame::Stats(s) => return Ok(s),
                DeviceFrame::Done(_) | DeviceFrame::Synced(_) => {}
                other => {
                    return Err(SessionError::Unexpected(format!(
                        "{other:?} while waiting for stats"
                    )))
                }
            }
        }
    }
}
