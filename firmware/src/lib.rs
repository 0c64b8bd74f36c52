//! The fpgfx controller: takes frames from the host and feeds the FPGA.
#![no_std]
