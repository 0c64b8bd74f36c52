//! The MSP430F168's serial ports (FITkit 1.x): USART0 in UART mode is the host link,
//! USART1 in SPI master mode the FPGA's SPI (registers from msp430mcu's `msp430f168.h`,
//! TI SLAU049 chapters 13 and 14). P3.4/P3.5 are UTXD0/URXD0, P5.1–P5.3 SIMO1, SOMI1 and
//! UCLK1; P5.0, the FPGA's chip select, is a plain output (`main.rs`).

use super::{clear, fpgfx_spi_rx_wait, rd, set, wr, BAUD, CORE_HZ, IFG1};

/// What `FPGFX_PART` holds for this part, so that the simulator harness drives the
/// registers this binary was built for.
pub const PART: u16 = 168;

const IE1: u16 = 0x00;
const IFG2: u16 = 0x03;
const ME1: u16 = 0x04;
const ME2: u16 = 0x05;
const P3SEL: u16 = 0x1B;
const P5SEL: u16 = 0x33;
const U0CTL: u16 = 0x70;
const U0TCTL: u16 = 0x71;
const U0RCTL: u16 = 0x72;
const U0MCTL: u16 = 0x73;
const U0BR0: u16 = 0x74;
const U0BR1: u16 = 0x75;
const U0RXBUF: u16 = 0x76;
const U0TXBUF: u16 = 0x77;
const U1CTL: u16 = 0x78;
const U1TCTL: u16 = 0x79;
const U1RCTL: u16 = 0x7A;
const U1MCTL: u16 = 0x7B;
const U1BR0: u16 = 0x7C;
const U1BR1: u16 = 0x7D;
const U1RXBUF: u16 = 0x7E;
const U1TXBUF: u16 = 0x7F;

const URXIFG0: u8 = 0x40;
const UTXIFG0: u8 = 0x80;
const URXIFG1: u8 = 0x10;
const UTXIFG1: u8 = 0x20;
const UTXE0: u8 = 0x80;
const URXE0: u8 = 0x40;
const USPIE1: u8 = 0x10;
const SWRST: u8 = 0x01;
const MM: u8 = 0x02;
const SYNC: u8 = 0x04;
const CHAR: u8 = 0x10;
const SSEL1: u8 = 0x20;
const CKPH: u8 = 0x80;
const STC: u8 = 0x02;

/// MCLK and SMCLK from XT2, the FITkit's 7.3728 MHz crystal (SLAU049, "Basic Clock
/// Module"); at reset both run from the DCO (~800 kHz). The F1xx needs no range set.
pub fn clock_init() {
    super::clock_from_xt2();
}

/// USART0 as an 8N1 UART at [`BAUD`] from SMCLK, polled (no interrupt enabled).
pub fn host_init() {
    wr(U0CTL, CHAR | SWRST);
    wr(U0TCTL, SSEL1);
    wr(U0RCTL, 0);
    let div = CORE_HZ / BAUD;
    wr(U0BR0, div as u8);
    wr(U0BR1, (div >> 8) as u8);
    wr(U0MCTL, 0);
    set(ME1, UTXE0 | URXE0);
    set(P3SEL, 0x30);
    clear(U0CTL, SWRST);
    clear(IE1, URXIFG0 | UTXIFG0);
}

/// Whether a received byte waits in U0RXBUF.
pub fn host_rx_ready() -> bool {
    rd(IFG1) & URXIFG0 != 0
}

/// The received byte. Reading RXBUF clears the flag on silicon; clearing it here too
/// keeps the simulator (whose flag is plain memory) in step.
pub fn host_rx() -> u8 {
    let b = rd(U0RXBUF);
    clear(IFG1, URXIFG0);
    b
}

/// Sends one byte once the transmit buffer is free.
pub fn host_tx(b: u8) {
    while rd(IFG1) & UTXIFG0 == 0 {}
    wr(U0TXBUF, b);
}

/// USART1 as SPI master: mode 0, 8 bits, MSB first, SMCLK / 2 (the block samples SPI at
/// f_clk / 8 or slower, f_clk being 50 MHz). P5.1–P5.3 to the module.
pub fn spi_init() {
    wr(U1CTL, CHAR | SYNC | MM | SWRST);
    wr(U1TCTL, CKPH | SSEL1 | STC);
    wr(U1RCTL, 0);
    wr(U1BR0, 2);
    wr(U1BR1, 0);
    wr(U1MCTL, 0);
    set(ME2, USPIE1);
    set(P5SEL, 0x0E);
    clear(U1CTL, SWRST);
}

/// Shifts one byte out and returns the one shifted in, calling [`fpgfx_spi_rx_wait`]
/// while it is shifted (the simulator's stop).
pub fn spi_exchange(out: u8) -> u8 {
    while rd(IFG2) & UTXIFG1 == 0 {}
    wr(U1TXBUF, out);
    while rd(IFG2) & URXIFG1 == 0 {
        fpgfx_spi_rx_wait();
    }
    let b = rd(U1RXBUF);
    clear(IFG2, URXIFG1);
    b
}
