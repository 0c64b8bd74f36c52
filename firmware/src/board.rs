//! What the board binaries share: the main loop that joins the host link, the controller,
//! the FPGA link and the clock; the interrupt-filled receive rings behind both UARTs; the
//! millisecond clock; exit and panic over semihosting; the defmt log.
//!
//! A chip's binary (`src/bin/stm32f405.rs`, `src/bin/microblaze_v.rs`) holds only what
//! differs between chips: its UART registers (a [`Transmit`] and the receive interrupt
//! that fills an [`RxRing`]), its interrupt controller, and the timer whose interrupt
//! calls [`tick`] every millisecond. Both cores sleep with `WFI` (the same mnemonic on
//! Armv7-M and RISC-V), so waiting is shared too. Built only with the `board-stm32` or
//! `board-riscv` feature: the semihosting calls and `WFI` exist only on those cores.

use core::cell::{RefCell, UnsafeCell};
use core::convert::Infallible;
use core::mem::MaybeUninit;
use core::panic::PanicInfo;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use critical_section::Mutex;
use defmt_semihosting as _;
use heapless::Deque;

use crate::{Clock, Controller, ControllerError, FpgaLink, FpgaLinkError};

/// Bytes a receive ring holds: two full link frames, so a burst from the host or the FPGA
/// waits in RAM while the main loop is busy instead of overrunning the UART's own FIFO
/// (one byte on the STM32, 8 or 16 on the MicroBlaze V's UARTs).
pub const RX_RING: usize = 1024;

/// The bytes one UART has received and the main loop has not yet taken: filled by the
/// chip's receive interrupt ([`RxRing::push`]), drained through [`Serial`]'s `Read`.
pub struct RxRing {
    bytes: Mutex<RefCell<Deque<u8, RX_RING>>>,
    /// Bytes lost to UART overruns (the interrupt came too late) and to a full ring. The
    /// link recovers them by retransmission; the main loop logs the count.
    lost: AtomicU32,
}

impl RxRing {
    /// An empty ring, for a `static` the interrupt handler and the main loop share.
    pub const fn new() -> Self {
        RxRing {
            bytes: Mutex::new(RefCell::new(Deque::new())),
            lost: AtomicU32::new(0),
        }
    }

    /// Queues a received byte (from the receive interrupt); a full ring counts it lost.
    pub fn push(&self, byte: u8) {
        let full = critical_section::with(|cs| self.bytes.borrow(cs).borrow_mut().push_back(byte))
            .is_err();
        if full {
            self.overrun();
        }
    }

    /// Counts a byte the UART itself dropped (its overrun flag).
    pub fn overrun(&self) {
        self.lost.fetch_add(1, Ordering::Relaxed);
    }

    fn is_empty(&self) -> bool {
        critical_section::with(|cs| self.bytes.borrow(cs).borrow().is_empty())
    }

    /// Moves what is queued, up to `buf.len()` bytes, into `buf`.
    fn take(&self, buf: &mut [u8]) -> usize {
        critical_section::with(|cs| {
            let mut ring = self.bytes.borrow(cs).borrow_mut();
            let mut n = 0;
            while n < buf.len() {
                let Some(b) = ring.pop_front() else { break };
                buf[n] = b;
                n += 1;
            }
            n
        })
    }
}

impl Default for RxRing {
    fn default() -> Self {
        Self::new()
    }
}

/// The transmit side of a chip's UART. Blocking, one byte at a time: the link hands over
/// whole frames, and the controller has nothing else to do until they are out.
pub trait Transmit {
    /// Waits until the UART takes another byte, then gives it `byte`.
    fn send(&mut self, byte: u8);
}

/// A UART as the controller and the FPGA link see it (`embedded_io` traits): reads come
/// from the ring its interrupt fills, writes go to the chip's [`Transmit`].
pub struct Serial<T> {
    tx: T,
    rx: &'static RxRing,
}

impl<T: Transmit> Serial<T> {
    /// Joins a UART's transmitter to the ring its receive interrupt fills.
    pub fn new(tx: T, rx: &'static RxRing) -> Self {
        Serial { tx, rx }
    }
}

impl<T> embedded_io::ErrorType for Serial<T> {
    type Error = Infallible;
}

impl<T> embedded_io::ReadReady for Serial<T> {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(!self.rx.is_empty())
    }
}

impl<T> embedded_io::Read for Serial<T> {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        // embedded_io: block until at least one byte, then take what is there.
        loop {
            let n = self.rx.take(buf);
            if n > 0 {
                return Ok(n);
            }
            wait_for_interrupt();
        }
    }
}

impl<T: Transmit> embedded_io::Write for Serial<T> {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            self.tx.send(b);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// Milliseconds since boot, counted by [`tick`].
static MILLIS: AtomicU32 = AtomicU32::new(0);

/// Counts one millisecond: the chip's timer interrupt calls it, so the link's clock is
/// whatever timer the chip has (SysTick, an AXI Timer) without the loop knowing which.
pub fn tick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}

/// The link clock: milliseconds from [`tick`]; idling sleeps until the next interrupt,
/// which is a received byte or the next tick, so no wait outlasts a millisecond.
#[derive(Clone, Copy, Debug, Default)]
pub struct BoardClock;

impl Clock for BoardClock {
    fn now_ms(&mut self) -> u64 {
        now_ms()
    }

    fn idle(&mut self) {
        wait_for_interrupt();
    }
}

fn now_ms() -> u64 {
    u64::from(MILLIS.load(Ordering::Relaxed))
}

/// Sleeps until an interrupt is pending. Under QEMU this matters beyond power: a vCPU
/// spinning on a status register holds QEMU's I/O lock and starves the thread that
/// delivers the UART bytes.
fn wait_for_interrupt() {
    // SAFETY: WFI only pauses the core until an interrupt is pending; it touches no
    // memory. Armv7-M and RISC-V spell it the same.
    unsafe { core::arch::asm!("wfi", options(nomem, nostack, preserves_flags)) }
}

/// The controller of a board whose host link is a `Serial<H>` and whose FPGA is behind a
/// `Serial<F>`.
pub type BoardController<H, F> = Controller<Serial<H>, FpgaLink<Serial<F>, BoardClock>>;

/// Static storage for the controller, filled once by [`run`]. A static rather than the
/// stack so that `llvm-size` shows the controller's whole RAM (link windows, inbox,
/// register shadow, FPGA link) in `.bss`; generic functions cannot declare statics, so
/// each chip's binary declares one of these for its concrete types.
pub struct Slot<T> {
    taken: AtomicBool,
    value: UnsafeCell<MaybeUninit<T>>,
}

// SAFETY: `put` hands out the only reference to the value, once (the flag is swapped
// atomically), so no two contexts ever share it; moving it there needs `T: Send`.
unsafe impl<T: Send> Sync for Slot<T> {}

impl<T> Slot<T> {
    /// An empty slot, for a `static`.
    pub const fn new() -> Self {
        Slot {
            taken: AtomicBool::new(false),
            value: UnsafeCell::new(MaybeUninit::uninit()),
        }
    }

    /// Moves `value` in and returns it, or `None` if the slot was filled before.
    // A `&mut` from a shared reference: sound because the flag lets exactly one caller
    // through, once (the same argument as `cortex_m::singleton!`).
    #[allow(clippy::mut_from_ref)]
    fn put(&'static self, value: T) -> Option<&'static mut T> {
        if self.taken.swap(true, Ordering::AcqRel) {
            return None;
        }
        // SAFETY: the flag was clear, so this is the first and only reference.
        Some(unsafe { (*self.value.get()).write(value) })
    }
}

impl<T> Default for Slot<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// The board's main loop: connects to the FPGA over `fpga_port` (retrying until it
/// answers), builds the controller in `slot` with `ident` as its hello text ("fpgfx-firmware
/// stm32f405"), then serves the host on `host` for ever.
pub fn run<H: Transmit, F: Transmit>(
    slot: &'static Slot<BoardController<H, F>>,
    host: Serial<H>,
    fpga_port: Serial<F>,
    ident: &'static str,
) -> ! {
    let rings = [host.rx, fpga_port.rx];
    defmt::info!(
        "fpgfx-firmware {=str}: controller {=usize} B, FPGA link {=usize} B of RAM",
        env!("CARGO_PKG_VERSION"),
        core::mem::size_of::<BoardController<H, F>>(),
        core::mem::size_of::<FpgaLink<Serial<F>, BoardClock>>()
    );

    let mut fpga = FpgaLink::new(fpga_port, BoardClock);
    fpga.timeout_ms = 5_000;
    let mut nonce: u16 = 1;
    let id = loop {
        match fpga.connect(nonce) {
            Ok(id) => break id,
            Err(e) => {
                defmt::warn!("FPGA link not up yet: {}", e);
                nonce = nonce.wrapping_add(1);
            }
        }
    };
    // From here a question may wait for a whole ray-traced frame.
    fpga.timeout_ms = 600_000;
    defmt::info!(
        "FPGA up: {=str} layout, FIFO {=u16} records, {=u8} objects",
        id.layout.layout().name,
        id.caps.fifo_depth,
        id.caps.max_objects
    );

    let Some(controller) = slot.put(Controller::new(
        host,
        fpga,
        id.caps,
        id.layout.layout(),
        ident,
    )) else {
        defmt::error!("controller created twice");
        exit(false)
    };
    let mut reported_lost = 0;
    loop {
        // Sleep until something arrives or the millisecond tick: every step of the
        // controller is triggered by a received byte (a request, an ACK, credit) or by a
        // timer, so nothing waits longer than one tick.
        if rings.iter().all(|r| r.is_empty()) {
            wait_for_interrupt();
        }
        match controller.poll(now_ms()) {
            Ok(()) => {}
            Err(ControllerError::Host(never)) => match never {},
            Err(ControllerError::Fpga(FpgaLinkError::PeerReset)) => {
                // The FPGA restarted: it lost scene and framebuffer; re-synchronise and let
                // the host's next request find out (its registers are sent again on reset).
                defmt::warn!("FPGA restarted; reconnecting");
                nonce = nonce.wrapping_add(1);
                if let Err(e) = controller.engine().bus().connect(nonce) {
                    defmt::error!("FPGA reconnect failed: {}", e);
                }
            }
            Err(ControllerError::Fpga(e)) => {
                defmt::error!("FPGA: {}", e);
            }
        }
        let lost = rings
            .iter()
            .fold(0u32, |n, r| n.wrapping_add(r.lost.load(Ordering::Relaxed)));
        if lost != reported_lost {
            defmt::warn!("UART bytes lost so far: {=u32}", lost);
            reported_lost = lost;
        }
    }
}

/// Ends the program through semihosting: under QEMU the emulator exits with status 0 for
/// `ok`, 1 otherwise (on silicon a debugger reports it).
pub fn exit(ok: bool) -> ! {
    semihosting::process::exit(if ok { 0 } else { 1 })
}

#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    // The location, not the message: formatting the message would pull core::fmt into a
    // binary whose flash budget is 64 KiB.
    match info.location() {
        Some(l) => defmt::error!("panic at {=str}:{=u32}", l.file(), l.line()),
        None => defmt::error!("panic"),
    }
    exit(false)
}
