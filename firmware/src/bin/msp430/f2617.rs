//! The MSP430F2617's serial ports (FITkit 2.x): USCI_A0 in UART mode is the host link,
//! USCI_B1 in SPI master mode the FPGA's SPI (registers from msp430mcu's
//! `msp430x26x.h`, TI SLAU144 chapters 15 and 16).
//!
//! The F261x is pin-compatible with the F16x it replaced on the board, and its USCIs sit
//! on the pins of the F168's USARTs: P3.4/P3.5 are UCA0TXD/UCA0RXD where the F168 has
//! UTXD0/URXD0, P5.1–P5.3 UCB1SIMO, UCB1SOMI and UCB1CLK where it has SIMO1, SOMI1 and
//! UCLK1, and P5.0 (UCB1STE, unused: 3-pin mode) stays the chip select, a plain output
//! (`main.rs`). The seeds describe the FITkit 1.x's F1xx only; this mapping is the one the
//! shared pins give, not a schematic's.

use super::{clear, fpgfx_spi_rx_wait, rd, set, wr, BAUD, CORE_HZ};

/// What `FPGFX_PART` holds for this part, so that the simulator harness drives the
/// registers this binary was built for.
pub const PART: u16 = 2617;

const IE2: u16 = 0x01;
const IFG2: u16 = 0x03;
const UC1IFG: u16 = 0x07;
const P3SEL: u16 = 0x1B;
const P5SEL: u16 = 0x33;
const UCA0CTL0: u16 = 0x60;
const UCA0CTL1: u16 = 0x61;
const UCA0BR0: u16 = 0x62;
const UCA0BR1: u16 = 0x63;
const UCA0MCTL: u16 = 0x64;
const UCA0RXBUF: u16 = 0x66;
const UCA0TXBUF: u16 = 0x67;
const UCB1CTL0: u16 = 0xD8;
const UCB1CTL1: u16 = 0xD9;
const UCB1BR0: u16 = 0xDA;
const UCB1BR1: u16 = 0xDB;
const UCB1RXBUF: u16 = 0xDE;
const UCB1TXBUF: u16 = 0xDF;

/// IFG2 / IE2: USCI_A0's receive and transmit flags.
const UCA0RXIFG: u8 = 0x01;
const UCA0TXIFG: u8 = 0x02;
/// UC1IFG: USCI_B1's receive and transmit flags.
const UCB1RXIFG: u8 = 0x04;
const UCB1TXIFG: u8 = 0x08;
/// UCxCTL1: clock from SMCLK, held in reset.
const UCSSEL_SMCLK: u8 = 0x80;
const UCSWRST: u8 = 0x01;
/// UCxCTL0 in SPI mode: capture on the first edge, idle low (mode 0), MSB first, master,
/// 3-pin, synchronous; 8 bits (UC7BIT clear).
const UCCKPH: u8 = 0x80;
const UCMSB: u8 = 0x20;
const UCMST: u8 = 0x08;
const UCSYNC: u8 = 0x01;

const BCSCTL3: u16 = 0x53;
/// BCSCTL3: XT2 is a 3–16 MHz crystal (XT2S_2).
const XT2S_3_16MHZ: u8 = 0x80;

/// MCLK and SMCLK from XT2, the FITkit's 7.3728 MHz crystal (SLAU144, "Basic Clock
/// Module+"), once XT2's range is set for it; at reset both run from the DCO (~1 MHz).
pub fn clock_init() {
    set(BCSCTL3, XT2S_3_16MHZ);
    super::clock_from_xt2();
}

/// USCI_A0 as an 8N1 UART at [`BAUD`] from SMCLK (7.3728 MHz / 115 200 = 64 exactly, so
/// no modulation), polled (no interrupt enabled).
pub fn host_init() {
    wr(UCA0CTL1, UCSSEL_SMCLK | UCSWRST);
    wr(UCA0CTL0, 0);
    let div = CORE_HZ / BAUD;
    wr(UCA0BR0, div as u8);
    wr(UCA0BR1, (div >> 8) as u8);
    wr(UCA0MCTL, 0);
    set(P3SEL, 0x30);
    clear(UCA0CTL1, UCSWRST);
    clear(IE2, UCA0RXIFG | UCA0TXIFG);
}

/// Whether a received byte waits in UCA0RXBUF.
pub fn host_rx_ready() -> bool {
    rd(IFG2) & UCA0RXIFG != 0
}

/// The received byte. Reading RXBUF clears the flag on silicon; clearing it here too
/// keeps the simulator (whose flag is plain memory) in step.
pub fn host_rx() -> u8 {
    let b = rd(UCA0RXBUF);
    clear(IFG2, UCA0RXIFG);
    b
}

/// Sends one byte once the transmit buffer is free.
pub fn host_tx(b: u8) {
    while rd(IFG2) & UCA0TXIFG == 0 {}
    wr(UCA0TXBUF, b);
}

/// USCI_B1 as SPI master: mode 0, 8 bits, MSB first, SMCLK / 2 (the block samples SPI
/// at f_clk / 8 or slower, f_clk being 50 MHz). P5.1–P5.3 to the module.
pub fn spi_init() {
    wr(UCB1CTL1, UCSSEL_SMCLK | UCSWRST);
    wr(UCB1CTL0, UCCKPH | UCMSB | UCMST | UCSYNC);
    wr(UCB1BR0, 2);
    wr(UCB1BR1, 0);
    set(P5SEL, 0x0E);
    clear(UCB1CTL1, UCSWRST);
}

/// Shifts one byte out and returns the one shifted in, calling [`fpgfx_spi_rx_wait`]
/// while it is shifted (the simulator's stop).
pub fn spi_exchange(out: u8) -> u8 {
    while rd(UC1IFG) & UCB1TXIFG == 0 {}
    wr(UCB1TXBUF, out);
    while rd(UC1IFG) & UCB1RXIFG == 0 {
        fpgfx_spi_rx_wait();
    }
    let b = rd(UCB1RXBUF);
    clear(UC1IFG, UCB1RXIFG);
    b
}
