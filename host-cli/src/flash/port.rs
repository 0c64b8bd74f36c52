//! The board's bootloader line: a serial port at 8E1, which is what AN3155 and SLAU319
//! specify and what sets it apart from the 8N1 link of every other command.

use std::io;
use std::time::Duration;

use super::{BslClient, Client, FlashError};
use crate::connect::{ConnectError, Target};
use crate::session::Transport;

/// A serial port at 8E1, the bootloader's line settings.
pub struct BootPort {
    port: Box<dyn serialport::SerialPort>,
}

impl BootPort {
    /// Opens `path` at `baud`, 8 data bits, even parity, one stop bit, no flow control.
    pub fn open(path: &str, baud: u32) -> Result<Self, ConnectError> {
        let port = serialport::new(path, baud)
            .data_bits(serialport::DataBits::Eight)
            .parity(serialport::Parity::Even)
            .stop_bits(serialport::StopBits::One)
            .flow_control(serialport::FlowControl::None)
            .timeout(Duration::from_millis(10))
            .open()
            .map_err(|e| ConnectError::serial_open(path, baud, e))?;
        Ok(Self { port })
    }
}

impl Transport for BootPort {
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        // Drained, unlike the link's writes: the answer timeouts then count from when the
        // bytes have left, which at a low baud rate is long after they were queued.
        io::Write::write_all(&mut self.port, bytes)?;
        io::Write::flush(&mut self.port)
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        crate::serial::read_within(self.port.as_mut(), buf, timeout)
    }
}

/// The bootloader behind `port` (the `--port` after the config file), at `baud`. Only a
/// serial port can have one: `builtin` and `tcp:` targets are refused by name.
pub fn open(port: Option<&str>, baud: u32) -> Result<Client<BootPort>, FlashError> {
    Ok(Client::new(open_port(port, baud)?, baud))
}

/// The MSP430's BSL behind `port` at `baud` (9600 unless changed), the same way.
pub fn open_bsl(port: Option<&str>, baud: u32) -> Result<BslClient<BootPort>, FlashError> {
    Ok(BslClient::new(open_port(port, baud)?, baud))
}

fn open_port(port: Option<&str>, baud: u32) -> Result<BootPort, FlashError> {
    match port.map(|p| (p, Target::parse(p, baud))) {
        Some((path, Target::Serial { .. })) => Ok(BootPort::open(path, baud)?),
        other => Err(FlashError::NotSerial {
            port: other.map_or("(none)", |(p, _)| p).to_string(),
        }),
    }
}
