//! The controller's main loop: host bytes in through [`protocol::link`], requests queued
//! in a bounded inbox, handled by the [`Engine`], answers back over the link.
//!
//! Back-pressure is end to end: the link advertises the inbox's free slots as its credit,
//! so the host never sends a request the controller has no room for, and the engine only
//! pushes FIFO records the FPGA says it has room for. Nothing is dropped for lack of space.

use core::mem::MaybeUninit;
use core::ptr::addr_of_mut;

use embedded_io::{Read, ReadReady, Write};
use heapless::Deque;
use protocol::bus::BusLayout;
use protocol::frame::{decode, encode, Caps, ErrorCode, Request};
use protocol::link::{Buffer, Capacity, Config, Event, Link, Small};
use protocol::MAX_PAYLOAD;

use crate::engine::Engine;
use crate::fpga::FpgaBus;

/// Requests the controller buffers between the link and the engine. Each slot holds a
/// request as received (at most [`MAX_PAYLOAD`] bytes; decoded it would be a
/// [`HostFrame`](protocol::frame::HostFrame), about 1.3 KiB for a raster batch; handled, a
/// [`Request`]: the batch is walked in place), so four cost ~1 KiB of RAM.
/// The default of [`Controller`]'s `INBOX` parameter; a board short of RAM (the MSP430)
/// picks fewer with [`Controller::sized`].
pub const INBOX: usize = 4;

/// Frames in flight each way on the host link: the default of [`Controller`]'s `WINDOW`
/// parameter, the window [`Link`] has by default.
pub const WINDOW: usize = 8;

/// Ray-tracer registers the engine mirrors: the default of [`Controller`]'s `SHADOW`
/// parameter (see [`Engine`]).
pub const SHADOW: usize = crate::engine::SHADOW_WORDS;

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
///
/// The const parameters size its RAM, so that one program serves a 128 KiB Cortex-M4 and
/// an 8 KiB MSP430: `INBOX` requests queued (the credit the link advertises, and
/// [`Caps::queue_depth`] should say the same), a link `WINDOW` (a power of two, 4..=128)
/// of frames of the link's capacity `C` each way ([`Small`], [`MAX_PAYLOAD`]-byte, on an
/// MCU; [`protocol::link::Bulk`] where RAM allows, so that a read-back goes in large
/// chunks to a host that takes them) and `SHADOW` mirrored ray-tracer registers (0 for a
/// board without a ray tracer, which refuses animation steps).
pub struct Controller<
    H,
    B: FpgaBus,
    const INBOX: usize = { crate::controller::INBOX },
    const WINDOW: usize = { crate::controller::WINDOW },
    const SHADOW: usize = { crate::controller::SHADOW },
    C: Capacity = Small,
> {
    host: H,
    link: Link<WINDOW, C>,
    engine: Engine<B, SHADOW>,
    /// Requests as received (postcard bytes), decoded one at a time when handled.
    inbox: Deque<(u16, heapless::Vec<u8, MAX_PAYLOAD>), INBOX>,
    /// Sequence number the next delivered request gets in error reports: the link
    /// delivers in order, so this counts the link's data frames.
    next_seq: u16,
    /// Requests refused before the engine saw them (sent without credit), answered
    /// before the queued ones.
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
    /// `layout` records, with the default sizes ([`INBOX`], [`WINDOW`], [`SHADOW`]).
    pub fn new(
        host: H,
        bus: B,
        caps: Caps,
        layout: &'static BusLayout,
        ident: &'static str,
    ) -> Self {
        Self::sized(host, bus, caps, layout, ident)
    }
}

impl<H, B, const INBOX: usize, const WINDOW: usize, const SHADOW: usize, C: Capacity>
    Controller<H, B, INBOX, WINDOW, SHADOW, C>
where
    H: Read + ReadReady + Write,
    B: FpgaBus,
{
    // The free slots are the link's credit, a byte; an empty inbox could never take a
    // request.
    const INBOX_OK: () = assert!(INBOX >= 1 && INBOX <= 255, "INBOX must be in 1..=255");

    /// [`Controller::new`] with the sizes its type names: how a board with little RAM
    /// picks a shorter inbox, a narrower window or no register shadow.
    pub fn sized(
        host: H,
        bus: B,
        caps: Caps,
        layout: &'static BusLayout,
        ident: &'static str,
    ) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::INBOX_OK;
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

    /// [`Controller::sized`] built where it will live: a board whose RAM is little more
    /// than the controller (the MSP430's 8 KiB) cannot afford the controller-sized
    /// temporary and copy that moving a returned value into a `static` costs. Each field
    /// is written in place; the largest temporary is then the link.
    pub fn init_in<'a>(
        slot: &'a mut MaybeUninit<Self>,
        host: H,
        bus: B,
        caps: Caps,
        layout: &'static BusLayout,
        ident: &'static str,
    ) -> &'a mut Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::INBOX_OK;
        let config = Config {
            rx_credit: INBOX as u8,
            ..Config::default()
        };
        let p = slot.as_mut_ptr();
        // SAFETY: `p` points to writable memory for a `Self`; every field is written
        // exactly once through a raw pointer (no reference to uninitialised memory is
        // made) before the slot is assumed initialised.
        unsafe {
            addr_of_mut!((*p).host).write(host);
            addr_of_mut!((*p).link).write(Link::new(config));
            addr_of_mut!((*p).engine).write(Engine::new(bus, caps, layout, ident));
            addr_of_mut!((*p).inbox).write(Deque::new());
            addr_of_mut!((*p).next_seq).write(0);
            addr_of_mut!((*p).malformed).write(Deque::new());
            addr_of_mut!((*p).outgoing).write(heapless::Vec::new());
            slot.assume_init_mut()
        }
    }

    /// The host link, e.g. to plug a new connection into a socket-backed one.
    pub fn host(&mut self) -> &mut H {
        &mut self.host
    }

    /// The engine: the way to its bus (a board reconnects its FPGA link through it) and
    /// to whether a host has shaken hands.
    pub fn engine(&mut self) -> &mut Engine<B, SHADOW> {
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
            } else {
                self.handle_next()?;
            }
        }
        let free = (INBOX - self.inbox.len() - self.malformed.len()) as u8;
        self.link.set_rx_credit(free);
        self.engine.set_queue_free(u16::from(free));
        self.send(now_ms)?;
        self.link.handle_timeout(now_ms);
        self.transmit(now_ms)
    }

    /// Decodes and handles the oldest queued request, if any.
    // Not inlined, like `receive`: the decoded frame and the engine's answers would
    // otherwise share `poll`'s frame with every other step's buffers.
    #[inline(never)]
    fn handle_next(&mut self) -> Result<(), ControllerError<H::Error, B::Error>> {
        let Some((seq, bytes)) = self.inbox.front() else {
            return Ok(());
        };
        let seq = *seq;
        let link = self.link.counters();
        // A `Request`, not a `HostFrame`: a raster batch is checked but stays in `bytes`,
        // so the decoded value is a texture chunk's size, not eight commands'.
        let handled = match decode::<Request>(bytes) {
            Ok(frame) => self.engine.handle(seq, &frame, bytes, link),
            Err(_) => {
                self.engine.refuse(ErrorCode::Malformed, seq, 0);
                Ok(())
            }
        };
        self.inbox.pop_front();
        handled.map_err(|e| {
            // The host gets an answer (sent on the next poll) and the caller the
            // transport's error, to log it and decide whether to reset the FPGA.
            self.engine.refuse(ErrorCode::Device, seq, 0);
            ControllerError::Fpga(e)
        })
    }

    // Not inlined, like `handle_next`, `send` and `transmit`: inlined into `poll`, their
    // buffers and the decoded request add up instead of taking turns. On the MSP430 (8 KiB
    // of RAM) that was 5.2 KB of stack in one frame; apart, the deepest path is 6.2 KB.
    #[inline(never)]
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
                    // Kept as received, decoded when handled: a slot then costs the
                    // payload's bytes, not a decoded `HostFrame`'s (four times as many),
                    // and no decoded frame is copied through this function's stack. The
                    // link never delivers more than MAX_PAYLOAD bytes.
                    let bytes = heapless::Vec::from_slice(payload).unwrap_or_default();
                    // Credit kept the inbox from filling; a peer that ignores it gets its
                    // request refused, not silently dropped.
                    if self.inbox.push_back((seq, bytes)).is_err() {
                        let _ = self.malformed.push_back((seq, ErrorCode::BadState));
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

    #[inline(never)]
    fn send(&mut self, now_ms: u64) -> Result<(), ControllerError<H::Error, B::Error>> {
        loop {
            if self.outgoing.is_empty() && !self.engine.chunk_due() {
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
            // The encoded answer, or else a read-back chunk written into the link's slot
            // itself (up to the link's payload: a bulk link's 16 KiB) with no copy on the
            // way. One call for both, so the MSP430 carries one copy of the link's send.
            // Trying even without credit matters: a refused send makes the link probe
            // the host for a window update.
            let (engine, outgoing) = (&mut self.engine, &self.outgoing);
            let sent = self.link.send_with(now_ms, |slot| {
                if outgoing.is_empty() {
                    engine.write_chunk(slot)
                } else {
                    // A slot holds at least MAX_PAYLOAD bytes, the answer at most that.
                    slot[..outgoing.len()].copy_from_slice(outgoing);
                    Ok(outgoing.len())
                }
            });
            match sent {
                Ok(Ok(_)) => self.outgoing.clear(),
                // No read-back after all: nothing was written or queued.
                Ok(Err(None)) => {}
                Ok(Err(Some(e))) => return Err(ControllerError::Fpga(e)),
                Err(_) => return Ok(()),
            }
        }
    }

    #[inline(never)]
    fn transmit(&mut self, now_ms: u64) -> Result<(), ControllerError<H::Error, B::Error>> {
        let mut out = C::Frame::ZERO;
        let out = out.as_mut();
        while let Some(n) = self.link.poll_transmit(now_ms, out) {
            self.host
                .write_all(&out[..n])
                .map_err(ControllerError::Host)?;
        }
        self.host.flush().map_err(ControllerError::Host)
    }
}
