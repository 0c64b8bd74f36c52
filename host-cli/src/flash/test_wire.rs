//! The chip the flash tests talk to: a bootloader emulator (the STM32's or the MSP430's)
//! as an in-process transport.

use std::collections::VecDeque;
use std::io;
use std::time::Duration;

use sim_board::bootloader::Bootloader;
use sim_board::bootloader_pty::RomLoader;
use sim_board::msp430_bsl::Bsl;

use super::{BslClient, Client};
use crate::session::Transport;

/// An emulator as an in-process transport, optionally dropping one answer.
pub struct Wire<B = Bootloader> {
    /// The emulated chip.
    pub chip: B,
    /// Its answers not yet read.
    pub rx: VecDeque<u8>,
    /// Swallow the answer to the Nth write from the host (1-based), to test retries.
    pub lose_answer_to_write: Option<usize>,
    /// Writes so far.
    pub writes: usize,
}

impl<B: RomLoader> Transport for Wire<B> {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.writes += 1;
        let mut out = Vec::new();
        self.chip.feed(bytes, &mut out);
        if self.lose_answer_to_write != Some(self.writes) {
            self.rx.extend(out);
        }
        Ok(())
    }

    fn read(&mut self, buf: &mut [u8], _timeout: Duration) -> io::Result<usize> {
        let n = buf.len().min(self.rx.len());
        for b in buf.iter_mut().take(n) {
            *b = self.rx.pop_front().unwrap_or(0);
        }
        Ok(n)
    }
}

/// A fresh chip that loses nothing.
pub fn wire() -> Wire {
    wire_to(Bootloader::new())
}

/// `chip` on a line that loses nothing.
pub fn wire_to<B>(chip: B) -> Wire<B> {
    Wire {
        chip,
        rx: VecDeque::new(),
        lose_answer_to_write: None,
        writes: 0,
    }
}

/// A BSL client with short timeouts on `w` (the emulator answers at once; 20 ms rather
/// than 1 so that a test thread descheduled on a loaded machine does not time out).
pub fn bsl_client(w: Wire<Bsl>) -> BslClient<Wire<Bsl>> {
    // The line rate only sizes the rescue burst's wait: a fast one keeps the tests quick.
    let mut c = BslClient::new(w, 115_200);
    c.timeouts.sync = Duration::from_millis(20);
    c.timeouts.ack = Duration::from_millis(20);
    c.timeouts.erase = Duration::from_millis(20);
    c
}

/// A client with short timeouts: the emulator answers at once, and 20 ms (not 1) keeps a
/// descheduled test on a loaded machine from timing out before its first read.
pub fn client(w: Wire) -> Client<Wire> {
    let mut c = Client::new(w, 115_200);
    c.timeouts.sync = Duration::from_millis(20);
    c.timeouts.ack = Duration::from_millis(20);
    c
}

/// Deterministic bytes that are not 0xFF-heavy (xorshift32).
pub fn pattern(n: usize, seed: u32) -> Vec<u8> {
    let mut x = seed.max(1);
    (0..n)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 17;
            x ^= x << 5;
            x as u8
        })
        .collect()
}
