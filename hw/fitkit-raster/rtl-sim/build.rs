//! Verilates the block's `rtl/` and `sim/` (`hw/fitkit-raster/`, top `fitkit_sim_top`) and
//! compiles it with Verilator's runtime and the C shim into a static library the crate
//! links.
//!
//! Without verilator, or before `sim/` has a top, the crate still builds (the rest
//! of the workspace must not need Verilator): `rtl_sim_verilated` stays unset and
//! `RTL_SIM_MISSING` names what was missing, which `Rtl::new` turns into its error.
//! `FPGFX_RTL_DIR` points it at another copy of `rtl/` (the simulation top stays the
//! block's own `sim/`: what is under test is the synthesisable part).
//!
//! The generated C++ is compiled optimised whatever the Cargo profile: a debug build of
//! it would make the differential tests several times slower.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The sim top the RTL provides (docs/rtl.md, "Simulating the RTL from Rust").
const TOP: &str = "fitkit_sim_top";

/// Where `cargo xtask setup` puts verilator (Debian's package): watched while verilator
/// is missing, so installing it triggers the rebuild the error message asks for.
const DEBIAN_VERILATOR: &str = "/usr/bin/verilator";

fn main() {
    println!("cargo::rustc-check-cfg=cfg(rtl_sim_verilated)");
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=csrc/shim.cpp");
    println!("cargo::rerun-if-env-changed=VERILATOR");
    println!("cargo::rerun-if-env-changed=FPGFX_RTL_DIR");
    let manifest = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("set by cargo"));
    // A scratch copy of rtl/ instead of the workspace's, e.g. a deliberately broken unit
    // to see the differential tests fail.
    let rtl = env::var_os("FPGFX_RTL_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| manifest.join("../rtl"));
    let sources = rtl_sources(&rtl, &manifest.join("../sim"));
    let Some(verilator) = find_verilator() else {
        println!("cargo::rerun-if-env-changed=PATH");
        println!("cargo::rerun-if-changed={DEBIAN_VERILATOR}");
        missing("verilator");
        return;
    };
    println!("cargo::rerun-if-changed={}", verilator.display());
    let has_top = sources
        .iter()
        .any(|p| fs::read_to_string(p).is_ok_and(|t| t.contains(&format!("module {TOP}"))));
    if !has_top {
        missing("rtl");
        return;
    }
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("set by cargo"));
    let mdir = out.join("verilated");
    // A stale tree would leave classes of removed modules to be compiled.
    let _ = fs::remove_dir_all(&mdir);
    let log = out.join("verilator.log");
    let run = Command::new(&verilator)
        .args(["--cc", "-O3", "--top-module", TOP, "-Wno-fatal", "--Mdir"])
        .arg(&mdir)
        // The modules include the generated map header (fitkit_map.vh) that sits beside
        // them, so a scratch copy of rtl/ brings its own.
        .arg(format!("-I{}", rtl.display()))
        .args(&sources)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", verilator.display()));
    // Verilator's warnings go to a log, not to cargo's output.
    let mut text = run.stdout.clone();
    text.extend_from_slice(&run.stderr);
    let _ = fs::write(&log, &text);
    if !run.status.success() {
        panic!(
            "verilator failed on {} ({}):\n{}",
            rtl.display(),
            run.status,
            String::from_utf8_lossy(&text)
        );
    }
    let include = verilator_include(&verilator);
    let mut build = cc::Build::new();
    build
        .cpp(true)
        .std("c++17")
        .opt_level(3)
        .debug(false)
        .warnings(false)
        .cargo_warnings(false)
        .define("VM_TRACE", "0")
        .include(&mdir)
        .include(&include)
        .include(include.join("vltstd"))
        .file(manifest.join("csrc/shim.cpp"));
    for runtime in [
        "verilated.cpp",
        "verilated_threads.cpp",
        "verilated_dpi.cpp",
    ] {
        build.file(include.join(runtime));
    }
    let mut generated: Vec<PathBuf> = fs::read_dir(&mdir)
        .unwrap_or_else(|e| panic!("{}: {e}", mdir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "cpp"))
        .collect();
    generated.sort();
    build.files(generated);
    build.compile("fitkit_rtl");
    println!("cargo::rustc-link-lib=pthread");
    println!("cargo::rustc-link-lib=atomic");
    println!("cargo::rustc-cfg=rtl_sim_verilated");
}

/// Tells the crate what was missing; see [`main`].
fn missing(what: &str) {
    println!("cargo::rustc-env=RTL_SIM_MISSING={what}");
}

/// `rtl/*.v` then `sim/*.v`, sorted, each watched with the headers beside them (and the
/// folders, for added files).
fn rtl_sources(rtl: &Path, sim: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for dir in [rtl, sim] {
        println!("cargo::rerun-if-changed={}", dir.display());
        let Ok(entries) = fs::read_dir(dir) else {
            continue;
        };
        let mut files: Vec<PathBuf> = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "v" || x == "vh"))
            .collect();
        files.sort();
        for f in &files {
            println!("cargo::rerun-if-changed={}", f.display());
        }
        all.extend(
            files
                .into_iter()
                .filter(|p| p.extension().is_some_and(|x| x == "v")),
        );
    }
    all
}

/// `VERILATOR` if set, else the first `verilator` on the PATH.
fn find_verilator() -> Option<PathBuf> {
    if let Some(v) = env::var_os("VERILATOR") {
        let p = PathBuf::from(v);
        return p.is_file().then_some(p);
    }
    env::split_paths(&env::var_os("PATH")?)
        .map(|d| d.join("verilator"))
        .find(|p| p.is_file())
}

/// The runtime's include folder: `$VERILATOR_ROOT/include` as verilator itself reports
/// it, else Debian's.
fn verilator_include(verilator: &Path) -> PathBuf {
    let root = Command::new(verilator)
        .arg("--getenv")
        .arg("VERILATOR_ROOT")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .filter(|r| !r.is_empty())
        .unwrap_or_else(|| "/usr/share/verilator".into());
    PathBuf::from(root).join("include")
}
