//! The board in this process: the real firmware controller and an FPGA bus, joined to
//! the host by an in-memory byte pipe (what `fpgfx --port builtin` talks to).
//!
//! Nothing is short-cut: the host's frames are COBS/CRC-framed by the link, cross the
//! pipe as bytes, are decoded by the same `firmware::Controller` a board runs, packed
//! into bus records and executed by the FPGA model. Only the wire is missing, which is
//! why built-in mode and a board must produce identical images.

use std::collections::VecDeque;
use std::convert::Infallible;
use std::io;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use firmware::{
    Controller, ControllerError, FpgaBus, FpgaLink, MmioBus, MmioError, Registers, INBOX, SHADOW,
    WINDOW,
};
use protocol::bus::BusLayout;
use protocol::frame::{Caps, DeviceCounters, FrameDone, ReadRequest, StartFrame};
use protocol::link::Bulk;
use protocol::raster::RasterSetup;
use sim_target::mmio::{RegisterError, RegisterFile};

/// One direction of an in-memory byte line. A mutex rather than a `RefCell` so that the
/// line can join threads (the FPGA-link emulation runs its FPGA on one).
#[derive(Clone, Default)]
struct Queue(Arc<Mutex<VecDeque<u8>>>);

impl Queue {
    fn lock(&self) -> MutexGuard<'_, VecDeque<u8>> {
        // A poisoned line means the other end panicked; its bytes are still bytes.
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Moves the oldest bytes, as many as fit, into `buf` (two slice copies, not a byte
    /// loop: a read-back moves its whole frame through here).
    fn take_into(&self, buf: &mut [u8]) -> usize {
        let mut q = self.lock();
        let n = buf.len().min(q.len());
        let (a, b) = q.as_slices();
        let first = n.min(a.len());
        buf[..first].copy_from_slice(&a[..first]);
        buf[first..n].copy_from_slice(&b[..n - first]);
        q.drain(..n);
        n
    }

    /// Whether the other end has gone (only this end holds the line).
    fn orphaned(&self) -> bool {
        Arc::strong_count(&self.0) == 1
    }
}

/// An end of an in-memory, full-duplex byte line (`embedded_io`, never blocking).
pub struct PipeEnd {
    rx: Queue,
    tx: Queue,
}

impl PipeEnd {
    /// Two connected ends.
    pub fn pair() -> (PipeEnd, PipeEnd) {
        let (a, b) = (Queue::default(), Queue::default());
        (
            PipeEnd {
                rx: a.clone(),
                tx: b.clone(),
            },
            PipeEnd { rx: b, tx: a },
        )
    }
}

impl embedded_io::ErrorType for PipeEnd {
    type Error = Infallible;
}

impl embedded_io::Read for PipeEnd {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        Ok(self.rx.take_into(buf))
    }
}

impl embedded_io::ReadReady for PipeEnd {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(!self.rx.lock().is_empty())
    }
}

impl embedded_io::Write for PipeEnd {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        self.tx.lock().extend(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// The controller of a [`BuiltIn`]: a board's defaults, but a link of
/// [`Bulk`] frames, since memory is no object here and the pipe has no line rate (a
/// read-back then goes in 16 KiB chunks to a host that takes them, not 224-byte ones).
pub type BuiltInController<B> = Controller<PipeEnd, B, INBOX, WINDOW, SHADOW, Bulk>;

/// The host's end of an in-process controller driving `B`: a byte transport with the
/// same two calls as a serial line (host-cli wraps it as its `Transport`).
pub struct BuiltIn<B: FpgaBus> {
    /// Boxed: its link's windows of bulk frames are 280 KiB.
    controller: Box<BuiltInController<B>>,
    to_device: Queue,
    from_device: Queue,
    epoch: Instant,
}

impl<B: FpgaBus> BuiltIn<B>
where
    B::Error: core::fmt::Display,
{
    /// A controller with `caps` over `bus`, reading raster records in `layout`.
    pub fn new(bus: B, caps: Caps, layout: &'static BusLayout) -> Self {
        Self::named(bus, caps, layout, "fpgfx built-in target")
    }

    /// [`BuiltIn::new`] with the `ident` the controller's hello carries, which the host
    /// prints in its messages (so a user can tell the model from the RTL).
    pub fn named(bus: B, caps: Caps, layout: &'static BusLayout, ident: &'static str) -> Self {
        let to_device = Queue::default();
        let from_device = Queue::default();
        let end = PipeEnd {
            rx: to_device.clone(),
            tx: from_device.clone(),
        };
        Self {
            controller: Box::new(Controller::sized(end, bus, caps, layout, ident)),
            to_device,
            from_device,
            epoch: Instant::now(),
        }
    }

    /// The FPGA bus (the model), e.g. to inspect it in tests.
    pub fn bus(&mut self) -> &mut B {
        self.controller.engine().bus()
    }

    fn run(&mut self, now: u64) -> io::Result<()> {
        self.controller.poll(now).map_err(|e| match e {
            ControllerError::Host(never) => match never {},
            ControllerError::Fpga(e) => io::Error::other(format!("FPGA bus: {e}")),
        })
    }

    /// Queues `bytes` for the controller; never blocks or fails (the pipe has no
    /// capacity limit), the `io::Result` only matches a real line's signature.
    pub fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.to_device.lock().extend(bytes);
        Ok(())
    }

    /// Runs the controller until it has answered or `timeout` has passed, then takes what
    /// it sent into `buf`: `Ok(0)` means nothing came in time, as on a serial line. Fails
    /// only when the FPGA bus does.
    pub fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        let start = Instant::now();
        loop {
            // The controller handles one request per poll; let it catch up with what the
            // host sent before declaring that nothing came. One clock reading for the
            // eight (they are microseconds apart; a read-back polls ≈ 10⁵ times).
            let now = self.epoch.elapsed().as_millis() as u64;
            for _ in 0..8 {
                self.run(now)?;
            }
            let n = self.from_device.take_into(buf);
            if n > 0 || buf.is_empty() {
                return Ok(n);
            }
            if start.elapsed() >= timeout {
                return Ok(0);
            }
        }
    }
}

/// The emulated FPGA ([`sim_target::Device`]) as the controller's bus.
pub struct SimBus(pub sim_target::Device);

impl FpgaBus for SimBus {
    type Error = sim_target::DeviceError;

    fn fifo_free(&mut self) -> Result<usize, Self::Error> {
        Ok(self.0.fifo_free())
    }
    fn push_packet(&mut self, channel: u8, records: &[u64]) -> Result<(), Self::Error> {
        self.0.push_packet(channel, records)
    }
    fn wait(&mut self) -> Result<(), Self::Error> {
        self.0.wait()
    }
    fn idle(&mut self) -> Result<bool, Self::Error> {
        Ok(self.0.idle())
    }
    fn raster_setup(&mut self, setup: &RasterSetup) -> Result<(), Self::Error> {
        self.0.raster_setup(setup)
    }
    fn write_regs(&mut self, offset: u16, words: &[u32]) -> Result<(), Self::Error> {
        self.0.write_regs(offset, words)
    }
    fn write_texels(&mut self, offset: u32, bytes: &[u8]) -> Result<(), Self::Error> {
        self.0.write_texels(offset, bytes)
    }
    fn start(&mut self, start: &StartFrame) -> Result<(), Self::Error> {
        self.0.start(start)
    }
    fn stop(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
    fn poll_done(&mut self) -> Result<Option<FrameDone>, Self::Error> {
        Ok(self.0.poll_done())
    }
    fn read_len(&mut self, req: &ReadRequest) -> Result<Option<u32>, Self::Error> {
        Ok(self.0.read_len(req))
    }
    fn read(&mut self, req: &ReadRequest, offset: u32, out: &mut [u8]) -> Result<(), Self::Error> {
        self.0.read(req, offset, out);
        Ok(())
    }
    fn counters(&mut self) -> Result<DeviceCounters, Self::Error> {
        Ok(self.0.counters())
    }
    fn reset(&mut self) -> Result<(), Self::Error> {
        self.0.reset();
        Ok(())
    }
}

/// The built-in target: controller and emulated FPGA in this process, WIDE bus layout
/// (16.8 coordinates, so the command file's 8 sub-pixel bits pass unchanged).
pub fn sim_target() -> BuiltIn<SimBus> {
    sim_target_with(&protocol::bus::WIDE)
}

/// The built-in target with another bus layout (e.g. the FITkit's, to check that a file
/// is drawable by seed 000's board).
pub fn sim_target_with(layout: &'static BusLayout) -> BuiltIn<SimBus> {
    let device = sim_target::Device::new(layout);
    let caps = device.caps();
    BuiltIn::new(SimBus(device), caps, layout)
}

/// The register-file model ([`sim_target::mmio`]) as the firmware driver's registers:
/// sim-target cannot implement the firmware's trait itself, since the FPGA model must
/// not depend on the controller.
pub struct ModelRegisters(pub RegisterFile);

impl Registers for ModelRegisters {
    type Error = RegisterError;

    fn read(&mut self, addr: u32) -> Result<u32, RegisterError> {
        self.0.read(addr)
    }

    fn write(&mut self, addr: u32, value: u32) -> Result<(), RegisterError> {
        self.0.write(addr, value)
    }
}

/// The FPGA bus of [`sim_target_mmio`].
pub type ModelMmioBus = MmioBus<ModelRegisters>;

/// The controller's hello on the register bus, so that a user sees which bus ran.
pub const MMIO_IDENT: &str = "fpgfx built-in: AXI4-Lite bus";

/// Polls of one wait on the built-in register bus: the model ends a frame within
/// [`sim_target::mmio::DONE_AFTER_POLLS`] reads, so a wait this long is a stuck block,
/// reported in well under a second rather than after the firmware's board-sized limit.
pub const MODEL_POLL_LIMIT: u32 = 100_000;

/// `--port builtin:mmio`: the built-in target with the controller's [`MmioBus`] on the
/// register-file model, WIDE bus layout as [`sim_target()`]. Images must equal
/// [`sim_target()`]'s; the difference is only the bus.
pub fn sim_target_mmio() -> Result<BuiltIn<ModelMmioBus>, MmioError<RegisterError>> {
    let layout = &protocol::bus::WIDE;
    let device = sim_target::Device::new(layout);
    let caps = device.caps();
    mmio_target(ModelRegisters(RegisterFile::new(device)), caps, layout)
}

/// The built-in target with the controller's [`MmioBus`] on any registers (a model with
/// a knob set, or one wrapped to break it, for tests), probed first, with
/// [`MODEL_POLL_LIMIT`].
pub fn mmio_target<R: Registers>(
    regs: R,
    caps: Caps,
    layout: &'static BusLayout,
) -> Result<BuiltIn<MmioBus<R>>, MmioError<R::Error>>
where
    R::Error: core::fmt::Display,
{
    let mut bus = MmioBus::new(regs);
    bus.poll_limit = MODEL_POLL_LIMIT;
    bus.probe()?;
    Ok(BuiltIn::named(bus, caps, layout, MMIO_IDENT))
}

/// Milliseconds since the line was made, as the firmware's link clock.
pub struct StdClock(Instant);

impl firmware::Clock for StdClock {
    fn now_ms(&mut self) -> u64 {
        self.0.elapsed().as_millis() as u64
    }
}

/// The FPGA bus of [`sim_target_via_fpga_link`].
pub type LinkBus = FpgaLink<PipeEnd, StdClock>;

/// The built-in target with the FPGA behind the serial FPGA link, as on a QEMU board:
/// the controller talks [`protocol::fpga_link`] over an in-memory line to an emulated FPGA on
/// its own thread, which stops when the target is dropped. Images must equal
/// [`sim_target()`]'s; the difference is only the transport.
pub fn sim_target_via_fpga_link() -> Result<BuiltIn<LinkBus>, firmware::FpgaLinkError<Infallible>> {
    let (controller_end, fpga_end) = PipeEnd::pair();
    std::thread::spawn(move || serve_fpga(fpga_end, &protocol::bus::WIDE));
    let mut bus = FpgaLink::new(controller_end, StdClock(Instant::now()));
    let id = bus.connect(1)?;
    Ok(BuiltIn::new(bus, id.caps, id.layout.layout()))
}

/// Runs an emulated FPGA on `end` until the other end is dropped.
fn serve_fpga(mut end: PipeEnd, layout: &'static BusLayout) {
    use embedded_io::{Read, Write};
    let device = sim_target::Device::new(layout);
    let caps = device.caps();
    let mut server = crate::FpgaServer::new(SimBus(device), caps, layout);
    let epoch = Instant::now();
    let mut buf = [0u8; 512];
    let mut out = [0u8; protocol::link::MAX_FRAME];
    while !end.rx.orphaned() {
        let now = epoch.elapsed().as_millis() as u64;
        let n = match end.read(&mut buf) {
            Ok(n) => n,
            Err(never) => match never {},
        };
        server.input(now, &buf[..n]);
        let mut sent = false;
        while let Some(m) = server.poll_transmit(now, &mut out) {
            let _ = end.write(&out[..m]);
            sent = true;
        }
        if n == 0 && !sent && !server.work() {
            std::thread::sleep(Duration::from_micros(50));
        }
    }
}
