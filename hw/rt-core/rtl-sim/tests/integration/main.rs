//! rt-core-rtl-sim's integration tests: the Verilated core held to the golden model
//! (`sim-target`). One binary, one module per part of the core.

mod arith;
mod cast;
mod isect;
