//! The controller's main loop: host bytes in through [`protocol::link`], requests queued
//! in a bounded inbox, handled by the [`Engine`], answers back over the link.
//!
//! Back-pressure is end to end: the link advertises the inbox's free slots as its credit,
//! so the host never sends a request the controller has no room for, and the engine only
//! pushes FIFO records the FPGA says it has room for. Nothing is dropped for lack of space.

use embedded_io::{Read, ReadReady, Write};
use heapless::Deque;
use protocol::bus::BusLayout;
use protocol::frame::{decode, encode, Caps, ErrorCode, HostFrame};
use protocol::link::{Config, Event, Link, MAX_FRAME};
use protocol::MAX_PAYLOAD;

use crate::engine::Engine;
use crate::fpga::FpgaBus;

/// Requests the controller buffers between the link and the engine. Each slot holds a
/// whole [`HostFrame`] (about 1.3 KiB for a raster batch), so four cost ~5 KiB of RAM.
pub const INBOX: usize = 4;

/// What stopped the controller: only transport failures; protocol errors are answered.
// Exhaustive on purpose: one variant per transport parameter, so a caller whose host link
// cannot fail (`H::Error = Infallible`) proves it with `match never {}`; another variant
// would need another transport parameter, which breaks callers anyway.
#[derive(Debug, thiserror::Error)]
pub enum ControllerError<H, B> {
    /// Reading or writing the host link failed.
    #[error("host link: {0}")]
    Host(H),
    /// The FPGA transport failed.
    #[error("FPGA: {0}")]
    Fpga(B),
}

/// The controller: host link `H`, FPGA bus `B`.
pub struct Controller<H, B: FpgaBus> {
    host: H,
    link: Link,
    engine: Engine<B>,
    inbox: Deque<(u16, HostFrame), INBOX>,
    /// Sequence number the next delivered request gets in error reports: the link
    /// delivers in order, so this counts the link's data frames.
    next_seq: u16,
    /// Requests refused before the engine saw them (undecodable, or sent without credit),
    /// answered in order with the rest.
    malformed: Deque<(u16, ErrorCode), INBOX>,
    /// An encoded answer the link has not accepted yet (window full or no credit).
    outgoing: heapless::Vec<u8, MAX_PAYLOAD>,
}

impl<H, B> Controller<H, B>
where
    H: Read + ReadReady + Write,
    B: FpgaBus,
{
    /// A controller for a target with capabilities `caps` whose raster block reads
    /// `layout` records.
    pub fn new(
        host: H,
        bus: B,
        caps: Caps,
        layout: &'static BusLayout,
        ident: &'static str,
    ) -> Self {
        let config = Config {
            rx_credit: INBOX as u8,
            ..Config::default()
        };
        Self {
            host,
            link: Link::new(config),
            engine: Engine::new(bus, caps, layout, ident),
            inbox: Deque::new(),
            next_seq: 0,
            malformed: Deque::new(),
            outgoing: heapless::Vec::new(),
        }
    }

    /// The host link, e.g. to plug a new connection into a socket-backed one.
    pub fn host(&mut self) -> &mut H {
        &mut self.host
    }

    /// The engine: the way to its bus (a board reconnects its FPGA link through it) and
    /// to whether a host has shaken hands.
    pub fn engine(&mut self) -> &mut Engine<B> {
        &mut self.engine
    }

    /// Does one round of work: reads what the host sent, handles at most one request,
    /// sends what is ready. Call it in the main loop with the current time in ms; it
    /// never blocks on the host link.
    pub fn poll(&mut self, now_ms: u64) -> Result<(), ControllerError<H::Error, B::Error>> {
        self.receive(now_ms)?;
        if self.engine.ready() {
            if let Some((seq, code)) = self.malformed.pop_front() {
                self.engine.refuse(code, seq, 0);
            } else if let Some((seq, frame)) = self.inbox.pop_front() {
                let link = self.link.counters();
                if let Err(e) = self.engine.handle(seq, &frame, link) {
                    // The host gets an answer (sent on the next poll) and the caller the
                    // transport's error, to log it and decide whether to reset the FPGA.
                    self.engine.refuse(ErrorCode::Device, seq, 0);
                    return Err(ControllerError::Fpga(e));
                }
            }
        }
        let free = (INBOX - self.inbox.len() - self.malformed.len()) as u8;
        self.link.set_rx_credit(free);
        self.engine.set_queue_free(u16::from(free));
        self.send(now_ms)?;
        self.link.handle_timeout(now_ms);
        self.transmit(now_ms)
    }

    fn receive(&mut self, now_ms: u64) -> Result<(), ControllerError<H::Error, B::Error>> {
        let mut buf = [0u8; 64];
        let n = if self.host.read_ready().map_err(ControllerError::Host)? {
            self.host.read(&mut buf).map_err(ControllerError::Host)?
        } else {
            0
        };
        let mut input = &buf[..n];
        loop {
            let (used, event) = self.link.handle_input(now_ms, input);
            input = &input[used..];
            match event {
                Some(Event::Data(payload)) => {
                    let seq = self.next_seq;
                    self.next_seq = self.next_seq.wrapping_add(1);
                    match decode::<HostFrame>(payload) {
                        // Credit kept the inbox from filling; a peer that ignores it
                        // gets its request refused, not silently dropped.
                        Ok(frame) => {
                            if self.inbox.push_back((seq, frame)).is_err() {
                                let _ = self.malformed.push_back((seq, ErrorCode::BadState));
                            }
                        }
                        Err(_) => {
                            let _ = self.malformed.push_back((seq, ErrorCode::Malformed));
                        }
                    }
                }
                Some(Event::PeerReset { discarded }) => {
                    crate::log::log_info!("host link reset ({} frames discarded)", discarded);
                    // A new host session: nothing of the old one may leak into it.
                    self.inbox.clear();
                    self.malformed.clear();
                    self.outgoing.clear();
                    self.engine.forget_host();
                    self.next_seq = 0;
                }
                Some(Event::Synced) => {}
                None if input.is_empty() => break,
                None => {}
            }
        }
        Ok(())
    }

    fn send(&mut self, now_ms: u64) -> Result<(), ControllerError<H::Error, B::Error>> {
        loop {
            if self.outgoing.is_empty() {
                let Some(frame) = self.engine.next_output().map_err(ControllerError::Fpga)? else {
                    return Ok(());
                };
                let mut buf = [0u8; MAX_PAYLOAD];
                // Every DeviceFrame fits MAX_PAYLOAD (a protocol test checks the worst
                // case), so encoding cannot fail in a correct build.
                if let Ok(bytes) = encode(&frame, &mut buf) {
                    let _ = self.outgoing.extend_from_slice(bytes);
                }
            }
            // Trying even without credit matters: a refused send makes the link probe
            // the host for a window update.
            match self.link.send(now_ms, &self.outgoing) {
                Ok(_) => self.outgoing.clear(),
                Err(_) => return Ok(()),
            }
        }
    }

    fn transmit(&mut self, now_ms: u64) -> Result<(), ControllerError<H::Error, B::Error>> {
        let mut out = [0u8; MAX_FRAME];
        while let Some(n) = self.link.poll_transmit(now_ms, &mut out) {
            self.host
                .write_all(&out[..n])
                .map_err(ControllerError::Host)?;
        }
        self.host.flush().map_err(ControllerError::Host)
    }
}
