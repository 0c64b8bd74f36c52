//! A serial port (a USB UART or a pseudo-terminal) as the host's link transport. The
//! board's end of such a line, inside `fpgfx-sim`, is sim-board's host link
//! (`sim-board/src/host_link.rs`).

use std::io::{self, Write};
use std::time::Duration;

use crate::session::Transport;

/// A serial port as a [`Transport`].
pub struct SerialTransport {
    port: Box<dyn serialport::SerialPort>,
}

impl SerialTransport {
    /// Opens `path` at `baud` (8N1, no flow control).
    pub fn open(path: &str, baud: u32) -> Result<Self, serialport::Error> {
        let port = serialport::new(path, baud)
            .timeout(Duration::from_millis(10))
            .open()?;
        Ok(Self { port })
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
