//! The MicroBlaze V board (RV32IMAC; QEMU `amd-microblaze-v-generic`, the peripherals of
//! AMD's generic MicroBlaze V design): the AXI UART Lite is the host link, the AXI UART
//! 16550 the FPGA link (to `fpgfx-sim --fpga-link`), AXI Timer 0 the millisecond clock,
//! the AXI interrupt controller between them and the core's machine external interrupt.
//! The main loop, the receive rings, the log and the panic handler are
//! `firmware::board`'s; this file holds the registers, the interrupts and the clock.
//!
//! No PAC: the few registers are named here, from AMD's product guides (PG142 UART Lite,
//! PG143 UART 16550, PG079 Timer, PG099 interrupt controller) and checked against QEMU's
//! models. Addresses and interrupt lines are those of the generic design, which QEMU's
//! machine reproduces; a Vivado design with other addresses changes the constants below.
#![no_std]
#![no_main]

use firmware::board::{self, BoardController, RxRing, Serial, Slot, Transmit};
use riscv::interrupt::Interrupt;

/// The AXI clock the timer and the 16550 count (the generic design's 100 MHz).
const AXI_HZ: u32 = 100_000_000;

/// Line rate of the 16550's divisor (the UART Lite's is fixed when the design is built;
/// QEMU ignores both).
const BAUD: u32 = 921_600;

/// Filled by the UART interrupts, drained by the main loop.
static RX_HOST: RxRing = RxRing::new();
static RX_FPGA: RxRing = RxRing::new();

static CONTROLLER: Slot<BoardController<UartLite, Uart16550>> = Slot::new();

/// A 32-bit device register.
fn reg(base: usize, off: usize) -> *mut u32 {
    (base + off) as *mut u32
}

/// # Safety
/// `base + off` must be a readable register of one of this board's devices.
unsafe fn read(base: usize, off: usize) -> u32 {
    // SAFETY: the caller names a device register.
    unsafe { core::ptr::read_volatile(reg(base, off)) }
}

/// # Safety
/// `base + off` must be a writable register of one of this board's devices, and the
/// write must not break an invariant another part of this file relies on.
unsafe fn write(base: usize, off: usize, value: u32) {
    // SAFETY: the caller names a device register.
    unsafe { core::ptr::write_volatile(reg(base, off), value) }
}

/// AXI interrupt controller (PG099), wired to the core's machine external interrupt.
mod intc {
    pub const BASE: usize = 0x4120_0000;
    pub const IPR: usize = 0x04;
    pub const IER: usize = 0x08;
    pub const IAR: usize = 0x0c;
    pub const MER: usize = 0x1c;
    /// Master enable and hardware interrupt enable (the latter, once set, stays set).
    pub const MER_ME_HIE: u32 = 0b11;
    /// Input lines in the generic design.
    pub const TIMER: u32 = 1 << 0;
    pub const UARTLITE: u32 = 1 << 1;
    pub const UART16550: u32 = 1 << 4;
}

/// AXI UART Lite (PG142): the host link. A 16-byte receive FIFO (8 in QEMU's model), an
/// edge-triggered interrupt whenever the receive FIFO becomes non-empty.
struct UartLite;

impl UartLite {
    const BASE: usize = 0x4060_0000;
    const RX: usize = 0x0;
    const TX: usize = 0x4;
    const STAT: usize = 0x8;
    const CTRL: usize = 0xc;
    const STAT_RX_VALID: u32 = 1 << 0;
    const STAT_TX_FULL: u32 = 1 << 3;
    const STAT_OVERRUN: u32 = 1 << 5;
    const CTRL_RST_TX: u32 = 1 << 0;
    const CTRL_RST_RX: u32 = 1 << 1;
    const CTRL_INTR_EN: u32 = 1 << 4;

    /// # Safety
    /// Once only: the UART Lite is used only through the returned value and the interrupt.
    unsafe fn new() -> Serial<Self> {
        // SAFETY: the control register; empties both FIFOs and enables the interrupt.
        unsafe {
            write(
                Self::BASE,
                Self::CTRL,
                Self::CTRL_RST_TX | Self::CTRL_RST_RX | Self::CTRL_INTR_EN,
            );
        }
        Serial::new(UartLite, &RX_HOST)
    }

    /// Moves the receive FIFO into the ring. Reading STAT clears the overrun flag.
    fn on_interrupt() {
        // SAFETY: STAT and RX of the UART Lite; reading RX pops one byte.
        unsafe {
            loop {
                let stat = read(Self::BASE, Self::STAT);
                if stat & Self::STAT_OVERRUN != 0 {
                    RX_HOST.overrun();
                }
                if stat & Self::STAT_RX_VALID == 0 {
                    break;
                }
                RX_HOST.push(read(Self::BASE, Self::RX) as u8);
            }
        }
    }
}

impl Transmit for UartLite {
    fn send(&mut self, byte: u8) {
        // SAFETY: STAT and TX of the UART Lite; a write to TX queues one byte.
        unsafe {
            while read(Self::BASE, Self::STAT) & Self::STAT_TX_FULL != 0 {}
            write(Self::BASE, Self::TX, u32::from(byte));
        }
    }
}

/// AXI UART 16550 (PG143): the FPGA link. The 16550 registers sit 0x1000 into the block,
/// one per 32-bit word; its interrupt is level-triggered.
struct Uart16550;

impl Uart16550 {
    const BASE: usize = 0x44a1_1000;
    const RBR_THR_DLL: usize = 0x00;
    const IER_DLM: usize = 0x04;
    const FCR: usize = 0x08;
    const LCR: usize = 0x0c;
    const MCR: usize = 0x10;
    const LSR: usize = 0x14;
    const IER_RX_DATA: u32 = 1 << 0;
    /// FIFOs on and emptied, receive interrupt at one byte: the link waits on single
    /// answers, and a higher trigger level would hold each answer's tail for the
    /// character timeout.
    const FCR_FIFO_RESET: u32 = 0b0000_0111;
    const LCR_8N1: u32 = 0b0000_0011;
    const LCR_DLAB: u32 = 1 << 7;
    /// OUT2: on PC-style wiring it gates the interrupt line; set for any such board.
    const MCR_OUT2: u32 = 1 << 3;
    const LSR_DATA_READY: u32 = 1 << 0;
    const LSR_OVERRUN: u32 = 1 << 1;
    const LSR_THR_EMPTY: u32 = 1 << 5;

    /// # Safety
    /// Once only: the 16550 is used only through the returned value and the interrupt.
    unsafe fn new() -> Serial<Self> {
        let divisor = (AXI_HZ + 8 * BAUD) / (16 * BAUD);
        // SAFETY: the 16550's set-up registers, written in the order PG143 gives: the
        // divisor behind DLAB, then the frame format, the FIFOs, the interrupt.
        unsafe {
            write(Self::BASE, Self::LCR, Self::LCR_DLAB | Self::LCR_8N1);
            write(Self::BASE, Self::RBR_THR_DLL, divisor & 0xff);
            write(Self::BASE, Self::IER_DLM, divisor >> 8);
            write(Self::BASE, Self::LCR, Self::LCR_8N1);
            write(Self::BASE, Self::FCR, Self::FCR_FIFO_RESET);
            write(Self::BASE, Self::MCR, Self::MCR_OUT2);
            write(Self::BASE, Self::IER_DLM, Self::IER_RX_DATA);
        }
        Serial::new(Uart16550, &RX_FPGA)
    }

    /// Moves the receive FIFO into the ring; emptying it drops the interrupt line.
    fn on_interrupt() {
        // SAFETY: LSR and RBR of the 16550 (DLAB is clear after `new`); reading LSR
        // clears the overrun flag, reading RBR pops one byte.
        unsafe {
            loop {
                let lsr = read(Self::BASE, Self::LSR);
                if lsr & Self::LSR_OVERRUN != 0 {
                    RX_FPGA.overrun();
                }
                if lsr & Self::LSR_DATA_READY == 0 {
                    break;
                }
                RX_FPGA.push(read(Self::BASE, Self::RBR_THR_DLL) as u8);
            }
        }
    }
}

impl Transmit for Uart16550 {
    fn send(&mut self, byte: u8) {
        // SAFETY: LSR and THR of the 16550; a write to THR queues one byte.
        unsafe {
            while read(Self::BASE, Self::LSR) & Self::LSR_THR_EMPTY == 0 {}
            write(Self::BASE, Self::RBR_THR_DLL, u32::from(byte));
        }
    }
}

/// AXI Timer 0 (PG079): counts down from TLR0 and reloads, interrupting every millisecond.
mod timer {
    pub const BASE: usize = 0x41c0_0000;
    pub const TCSR0: usize = 0x00;
    pub const TLR0: usize = 0x04;
    pub const UDT0: u32 = 1 << 1;
    pub const ARHT0: u32 = 1 << 4;
    pub const LOAD0: u32 = 1 << 5;
    pub const ENIT0: u32 = 1 << 6;
    pub const ENT0: u32 = 1 << 7;
    /// Interrupt flag; written as 1 to clear it.
    pub const T0INT: u32 = 1 << 8;
    /// Down-counting, auto-reloading, interrupting, running.
    pub const RUN: u32 = UDT0 | ARHT0 | ENIT0 | ENT0;
}

fn start_tick() {
    // SAFETY: timer 0's registers: load TLR0, then start it. A down-counting timer in
    // generate mode interrupts every TLR0 + 2 clocks (PG079).
    unsafe {
        write(timer::BASE, timer::TLR0, AXI_HZ / 1000 - 2);
        write(timer::BASE, timer::TCSR0, timer::LOAD0);
        write(timer::BASE, timer::TCSR0, timer::RUN | timer::T0INT);
    }
}

fn on_timer() {
    // SAFETY: timer 0's control register. Writing back what was read clears T0INT and
    // leaves the rest as it was. (QEMU's model also restarts the count on that write, so
    // there a tick is a millisecond plus the interrupt's latency.)
    unsafe {
        let tcsr = read(timer::BASE, timer::TCSR0);
        if tcsr & timer::T0INT != 0 {
            write(timer::BASE, timer::TCSR0, tcsr);
            board::tick();
        }
    }
}

#[riscv_rt::core_interrupt(Interrupt::MachineExternal)]
fn machine_external() {
    // SAFETY: the interrupt controller's pending and acknowledge registers.
    let pending = unsafe { read(intc::BASE, intc::IPR) };
    if pending & intc::UARTLITE != 0 {
        // Edge-triggered: acknowledged before the FIFO is drained, so a byte arriving
        // meanwhile raises a new edge instead of being lost with the old one.
        // SAFETY: as above.
        unsafe { write(intc::BASE, intc::IAR, intc::UARTLITE) };
        UartLite::on_interrupt();
    }
    // Level-triggered: cleared at the device first, else the acknowledge would not hold.
    if pending & intc::UART16550 != 0 {
        Uart16550::on_interrupt();
        // SAFETY: as above.
        unsafe { write(intc::BASE, intc::IAR, intc::UART16550) };
    }
    if pending & intc::TIMER != 0 {
        on_timer();
        // SAFETY: as above.
        unsafe { write(intc::BASE, intc::IAR, intc::TIMER) };
    }
}

/// Any exception (illegal instruction, bad access) ends the program with its cause and
/// address in the log: riscv-rt's default would spin silently.
#[export_name = "ExceptionHandler"]
fn exception_handler(_frame: &riscv_rt::TrapFrame) -> ! {
    defmt::error!(
        "trap: exception {=usize} at {=usize:#x}",
        riscv::register::mcause::read().code(),
        riscv::register::mepc::read()
    );
    board::exit(false)
}

#[riscv_rt::entry]
fn main() -> ! {
    // SAFETY: each UART is set up once, here, and from then on used only through its
    // `Serial` and its interrupt.
    let (host, fpga_port) = unsafe { (UartLite::new(), Uart16550::new()) };
    start_tick();
    // SAFETY: the controller's enable and master-enable registers; then the core takes
    // the machine external interrupt, whose handler touches only the rings, the tick and
    // these devices' interrupt registers.
    unsafe {
        write(
            intc::BASE,
            intc::IER,
            intc::TIMER | intc::UARTLITE | intc::UART16550,
        );
        write(intc::BASE, intc::MER, intc::MER_ME_HIE);
        riscv::register::mie::set_mext();
        riscv::interrupt::enable();
    }
    board::run(&CONTROLLER, host, fpga_port, "fpgfx-firmware microblaze-v")
}
