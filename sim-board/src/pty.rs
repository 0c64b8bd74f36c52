//! The pseudo-terminal a board is served on, and how its master end reports that the host
//! has gone.

use std::io;

/// Why no pseudo-terminal could be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PtyError {
    /// The OS refused a new pair (out of ptys, no /dev/ptmx).
    #[error("cannot create a pseudo-terminal pair")]
    Create(#[source] serialport::Error),
    /// The slave end has no device node to give the host.
    #[error("the pseudo-terminal has no path")]
    NoPath,
}

/// A new pseudo-terminal: its master end, which the board serves, and the path of its
/// slave end, which the host opens as a serial port.
pub fn open() -> Result<(serialport::TTYPort, String), PtyError> {
    let (master, slave) = serialport::TTYPort::pair().map_err(PtyError::Create)?;
    let path = serialport::SerialPort::name(&slave).ok_or(PtyError::NoPath)?;
    // The host opens the slave by path and takes the exclusive lock a serial port gets;
    // our handle would hold it. The node lives as long as the master is open.
    drop(slave);
    Ok((master, path))
}

/// Whether `e` only means that nobody is on the other end: EIO (read) or EPIPE (write) on
/// a pty master whose slave no process has open, or a TCP peer that closed.
pub(crate) fn peer_gone(e: &io::Error) -> bool {
    e.kind() == io::ErrorKind::BrokenPipe || matches!(e.raw_os_error(), Some(5) | Some(32))
}
