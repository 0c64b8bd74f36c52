//! The FPGA alone behind a serial port: the emulated device answering the serial FPGA
//! link ([`protocol::fpga_link`]) for a controller elsewhere, e.g. a QEMU board's USART2.

use std::io::{self, Read, Write};
use std::time::{Duration, Instant};

use firmware::FpgaBus;
use serialport::SerialPort;
use sim_target::Device;

use crate::board::Fpga;
use crate::fpga_server::{FpgaServer, Served};
use crate::in_process::SimBus;
use crate::pty::peer_gone;
use crate::rtl::RtlTargetError;

/// Why the FPGA stopped serving before its peer went away.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FpgaPortError {
    /// The port could not be opened.
    #[error("cannot open FPGA-link port {path}")]
    Open {
        /// The port as given.
        path: String,
        /// What the serial layer said.
        #[source]
        source: serialport::Error,
    },
    /// Reading the port failed other than by the peer closing it.
    #[error("reading {path}")]
    Read {
        /// The port's device path, as given.
        path: String,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// Writing the port failed.
    #[error("writing {path}")]
    Write {
        /// The port's device path, as given.
        path: String,
        /// What the OS said.
        #[source]
        source: io::Error,
    },
    /// The port refused a read timeout.
    #[error(transparent)]
    Timeout(#[from] serialport::Error),
    /// The RTL could not be built (no Verilated model in this build).
    #[error(transparent)]
    Rtl(#[from] RtlTargetError),
    /// The ray-casting core's RTL could not be made (no verilator in this build).
    #[error("--fpga rtl:rt")]
    RtlRt(#[from] crate::rt_rtl::RtRtlTargetError),
}

/// An open port the FPGA will be served on.
pub struct FpgaPort {
    port: serialport::TTYPort,
    path: String,
}

impl FpgaPort {
    /// Opens `path` at `baud` (8N1), before serving, so that the caller can report it.
    pub fn open(path: &str, baud: u32) -> Result<Self, FpgaPortError> {
        let port = serialport::new(path, baud)
            .timeout(Duration::from_millis(1))
            .open_native()
            .map_err(|source| FpgaPortError::Open {
                path: path.to_string(),
                source,
            })?;
        Ok(Self {
            port,
            path: path.to_string(),
        })
    }

    /// Serves `fpga` (the model in the WIDE bus layout, or the RTL in the FITkit's) until
    /// the peer closes the port (QEMU exited): then `Ok`, as nothing is left to serve.
    /// Each fault the FPGA flags to the controller is also handed to `on_fault` as text.
    pub fn serve(self, fpga: Fpga, on_fault: impl FnMut(&str)) -> Result<(), FpgaPortError> {
        match fpga {
            Fpga::Model => {
                let layout = &protocol::bus::WIDE;
                let device = Device::new(layout);
                let caps = device.caps();
                self.serve_on(FpgaServer::new(SimBus(device), caps, layout), on_fault)
            }
            Fpga::Rtl => {
                let rtl = fitkit_rtl_sim::Rtl::shared().map_err(RtlTargetError::from)?;
                let bus = crate::rtl::bus_on(&rtl, fitkit_rtl_sim::SpiConfig::default())?;
                let server = FpgaServer::new(bus, crate::rtl::caps(), &protocol::bus::FITKIT);
                self.serve_on(server, on_fault)
            }
            Fpga::RtlRt => {
                let bus = crate::rt_rtl::bus()?;
                let server = FpgaServer::new(bus, crate::rt_rtl::caps(), &protocol::bus::WIDE);
                self.serve_on(server, on_fault)
            }
        }
    }

    fn serve_on<B: FpgaBus>(
        mut self,
        mut server: FpgaServer<B>,
        mut on_fault: impl FnMut(&str),
    ) -> Result<(), FpgaPortError>
    where
        B::Error: Served,
    {
        let path = self.path;
        let epoch = Instant::now();
        let mut buf = [0u8; 4096];
        let mut out = [0u8; protocol::link::MAX_FRAME];
        let mut busy = false;
        loop {
            // While the FIFO holds work, only peek at the line; when idle, sleep in the read.
            self.port.set_timeout(if busy {
                Duration::ZERO
            } else {
                Duration::from_millis(1)
            })?;
            let n = match self.port.read(&mut buf) {
                Ok(n) => n,
                Err(e) if e.kind() == io::ErrorKind::TimedOut => 0,
                Err(e) if peer_gone(&e) => return Ok(()),
                Err(source) => return Err(FpgaPortError::Read { path, source }),
            };
            let now = epoch.elapsed().as_millis() as u64;
            server.input(now, &buf[..n]);
            while let Some(m) = server.poll_transmit(now, &mut out) {
                self.port
                    .write_all(&out[..m])
                    .map_err(|source| FpgaPortError::Write {
                        path: path.clone(),
                        source,
                    })?;
            }
            if let Some(text) = server.take_fault_text() {
                on_fault(&text);
            }
            busy = server.work();
        }
    }
}
