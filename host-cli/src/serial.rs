//! Byte streams of the operating system as link transports: a serial port (a USB UART or
//! a pseudo-terminal) or TCP on the host side, and the same streams as the controller's
//! `embedded_io` host link inside `fpgfx-sim`.

use std::io::{self, Read, Write};
use std::time::Duration;

use crate::session::Transport;

/// A serial port as a [`Transport`].
pub struct SerialTransport {
    port: Box<dyn serialport::SerialPort>,
    name: String,
}

impl SerialTransport {
    /// Opens `path` at `baud` (8N1, no flow control).
    pub fn open(path: &str, baud: u32) -> Result<Self, serialport::Error> {
        let port = serialport::new(path, baud)
            .timeout(Duration::from_millis(10))
            .open()?;
        Ok(Self {
            port,
            name: path.to_string(),
        })
    }

    /// The path the port was opened with.
    pub fn name(&self) -> &str {
        &self.name
    }
}

impl Transport for SerialTransport {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        // No flush: on a tty it is tcdrain, which blocks until the line has carried every
        // byte, so the next frame would only be queued once the line had gone idle. The
        // kernel's buffer transmits on its own.
        self.port.write_all(bytes)
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        read_within(self.port.as_mut(), buf, timeout)
    }
}

/// [`Transport::read`] for any serial port, whatever its line settings (the link's 8N1
/// here, the bootloader's 8E1 in `flash`): what arrives within `timeout`, 0 bytes when
/// nothing does.
pub(crate) fn read_within(
    port: &mut dyn serialport::SerialPort,
    buf: &mut [u8],
    timeout: Duration,
) -> io::Result<usize> {
    port.set_timeout(timeout.max(Duration::from_millis(1)))
        .map_err(io::Error::other)?;
    match port.read(buf) {
        Ok(n) => Ok(n),
        Err(e) if e.kind() == io::ErrorKind::TimedOut => Ok(0),
        Err(e) => Err(e),
    }
}

impl Transport for Box<dyn Transport> {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        (**self).write_all(bytes)
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        (**self).read(buf, timeout)
    }
}

/// Something that can say how many received bytes are waiting, so the controller never
/// blocks on its host link (a board's UART has a status flag for this).
pub trait Pending {
    /// Bytes readable without blocking.
    fn pending(&mut self) -> io::Result<usize>;
}

impl Pending for serialport::TTYPort {
    fn pending(&mut self) -> io::Result<usize> {
        use serialport::SerialPort;
        self.bytes_to_read()
            .map(|n| n as usize)
            .map_err(io::Error::other)
    }
}

/// A std byte stream as the controller's `embedded_io` host link.
pub struct HostLink<S>(pub S);

impl<S> embedded_io::ErrorType for HostLink<S> {
    type Error = io::Error;
}

impl<S: Read> embedded_io::Read for HostLink<S> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        self.0.read(buf)
    }
}

impl<S: Pending> embedded_io::ReadReady for HostLink<S> {
    fn read_ready(&mut self) -> io::Result<bool> {
        Ok(self.0.pending()? > 0)
    }
}

impl<S: Write> embedded_io::Write for HostLink<S> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.write(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

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

impl Pending for std::net::TcpStream {
    fn pending(&mut self) -> io::Result<usize> {
        self.set_nonblocking(true)?;
        let mut probe = [0u8; 256];
        let r = self.peek(&mut probe);
        self.set_nonblocking(false)?;
        match r {
            Ok(0) => Err(io::Error::new(
                io::ErrorKind::BrokenPipe,
                "the host closed the connection",
            )),
            Ok(n) => Ok(n),
            Err(e) if e.kind() == io::ErrorKind::WouldBlock => Ok(0),
            Err(e) => Err(e),
        }
    }
}

/// A stream that may be absent (between TCP clients): without one, nothing arrives and
/// what is written is dropped, as on a UART with no cable.
pub struct Socket<S>(pub Option<S>);

impl<S: Read> Read for Socket<S> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match &mut self.0 {
            Some(s) => s.read(buf),
            None => Ok(0),
        }
    }
}

impl<S: Write> Write for Socket<S> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.0 {
            Some(s) => s.write(buf),
            None => Ok(buf.len()),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.0 {
            Some(s) => s.flush(),
            None => Ok(()),
        }
    }
}

impl<S: Pending> Pending for Socket<S> {
    fn pending(&mut self) -> io::Result<usize> {
        match &mut self.0 {
            Some(s) => s.pending(),
            None => Ok(0),
        }
    }
}
