//! What a Verilated bridge crate's `build.rs` does, in one place: find Verilator, run it
//! on the block's folders, compile its C++ (at `-O1` whatever the Cargo profile: a debug
//! build of it makes the differential tests several times slower, and `-O3` buys little
//! over `-O1` for what it costs to compile: both blocks' models took 264 CPU-seconds to
//! build at `-O3`, 152 at `-O1` and 209 at `-Os`, and their crates' tests 38, 44 and 48
//! CPU-seconds to run, on the 2-core machine the test command is timed on) with Verilator's
//! runtime and the crate's C shim into a static library, and tell the crate whether that
//! worked. Under Clippy, which links nothing, the C++ is not compiled.
//!
//! Without verilator, or before the folders hold the sim top, the crate still builds (the
//! rest of the workspace must not need Verilator): the cfg `verilated` stays unset and the
//! environment variable `VERILATED_MISSING` names what was missing (`verilator` or
//! `rtl`), which the crate turns into its constructor's error. A build script panics (the
//! build fails) only when Verilator or the C++ compiler rejects the sources.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Where `cargo xtask setup` puts verilator (Debian's package): watched while verilator
/// is missing, so installing it triggers the rebuild the crate's error message asks for.
const DEBIAN_VERILATOR: &str = "/usr/bin/verilator";

/// One Verilated model: a sim top's module with parameters, under a class name of its
/// own, so one top built with several parameter sets needs no wrapper module per set.
#[derive(Debug, Clone)]
pub struct Top<'a> {
    /// The C++ class, less its `V` (Verilator's `--prefix`): what the shim includes.
    pub class: &'a str,
    /// The top module (`module <module>` must be in one of the sources).
    pub module: &'a str,
    /// Its parameters (Verilator's `-G<name>=<value>`).
    pub params: Vec<(&'a str, u32)>,
}

impl<'a> Top<'a> {
    /// A top built as written: its class is its module's name.
    pub fn plain(module: &'a str) -> Self {
        Top {
            class: module,
            module,
            params: Vec::new(),
        }
    }
}

/// What to Verilate and what to call the result: one or more sim tops of one block, each
/// its own Verilated model (class `V<class>`), in one library with one copy of Verilator's
/// runtime.
pub struct Model<'a> {
    /// The sim tops.
    pub tops: Vec<Top<'a>>,
    /// The synthesisable folder (its `*.v`, and its headers on the include path).
    pub rtl: PathBuf,
    /// An environment variable that, when set, replaces `rtl` (a scratch copy with a
    /// deliberately broken unit, to see the differential tests fail).
    pub rtl_override: &'a str,
    /// Further folders of sources read after `rtl` (the simulation top and its memories).
    pub sim: Vec<PathBuf>,
    /// The C++ shim that gives the model its C ABI.
    pub shim: PathBuf,
    /// The static library's name.
    pub lib: &'a str,
    /// Build the model able to write a VCD (Verilator's `--trace`), for a shim that opens
    /// one when a case fails; a model never asked for one pays only Verilator's activity
    /// flags.
    pub trace: bool,
}

impl Model<'_> {
    /// Runs the whole build; see the crate docs for what the crate learns.
    pub fn build(&self) {
        println!("cargo::rustc-check-cfg=cfg(verilated)");
        println!("cargo::rerun-if-changed=build.rs");
        println!("cargo::rerun-if-changed={}", self.shim.display());
        println!("cargo::rerun-if-env-changed=VERILATOR");
        println!("cargo::rerun-if-env-changed={}", self.rtl_override);
        let rtl = env::var_os(self.rtl_override)
            .map(PathBuf::from)
            .unwrap_or_else(|| self.rtl.clone());
        let mut dirs = vec![rtl.clone()];
        dirs.extend(self.sim.iter().cloned());
        let sources = sources(&dirs);
        let Some(verilator) = find_verilator() else {
            println!("cargo::rerun-if-env-changed=PATH");
            println!("cargo::rerun-if-changed={DEBIAN_VERILATOR}");
            missing("verilator");
            return;
        };
        println!("cargo::rerun-if-changed={}", verilator.display());
        let has_tops = self.tops.iter().all(|top| {
            sources.iter().any(|p| {
                fs::read_to_string(p).is_ok_and(|t| t.contains(&format!("module {}", top.module)))
            })
        });
        if !has_tops {
            missing("rtl");
            return;
        }
        let out = PathBuf::from(env::var_os("OUT_DIR").expect("set by cargo"));
        let verilated = out.join("verilated");
        // A stale tree would leave classes of removed modules to be compiled.
        let _ = fs::remove_dir_all(&verilated);
        let mdirs: Vec<PathBuf> = self
            .tops
            .iter()
            .map(|top| verilated.join(top.class))
            .collect();
        for (top, mdir) in self.tops.iter().zip(&mdirs) {
            // Verilator makes its own folder but not the one above it
            fs::create_dir_all(mdir).unwrap_or_else(|e| panic!("{}: {e}", mdir.display()));
            let run = Command::new(&verilator)
                // Uninitialised state and X assignments become values the shim can draw
                // at random (`randReset(2)` and a seed on the context; the default, 0,
                // keeps zeros), so a test can show that no X reaches an output.
                .args([
                    "--cc",
                    "-O3",
                    "--x-assign",
                    "unique",
                    "--x-initial",
                    "unique",
                ])
                .args(if self.trace {
                    &["--trace"][..]
                } else {
                    &[][..]
                })
                .args(["--top-module", top.module, "--prefix"])
                .arg(format!("V{}", top.class))
                .args(
                    top.params
                        .iter()
                        .map(|(name, value)| format!("-G{name}={value}")),
                )
                .args(["-Wno-fatal", "--Mdir"])
                .arg(mdir)
                // The modules include headers that sit beside them (a generated map), so a
                // scratch copy of the folder brings its own.
                .arg(format!("-I{}", rtl.display()))
                .args(&sources)
                .output()
                .unwrap_or_else(|e| panic!("cannot run {}: {e}", verilator.display()));
            // Verilator's warnings go to a log, not to cargo's output.
            let mut text = run.stdout.clone();
            text.extend_from_slice(&run.stderr);
            let _ = fs::write(out.join(format!("verilator-{}.log", top.class)), &text);
            if !run.status.success() {
                panic!(
                    "verilator failed on {} with top {} ({}):\n{}",
                    rtl.display(),
                    top.class,
                    run.status,
                    String::from_utf8_lossy(&text)
                );
            }
        }
        if linted_only() {
            // Clippy never links, so the C++ (most of this build's time) is left out; the
            // crate still sees the same cfg. Without this the test command compiled each
            // model twice: Clippy's build scripts are other units than the test build's.
            println!("cargo::rustc-cfg=verilated");
            return;
        }
        let include = verilator_include(&verilator);
        let mut build = cc::Build::new();
        build
            .cpp(true)
            .std("c++17")
            .opt_level(1)
            .debug(false)
            .warnings(false)
            .cargo_warnings(false)
            .define("VM_TRACE", if self.trace { "1" } else { "0" })
            .includes(&mdirs)
            .include(&include)
            .include(include.join("vltstd"))
            .file(&self.shim);
        for runtime in [
            "verilated.cpp",
            "verilated_threads.cpp",
            "verilated_dpi.cpp",
        ] {
            build.file(include.join(runtime));
        }
        if self.trace {
            build.file(include.join("verilated_vcd_c.cpp"));
        }
        for mdir in &mdirs {
            let mut generated: Vec<PathBuf> = fs::read_dir(mdir)
                .unwrap_or_else(|e| panic!("{}: {e}", mdir.display()))
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "cpp"))
                .collect();
            generated.sort();
            build.files(generated);
        }
        build.compile(self.lib);
        println!("cargo::rustc-link-lib=pthread");
        println!("cargo::rustc-link-lib=atomic");
        println!("cargo::rustc-cfg=verilated");
    }
}

/// Tells the crate what was missing; see the crate docs.
fn missing(what: &str) {
    println!("cargo::rustc-env=VERILATED_MISSING={what}");
}

/// Every folder's `*.v`, each folder sorted, watched with the headers beside them (and
/// the folders, for added files).
fn sources(dirs: &[PathBuf]) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for dir in dirs {
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

/// Whether Cargo runs this build script for Clippy: cargo clippy compiles the workspace's
/// crates through `clippy-driver` as `RUSTC_WORKSPACE_WRAPPER`, which Cargo passes on to
/// build scripts. Nothing is linked in that build.
fn linted_only() -> bool {
    println!("cargo::rerun-if-env-changed=RUSTC_WORKSPACE_WRAPPER");
    env::var_os("RUSTC_WORKSPACE_WRAPPER")
        .map(PathBuf::from)
        .is_some_and(|w| {
            w.file_stem()
                .is_some_and(|n| n.to_string_lossy().starts_with("clippy-driver"))
        })
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
