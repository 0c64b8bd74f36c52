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
        self.port.write_all(bytes)?;
        self.port.flush()
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        self.port
            .set_timeout(timeout.max(Duration::from_millis(1)))
            .map_err(io::Error::other)?;
        match self.port.read(buf) {
            Ok(n) => Ok(n),
            Err(e) if e.kind() == io::ErrorKind::TimedOut => Ok(0),
            Err(e) => Err(e),
        }
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
