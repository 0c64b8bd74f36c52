//! A whole board on a byte stream: the firmware's controller and its FPGA (the model, or
//! the Verilated RTL) served on a pty master or on TCP, until the line itself fails.

use std::convert::Infallible;
use std::fmt::Display;
use std::io::{self, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::time::{Duration, Instant};

use firmware::{Controller, ControllerError, FpgaBus};
use sim_target::Device;

use crate::host_link::{HostLink, Pending};
use crate::in_process::SimBus;
use crate::paced::Paced;
use crate::pty::peer_gone;
use crate::rtl::RtlTargetError;
use crate::socket::Socket;

/// Which FPGA the board carries (`fpgfx-sim --fpga`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum Fpga {
    /// The golden model (`sim-target`), WIDE layout: every command the tool has.
    #[default]
    Model,
    /// The FITkit block's RTL, Verilated, behind the controller's SPI driver: FITkit
    /// layout, raster only.
    Rtl,
    /// The ray-casting core's RTL, Verilated, behind the controller's AXI4-Lite register
    /// driver: ray tracing only, in Q16.16, what the core builds.
    #[value(name = "rtl:rt")]
    RtlRt,
}

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
    /// The RTL board could not be built (no Verilated model in this build).
    #[error(transparent)]
    Rtl(#[from] RtlTargetError),
    /// The ray-casting core's RTL could not be made (no verilator in this build).
    #[error("--fpga rtl:rt")]
    RtlRt(#[from] crate::rt_rtl::RtRtlTargetError),
}

/// Serves the board carrying `fpga` on `link` (a pty master), slowed to a UART at `pace`
/// baud if given.
///
/// A host that goes away is waited for, as a board waits with its cable unplugged (the
/// next one resets the link in its handshake). An FPGA fault is answered to the host as a
/// Device error, like on a board, and also handed to `on_fault`; serving goes on. Only a
/// failing line ends it.
pub fn serve<S: Read + Write + Pending>(
    link: S,
    pace: Option<u32>,
    fpga: Fpga,
    on_fault: impl FnMut(&dyn Display),
) -> Result<Infallible, BoardError> {
    match pace {
        Some(baud) => run(Paced::new(link, baud), fpga, |_| {}, on_fault),
        None => run(link, fpga, |_| {}, on_fault),
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
    fpga: Fpga,
    on_fault: impl FnMut(&dyn Display),
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
            fpga,
            move |p| accept(p.get_mut()),
            on_fault,
        ),
        None => run(Socket(None), fpga, accept, on_fault),
    }
}

/// The controller and `fpga` on `link`; `between` runs once per turn with the link (to
/// plug in a new TCP client).
fn run<S: Read + Write + Pending>(
    link: S,
    fpga: Fpga,
    between: impl FnMut(&mut S),
    on_fault: impl FnMut(&dyn Display),
) -> Result<Infallible, BoardError> {
    match fpga {
        Fpga::Model => {
            let layout = &protocol::bus::WIDE;
            let device = Device::new(layout);
            let caps = device.caps();
            let bus = SimBus(device);
            let c = Controller::new(HostLink(link), bus, caps, layout, "fpgfx-sim");
            run_on(c, between, on_fault)
        }
        Fpga::Rtl => {
            let rtl = fitkit_rtl_sim::Rtl::shared().map_err(RtlTargetError::from)?;
            let bus = crate::rtl::bus_on(&rtl, fitkit_rtl_sim::SpiConfig::default())?;
            let caps = crate::rtl::caps();
            let layout = &protocol::bus::FITKIT;
            let c = Controller::new(HostLink(link), bus, caps, layout, "fpgfx-sim --fpga rtl");
            run_on(c, between, on_fault)
        }
        Fpga::RtlRt => {
            let bus = crate::rt_rtl::bus()?;
            let caps = crate::rt_rtl::caps();
            let ident = "fpgfx-sim --fpga rtl:rt";
            let c = Controller::new(HostLink(link), bus, caps, &protocol::bus::WIDE, ident);
            run_on(c, between, on_fault)
        }
    }
}

fn run_on<S: Read + Write + Pending, B: FpgaBus>(
    mut controller: Controller<HostLink<S>, B>,
    mut between: impl FnMut(&mut S),
    mut on_fault: impl FnMut(&dyn Display),
) -> Result<Infallible, BoardError>
where
    B::Error: Display,
{
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
            Err(ControllerError::Fpga(e)) => on_fault(&e as &dyn Display),
        }
        // Sleep only when the line is quiet: a UART (with its FIFO or DMA) keeps
        // receiving while the MCU works, and a sleep per turn would cap the rate.
        if !matches!(controller.host().0.pending(), Ok(n) if n > 0) {
            std::thread::sleep(Duration::from_micros(100));
        }
    }
}
