//! A byte stream slowed to a UART's rate, so that throughput measured through a pty or
//! TCP means what it would on a board's serial line.

use std::io::{self, Read, Write};

use crate::host_link::Pending;

/// A byte stream slowed to a serial line's rate (8N1: ten bit times per byte), in both
/// directions, so that throughput measured through a pty or TCP means what it would on
/// a UART at that baud rate.
///
/// Writes go out at once and the writer sleeps while more than [`TX_BUFFER`] bytes are
/// still "on the line" (a UART's DMA buffer: the next frame is queued while the last one
/// is being sent, so the line never idles between frames); reads deliver at most what the line could have carried since the last
/// read, with a 512-byte allowance for a reader that was busy (a UART DMA ring).
pub struct Paced<S> {
    inner: S,
    byte: std::time::Duration,
    tx_free: std::time::Instant,
    rx_free: std::time::Instant,
}

/// Bytes a line may deliver at once after the reader was busy: a UART's receive FIFO
/// or DMA ring keeps filling meanwhile.
const RX_BURST: u32 = 512;

/// Bytes a paced writer may have queued ahead of the line (two link frames).
pub const TX_BUFFER: u32 = 512;

impl<S> Paced<S> {
    /// Paces `inner` at `baud`.
    pub fn new(inner: S, baud: u32) -> Self {
        let now = std::time::Instant::now();
        Self {
            inner,
            byte: std::time::Duration::from_secs_f64(10.0 / f64::from(baud.max(1))),
            tx_free: now,
            rx_free: now,
        }
    }

    /// Bytes the line has carried to us by now and not yet read.
    fn rx_allowance(&self) -> usize {
        let now = std::time::Instant::now();
        if now < self.rx_free {
            return 0;
        }
        let elapsed = now - self.rx_free;
        let bytes = elapsed.as_nanos() / self.byte.as_nanos().max(1) + 1;
        bytes.min(u128::from(RX_BURST)) as usize
    }

    /// The wrapped stream.
    pub fn get_mut(&mut self) -> &mut S {
        &mut self.inner
    }
}

impl<S: Read> Read for Paced<S> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let allowed = self.rx_allowance().min(buf.len());
        if allowed == 0 {
            return Ok(0);
        }
        let n = self.inner.read(&mut buf[..allowed])?;
        let now = std::time::Instant::now();
        let earliest = now.checked_sub(self.byte * RX_BURST).unwrap_or(now);
        self.rx_free = self.rx_free.max(earliest) + self.byte * n as u32;
        Ok(n)
    }
}

impl<S: Write> Write for Paced<S> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        let now = std::time::Instant::now();
        self.tx_free = self.tx_free.max(now) + self.byte * n as u32;
        let ahead = self.tx_free.saturating_duration_since(now);
        let buffered = self.byte * TX_BUFFER;
        if ahead > buffered {
            std::thread::sleep(ahead - buffered);
        }
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

impl<S: Pending> Pending for Paced<S> {
    fn pending(&mut self) -> io::Result<usize> {
        Ok(self.inner.pending()?.min(self.rx_allowance()))
    }
}
