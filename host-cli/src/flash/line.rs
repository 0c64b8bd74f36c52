//! What both ROM bootloader clients do on the line the same way: read a number of bytes
//! within a deadline, empty the receive buffer, describe bytes in messages, and the sync
//! that also rescues a chip left half-way through a frame by a host that died.

use std::io;
use std::time::{Duration, Instant};

use super::FlashError;
use crate::session::Transport;

/// Up to 16 bytes as hex for a message, "nothing" when there are none.
pub fn hex(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "nothing".into();
    }
    let shown: Vec<String> = bytes.iter().take(16).map(|b| format!("{b:02x}")).collect();
    let more = if bytes.len() > 16 { " …" } else { "" };
    format!("[{}{more}]", shown.join(" "))
}

/// Reads exactly `n` bytes or fails with what arrived (and whether it was the deadline
/// rather than the port that ended it).
pub fn read_exact<T: Transport>(
    port: &mut T,
    n: usize,
    timeout: Duration,
) -> Result<Vec<u8>, (Vec<u8>, bool)> {
    let deadline = Instant::now() + timeout;
    let mut got = Vec::with_capacity(n);
    let mut buf = [0u8; 300];
    while got.len() < n {
        let now = Instant::now();
        if now >= deadline {
            return Err((got, true));
        }
        let want = (n - got.len()).min(buf.len());
        match port.read(&mut buf[..want], deadline - now) {
            Ok(k) => got.extend_from_slice(&buf[..k]),
            Err(_) => return Err((got, false)),
        }
    }
    Ok(got)
}

/// Empties the receive buffer, waiting 5 ms for stragglers; returns (the first 64 of)
/// what was in it.
pub fn drain<T: Transport>(port: &mut T) -> io::Result<Vec<u8>> {
    drain_within(port, Duration::from_millis(5))
}

/// [`drain`] waiting `quiet` for each further byte: the MSP430 syncs before every
/// command, so its first try only clears what already arrived.
fn drain_within<T: Transport>(port: &mut T, quiet: Duration) -> io::Result<Vec<u8>> {
    let mut buf = [0u8; 256];
    let mut seen = Vec::new();
    loop {
        let n = port.read(&mut buf, quiet)?;
        if n == 0 {
            return Ok(seen);
        }
        let room = 64usize.saturating_sub(seen.len());
        seen.extend_from_slice(&buf[..n.min(room)]);
    }
}

/// How a bootloader is synced and how a chip stuck in a half-received frame is freed.
pub struct Sync {
    /// The byte sent to sync.
    pub byte: u8,
    /// Answers that mean "listening and idle".
    pub answers: &'static [u8],
    /// The byte a rescue burst is made of: one the chip cannot take for the start of
    /// something that would swallow the sync after it.
    pub burst_byte: u8,
    /// Burst length: longer than any frame the chip could be in the middle of.
    pub burst: usize,
    /// What a chip answers to the burst (anything else is shown in the error).
    pub burst_answers: &'static [u8],
    /// What the error message says about the burst.
    pub burst_note: &'static str,
    /// What the error message suggests to check.
    pub hint: &'static str,
    /// How long the first try waits for stale bytes before it sends: a sync that comes
    /// before every command (the MSP430's) must not cost a wait each time.
    pub first_drain: Duration,
}

/// Sends `how.byte` until the chip answers one of `how.answers`, up to `attempts` times.
/// A chip whose previous host died mid-frame swallows single bytes, so after two silent
/// tries one burst of `how.burst` bytes ends that frame (its answers are drained; a
/// chip then answers the next sync).
pub fn sync<T: Transport>(
    port: &mut T,
    baud: u32,
    how: &Sync,
    timeout: Duration,
    attempts: u32,
) -> Result<(), FlashError> {
    let mut got = Vec::new();
    let mut burst = false;
    for i in 0..attempts {
        if i == 2 {
            port.write_all(&vec![how.burst_byte; how.burst])?;
            burst = true;
            // Let the burst and its answers cross the line (2 × burst byte times, 8E1).
            let line =
                Duration::from_secs_f64(2.0 * how.burst as f64 * 11.0 / f64::from(baud.max(1)));
            std::thread::sleep(line.min(Duration::from_secs(1)) + Duration::from_millis(20));
            let answers = drain(port)?;
            if !answers.iter().all(|b| how.burst_answers.contains(b)) {
                got.extend(answers);
            }
        }
        let quiet = if i == 0 {
            how.first_drain
        } else {
            Duration::from_millis(5)
        };
        got.extend(drain_within(port, quiet)?);
        port.write_all(&[how.byte])?;
        match read_exact(port, 1, timeout) {
            Ok(b) if how.answers.contains(&b[0]) => return Ok(()),
            Ok(b) => got.extend(b),
            Err((b, _)) => got.extend(b),
        }
    }
    Err(FlashError::NoSync {
        sync: how.byte,
        attempts,
        baud,
        burst: if burst { how.burst_note } else { "" },
        got: hex(&got),
        hint: how.hint,
    })
}
