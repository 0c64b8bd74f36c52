//! rt-core-rtl-sim's integration tests: the Verilated core held to the golden model
//! (`sim-target`). One binary, one module per part of the core; `scenes` is the scene
//! generator and comparison the frame core's and the device's tests share, `waves` the
//! replay of a failing case into a waveform.

mod arith;
mod cast;
mod device;
mod isect;
mod readback;
mod scenes;
mod waves;
