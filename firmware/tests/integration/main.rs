//! firmware's integration tests, one module per area (the controller driven byte for byte
//! on the host, the register-bus driver on a scripted register file). One binary rather
//! than one per file: each test binary compiles and links the whole dependency stack
//! again, so new areas go in here as modules and the stack is built and linked once.

mod controller;
mod mmio;
