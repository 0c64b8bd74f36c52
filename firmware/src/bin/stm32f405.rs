//! The STM32F405 board: USART1 is the host link, USART2 the FPGA link (to
//! `fpgfx-sim --fpga-link`), SysTick the millisecond clock. The main loop, the receive
//! rings, the log and the panic handler are `firmware::board`'s; this file holds the
//! registers, the interrupts and the clock.
//!
//! Clocks: the core runs on whatever the reset state gives (HSI 16 MHz on silicon; QEMU's
//! `netduinoplus2` model runs its SysTick from a fixed 168 MHz system clock and has no RCC to
//! program), so the SysTick reload comes from `CORE_HZ`, chosen per target at build time.
#![no_std]
#![no_main]

use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use firmware::board::{self, BoardController, RxRing, Serial, Slot, Transmit};

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

/// Filled by the USART interrupts, drained by the main loop.
static RX1: RxRing = RxRing::new();
static RX2: RxRing = RxRing::new();

static CONTROLLER: Slot<BoardController<Usart, Usart>> = Slot::new();

/// STM32F4 USART register block (RM0090 §30.6), as QEMU's stm32f2xx_usart models it.
struct Usart {
    base: usize,
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
    /// nothing else, and whose interrupt fills `rx`.
    unsafe fn new(base: usize, irq: Irq, rx: &'static RxRing, pclk_hz: u32) -> Serial<Self> {
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
        Serial::new(Usart { base }, rx)
    }

    /// The receive interrupt: move what DR holds into the ring.
    fn on_interrupt(base: usize, rx: &RxRing) {
        // SAFETY: registers of a USART block named by the vector that fired.
        unsafe {
            loop {
                let sr = core::ptr::read_volatile(Self::reg(base, Self::SR));
                if sr & Self::SR_ORE != 0 {
                    rx.overrun();
                }
                if sr & Self::SR_RXNE == 0 {
                    break;
                }
                // Reading DR clears RXNE (and ORE after the SR read), as RM0090 says.
                rx.push(core::ptr::read_volatile(Self::reg(base, Self::DR)) as u8);
            }
        }
    }
}

impl Transmit for Usart {
    fn send(&mut self, byte: u8) {
        // SAFETY: SR and DR of this block; writing DR with TXE set queues one byte.
        unsafe {
            while core::ptr::read_volatile(Self::reg(self.base, Self::SR)) & Self::SR_TXE == 0 {}
            core::ptr::write_volatile(Self::reg(self.base, Self::DR), u32::from(byte));
        }
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

#[exception]
fn SysTick() {
    board::tick();
}

const RCC_APB2ENR: *mut u32 = 0x4002_3844 as *mut u32;
const RCC_APB1ENR: *mut u32 = 0x4002_3840 as *mut u32;

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        defmt::error!("core peripherals taken twice");
        board::exit(false)
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
    // SAFETY: USART1 and USART2 of the STM32F405, used only through these two values,
    // each filling its own ring.
    let (host, fpga_port) = unsafe {
        (
            Usart::new(USART1_BASE, USART1_IRQ, &RX1, CORE_HZ / 2),
            Usart::new(USART2_BASE, USART2_IRQ, &RX2, CORE_HZ / 4),
        )
    };
    board::run(&CONTROLLER, host, fpga_port, "fpgfx-firmware stm32f405")
}
