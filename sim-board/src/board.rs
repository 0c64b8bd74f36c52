//! A whole board on a byte stream: the firmware's controller and the FPGA model served on
//! a pty master or on TCP, until the line itself fails.

use std::convert::Infallible;
use std::io::{self, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::time::{Duration, Instant};

use firmware::{Controller, ControllerError};
use sim_target::{Device, DeviceError};

use crate::host_link::{HostLink, Pending};
use crate::in_process::SimBus;
use crate::paced::Paced;
use crate::pty::peer_gone;
use crate::socket::Socket;

/// Why a board stopped serving (it never stops otherwise).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BoardError {
    /// The TCP address could not be bound.
    #[error("cannot listen on {addr}")]
    Listen {
        /// The address as given.
        addr: String,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// The line failed in a way other than the host going away.
    #[error("host link")]
    HostLink(#[source] io::Error),
    /// The bound listener could not be switched to non-blocking accepts.
    #[error(transparent)]
    Io(#[from] io::Error),
}

/// Serves the board on `link` (a pty master), slowed to a UART at `pace` baud if given.
///
/// A host that goes away is waited for, as a board waits with its cable unplugged (the
/// next one resets the link in its handshake). An FPGA model fault is answered to the
/// host as a Device error, like on a board, and also handed to `on_fault`; serving goes
/// on. Only a failing line ends it.
pub fn serve<S: Read + Write + Pending>(
    link: S,
    pace: Option<u32>,
    on_fault: impl FnMut(&DeviceError),
) -> Result<Infallible, BoardError> {
    match pace {
        Some(baud) => run(Paced::new(link, baud), |_| {}, on_fault),
        None => run(link, |_| {}, on_fault),
    }
}

/// A listener on `addr` (port 0 picks one) for [`serve_tcp`]; bound before serving so
/// that the caller can say where it is.
pub fn listen(addr: &str) -> Result<TcpListener, BoardError> {
    let listener = TcpListener::bind(addr).map_err(|source| BoardError::Listen {
        addr: addr.to_string(),
        source,
    })?;
    listener.set_nonblocking(true)?;
    Ok(listener)
}

/// Serves the board on TCP as [`serve`] does on a pty, one client at a time: a new client
/// replaces a gone one (and resets the link itself in its handshake).
pub fn serve_tcp(
    listener: TcpListener,
    pace: Option<u32>,
    on_fault: impl FnMut(&DeviceError),
) -> Result<Infallible, BoardError> {
    let accept = move |socket: &mut Socket<TcpStream>| {
        if let Ok((stream, _)) = listener.accept() {
            let ok = stream.set_nodelay(true).is_ok() && stream.set_nonblocking(false).is_ok();
            socket.0 = ok.then_some(stream);
        }
    };
    match pace {
        Some(baud) => run(
            Paced::new(Socket(None), baud),
            move |p| accept(p.get_mut()),
            on_fault,
        ),
        None => run(Socket(None), accept, on_fault),
    }
}

/// The controller and the FPGA model on `link`; `between` runs once per turn with the
/// link (to plug in a new TCP client).
fn run<S: Read + Write + Pending>(
    link: S,
    mut between: impl FnMut(&mut S),
    mut on_fault: impl FnMut(&DeviceError),
) -> Result<Infallible, BoardError> {
    let layout = &protocol::bus::WIDE;
    let device = Device::new(layout);
    let caps = device.caps();
    let mut controller = Controller::new(HostLink(link), SimBus(device), caps, layout, "fpgfx-sim");
    let epoch = Instant::now();
    loop {
        between(&mut controller.host().0);
        let now = epoch.elapsed().as_millis() as u64;
        match controller.poll(now) {
            Ok(()) => {}
            // EIO (read) or EPIPE (write) on the master while no one has the slave open:
            // the host went away; wait for the next one (it will reset the link).
            Err(ControllerError::Host(e)) if peer_gone(&e) => {
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(ControllerError::Host(e)) => return Err(BoardError::HostLink(e)),
            // The host was answered with a Device error; like a board, keep serving.
            Err(ControllerError::Fpga(e)) => on_fault(&e),
        }
        // Sleep only when the line is quiet: a UART (with its FIFO or DMA) keeps
        // receiving while the MCU works, and a sleep per turn would cap the rate.
        if !matches!(controller.host().0.pending(), Ok(n) if n > 0) {
            std::thread::sleep(Duration::from_micros(100));
        }
    }
}
