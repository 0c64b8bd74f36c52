//! The FITkit's MSP430 board binary: the controller with the host link on the part's
//! UART and the FITkit raster block on its SPI through [`FitkitSpi`], polled, no
//! interrupts. `FPGFX_MSP430_PART` picks the part at build time: `f2617` (FITkit 2.x,
//! `f2617.rs`: USCI_A0 and USCI_B1, `msp430f2617.x`), `f168` (FITkit 1.x, `f168.rs`:
//! USART0 and USART1, `msp430f168.x`, which this program does not fit:
//! docs/firmware.md, "MSP430"), or `sim` (the F168's registers on mspdebug's flat
//! memory, `msp430sim.x`, to run the F168's register code in the simulator).
//!
//! Nightly only (rustc's `msp430-none-elf` has no prebuilt core): `cargo +nightly build
//! -Zbuild-std=core --target msp430-none-elf -p firmware --features board-msp430
//! --profile firmware` (docs/firmware.md, "MSP430"). Start-up is hand-written (vector,
//! stack, watchdog, .data/.bss) rather than msp430-rt, whose vector table wants a device
//! crate for the part and which brings nothing else this polled program uses.
//!
//! Everything is polled because mspdebug's simulator, the only MSP430 this is run on
//! here, models neither USART nor USCI: the simulator harness
//! (`firmware/examples/msp430_sim.rs`) breaks on [`fpgfx_host_rx_idle`] and
//! [`fpgfx_spi_rx_wait`] to hand the firmware its next byte.
#![no_std]
#![no_main]
#![feature(asm_experimental_arch)]

use core::convert::Infallible;
use core::mem::MaybeUninit;
use core::panic::PanicInfo;
use core::ptr::{addr_of_mut, read_volatile, write_volatile};

use embedded_hal::delay::DelayNs;
use embedded_hal::spi::{ErrorType, Operation, SpiDevice};
use firmware::{Controller, FitkitSpi};
use protocol::bus::FITKIT;
use protocol::fitkit_spi::{FIFO_RECORDS, FRAME_SIDE};
use protocol::frame::{Caps, NumericSet, PixelFormat, RtBuild};

/// Requests queued: one, so the link grants the host one frame at a time.
const INBOX: usize = 1;
/// The link's smallest window (`protocol::link::Link` needs a power of two ≥ 4).
const WINDOW: usize = 4;
/// No ray tracer on the FITkit, so no register shadow.
const SHADOW: usize = 0;

/// SMCLK and MCLK: the FITkit's 7.3728 MHz XT2 crystal.
const CORE_HZ: u32 = 7_372_800;
/// Host link baud rate.
const BAUD: u32 = 115_200;

type Fpga = FitkitSpi<FpgaSpi, CycleDelay>;
type Board = Controller<HostUart, Fpga, INBOX, WINDOW, SHADOW>;

#[cfg(not(msp430_f2617))]
mod f168;
#[cfg(not(msp430_f2617))]
use f168 as part;
#[cfg(msp430_f2617)]
mod f2617;
#[cfg(msp430_f2617)]
use f2617 as part;

// Registers both parts have at the same addresses (msp430mcu's msp430f168.h and
// msp430x26x.h).
const P5OUT: u16 = 0x31;
const P5DIR: u16 = 0x32;
const TACTL: u16 = 0x160;
const TAR: u16 = 0x170;
const WDTCTL: u16 = 0x120;

/// P5.0: the FPGA's chip select (active low) on both parts; P5.1–3 are the SPI's data
/// and clock pins.
const CS: u8 = 0x01;
/// Timer_A: ACLK (the 32 768 Hz watch crystal), continuous mode, cleared.
const TACTL_ACLK_CONT: u16 = 0x0100 | 0x0020 | 0x0004;
/// ACLK is 32 768 Hz = 2^15 Hz.
const ACLK_LOG2: u32 = 15;

fn rd(addr: u16) -> u8 {
    // SAFETY: `addr` is one of the peripheral registers above, always mapped.
    unsafe { read_volatile(addr as *const u8) }
}

fn wr(addr: u16, value: u8) {
    // SAFETY: as in `rd`.
    unsafe { write_volatile(addr as *mut u8, value) }
}

fn set(addr: u16, bits: u8) {
    wr(addr, rd(addr) | bits);
}

fn clear(addr: u16, bits: u8) {
    wr(addr, rd(addr) & !bits);
}

/// The basic clock module's registers both parts share (SLAU049 and SLAU144).
const IFG1: u16 = 0x02;
const IFG1_OFIFG: u8 = 0x02;
const BCSCTL1: u16 = 0x57;
const BCSCTL2: u16 = 0x58;
/// BCSCTL1: XT2 off (set at reset).
const XT2OFF: u8 = 0x80;
/// BCSCTL2: MCLK from XT2 (SELM_2), SMCLK from XT2 (SELS).
const SELM_XT2: u8 = 0x80;
const SELS: u8 = 0x08;

/// Switches MCLK and SMCLK to XT2, the FITkit's 7.3728 MHz crystal ([`CORE_HZ`], which
/// the baud and SPI divisors assume), once the oscillator has settled: the fault flag is
/// cleared until it stays clear. A part's `clock_init` calls it after its own settings.
fn clock_from_xt2() {
    clear(BCSCTL1, XT2OFF);
    loop {
        clear(IFG1, IFG1_OFIFG);
        // ≥ 50 µs at the DCO's reset frequency for the fault flag to come back.
        for i in 0..64u16 {
            core::hint::black_box(i);
        }
        if rd(IFG1) & IFG1_OFIFG == 0 {
            break;
        }
    }
    wr(BCSCTL2, SELM_XT2 | SELS);
}

/// Called whenever the host link has no byte: a place for the simulator to stop and
/// deliver one (`setbreak fpgfx_host_rx_idle`). Never inlined, so the symbol exists.
#[no_mangle]
#[inline(never)]
pub extern "C" fn fpgfx_host_rx_idle() {
    // Distinct bodies, so that the linker does not fold the two hooks into one address.
    // SAFETY: single-threaded, no interrupts.
    unsafe { write_volatile(addr_of_mut!(FPGFX_WAITING), 1) };
}

/// Called while an SPI byte is being shifted: the simulator's stop to supply MISO.
#[no_mangle]
#[inline(never)]
pub extern "C" fn fpgfx_spi_rx_wait() {
    // SAFETY: as in `fpgfx_host_rx_idle`.
    unsafe { write_volatile(addr_of_mut!(FPGFX_WAITING), 2) };
}

/// The part this binary drives (168 or 2617): the simulator harness reads it to know
/// which registers to play.
#[no_mangle]
#[used]
pub static FPGFX_PART: u16 = part::PART;

/// Which hook the program last waited in (1 host byte, 2 SPI byte), for a debugger.
#[no_mangle]
pub static mut FPGFX_WAITING: u16 = 0;

/// The host link: the part's UART (`part::host_init`), 8N1 at [`BAUD`].
struct HostUart;

impl HostUart {
    fn init() -> Self {
        part::host_init();
        HostUart
    }
}

impl embedded_io::ErrorType for HostUart {
    type Error = Infallible;
}

impl embedded_io::ReadReady for HostUart {
    fn read_ready(&mut self) -> Result<bool, Infallible> {
        let ready = part::host_rx_ready();
        if !ready {
            fpgfx_host_rx_idle();
        }
        Ok(ready)
    }
}

impl embedded_io::Read for HostUart {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Infallible> {
        let mut n = 0;
        while n < buf.len() {
            if !part::host_rx_ready() {
                if n > 0 {
                    break;
                }
                fpgfx_host_rx_idle();
                continue;
            }
            buf[n] = part::host_rx();
            n += 1;
        }
        Ok(n)
    }
}

impl embedded_io::Write for HostUart {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Infallible> {
        for &b in buf {
            part::host_tx(b);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Infallible> {
        Ok(())
    }
}

/// The part's SPI master (mode 0, 8 bits, MSB first) with P5.0 as chip select: the
/// embedded-hal device [`FitkitSpi`] drives the raster block through.
struct FpgaSpi;

impl FpgaSpi {
    fn init() -> Self {
        part::spi_init();
        set(P5OUT, CS);
        set(P5DIR, CS);
        FpgaSpi
    }

    fn exchange(&mut self, out: u8) -> u8 {
        part::spi_exchange(out)
    }
}

impl ErrorType for FpgaSpi {
    type Error = Infallible;
}

impl SpiDevice for FpgaSpi {
    fn transaction(&mut self, operations: &mut [Operation<'_, u8>]) -> Result<(), Infallible> {
        clear(P5OUT, CS);
        for op in operations {
            match op {
                Operation::Write(bytes) => {
                    for &b in bytes.iter() {
                        self.exchange(b);
                    }
                }
                Operation::Read(bytes) => {
                    for b in bytes.iter_mut() {
                        *b = self.exchange(0);
                    }
                }
                Operation::Transfer(read, write) => {
                    for i in 0..read.len().max(write.len()) {
                        let got = self.exchange(write.get(i).copied().unwrap_or(0));
                        if let Some(r) = read.get_mut(i) {
                            *r = got;
                        }
                    }
                }
                Operation::TransferInPlace(bytes) => {
                    for b in bytes.iter_mut() {
                        *b = self.exchange(*b);
                    }
                }
                Operation::DelayNs(ns) => CycleDelay.delay_ns(*ns),
            }
        }
        set(P5OUT, CS);
        Ok(())
    }
}

/// Waits by counting core cycles: the driver's poll interval needs no better.
struct CycleDelay;

impl DelayNs for CycleDelay {
    fn delay_ns(&mut self, ns: u32) {
        // About four cycles, 543 ns at 7.3728 MHz, per iteration; 32-bit arithmetic,
        // since the 64-bit division helper alone costs ~900 bytes of flash.
        let loops = ns / (4_000_000_000 / CORE_HZ);
        for i in 0..loops {
            core::hint::black_box(i);
        }
    }
}

/// Milliseconds from Timer_A's 16-bit count of ACLK, advanced by the ticks since the last
/// read (the main loop reads it far more often than the count wraps, every 2 s). Only
/// 32-bit arithmetic: a 64-bit multiply or divide would cost the flash a helper the
/// F2617's 16-bit space has no room for.
struct Clock {
    last: u16,
    /// Ticks × 1000 not yet a whole millisecond (below 2^15).
    residue: u32,
    ms: u64,
}

impl Clock {
    fn init() -> Self {
        // SAFETY: TACTL and TAR are Timer_A's word registers.
        unsafe { write_volatile(TACTL as *mut u16, TACTL_ACLK_CONT) };
        Clock {
            last: 0,
            residue: 0,
            ms: 0,
        }
    }

    fn now_ms(&mut self) -> u64 {
        // SAFETY: as in `init`.
        let t = unsafe { read_volatile(TAR as *const u16) };
        let ticks = u32::from(t.wrapping_sub(self.last));
        self.last = t;
        // ACLK is 2^15 Hz.
        self.residue += ticks * 1000;
        self.ms += u64::from(self.residue >> ACLK_LOG2);
        self.residue &= (1 << ACLK_LOG2) - 1;
        self.ms
    }
}

/// What the board can do: the FITkit block's caps with this board's queue.
fn caps() -> Caps {
    Caps {
        raster: true,
        ray_trace: false,
        numeric: NumericSet::default(),
        pixel_formats: PixelFormat::Rgb888.bit() | PixelFormat::Rgb332.bit(),
        max_width: FRAME_SIDE,
        max_height: FRAME_SIDE,
        max_subpixel_bits: 0,
        queue_depth: INBOX as u16,
        fifo_depth: FIFO_RECORDS,
        max_objects: 0,
        max_lights: 0,
        texture_words: 0,
        raster_layout: None,
        float_regs: NumericSet::default(),
        rt_build: RtBuild::FULL,
        link_payload: 0,
    }
}

/// The sizes that decide whether the controller fits, for `llvm-objdump -s` or the
/// simulator's `md` to read: this board's controller, its FPGA driver, one inbox slot,
/// a decoded `HostFrame`, a link with the default window (8) and this board's (4), one
/// `DeviceFrame`, the engine, the controller with the default sizes.
#[no_mangle]
#[used]
pub static FPGFX_SIZES: [u16; 9] = [
    core::mem::size_of::<Board>() as u16,
    core::mem::size_of::<Fpga>() as u16,
    core::mem::size_of::<(u16, heapless::Vec<u8, { protocol::MAX_PAYLOAD }>)>() as u16,
    core::mem::size_of::<protocol::frame::HostFrame>() as u16,
    core::mem::size_of::<protocol::link::Link>() as u16,
    core::mem::size_of::<protocol::link::Link<WINDOW>>() as u16,
    core::mem::size_of::<protocol::frame::DeviceFrame>() as u16,
    core::mem::size_of::<firmware::Engine<Fpga, SHADOW>>() as u16,
    core::mem::size_of::<Controller<HostUart, Fpga>>() as u16,
];

extern "C" {
    static _ebss: u8;
    static _stack_top: u8;
}

/// Where the stack may grow: from the end of .bss to the top of RAM (linker symbols,
/// which mspdebug does not load), for the simulator to read the high-water mark.
#[repr(C)]
pub struct StackArea {
    bottom: *const u8,
    top: *const u8,
}

// SAFETY: two addresses, never dereferenced.
unsafe impl Sync for StackArea {}

/// The stack's bounds, named so that a debugger can read them.
#[no_mangle]
#[used]
pub static FPGFX_STACK_AREA: StackArea = StackArea {
    bottom: core::ptr::addr_of!(_ebss),
    top: core::ptr::addr_of!(_stack_top),
};

/// Why the program stopped: 0 never, 1 a panic. Read by the simulator after the stop.
#[no_mangle]
pub static mut FPGFX_EXIT_CODE: u16 = 0;
/// FPGA transport errors the controller returned (each was answered to the host).
#[no_mangle]
pub static mut FPGFX_FPGA_ERRORS: u16 = 0;

/// Stops the core for good: records `code`, then LPM4 with interrupts off, which only a
/// reset leaves (mspdebug's simulator ends `run` there).
#[no_mangle]
#[inline(never)]
pub extern "C" fn fpgfx_exit(code: u16) -> ! {
    // SAFETY: single-threaded, no interrupts.
    unsafe { write_volatile(addr_of_mut!(FPGFX_EXIT_CODE), code) };
    loop {
        // SAFETY: sets CPUOFF, OSCOFF, SCG0 and SCG1 in SR, GIE clear: LPM4.
        unsafe { core::arch::asm!("bis #0xf0, r2", options(nomem, nostack)) };
    }
}

#[panic_handler]
fn panic(_: &PanicInfo) -> ! {
    fpgfx_exit(1)
}

/// Built with `-C panic=immediate-abort` (.cargo/config.toml), a panic (an index out of
/// bounds, an overflow) calls `abort` without formatting anything: the same exit.
#[no_mangle]
extern "C" fn abort() -> ! {
    fpgfx_exit(1)
}

static mut CONTROLLER: MaybeUninit<Board> = MaybeUninit::uninit();

#[no_mangle]
extern "C" fn main() -> ! {
    let (controller, mut clock) = init();
    loop {
        if controller.poll(clock.now_ms()).is_err() {
            // The host was told (ErrorCode::Device); count it and go on, as the other
            // boards do.
            // SAFETY: single-threaded, no interrupts.
            unsafe {
                let n = read_volatile(addr_of_mut!(FPGFX_FPGA_ERRORS));
                write_volatile(addr_of_mut!(FPGFX_FPGA_ERRORS), n.wrapping_add(1));
            }
        }
    }
}

/// Peripherals and the controller. Not inlined, so that its temporaries (the link is
/// built on the stack first) are gone before the main loop's calls need the stack.
#[inline(never)]
fn init() -> (&'static mut Board, Clock) {
    // The watchdog is already held by the start-up code.
    let _ = WDTCTL;
    part::clock_init();
    let clock = Clock::init();
    let host = HostUart::init();
    let fpga = FitkitSpi::new(FpgaSpi::init(), CycleDelay);
    // SAFETY: init runs once; nothing else touches CONTROLLER.
    let slot = unsafe { &mut *addr_of_mut!(CONTROLLER) };
    let controller = Board::init_in(slot, host, fpga, caps(), &FITKIT, "fpgfx-firmware msp430");
    (controller, clock)
}

// Reset: stack at the top of RAM, watchdog held, RAM between .bss and the stack filled with
// 0xA5 (the stack's high-water mark), .data copied from flash, .bss zeroed, then main.
core::arch::global_asm!(
    ".section .reset_vector,\"a\"",
    ".word _start",
    ".section .text._start,\"ax\"",
    ".global _start",
    "_start:",
    "mov #_stack_top, r1",
    "mov #0x5a80, &0x0120",
    "mov #_ebss, r12",
    "1:",
    "cmp #_stack_top, r12",
    "jc 2f",
    "mov #0xa5a5, 0(r12)",
    "add #2, r12",
    "jmp 1b",
    "2:",
    "mov #_sdata, r12",
    "mov #_sidata, r13",
    "3:",
    "cmp #_edata, r12",
    "jc 4f",
    "mov @r13+, r14",
    "mov r14, 0(r12)",
    "add #2, r12",
    "jmp 3b",
    "4:",
    "mov #_sbss, r12",
    "5:",
    "cmp #_ebss, r12",
    "jc 6f",
    "mov #0, 0(r12)",
    "add #2, r12",
    "jmp 5b",
    "6:",
    "call #main",
    "7:",
    "jmp 7b",
);

/// The MSP430 EABI's integer helpers, which LLVM calls for what the core cannot do in
/// one instruction (no multiplier on the F168's core, no divider, one-bit shifts). GCC's
/// libgcc provides them; rustc's compiler_builtins does not under these names, and
/// msp430-elf-gcc is not in Debian. Each is written with one-bit shifts, adds and
/// compares only, so that none calls itself.
mod mspabi {
    /// Shift-and-add multiplication, the low half of the product: one helper per width.
    macro_rules! mul {
        ($(#[$doc:meta])* $name:ident, $t:ty) => {
            $(#[$doc])*
            #[no_mangle]
            extern "C" fn $name(a: $t, b: $t) -> $t {
                let (mut a, mut b, mut r) = (a, b, 0 as $t);
                while b != 0 {
                    if b & 1 != 0 {
                        r = r.wrapping_add(a);
                    }
                    a <<= 1;
                    b >>= 1;
                }
                r
            }
        };
    }
    mul!(__mspabi_mpyi, u16);
    mul!(__mspabi_mpyl, u32);
    mul!(
        /// Called through the 64-bit shims below (C convention: `a` in R12–R15, `b` on
        /// the stack).
        fpgfx_mul64,
        u64
    );

    macro_rules! divmod {
        ($name:ident, $t:ty, $bits:expr) => {
            /// Restoring division: (quotient, remainder); division by zero gives
            /// (all ones, n) as libgcc's does not trap either.
            fn $name(n: $t, d: $t) -> ($t, $t) {
                if d == 0 {
                    return (<$t>::MAX, n);
                }
                let (mut q, mut r): ($t, $t) = (0, 0);
                let mut n = n;
                for _ in 0..$bits {
                    let top = n >> ($bits - 1);
                    n <<= 1;
                    let carry = r >> ($bits - 1);
                    r = (r << 1) | top;
                    q <<= 1;
                    if carry != 0 || r >= d {
                        r = r.wrapping_sub(d);
                        q |= 1;
                    }
                }
                (q, r)
            }
        };
    }
    divmod!(divmod16, u16, 16);
    divmod!(divmod32, u32, 32);
    divmod!(divmod64, u64, 64);

    #[no_mangle]
    extern "C" fn __mspabi_divu(n: u16, d: u16) -> u16 {
        divmod16(n, d).0
    }

    #[no_mangle]
    extern "C" fn __mspabi_remu(n: u16, d: u16) -> u16 {
        divmod16(n, d).1
    }

    #[no_mangle]
    extern "C" fn __mspabi_divul(n: u32, d: u32) -> u32 {
        divmod32(n, d).0
    }

    #[no_mangle]
    extern "C" fn __mspabi_remul(n: u32, d: u32) -> u32 {
        divmod32(n, d).1
    }

    #[no_mangle]
    extern "C" fn fpgfx_divu64(n: u64, d: u64) -> u64 {
        divmod64(n, d).0
    }

    #[no_mangle]
    extern "C" fn fpgfx_remu64(n: u64, d: u64) -> u64 {
        divmod64(n, d).1
    }

    #[no_mangle]
    extern "C" fn __mspabi_divli(n: i32, d: i32) -> i32 {
        let q = divmod32(n.unsigned_abs(), d.unsigned_abs()).0 as i32;
        if (n < 0) != (d < 0) {
            q.wrapping_neg()
        } else {
            q
        }
    }

    #[no_mangle]
    extern "C" fn __mspabi_remli(n: i32, d: i32) -> i32 {
        let r = divmod32(n.unsigned_abs(), d.unsigned_abs()).1 as i32;
        if n < 0 {
            r.wrapping_neg()
        } else {
            r
        }
    }

    #[no_mangle]
    extern "C" fn __mspabi_slll(x: u32, n: i16) -> u32 {
        let mut x = x;
        for _ in 0..(n & 31) {
            x <<= 1;
        }
        x
    }

    #[no_mangle]
    extern "C" fn __mspabi_srll(x: u32, n: i16) -> u32 {
        let mut x = x;
        for _ in 0..(n & 31) {
            x >>= 1;
        }
        x
    }

    #[no_mangle]
    extern "C" fn __mspabi_sral(x: i32, n: i16) -> i32 {
        let mut x = x;
        for _ in 0..(n & 31) {
            x >>= 1;
        }
        x
    }

    // The 64-bit helpers use LLVM's MSP430_BUILTIN convention: the first operand in
    // R8–R11, the second in R12–R15. Each shim pushes the second as the C function's
    // stacked argument and moves the first into R12–R15.
    macro_rules! builtin_shim {
        ($name:literal, $target:literal) => {
            core::arch::global_asm!(
                concat!(".section .text.", $name, ",\"ax\""),
                concat!(".global ", $name),
                concat!($name, ":"),
                "push r15",
                "push r14",
                "push r13",
                "push r12",
                "mov r8, r12",
                "mov r9, r13",
                "mov r10, r14",
                "mov r11, r15",
                concat!("call #", $target),
                "add #8, r1",
                "ret",
            );
        };
    }
    builtin_shim!("__mspabi_mpyll", "fpgfx_mul64");
    builtin_shim!("__mspabi_divull", "fpgfx_divu64");
    builtin_shim!("__mspabi_remull", "fpgfx_remu64");

    /// Floating point is never used by the firmware, but compiler_builtins' soft-float
    /// and libm code names the EABI's float helpers; they resolve to a stop with exit code
    /// 3, so that a float operation that does run is a defined exit, not a jump to 0. The
    /// map shows whether any is linked at all.
    #[no_mangle]
    extern "C" fn fpgfx_no_float() -> ! {
        super::fpgfx_exit(3)
    }

    macro_rules! no_float {
        ($($name:literal),*) => {
            core::arch::global_asm!($(concat!(".global ", $name, "\n.set ", $name, ", fpgfx_no_float")),*);
        };
    }
    no_float!(
        "__mspabi_mpyd",
        "__mspabi_cmpd",
        "__mspabi_cmpf",
        "__mspabi_addd",
        "__mspabi_fltllid",
        "__mspabi_subd",
        "__mspabi_divd",
        "__mspabi_cvtfd",
        "__mspabi_cvtdf",
        "__mspabi_addf",
        "__mspabi_mpyf",
        "__mspabi_subf",
        "__mspabi_divf",
        "__mspabi_fixdli",
        "__mspabi_fltuld",
        "__mspabi_fltulf",
        "__mspabi_fltlid",
        "__mspabi_fltlif",
        "__mspabi_fltulld",
        "__mspabi_fixdul",
        "__mspabi_fixdull",
        "__mspabi_fixfli",
        "__mspabi_fixful",
        "__mspabi_fixfull",
        "__mspabi_fixdlli",
        "__mspabi_fixflli",
        "__mspabi_fltllif",
        "__mspabi_fltullf"
    );
}
