//! rt-core-rtl-sim's integration tests: the Verilated core held to the golden model
//! (`sim-target`). One binary, one module per part of the core; `scenes` is the scene
//! generator and comparison the frame core's and the device's tests share.

mod arith;
mod cast;
mod device;
mod isect;
mod readback;
mod scenes;
