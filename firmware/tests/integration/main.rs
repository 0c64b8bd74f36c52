//! firmware's integration tests, one module per area (today the controller driven byte for
//! byte on the host). One binary rather than one per file: each test binary compiles and
//! links the whole dependency stack again, so new areas go in here as modules and the
//! stack is built and linked once.

mod controller;
