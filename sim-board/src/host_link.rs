//! The board's end of an operating-system byte stream (a pty master, a TCP socket) as the
//! controller's `embedded_io` host link, the way a board's UART is.

use std::io::{self, Read, Write};

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
