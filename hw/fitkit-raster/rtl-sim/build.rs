//! Verilates the block's `rtl/` and `sim/` (`hw/fitkit-raster/`, top `fitkit_sim_top`,
//! once per build of the crate's build table) with its C shim (the shared recipe: the
//! `verilate` crate). `FPGFX_RTL_DIR` points it at another copy of `rtl/` (the
//! simulation top stays the block's own `sim/`: what is under test is the synthesisable
//! part).

use std::path::PathBuf;

// The library's table of builds, read here for each build's class and parameters; the
// library's names the build script does not use are no error of it.
#[allow(dead_code)]
#[path = "src/build_table.rs"]
mod build_table;

fn main() {
    let manifest = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    println!("cargo::rerun-if-changed=src/build_table.rs");
    verilate::Model {
        // the sim top the RTL provides (docs/rtl.md, "Simulating the RTL from Rust"), in
        // the order of `Build::ALL`, the index the shim takes
        tops: build_table::Build::ALL
            .iter()
            .map(|b| verilate::Top {
                class: b.class,
                module: "fitkit_sim_top",
                params: b.params().to_vec(),
            })
            .collect(),
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
