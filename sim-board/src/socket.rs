//! The board's host line when it may have nobody on it: a TCP board between clients.

use std::io::{self, Read, Write};

use crate::host_link::Pending;

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
