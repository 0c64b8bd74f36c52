//! The STM32F405 board: USART1 is the host link, USART2 the FPGA link (to
//! `fpgfx-sim --fpga-link`), SysTick the millisecond clock, defmt over semihosting the log.
//!
//! Clocks: the core runs on whatever the reset state gives (HSI 16 MHz on silicon; QEMU's
//! `netduinoplus2` model runs its SysTick from a fixed 168 MHz system clock and has no RCC to
//! program), so the SysTick reload comes from `CORE_HZ`, chosen per target at build time.
#![no_std]
#![no_main]

use core::cell::RefCell;
use core::convert::Infallible;
use core::panic::PanicInfo;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::interrupt::{self, Mutex};
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::debug;
use defmt_semihosting as _;
use firmware::{Clock, Controller, ControllerError, FpgaLink, FpgaLinkError};
use heapless::Deque;

/// Core clock feeding SysTick. QEMU's STM32F405 SoC fixes SYSCLK at 168 MHz; on silicon
/// without PLL set-up this would be 16 MHz (set `FPGFX_CORE_HZ` when building for one).
const CORE_HZ: u32 = match option_env!("FPGFX_CORE_HZ") {
    Some(s) => parse_u32(s),
    None => 168_000_000,
};

const fn parse_u32(s: &str) -> u32 {
    let b = s.as_bytes();
    let mut i = 0;
    let mut v = 0u32;
    while i < b.len() {
        v = v * 10 + (b[i] - b'0') as u32;
        i += 1;
    }
    v
}

/// Line rate programmed into BRR (QEMU ignores it; a board's USB-UART must match).
const BAUD: u32 = 921_600;

/// Bytes a receive ring holds: two full link frames, so a burst from the host or the FPGA
/// waits in RAM while the main loop is busy instead of overrunning the one-byte DR.
const RX_RING: usize = 1024;

type Ring = Mutex<RefCell<Deque<u8, RX_RING>>>;

/// Filled by the USART interrupts, drained by the main loop.
static RX1: Ring = Mutex::new(RefCell::new(Deque::new()));
static RX2: Ring = Mutex::new(RefCell::new(Deque::new()));

/// Bytes lost: DR overruns (the interrupt came too late) and full rings. The link
/// recovers them by retransmission; the count goes to the log.
static LOST: AtomicU32 = AtomicU32::new(0);

/// STM32F4 USART register block (RM0090 §30.6), as QEMU's stm32f2xx_usart models it.
struct Usart {
    base: usize,
    rx: &'static Ring,
}

/// USART1 and USART2 interrupt numbers (RM0090 table 61).
#[derive(Clone, Copy)]
struct Irq(u16);

// SAFETY: the numbers are the STM32F405's USART1/USART2 vectors.
unsafe impl cortex_m::interrupt::InterruptNumber for Irq {
    fn number(self) -> u16 {
        self.0
    }
}

const USART1_IRQ: Irq = Irq(37);
const USART2_IRQ: Irq = Irq(38);
const USART1_BASE: usize = 0x4001_1000;
const USART2_BASE: usize = 0x4000_4400;

impl Usart {
    const SR: usize = 0x00;
    const DR: usize = 0x04;
    const BRR: usize = 0x08;
    const CR1: usize = 0x0c;
    const SR_RXNE: u32 = 1 << 5;
    const SR_TXE: u32 = 1 << 7;
    const SR_ORE: u32 = 1 << 3;
    const CR1_UE: u32 = 1 << 13;
    const CR1_RXNEIE: u32 = 1 << 5;
    const CR1_TE: u32 = 1 << 3;
    const CR1_RE: u32 = 1 << 2;

    fn reg(base: usize, off: usize) -> *mut u32 {
        (base + off) as *mut u32
    }

    /// # Safety
    /// `base` must be a USART block of this chip whose interrupt is `irq`, owned by
    /// nothing else.
    unsafe fn new(base: usize, irq: Irq, rx: &'static Ring, pclk_hz: u32) -> Self {
        // SAFETY: the caller gives a USART block; these are its documented registers, and
        // unmasking its interrupt is sound because the handler only touches `rx`.
        unsafe {
            core::ptr::write_volatile(Self::reg(base, Self::BRR), pclk_hz.div_ceil(BAUD));
            core::ptr::write_volatile(
                Self::reg(base, Self::CR1),
                Self::CR1_UE | Self::CR1_TE | Self::CR1_RE | Self::CR1_RXNEIE,
            );
            cortex_m::peripheral::NVIC::unmask(irq);
        }
        Usart { base, rx }
    }

    /// The receive interrupt: move what DR holds into the ring.
    fn on_interrupt(base: usize, rx: &Ring) {
        // SAFETY: registers of a USART block named by the vector that fired.
        unsafe {
            loop {
                let sr = core::ptr::read_volatile(Self::reg(base, Self::SR));
                if sr & Self::SR_ORE != 0 {
                    LOST.fetch_add(1, Ordering::Relaxed);
                }
                if sr & Self::SR_RXNE == 0 {
                    break;
                }
                // Reading DR clears RXNE (and ORE after the SR read), as RM0090 says.
                let b = core::ptr::read_volatile(Self::reg(base, Self::DR)) as u8;
                let full = interrupt::free(|cs| rx.borrow(cs).borrow_mut().push_back(b).is_err());
                if full {
                    LOST.fetch_add(1, Ordering::Relaxed);
                }
            }
        }
    }
}

impl embedded_io::ErrorType for Usart {
    type Error = Infallible;
}

impl embedded_io::ReadReady for Usart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        Ok(interrupt::free(|cs| {
            !self.rx.borrow(cs).borrow().is_empty()
        }))
    }
}

impl embedded_io::Read for Usart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        if buf.is_empty() {
            return Ok(0);
        }
        // embedded_io: block until at least one byte, then take what is there.
        loop {
            let n = interrupt::free(|cs| {
                let mut ring = self.rx.borrow(cs).borrow_mut();
                let mut n = 0;
                while n < buf.len() {
                    let Some(b) = ring.pop_front() else { break };
                    buf[n] = b;
                    n += 1;
                }
                n
            });
            if n > 0 {
                return Ok(n);
            }
            cortex_m::asm::wfi();
        }
    }
}

impl embedded_io::Write for Usart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            // SAFETY: SR and DR of this block; writing DR with TXE set queues one byte.
            unsafe {
                while core::ptr::read_volatile(Self::reg(self.base, Self::SR)) & Self::SR_TXE == 0 {
                }
                core::ptr::write_volatile(Self::reg(self.base, Self::DR), u32::from(b));
            }
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

#[exception]
unsafe fn DefaultHandler(irqn: i16) {
    // No PAC, so cortex-m-rt's default vector table sends every device interrupt here.
    match irqn {
        37 => Usart::on_interrupt(USART1_BASE, &RX1),
        38 => Usart::on_interrupt(USART2_BASE, &RX2),
        _ => {}
    }
}

/// The SysTick clock; idling sleeps until the next interrupt.
struct BoardClock;

impl Clock for BoardClock {
    fn now_ms(&mut self) -> u64 {
        now_ms()
    }

    fn idle(&mut self) {
        cortex_m::asm::wfi();
    }
}

const RCC_APB2ENR: *mut u32 = 0x4002_3844 as *mut u32;
const RCC_APB1ENR: *mut u32 = 0x4002_3840 as *mut u32;

/// Milliseconds since boot, counted by the SysTick exception.
static MILLIS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    MILLIS.fetch_add(1, Ordering::Relaxed);
}

fn now_ms() -> u64 {
    u64::from(MILLIS.load(Ordering::Relaxed))
}

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        defmt::error!("core peripherals taken twice");
        exit(false)
    };
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(CORE_HZ / 1000 - 1);
    cp.SYST.clear_current();
    cp.SYST.enable_interrupt();
    cp.SYST.enable_counter();

    // SAFETY: RCC enable registers; set the USART1 (APB2 bit 4) and USART2 (APB1 bit 17)
    // clocks before touching the blocks.
    unsafe {
        core::ptr::write_volatile(RCC_APB2ENR, core::ptr::read_volatile(RCC_APB2ENR) | 1 << 4);
        core::ptr::write_volatile(RCC_APB1ENR, core::ptr::read_volatile(RCC_APB1ENR) | 1 << 17);
    }
    // SAFETY: USART1 and USART2 of the STM32F405, used only through these two values.
    let (host, fpga_port) = unsafe {
        (
            Usart::new(USART1_BASE, USART1_IRQ, &RX1, CORE_HZ / 2),
            Usart::new(USART2_BASE, USART2_IRQ, &RX2, CORE_HZ / 4),
        )
    };
    defmt::info!(
        "fpgfx-firmware {=str}: controller {=usize} B, FPGA link {=usize} B of RAM",
        env!("CARGO_PKG_VERSION"),
        core::mem::size_of::<Controller<Usart, FpgaLink<Usart, BoardClock>>>(),
        core::mem::size_of::<FpgaLink<Usart, BoardClock>>()
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

    // In a static rather than on the stack, so that `llvm-size` shows the controller's
    // whole RAM (link windows, inbox, register shadow) in .bss.
    let Some(controller) = cortex_m::singleton!(: Controller<Usart, FpgaLink<Usart, BoardClock>> =
        Controller::new(host, fpga, id.caps, id.layout.layout(), "fpgfx-firmware stm32f405"))
    else {
        defmt::error!("controller created twice");
        exit(false)
    };
    let mut reported_lost = 0;
    loop {
        // Sleep until something arrives or the millisecond tick: every step of the
        // controller is triggered by a received byte (a request, an ACK, credit) or by a
        // timer, so nothing waits longer than one tick.
        let quiet = interrupt::free(|cs| {
            RX1.borrow(cs).borrow().is_empty() && RX2.borrow(cs).borrow().is_empty()
        });
        if quiet {
            cortex_m::asm::wfi();
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
        let lost = LOST.load(Ordering::Relaxed);
        if lost != reported_lost {
            defmt::warn!("UART bytes lost so far: {=u32}", lost);
            reported_lost = lost;
        }
    }
}

fn exit(ok: bool) -> ! {
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    #[allow(clippy::empty_loop)]
    loop {}
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
