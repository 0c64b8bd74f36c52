//! What the controller does with each host message, independent of how bytes arrive.
//!
//! Every request is checked against the target's [`Caps`] before anything reaches the
//! FPGA, so a job the board cannot do is refused up front with an error frame naming the
//! request and the position inside it, never half-drawn.

use heapless::Deque;

use protocol::bus::{BusError, BusLayout, PackOptions};
use protocol::frame::{
    chunk_header, raster_commands, read_chunk_len, Animation, Block, Caps, DeviceCounters,
    DeviceFrame, ErrorCode, ErrorReport, Hello, HostFrame, LinkCounters, ReadDone, ReadRequest,
    Request, StartFrame, Stats,
};
use protocol::link::{Crc32Digest, CRC32};
use protocol::raster::{RasterCmd, RasterSetup};
use protocol::scene::{hdr, ValueFormat};
use protocol::MAX_PAYLOAD;

use crate::fpga::{push_command, FpgaBus, PushError};

/// Answers waiting for the link. A request is handled only once the outbox is empty
/// ([`Engine::ready`]) and queues at most two (a hello and a handshake error; otherwise
/// one error, stats or synced answer, or a device error after a failed bus call), and a
/// read-back's error is queued only when the outbox is empty, so two never overflow. Each
/// slot is a decoded `DeviceFrame` (232 B on the MSP430), which is why it is not four.
const OUTBOX: usize = 2;

/// A read-back in progress: streamed one chunk per poll so that it never needs a buffer
/// the size of the framebuffer, and interleaves with other traffic.
struct ReadJob {
    /// The request that started it, for an error answer.
    seq: u16,
    req: ReadRequest,
    offset: u32,
    len: u32,
    crc: Crc32Digest,
}

/// The controller's message semantics over an [`FpgaBus`]. Only the [`crate::Controller`]
/// drives it; callers reach it through [`crate::Controller::engine`] to get at the bus (a
/// board reconnects its FPGA link that way) or to see whether a host has shaken hands.
pub struct Engine<B: FpgaBus, const SHADOW: usize = SHADOW_WORDS> {
    bus: B,
    caps: Caps,
    layout: &'static BusLayout,
    ident: &'static str,
    handshaken: bool,
    setup: Option<RasterSetup>,
    outbox: Deque<DeviceFrame, OUTBOX>,
    read: Option<ReadJob>,
    counters: DeviceCounters,
    /// What the ray tracer's registers hold, so an animation step can compute the next
    /// value of a register without reading it back over the bus.
    shadow: [u32; SHADOW],
    /// The frame to start again when one is done (ViRAY's auto-restart).
    auto: Option<StartFrame>,
    animation: Animation,
    /// Frames started and not yet reported done: the FPGA is only asked about completion
    /// while this is non-zero (over a serial FPGA link every question is a round trip).
    running: u32,
    /// The largest link payload the host accepts, as its hello said
    /// ([`Caps::link_payload`]): a read-back's chunks are sized for the smaller of this and
    /// the controller's link slot.
    host_payload: usize,
}

/// Ray-tracer registers mirrored in the controller (2 KiB): the whole map for the
/// default 8 objects and 2 lights, with room to spare. A board without a ray tracer
/// mirrors none (`SHADOW` = 0): its animation steps are refused like those on a binary32
/// image, since nothing says the registers hold Q16.16.
pub(crate) const SHADOW_WORDS: usize = 512;

impl<B: FpgaBus, const SHADOW: usize> Engine<B, SHADOW> {
    /// An engine for a target with these capabilities whose raster block reads records in
    /// `layout`. `ident` goes into the hello ("fpgfx-firmware 0.1.0 stm32f405").
    pub(crate) fn new(
        bus: B,
        mut caps: Caps,
        layout: &'static BusLayout,
        ident: &'static str,
    ) -> Self {
        // The engine packs the records, so it is the one that knows the layout.
        caps.raster_layout = protocol::bus::LayoutId::of(layout);
        // The controller queues requests as received in MAX_PAYLOAD-byte slots, whatever
        // its link's frames: that is what it accepts.
        caps.link_payload = MAX_PAYLOAD as u32;
        Self {
            bus,
            caps,
            layout,
            ident,
            handshaken: false,
            setup: None,
            outbox: Deque::new(),
            read: None,
            counters: DeviceCounters::default(),
            shadow: [0; SHADOW],
            auto: None,
            animation: Animation::default(),
            running: 0,
            host_payload: MAX_PAYLOAD,
        }
    }

    /// The bus, for inspection in tests and for the board's idle loop.
    pub fn bus(&mut self) -> &mut B {
        &mut self.bus
    }

    /// Whether the handshake has succeeded.
    pub fn handshaken(&self) -> bool {
        self.handshaken
    }

    fn answer(&mut self, frame: DeviceFrame) {
        // The outbox is drained before each request is handled, and one request queues at
        // most two answers (see OUTBOX), so this cannot overflow; if it ever did, the oldest
        // answer would be kept and this one counted as an overflow by the caller's stats.
        let _ = self.outbox.push_back(frame);
    }

    /// Drops answers and read-backs meant for a host session that has ended; the next
    /// session must shake hands again. The FPGA keeps its state (a board does too).
    pub(crate) fn forget_host(&mut self) {
        self.outbox.clear();
        self.read = None;
        self.handshaken = false;
        self.host_payload = MAX_PAYLOAD;
    }

    /// Refuses a request the controller could not even hand to the engine.
    pub(crate) fn refuse(&mut self, code: ErrorCode, seq: u16, index: u32) {
        self.error(code, seq, index);
    }

    fn error(&mut self, code: ErrorCode, seq: u16, index: u32) {
        crate::log::log_warn!("request {} refused: {} at {}", seq, code as u8, index);
        self.answer(DeviceFrame::Error(ErrorReport { code, seq, index }));
    }

    /// Whether the engine can take another request now (its answers have been collected).
    pub(crate) fn ready(&self) -> bool {
        self.outbox.is_empty()
    }

    /// Handles one request: `frame` decoded from `payload`, the bytes as received, where
    /// a raster batch's commands still are (a [`Request`] checks them but does not hold
    /// them). `seq` identifies it in error answers; `link` is the controller's link
    /// counters, reported by [`HostFrame::GetStats`].
    /// Returns an error only when the FPGA transport itself fails.
    // Not inlined: its answers' temporaries and the caller's decoded request would share
    // one stack frame (several KB on the MSP430, whose RAM is 8 KiB).
    #[inline(never)]
    pub(crate) fn handle(
        &mut self,
        seq: u16,
        frame: &Request,
        payload: &[u8],
        link: LinkCounters,
    ) -> Result<(), B::Error> {
        if let HostFrame::Hello(peer) = frame {
            return self.hello(seq, peer);
        }
        if !self.handshaken {
            self.error(ErrorCode::Handshake, seq, 0);
            return Ok(());
        }
        match frame {
            HostFrame::Hello(_) => {}
            HostFrame::RasterSetup(setup) => self.raster_setup(seq, setup)?,
            HostFrame::Raster(_) => self.raster(seq, payload)?,
            HostFrame::Texture(t) => {
                let words = (t.data.len() / 4) as u64;
                if t.data.len() % 4 != 0 {
                    self.error(ErrorCode::Malformed, seq, t.data.len() as u32);
                } else if u64::from(t.offset) + words > u64::from(self.caps.texture_words) {
                    self.error(ErrorCode::OutOfRange, seq, t.offset);
                } else {
                    self.bus.write_texels(t.offset, &t.data)?;
                    self.counters.bus_words += words as u32;
                }
            }
            HostFrame::Regs(r) => {
                let end = usize::from(r.offset) + r.words.len();
                if !self.caps.ray_trace {
                    self.error(ErrorCode::Unsupported, seq, 0);
                } else if end > self.reg_words() {
                    self.error(ErrorCode::OutOfRange, seq, u32::from(r.offset));
                } else {
                    self.bus.write_regs(r.offset, &r.words)?;
                    self.counters.bus_words += r.words.len() as u32;
                    let start = usize::from(r.offset).min(SHADOW);
                    let end = (start + r.words.len()).min(SHADOW);
                    self.shadow[start..end].copy_from_slice(&r.words[..end - start]);
                }
            }
            HostFrame::Start(s) => {
                let ok = match s.block {
                    Block::Raster => self.caps.raster && self.setup.is_some(),
                    Block::RayTrace => self.caps.ray_trace && self.caps.numeric.contains(s.numeric),
                };
                if ok {
                    self.bus.start(s)?;
                    self.running += 1;
                    self.auto = s.auto_restart.then_some(*s);
                } else {
                    self.error(ErrorCode::Unsupported, seq, 0);
                }
            }
            HostFrame::Stop => {
                self.auto = None;
                self.bus.stop()?
            }
            HostFrame::Animate(a) => {
                let regs = self.reg_words();
                let bad = a
                    .ramps
                    .iter()
                    .map(|r| r.reg)
                    .chain(a.orbits.iter().flat_map(|o| [o.x_reg, o.z_reg]))
                    .position(|reg| usize::from(reg) >= regs);
                // The steps add and rotate Q16.16 words; on a binary32 image they would
                // write other numbers than the host asked for, so they are refused.
                let format = hdr::VALUE_FORMAT;
                let fixed = self.shadow.get(format) == Some(&ValueFormat::Q16_16.code());
                let animates = !a.ramps.is_empty() || !a.orbits.is_empty();
                match bad {
                    Some(i) => self.error(ErrorCode::OutOfRange, seq, i as u32),
                    None if animates && !fixed => {
                        self.error(ErrorCode::Unsupported, seq, format as u32)
                    }
                    None => self.animation = a.clone(),
                }
            }
            HostFrame::Sync(token) => {
                // The raster block drains its FIFO at one record per cycle, so this wait
                // is short; the link keeps its timers because the host sees no ACK delay
                // beyond one frame time.
                while !self.bus.idle()? {
                    self.bus.wait()?;
                }
                self.answer(DeviceFrame::Synced(*token));
            }
            HostFrame::Read(req) => match self.bus.read_len(req)? {
                Some(len) if self.read.is_none() => {
                    self.read = Some(ReadJob {
                        seq,
                        req: *req,
                        offset: 0,
                        len,
                        crc: CRC32.digest(),
                    });
                }
                _ => self.error(ErrorCode::BadState, seq, 0),
            },
            HostFrame::GetStats => {
                let device = self.device_counters()?;
                self.answer(DeviceFrame::Stats(Stats { link, device }));
            }
            HostFrame::Reset => {
                self.bus.reset()?;
                self.auto = None;
                self.animation = Animation::default();
                self.running = 0;
                self.shadow = [0; SHADOW];
                self.setup = None;
                self.read = None;
                self.outbox.clear();
                self.counters = DeviceCounters::default();
            }
        }
        Ok(())
    }

    /// Registers of the target's map (header, camera, its lights and objects).
    fn reg_words(&self) -> usize {
        protocol::scene::map_words(
            usize::from(self.caps.max_objects),
            usize::from(self.caps.max_lights),
        )
    }

    /// One animation step: the next values of the animated registers, written to the
    /// FPGA between two auto-restarted frames.
    fn step_animation(&mut self) -> Result<(), B::Error> {
        for i in 0..self.animation.ramps.len() {
            let r = self.animation.ramps[i];
            let reg = usize::from(r.reg);
            if reg < SHADOW {
                self.shadow[reg] = r.apply(self.shadow[reg]);
                self.bus.write_regs(r.reg, &[self.shadow[reg]])?;
            }
        }
        for i in 0..self.animation.orbits.len() {
            let o = self.animation.orbits[i];
            let (xr, zr) = (usize::from(o.x_reg), usize::from(o.z_reg));
            if xr < SHADOW && zr < SHADOW {
                let (x, z) = o.apply(self.shadow[xr], self.shadow[zr]);
                self.shadow[xr] = x;
                self.shadow[zr] = z;
                self.bus.write_regs(o.x_reg, &[x])?;
                self.bus.write_regs(o.z_reg, &[z])?;
            }
        }
        Ok(())
    }

    fn device_counters(&mut self) -> Result<DeviceCounters, B::Error> {
        let fpga = self.bus.counters()?;
        Ok(DeviceCounters {
            commands: self.counters.commands,
            bus_words: self.counters.bus_words,
            fragments: fpga.fragments,
            cycles: fpga.cycles,
            fifo_stalls: self.counters.fifo_stalls,
            frames: fpga.frames,
            queue_free: self.counters.queue_free,
            saturations: fpga.saturations,
        })
    }

    /// Lets the link layer report its free slots in the stats.
    pub(crate) fn set_queue_free(&mut self, free: u16) {
        self.counters.queue_free = free;
    }

    fn hello(&mut self, seq: u16, peer: &Hello) -> Result<(), B::Error> {
        // Answer with our hello either way: the host needs our version and hash to name
        // both sides in its error message.
        self.answer(DeviceFrame::Hello(Hello::new(self.caps, self.ident)));
        match peer.check() {
            Ok(()) => {
                crate::log::log_info!("host session: protocol {}", peer.protocol_version);
                self.handshaken = true;
                self.host_payload = peer.caps.link_payload();
            }
            Err(_) => {
                self.handshaken = false;
                self.error(ErrorCode::Handshake, seq, 0);
            }
        }
        Ok(())
    }

    fn raster_setup(&mut self, seq: u16, s: &RasterSetup) -> Result<(), B::Error> {
        if !self.caps.raster {
            self.error(ErrorCode::Unsupported, seq, 0);
        } else if s.width == 0
            || s.height == 0
            || s.width > self.caps.max_width
            || s.height > self.caps.max_height
            || s.subpixel_bits > self.caps.max_subpixel_bits
        {
            self.error(ErrorCode::OutOfRange, seq, 0);
        } else {
            self.bus.raster_setup(s)?;
            self.setup = Some(*s);
        }
        Ok(())
    }

    /// Pushes the raster batch in `payload` (decoded as a [`Request`], so every command
    /// is known to decode), one command on the stack at a time.
    fn raster(&mut self, seq: u16, payload: &[u8]) -> Result<(), B::Error> {
        let Some(setup) = self.setup else {
            self.error(ErrorCode::BadState, seq, 0);
            return Ok(());
        };
        let Ok(cmds) = raster_commands(payload) else {
            self.error(ErrorCode::Malformed, seq, 0);
            return Ok(());
        };
        for (i, cmd) in cmds.enumerate() {
            // The request decoded, so this cannot fail; if it did, the batch stops here.
            let Ok(cmd) = cmd else {
                self.error(ErrorCode::Malformed, seq, i as u32);
                return Ok(());
            };
            let cmd = &cmd;
            // The one value the packer cannot judge: a seed must lie in this frame's
            // framebuffer, or the FPGA's fill unit would fault.
            if let RasterCmd::Fill(f) = cmd {
                if f.seed.x >= setup.width || f.seed.y >= setup.height {
                    self.error(ErrorCode::OutOfRange, seq, i as u32);
                    return Ok(());
                }
            }
            // A clear is its own command here; folding it into the next command's CB
            // bit is the packer's business.
            let opts = PackOptions {
                subpixel_bits: setup.subpixel_bits,
                clear: false,
            };
            let (records, stalls) = match push_command(&mut self.bus, self.layout, cmd, opts) {
                Ok(pushed) => pushed,
                Err(PushError::Bus(e)) => return Err(e),
                Err(PushError::Pack(e)) => {
                    let code = match e {
                        BusError::UnsupportedCommand { .. }
                        | BusError::UnsupportedFeature { .. } => ErrorCode::Unsupported,
                        _ => ErrorCode::OutOfRange,
                    };
                    self.error(code, seq, i as u32);
                    return Ok(());
                }
            };
            self.counters.fifo_stalls += stalls;
            self.counters.commands += 1;
            self.counters.bus_words += records as u32;
        }
        Ok(())
    }

    /// Whether the next answer is a read-back chunk ([`Engine::write_chunk`]): a read-back
    /// is under way with bytes left and no other answer is queued before it.
    pub(crate) fn chunk_due(&self) -> bool {
        self.outbox.is_empty() && self.read.as_ref().is_some_and(|j| j.offset < j.len)
    }

    /// Writes the next read-back chunk, as the encoded [`DeviceFrame::Chunk`] message, into
    /// `out` (the link's slot, so the FPGA's bytes land where they are sent from) and
    /// returns its length. `Err(None)`: no read-back is under way; `Err(Some(e))`: the
    /// bus failed, the read-back was stopped and an error answer queued for the host.
    pub(crate) fn write_chunk(&mut self, out: &mut [u8]) -> Result<usize, Option<B::Error>> {
        let Some(job) = &mut self.read else {
            return Err(None);
        };
        let n = (job.len - job.offset).min(read_chunk_len(out.len().min(self.host_payload)) as u32)
            as usize;
        let (req, offset, seq) = (job.req, job.offset, job.seq);
        // The slot holds at least MAX_PAYLOAD bytes and `n` leaves room for the message
        // around the bytes (at most CHUNK_HEADER_MAX of them).
        let (head, start) = chunk_header(offset, n as u32);
        out[..start].copy_from_slice(&head[..start]);
        let data = &mut out[start..start + n];
        if let Err(e) = self.bus.read(&req, offset, data) {
            // The host must hear why its read-back stops, not wait for the rest.
            self.read = None;
            self.error(ErrorCode::Device, seq, offset);
            return Err(Some(e));
        }
        job.crc.update(data);
        job.offset += n as u32;
        Ok(start + n)
    }

    /// The next answer for the host other than a read-back chunk, if any: queued answers
    /// first, then the end of a read-back whose chunks are all sent, then a finished
    /// frame. While [`Engine::chunk_due`], the controller sends chunks instead.
    // Not inlined into the controller's send loop, for the reason `receive` is not (on
    // the MSP430 that saved 0.4 KB of flash).
    #[inline(never)]
    pub(crate) fn next_output(&mut self) -> Result<Option<DeviceFrame>, B::Error> {
        if let Some(f) = self.outbox.pop_front() {
            return Ok(Some(f));
        }
        if let Some(job) = &mut self.read {
            if job.offset < job.len {
                return Ok(None);
            }
            let done = ReadDone {
                len: job.len,
                crc32: core::mem::replace(&mut job.crc, CRC32.digest()).finalize(),
            };
            self.read = None;
            return Ok(Some(DeviceFrame::ReadDone(done)));
        }
        if self.running == 0 {
            return Ok(None);
        }
        let Some(done) = self.bus.poll_done()? else {
            return Ok(None);
        };
        self.running -= 1;
        if let Some(mut next) = self.auto {
            self.step_animation()?;
            next.frame_id = next.frame_id.wrapping_add(1);
            self.bus.start(&next)?;
            self.running += 1;
            self.auto = Some(next);
        }
        Ok(Some(DeviceFrame::Done(done)))
    }
}
