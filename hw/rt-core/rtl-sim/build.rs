//! Verilates the core's `rtl/` with the arithmetic units' sim top (`hw/rt-core/sim/`, top
//! `rt_math_top`), the intersection unit, the frame and the device on its bus (`rt_isect`,
//! `rt_cast`, `rt_device`) and its C shim (the shared recipe: the `verilate` crate).
//! `FPGFX_RT_RTL_DIR` points it at another copy of `rtl/`; the `trace` feature builds
//! models that can write a VCD.

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    verilate::Model {
        tops: ["rt_math_top", "rt_isect", "rt_cast", "rt_device"]
            .into_iter()
            .map(verilate::Top::plain)
            .collect(),
        rtl: manifest.join("../rtl"),
        rtl_override: "FPGFX_RT_RTL_DIR",
        sim: vec![manifest.join("../sim")],
        shim: manifest.join("csrc/shim.cpp"),
        lib: "rt_core_rtl",
        // Only the replay of a failing differential case asks for a waveform, and tracing
        // doubles the C++ to compile: the suite builds without it, and a failure rebuilds
        // the crate with the `trace` feature (tests/integration/waves.rs).
        trace: std::env::var_os("CARGO_FEATURE_TRACE").is_some(),
    }
    .build();
}
