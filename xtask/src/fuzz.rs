//! `cargo xtask fuzz`: builds the cargo-fuzz targets of `fuzz/` with the pinned nightly
//! and runs each with libFuzzer on a scratch copy of its seeds, then prints what each run
//! did. `cargo xtask test` runs it with `--smoke`.
//!
//! ```text
//! cargo xtask fuzz [--target NAME]... [--runs N | --time SECONDS] [--smoke]
//! ```
//!
//! `--smoke`: every target for [`SMOKE_RUNS`] executions on a fresh copy of its seeds,
//! built with the dev profile (debug assertions, the fuzz crate's own opt-levels) under
//! ASan into `fuzz/target` apart from a campaign's release build, so the test command
//! pays for one cheap build. Without it: a campaign, release build (`cargo fuzz build`'s
//! default: optimised, debug assertions, ASan), each target for `--runs` executions or
//! `--time` seconds (default 60 s) on `fuzz/target/xtask/corpus/TARGET`, which keeps what
//! earlier campaigns found and gets the committed seeds copied in again each time.
//!
//! Every libFuzzer run gets `-rss_limit_mb=2048 -print_final_stats=1`, one rayon thread
//! (the renders are tiny; a second thread only competes with the other fuzzer) and an
//! artifact prefix `fuzz/artifacts/TARGET/`, where a crashing input is written. The whole
//! libFuzzer output of a run is kept in `fuzz/target/xtask/TARGET.log` (`smoke-TARGET.log`
//! for the smoke). The command fails
//! if any target crashed, leaked, timed out or ran out of memory.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

use anyhow::{bail, Context, Result};

/// Executions per target in `--smoke`: enough for every seed and a few thousand mutations.
pub const SMOKE_RUNS: u64 = 3000;

/// The cargo-fuzz release `setup` installs with the pinned nightly.
pub const CARGO_FUZZ_VERSION: &str = "0.13.2";

/// What `cargo xtask fuzz` was asked for.
#[derive(Debug, Default)]
pub struct Options {
    /// Only these targets (every target when empty).
    pub targets: Vec<String>,
    /// Executions per target.
    pub runs: Option<u64>,
    /// Seconds per target.
    pub time: Option<u64>,
    /// The test command's quick pass.
    pub smoke: bool,
}

impl Options {
    /// Parses the arguments after `fuzz`.
    pub fn parse(args: &[String]) -> Result<Self> {
        let mut o = Options::default();
        let mut it = args.iter();
        while let Some(a) = it.next() {
            let mut value = |name: &str| {
                it.next()
                    .with_context(|| format!("{name} needs a value"))
                    .cloned()
            };
            match a.as_str() {
                "--target" => o.targets.push(value("--target")?),
                "--runs" => {
                    o.runs = Some(value("--runs")?.parse().context("--runs takes a count")?)
                }
                "--time" => {
                    o.time = Some(value("--time")?.parse().context("--time takes seconds")?)
                }
                "--smoke" => o.smoke = true,
                other => bail!(
                    "unknown fuzz argument {other:?}: cargo xtask fuzz [--target NAME]... \
                     [--runs N | --time SECONDS] [--smoke]"
                ),
            }
        }
        if o.runs.is_some() && o.time.is_some() {
            bail!("give --runs or --time, not both");
        }
        Ok(o)
    }
}

/// `cargo +TOOLCHAIN ARGS` with the workspace's toolchain choice removed, so that the
/// pinned nightly is the one that runs.
fn cargo(toolchain: &str) -> Command {
    let mut c = Command::new("cargo");
    c.env_remove("RUSTUP_TOOLCHAIN")
        .env_remove("CARGO")
        .env_remove("RUSTC")
        .env_remove("RUSTDOC")
        .arg(format!("+{toolchain}"));
    c
}

/// Installs cargo-fuzz [`CARGO_FUZZ_VERSION`] with the pinned nightly unless that
/// version is there already; never removes anything.
pub fn install_cargo_fuzz(toolchain: &str) -> Result<()> {
    let out = cargo(toolchain).args(["fuzz", "--version"]).output();
    if let Ok(o) = &out {
        if o.status.success() && String::from_utf8_lossy(&o.stdout).contains(CARGO_FUZZ_VERSION) {
            return Ok(());
        }
    }
    eprintln!(
        "xtask setup: installing cargo-fuzz {CARGO_FUZZ_VERSION} with {toolchain} (cargo xtask fuzz and the test command's fuzz smoke build the fuzz/ targets with it)"
    );
    let status = cargo(toolchain)
        .args([
            "install",
            "cargo-fuzz",
            "--locked",
            "--version",
            CARGO_FUZZ_VERSION,
        ])
        .status()
        .context("could not start cargo install")?;
    if !status.success() {
        bail!("installing cargo-fuzz {CARGO_FUZZ_VERSION} failed with {status}");
    }
    Ok(())
}

/// The targets `fuzz/Cargo.toml` declares, in its order.
fn all_targets(fuzz: &Path) -> Result<Vec<String>> {
    let manifest = fuzz.join("Cargo.toml");
    let text = std::fs::read_to_string(&manifest)
        .with_context(|| format!("cannot read {}", manifest.display()))?;
    let mut names = Vec::new();
    let mut in_bin = false;
    for line in text.lines().map(str::trim) {
        if line.starts_with('[') {
            in_bin = line == "[[bin]]";
        } else if let Some(v) = line.strip_prefix("name") {
            if in_bin {
                let v = v
                    .trim_start()
                    .trim_start_matches('=')
                    .trim()
                    .trim_matches('"');
                names.push(v.to_string());
            }
        }
    }
    if names.is_empty() {
        bail!("{} declares no fuzz target", manifest.display());
    }
    Ok(names)
}

/// What one libFuzzer run did, read from its output.
#[derive(Debug, Default)]
struct Outcome {
    target: String,
    execs: u64,
    per_sec: u64,
    cov: u64,
    ft: u64,
    corpus: u64,
    seconds: f64,
    /// Inputs libFuzzer wrote for a crash, leak, timeout or OOM.
    crashes: Vec<String>,
    /// Inputs libFuzzer wrote as slow units (one run over 10 s of wall time): not a
    /// failure, and a fuzzer that was stopped or starved of CPU mid-input writes them too,
    /// so they are listed apart for a second look, not counted as crashes.
    slow: Vec<String>,
    /// libFuzzer's exit status was not success.
    failed: bool,
    /// libFuzzer was interrupted (SIGINT: "run interrupted", exit 72): the run ended
    /// early, which is no finding about the target.
    interrupted: bool,
}

/// The number after `key` in `line` (`cov: 123`, `stat::…: 45`).
fn number_after(line: &str, key: &str) -> Option<u64> {
    let rest = &line[line.find(key)? + key.len()..];
    let digits: String = rest
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    digits.parse().ok()
}

fn read_outcome(target: &str, log: &str) -> Outcome {
    let mut o = Outcome {
        target: target.to_string(),
        ..Outcome::default()
    };
    for line in log.lines() {
        if line.starts_with('#') {
            if let Some(v) = number_after(line, "cov:") {
                o.cov = v;
            }
            if let Some(v) = number_after(line, "ft:") {
                o.ft = v;
            }
            if let Some(v) = number_after(line, "corp:") {
                o.corpus = v;
            }
        }
        if line.contains("libFuzzer: run interrupted") {
            o.interrupted = true;
        }
        if let Some(v) = number_after(line, "stat::number_of_executed_units:") {
            o.execs = v;
        }
        if let Some(v) = number_after(line, "stat::average_exec_per_sec:") {
            o.per_sec = v;
        }
        if let Some(p) = line
            .split_once("Test unit written to ")
            .map(|(_, p)| p.trim().to_string())
        {
            let slow = Path::new(&p)
                .file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("slow-unit-"));
            if slow {
                o.slow.push(p);
            } else {
                o.crashes.push(p);
            }
        }
    }
    o
}

/// Runs `cargo xtask fuzz` with `opts` for the workspace at `root`.
pub fn run(root: &Path, toolchain: &str, opts: &Options) -> Result<()> {
    install_cargo_fuzz(toolchain)?;
    let fuzz = root.join("fuzz");
    let all = all_targets(&fuzz)?;
    let targets = if opts.targets.is_empty() {
        all.clone()
    } else {
        for t in &opts.targets {
            if !all.contains(t) {
                bail!("no fuzz target {t:?}; the targets are {}", all.join(", "));
            }
        }
        opts.targets.clone()
    };

    // One build of every asked-for target; the smoke's in the dev profile.
    let started = Instant::now();
    let mut build = cargo(toolchain);
    build.current_dir(&fuzz).args(["fuzz", "build"]);
    if opts.smoke {
        build.arg("--dev");
    }
    if opts.targets.len() == 1 {
        build.arg(&targets[0]);
    }
    eprintln!(
        "+ (cd fuzz && cargo +{toolchain} fuzz build{}{})",
        if opts.smoke { " --dev" } else { "" },
        if opts.targets.len() == 1 {
            format!(" {}", targets[0])
        } else {
            String::new()
        }
    );
    let status = build.status().context("could not start cargo fuzz build")?;
    if !status.success() {
        bail!("cargo fuzz build failed with {status}");
    }
    let build_time = started.elapsed().as_secs_f64();
    let profile = if opts.smoke { "debug" } else { "release" };
    let bin_dir = fuzz.join("target").join(host_triple()?).join(profile);

    let scratch = fuzz.join("target").join("xtask");
    let mut outcomes = Vec::new();
    for t in &targets {
        let corpus = if opts.smoke {
            scratch.join("smoke").join(t)
        } else {
            scratch.join("corpus").join(t)
        };
        if opts.smoke && corpus.exists() {
            std::fs::remove_dir_all(&corpus)
                .with_context(|| format!("cannot empty {}", corpus.display()))?;
        }
        std::fs::create_dir_all(&corpus)
            .with_context(|| format!("cannot make {}", corpus.display()))?;
        copy_seeds(&fuzz.join("corpus").join(t), &corpus)?;
        let artifacts = fuzz.join("artifacts").join(t);
        std::fs::create_dir_all(&artifacts)
            .with_context(|| format!("cannot make {}", artifacts.display()))?;
        let limit = match (opts.smoke, opts.runs, opts.time) {
            (true, None, None) => format!("-runs={SMOKE_RUNS}"),
            (_, Some(n), _) => format!("-runs={n}"),
            (_, None, Some(s)) => format!("-max_total_time={s}"),
            (false, None, None) => "-max_total_time=60".to_string(),
        };
        // Apart from a campaign's, which may be running beside the smoke.
        let log_path = if opts.smoke {
            scratch.join(format!("smoke-{t}.log"))
        } else {
            scratch.join(format!("{t}.log"))
        };
        let log = std::fs::File::create(&log_path)
            .with_context(|| format!("cannot write {}", log_path.display()))?;
        let args = [
            corpus.to_string_lossy().into_owned(),
            limit,
            "-rss_limit_mb=2048".into(),
            "-timeout=60".into(),
            "-print_final_stats=1".into(),
            format!("-artifact_prefix={}/", artifacts.display()),
        ];
        let exe = bin_dir.join(t);
        eprintln!(
            "+ {} {}  2> {}",
            exe.display(),
            args.join(" "),
            log_path.display()
        );
        let t0 = Instant::now();
        let status = Command::new(&exe)
            .args(&args)
            .env("RAYON_NUM_THREADS", "1")
            .stdout(Stdio::null())
            .stderr(log)
            .status()
            .with_context(|| format!("could not start {}", exe.display()))?;
        let text = std::fs::read_to_string(&log_path).unwrap_or_default();
        let mut o = read_outcome(t, &text);
        o.seconds = t0.elapsed().as_secs_f64();
        o.failed = !status.success() && !o.interrupted;
        if o.failed {
            // The end of the log says why and holds the input (libFuzzer's "Base64:"
            // line): printed, so a failure on a machine whose files are gone (CI) can
            // still be reproduced from its output.
            let tail: Vec<&str> = text.lines().rev().take(60).collect();
            eprintln!("fuzz: {t} failed; the end of {}:", log_path.display());
            for line in tail.iter().rev() {
                eprintln!("  {line}");
            }
        }
        if o.failed && o.crashes.is_empty() {
            o.crashes
                .push(format!("(exit {status}, see {})", log_path.display()));
        }
        outcomes.push(o);
    }

    println!(
        "\nfuzz ({}; build {:.0} s):",
        if opts.smoke { "smoke" } else { "campaign" },
        build_time
    );
    println!(
        "| target | executions | exec/s | cov | ft | corpus | seconds | crashes |\n|---|---:|---:|---:|---:|---:|---:|---|"
    );
    for o in &outcomes {
        println!(
            "| {} | {} | {} | {} | {} | {} | {:.0} | {} |",
            o.target,
            o.execs,
            o.per_sec,
            o.cov,
            o.ft,
            o.corpus,
            o.seconds,
            match (o.crashes.is_empty(), o.interrupted) {
                (true, false) => "0".to_string(),
                (true, true) =>
                    "0 (interrupted: the counts are up to the interruption)".to_string(),
                (false, _) => o.crashes.join(", "),
            }
        );
    }
    for o in outcomes.iter().filter(|o| !o.slow.is_empty()) {
        println!(
            "{}: slow units (not failures; time each with the target's binary and the file, as a stopped or starved fuzzer writes them too): {}",
            o.target,
            o.slow.join(", ")
        );
    }
    let bad: Vec<&str> = outcomes
        .iter()
        .filter(|o| o.failed)
        .map(|o| o.target.as_str())
        .collect();
    let stopped: Vec<&str> = outcomes
        .iter()
        .filter(|o| o.interrupted)
        .map(|o| o.target.as_str())
        .collect();
    if bad.is_empty() && !stopped.is_empty() {
        bail!("interrupted during {} (no crash)", stopped.join(", "));
    }
    if !bad.is_empty() {
        bail!(
            "fuzz targets crashed: {} (inputs in fuzz/artifacts/; minimise with `cargo +{toolchain} fuzz tmin TARGET FILE` in fuzz/)",
            bad.join(", ")
        );
    }
    Ok(())
}

/// Copies `from/seed-*` into `to` (the files libFuzzer found in earlier runs stay).
fn copy_seeds(from: &Path, to: &Path) -> Result<()> {
    let entries =
        std::fs::read_dir(from).with_context(|| format!("no seeds in {}", from.display()))?;
    for e in entries.flatten() {
        let name = e.file_name();
        if name.to_string_lossy().starts_with("seed-") {
            let dest: PathBuf = to.join(&name);
            std::fs::copy(e.path(), &dest)
                .with_context(|| format!("cannot copy {}", e.path().display()))?;
        }
    }
    Ok(())
}

/// The host's target triple: cargo-fuzz builds for it explicitly, so the binaries are
/// under `fuzz/target/<triple>/`.
fn host_triple() -> Result<String> {
    let out = Command::new("rustc")
        .arg("-vV")
        .output()
        .context("could not run rustc -vV")?;
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: "))
        .map(str::to_string)
        .context("rustc -vV names no host")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_libfuzzer_output() {
        let log = "INFO: Seed: 1\n#2\tINITED cov: 10 ft: 12 corp: 1/1b exec/s: 0 rss: 30Mb\n\
                   #3000\tDONE   cov: 1234 ft: 5678 corp: 90/1234b lim: 4 exec/s: 1500 rss: 60Mb\n\
                   ==1== ERROR: libFuzzer: deadly signal\n\
                   artifact_prefix='a/'; Test unit written to a/slow-unit-0a0a\n\
                   artifact_prefix='a/'; Test unit written to a/crash-00ff\n\
                   stat::number_of_executed_units: 3000\nstat::average_exec_per_sec:     1500\n";
        let o = read_outcome("t", log);
        assert_eq!(
            (o.execs, o.per_sec, o.cov, o.ft, o.corpus),
            (3000, 1500, 1234, 5678, 90)
        );
        assert_eq!(o.crashes, ["a/crash-00ff"]);
        assert_eq!(o.slow, ["a/slow-unit-0a0a"]);
        assert!(!o.interrupted);
        let o = read_outcome(
            "t",
            "==7== libFuzzer: run interrupted; exiting\nstat::number_of_executed_units: 42\n",
        );
        assert!(o.interrupted && o.crashes.is_empty());
        assert_eq!(o.execs, 42);
    }

    #[test]
    fn parses_arguments() {
        let a = |s: &str| s.split_whitespace().map(String::from).collect::<Vec<_>>();
        let o = Options::parse(&a("--target capi --target python --runs 10")).unwrap();
        assert_eq!((o.targets.len(), o.runs, o.smoke), (2, Some(10), false));
        assert!(Options::parse(&a("--runs 1 --time 2")).is_err());
        assert!(Options::parse(&a("--bogus")).is_err());
        assert!(Options::parse(&a("--smoke")).unwrap().smoke);
    }

    #[test]
    fn lists_the_fuzz_crate_targets() {
        let fuzz = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz");
        let t = all_targets(&fuzz).unwrap();
        assert!(t.contains(&"frame_decode".to_string()) && t.contains(&"capi".to_string()));
    }
}
