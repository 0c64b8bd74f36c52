//! protocol's integration tests, one module per area (golden byte vectors and properties
//! of the bus words, the FPGA link, the host frames, the link layer and the scene
//! registers, plus the fuzz-style properties). One binary rather than one per file: each
//! test binary compiles and links the whole dependency stack again (debug info, generic
//! code instantiated per binary), so a single one is built and linked once.

mod bus;
mod crc;
mod fitkit_spi;
mod fpga_link;
mod frame;
mod fuzz_props;
mod generated;
mod link;
mod modules;
mod msp430_bsl;
mod names;
mod scene;
