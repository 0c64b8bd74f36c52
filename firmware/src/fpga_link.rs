//! [`FpgaBus`] over a serial line: each bus operation becomes a [`protocol::fpga_link`] message
//! on a [`protocol::link`], for a board whose FPGA is `fpgfx-sim --fpga-link` on the second
//! UART.
//!
//! Writes are posted (sent without waiting); questions block until their answer arrives,
//! servicing the link meanwhile, because the engine's calls are synchronous. FIFO credit
//! is tracked here so that a stream of pushes costs no round trips until the credit runs
//! low (see the module docs of [`protocol::fpga_link`]).

use embedded_io::{Read, ReadReady, Write};
use heapless::{Deque, Vec};
use protocol::fpga_link::{
    Fault, FpgaReply, FpgaRequest, FpgaStatus, Identity, FPGA_SCHEMA_HASH, PUSH_RECORDS,
};
use protocol::frame::{
    decode, encode, DeviceCounters, FrameDone, ReadRequest, StartFrame, READ_CHUNK,
    REG_WRITE_WORDS, TEXTURE_CHUNK,
};
use protocol::link::{Config, Event, Link, MAX_FRAME};
use protocol::raster::RasterSetup;
use protocol::MAX_PAYLOAD;

use crate::fpga::FpgaBus;

/// Milliseconds since some fixed point; the link's retransmission timers run on it.
pub trait Clock {
    /// Milliseconds now; must never go backwards, or retransmissions and timeouts fire
    /// late.
    fn now_ms(&mut self) -> u64;

    /// Called while waiting for an answer when nothing has arrived. A board sleeps until
    /// the next interrupt (a received byte or the millisecond tick): busy-polling a UART
    /// wastes power on silicon and, under QEMU, starves the thread that delivers the bytes.
    fn idle(&mut self) {}
}

impl<F: FnMut() -> u64> Clock for F {
    fn now_ms(&mut self) -> u64 {
        self()
    }
}

/// Below this many records of known credit, ask the FPGA for a fresh figure before the
/// next push. Larger than any single packet, so a packet never waits on stale credit.
const LOW_CREDIT: usize = 128;

/// Frames the controller keeps in flight towards the FPGA. Four 256-byte payloads each way
/// keep a 921 600-baud line busy while costing ~2 KiB of RAM.
const WINDOW: usize = 4;

/// What went wrong on the FPGA link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum FpgaLinkError<E> {
    /// The UART failed; the port's own error, as the board's driver reports it.
    #[error("the FPGA link's UART failed: {0}")]
    Io(E),
    /// No answer within the time limit; `waiting_for` names the question.
    #[error("no answer from the FPGA to {waiting_for}")]
    Timeout {
        /// The unanswered question.
        waiting_for: &'static str,
    },
    /// The FPGA refused an earlier posted request.
    #[error("the FPGA refused request {} ({:?})", .0.request, .0.code)]
    Fault(Fault),
    /// An answer that does not fit the question, or that does not decode.
    #[error("an answer from the FPGA that does not fit {question}")]
    Unexpected {
        /// The question it should have answered.
        question: &'static str,
    },
    /// The FPGA side was built from another message set.
    #[error(
        "the FPGA side was built from another message set (schema hash {theirs:#018x}, \
         ours {ours:#018x})"
    )]
    Schema {
        /// This build's [`FPGA_SCHEMA_HASH`].
        ours: u64,
        /// The hash the FPGA side reported in its identity.
        theirs: u64,
    },
    /// The FPGA side restarted: everything it held is gone; reset and start over.
    #[error("the FPGA side restarted and lost everything it held")]
    PeerReset,
}

#[cfg(feature = "defmt")]
impl<E> defmt::Format for FpgaLinkError<E> {
    // By hand rather than derived: protocol's types stay free of a logging dependency, and
    // numbers are all a log reader needs next to the names.
    fn format(&self, f: defmt::Formatter<'_>) {
        match self {
            FpgaLinkError::Io(_) => defmt::write!(f, "UART error"),
            FpgaLinkError::Timeout { waiting_for } => {
                defmt::write!(f, "no answer to {=str}", waiting_for)
            }
            FpgaLinkError::Fault(x) => defmt::write!(
                f,
                "FPGA refused request {=u32} (fault {=u8})",
                x.request,
                x.code as u8
            ),
            FpgaLinkError::Unexpected { question } => {
                defmt::write!(f, "unexpected answer to {=str}", question)
            }
            FpgaLinkError::Schema { ours, theirs } => {
                defmt::write!(f, "FPGA message set {=u64:x}, ours {=u64:x}", theirs, ours)
            }
            FpgaLinkError::PeerReset => defmt::write!(f, "FPGA restarted"),
        }
    }
}

/// The FPGA at the other end of a serial line.
pub struct FpgaLink<U, C> {
    port: U,
    clock: C,
    link: Link<WINDOW>,
    /// A lower bound of the FIFO's free records: the last reported figure minus what was
    /// pushed since.
    credit: usize,
    /// `credit` must be refreshed before it is trusted again (after a `wait`).
    stale: bool,
    done: Deque<FrameDone, 4>,
    /// Answers not yet taken by a question (`None`: one that did not decode).
    replies: Deque<Option<FpgaReply>, 2>,
    /// Give up on a question after this long without its answer.
    pub timeout_ms: u64,
    identity: Option<Identity>,
}

impl<U, C> FpgaLink<U, C>
where
    U: Read + ReadReady + Write,
    C: Clock,
{
    /// A link over `port`; call [`FpgaLink::connect`] before using it as a bus.
    pub fn new(port: U, clock: C) -> Self {
        Self {
            port,
            clock,
            link: Link::new(Config::default()),
            credit: 0,
            stale: true,
            done: Deque::new(),
            replies: Deque::new(),
            // A ray-traced frame is rendered between a posted Start and the next answer:
            // give a full-HD frame in the slowest format time to finish.
            timeout_ms: 120_000,
            identity: None,
        }
    }

    /// Resynchronises the link with a fresh epoch and asks the FPGA who it is. `nonce`
    /// tells this epoch from an earlier one (a board uses a counter or a timer value).
    pub fn connect(&mut self, nonce: u16) -> Result<Identity, FpgaLinkError<U::Error>> {
        let now = self.clock.now_ms();
        self.link.reset(now, nonce);
        self.credit = 0;
        self.stale = true;
        self.done.clear();
        self.replies.clear();
        let deadline = now + self.timeout_ms;
        loop {
            if self.pump()? {
                break;
            }
            if self.clock.now_ms() > deadline {
                return Err(FpgaLinkError::Timeout {
                    waiting_for: "link reset",
                });
            }
        }
        match self.ask(&FpgaRequest::Identify, "identify")? {
            FpgaReply::Identity(id) if id.schema_hash == FPGA_SCHEMA_HASH => {
                self.identity = Some(id);
                Ok(id)
            }
            FpgaReply::Identity(id) => Err(FpgaLinkError::Schema {
                ours: FPGA_SCHEMA_HASH,
                theirs: id.schema_hash,
            }),
            _ => Err(FpgaLinkError::Unexpected {
                question: "identify",
            }),
        }
    }

    /// The link's counters (for statistics and the log).
    pub fn link_counters(&self) -> protocol::frame::LinkCounters {
        self.link.counters()
    }

    /// Reads what arrived, runs the link's timers and sends what is ready. Answers go to
    /// `replies`; returns whether the reset this end started was confirmed.
    fn pump(&mut self) -> Result<bool, FpgaLinkError<U::Error>> {
        let now = self.clock.now_ms();
        let mut buf = [0u8; 64];
        let n = if self.port.read_ready().map_err(FpgaLinkError::Io)? {
            self.port.read(&mut buf).map_err(FpgaLinkError::Io)?
        } else {
            0
        };
        let mut input = &buf[..n];
        let mut synced = false;
        loop {
            let (used, event) = self.link.handle_input(now, input);
            input = &input[used..];
            match event {
                Some(Event::Data(payload)) => {
                    // Answers own their data, so the link's buffer is free again at once.
                    let reply = decode::<FpgaReply>(payload).ok();
                    // One question is outstanding at a time, so at most one answer waits;
                    // a second would be a broken FPGA side and is reported as garbled.
                    if self.replies.push_back(reply).is_err() {
                        self.replies.clear();
                        let _ = self.replies.push_back(None);
                    }
                }
                Some(Event::Synced) => synced = true,
                Some(Event::PeerReset { .. }) => return Err(FpgaLinkError::PeerReset),
                None if input.is_empty() => break,
                None => {}
            }
        }
        self.link.handle_timeout(now);
        self.transmit(now)?;
        Ok(synced)
    }

    fn transmit(&mut self, now: u64) -> Result<(), FpgaLinkError<U::Error>> {
        let mut out = [0u8; MAX_FRAME];
        while let Some(n) = self.link.poll_transmit(now, &mut out) {
            self.port.write_all(&out[..n]).map_err(FpgaLinkError::Io)?;
        }
        self.port.flush().map_err(FpgaLinkError::Io)
    }

    /// Queues a request on the link, waiting for window space if the FPGA is behind.
    fn post(
        &mut self,
        req: &FpgaRequest<'_>,
        what: &'static str,
    ) -> Result<(), FpgaLinkError<U::Error>> {
        let mut buf = [0u8; MAX_PAYLOAD];
        // Every request is bounded below MAX_PAYLOAD (a protocol test checks the worst
        // case), so encoding fails only on a broken build; report it rather than panic.
        let bytes =
            encode(req, &mut buf).map_err(|_| FpgaLinkError::Unexpected { question: what })?;
        let deadline = self.clock.now_ms() + self.timeout_ms;
        loop {
            let now = self.clock.now_ms();
            if self.link.send(now, bytes).is_ok() {
                return self.transmit(now);
            }
            self.pump()?;
            if !self.port.read_ready().map_err(FpgaLinkError::Io)? {
                self.clock.idle();
            }
            if now > deadline {
                return Err(FpgaLinkError::Timeout { waiting_for: what });
            }
        }
    }

    /// Sends a question and waits for its answer.
    fn ask(
        &mut self,
        req: &FpgaRequest<'_>,
        what: &'static str,
    ) -> Result<FpgaReply, FpgaLinkError<U::Error>> {
        self.post(req, what)?;
        let deadline = self.clock.now_ms() + self.timeout_ms;
        loop {
            if !self.pump()?
                && self.replies.is_empty()
                && !self.port.read_ready().map_err(FpgaLinkError::Io)?
            {
                self.clock.idle();
            }
            match self.replies.pop_front() {
                Some(Some(FpgaReply::Fault(f))) => return Err(FpgaLinkError::Fault(f)),
                Some(Some(reply)) => return Ok(reply),
                Some(None) => return Err(FpgaLinkError::Unexpected { question: what }),
                None => {}
            }
            if self.clock.now_ms() > deadline {
                return Err(FpgaLinkError::Timeout { waiting_for: what });
            }
        }
    }

    fn status(&mut self) -> Result<FpgaStatus, FpgaLinkError<U::Error>> {
        match self.ask(&FpgaRequest::Status, "status")? {
            FpgaReply::Status(s) => {
                self.credit = usize::from(s.fifo_free);
                self.stale = false;
                if let Some(d) = s.done {
                    // Four unread completions would mean the engine stopped polling;
                    // the oldest is the one it no longer waits for.
                    if self.done.is_full() {
                        self.done.pop_front();
                    }
                    let _ = self.done.push_back(d);
                }
                Ok(s)
            }
            _ => Err(FpgaLinkError::Unexpected { question: "status" }),
        }
    }
}

impl<U, C> FpgaBus for FpgaLink<U, C>
where
    U: Read + ReadReady + Write,
    C: Clock,
{
    type Error = FpgaLinkError<U::Error>;

    fn fifo_free(&mut self) -> Result<usize, Self::Error> {
        if self.stale || self.credit < LOW_CREDIT {
            self.status()?;
        }
        Ok(self.credit)
    }

    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Self::Error> {
        let parts = records.len().div_ceil(PUSH_RECORDS).max(1);
        for (i, part) in records.chunks(PUSH_RECORDS).enumerate() {
            let mut v = Vec::new();
            // chunks() yields at most PUSH_RECORDS, the vector's capacity.
            let _ = v.extend_from_slice(part);
            let req = FpgaRequest::Push {
                channel,
                last: i + 1 == parts,
                records: v,
            };
            self.post(&req, "push")?;
        }
        self.credit = self.credit.saturating_sub(records.len());
        Ok(())
    }

    fn wait(&mut self) -> Result<(), Self::Error> {
        // The FPGA works on its own; waiting means letting the link breathe and not
        // trusting the credit figure until it is asked again.
        self.stale = true;
        self.pump().map(drop)
    }

    fn idle(&mut self) -> Result<bool, Self::Error> {
        Ok(self.status()?.idle)
    }

    fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), Self::Error> {
        self.post(&FpgaRequest::RasterSetup(*setup), "raster set-up")
    }

    fn write_regs(&mut self, offset: u16, words: &[u32]) -> Result<(), Self::Error> {
        for (i, part) in words.chunks(REG_WRITE_WORDS).enumerate() {
            let mut v = Vec::new();
            let _ = v.extend_from_slice(part);
            let offset = offset.wrapping_add((i * REG_WRITE_WORDS) as u16);
            self.post(&FpgaRequest::Regs { offset, words: v }, "register write")?;
        }
        Ok(())
    }

    fn write_texels(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        for (i, part) in bytes.chunks(TEXTURE_CHUNK).enumerate() {
            let offset = offset.wrapping_add((i * TEXTURE_CHUNK / 4) as u32);
            self.post(
                &FpgaRequest::Texels {
                    offset,
                    bytes: part,
                },
                "texel write",
            )?;
        }
        Ok(())
    }

    fn start(&mut self, start: &StartFrame) -> Result<(), Self::Error> {
        self.post(&FpgaRequest::Start(*start), "start")
    }

    fn stop(&mut self) -> Result<(), Self::Error> {
        self.post(&FpgaRequest::Stop, "stop")
    }

    fn poll_done(&mut self) -> Result<Option<FrameDone>, Self::Error> {
        if self.done.is_empty() {
            self.status()?;
        }
        Ok(self.done.pop_front())
    }

    fn read_len(&mut self, req: &ReadRequest) -> Result<Option<u32>, Self::Error> {
        match self.ask(&FpgaRequest::ReadLen(*req), "read length")? {
            FpgaReply::ReadLen(n) => Ok(n),
            _ => Err(FpgaLinkError::Unexpected {
                question: "read length",
            }),
        }
    }

    fn read(&mut self, req: &ReadRequest, offset: u32, out: &mut [u8]) -> Result<(), Self::Error> {
        for (i, part) in out.chunks_mut(READ_CHUNK).enumerate() {
            let offset = offset + (i * READ_CHUNK) as u32;
            let q = FpgaRequest::Read {
                req: *req,
                offset,
                len: part.len() as u16,
            };
            match self.ask(&q, "read")? {
                FpgaReply::Data(d) if d.len() == part.len() => part.copy_from_slice(&d),
                _ => return Err(FpgaLinkError::Unexpected { question: "read" }),
            }
        }
        Ok(())
    }

    fn counters(&mut self) -> Result<DeviceCounters, Self::Error> {
        match self.ask(&FpgaRequest::Counters, "counters")? {
            FpgaReply::Counters(c) => Ok(c),
            _ => Err(FpgaLinkError::Unexpected {
                question: "counters",
            }),
        }
    }

    fn reset(&mut self) -> Result<(), Self::Error> {
        self.post(&FpgaRequest::Reset, "reset")?;
        self.credit = 0;
        self.stale = true;
        self.done.clear();
        Ok(())
    }
}
