//! Verilates the block's `rtl/` and `sim/` (`hw/fitkit-raster/`, top `fitkit_sim_top`)
//! with its C shim (the shared recipe: the `verilate` crate). `FPGFX_RTL_DIR` points it at
//! another copy of `rtl/` (the simulation top stays the block's own `sim/`: what is under
//! test is the synthesisable part).

use std::path::PathBuf;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    verilate::Model {
        // the sim top the RTL provides (docs/rtl.md, "Simulating the RTL from Rust")
        // the seed's build, the one testing eight pixels per cycle (TRI_LANES = 8), and
        // the line-only and triangle-only builds for the seed's XC3S50; in the order of
        // `Build::ALL`, the index the shim takes
        tops: &[
            "fitkit_sim_top",
            "fitkit_sim_top8",
            "fitkit_sim_top_line",
            "fitkit_sim_top_tri",
        ],
        rtl: manifest.join("../rtl"),
        rtl_override: "FPGFX_RTL_DIR",
        sim: vec![manifest.join("../sim")],
        shim: manifest.join("csrc/shim.cpp"),
        lib: "fitkit_rtl",
        // a failing differential case writes its waveform (Rtl::trace_to)
        trace: true,
    }
    .build();
}
