//! The built-in target (`--port builtin`) as a [`Transport`]. The board itself — the
//! firmware's controller and the FPGA model in this process — is
//! [`sim_board::in_process`]; it cannot implement this crate's trait, since sim-board sits
//! below host-cli, so the impl lives here and only delegates.

use std::io;
use std::time::Duration;

use firmware::FpgaBus;
use sim_board::in_process::BuiltIn;

use crate::session::Transport;

impl<B: FpgaBus> Transport for BuiltIn<B>
where
    B::Error: core::fmt::Display,
{
    fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        BuiltIn::write_all(self, bytes)
    }

    fn read(&mut self, buf: &mut [u8], timeout: Duration) -> io::Result<usize> {
        BuiltIn::read(self, buf, timeout)
    }
}
