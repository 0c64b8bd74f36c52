//! The STM32F405 board: USART1 is the host link, USART2 the FPGA link.
#![no_std]
#![no_main]

use core::panic::PanicInfo;

use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln};

/// STM32F4 USART register block (RM0090 §30.6), as QEMU's stm32f2xx_usart models it.
struct Usart(usize);

impl Usart {
    const SR: usize = 0x00;
    const DR: usize = 0x04;
    const CR1: usize = 0x0c;
    const SR_RXNE: u32 = 1 << 5;
    const SR_TXE: u32 = 1 << 7;
    const CR1_UE: u32 = 1 << 13;
    const CR1_TE: u32 = 1 << 3;
    const CR1_RE: u32 = 1 << 2;

    fn reg(&self, off: usize) -> *mut u32 {
        (self.0 + off) as *mut u32
    }

    fn enable(&self) {
        // SAFETY: a fixed, aligned MMIO address of this chip.
        unsafe {
            core::ptr::write_volatile(
                self.reg(Self::CR1),
                Self::CR1_UE | Self::CR1_TE | Self::CR1_RE,
            )
        }
    }

    fn try_read(&self) -> Option<u8> {
        // SAFETY: as above.
        unsafe {
            if core::ptr::read_volatile(self.reg(Self::SR)) & Self::SR_RXNE != 0 {
                Some(core::ptr::read_volatile(self.reg(Self::DR)) as u8)
            } else {
                None
            }
        }
    }

    fn write(&self, b: u8) {
        // SAFETY: as above.
        unsafe {
            while core::ptr::read_volatile(self.reg(Self::SR)) & Self::SR_TXE == 0 {}
            core::ptr::write_volatile(self.reg(Self::DR), u32::from(b));
        }
    }
}

const RCC_APB2ENR: *mut u32 = 0x4002_3844 as *mut u32;
const RCC_APB1ENR: *mut u32 = 0x4002_3840 as *mut u32;

#[entry]
fn main() -> ! {
    // SAFETY: RCC enable registers; set the USART1 (APB2 bit 4) and USART2 (APB1 bit 17) clocks.
    unsafe {
        core::ptr::write_volatile(RCC_APB2ENR, core::ptr::read_volatile(RCC_APB2ENR) | 1 << 4);
        core::ptr::write_volatile(RCC_APB1ENR, core::ptr::read_volatile(RCC_APB1ENR) | 1 << 17);
    }
    let host = Usart(0x4001_1000);
    host.enable();
    hprintln!("fpgfx-firmware: boot");
    for &b in b"ready\n" {
        host.write(b);
    }
    loop {
        if let Some(b) = host.try_read() {
            if b == b'q' {
                hprintln!("fpgfx-firmware: quit");
                debug::exit(debug::EXIT_SUCCESS);
            }
            host.write(b.to_ascii_uppercase());
        }
    }
}

#[panic_handler]
fn panic(info: &PanicInfo) -> ! {
    hprintln!("fpgfx-firmware: {}", info);
    debug::exit(debug::EXIT_FAILURE);
    loop {}
}
