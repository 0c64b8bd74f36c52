//! The crate graph's rule, checked: every dependency of a crate points to a crate on a
//! lower layer, so a reader can follow any data path downwards and no crate climbs into
//! the tool above it. docs/architecture.md draws the same layers.
//!
//! A dev-dependency may point up (a model's tests read scene files through `jobs`), but
//! never into the two crates that only assemble others: the tool (`host-cli`) and the
//! emulated board (`sim-board`). Normal and build dependencies always point down.

use std::collections::BTreeMap;
use std::process::Command;

use anyhow::{bail, Context, Result};
use serde_json::Value;

/// The workspace's crates by layer, lowest first. A crate may depend only on crates of a
/// lower layer. A new crate must be placed here (the check refuses an unknown one).
pub const LAYERS: &[&[&str]] = &[
    // The build recipe of the Verilated bridges.
    &["verilate"],
    // Wire formats, no dependency of ours; the Verilated RTL blocks.
    &["protocol", "fitkit-rtl-sim", "rt-core-rtl-sim"],
    // The controller; frame comparison.
    &["firmware", "compare"],
    // The FPGA's golden model.
    &["sim-target"],
    // What the user writes, and what the host makes of it.
    &["jobs"],
    // Test vectors; the C library.
    &["vectors", "fpgfx-capi"],
    // The emulated board; the Python package (the model for cocotb scoreboards).
    &["sim-board", "fpgfx-python"],
    // The tool.
    &["host-cli"],
    // Automation: depends on nothing of ours.
    &["xtask"],
];

/// Crates no other crate may depend on, not even for tests.
const TOP: &[&str] = &["host-cli", "sim-board"];

/// One arrow of the graph that breaks the rule, in words.
fn violations(edges: &[(String, String, String)]) -> Result<Vec<String>> {
    let layer: BTreeMap<&str, usize> = LAYERS
        .iter()
        .enumerate()
        .flat_map(|(i, names)| names.iter().map(move |n| (*n, i)))
        .collect();
    let find = |name: &str| {
        layer.get(name).copied().with_context(|| {
            format!("crate `{name}` is in no layer of xtask/src/layers.rs: place it")
        })
    };
    let mut bad = Vec::new();
    for (from, to, kind) in edges {
        let (a, b) = (find(from)?, find(to)?);
        if kind == "dev" {
            if TOP.contains(&to.as_str()) {
                bad.push(format!("{from} → {to} (dev): nothing may depend on {to}"));
            }
        } else if b >= a {
            bad.push(format!(
                "{from} (layer {a}) → {to} (layer {b}){}: a dependency must point down",
                if kind == "build" { " (build)" } else { "" }
            ));
        }
    }
    Ok(bad)
}

/// The workspace's arrows between its own crates: (from, to, kind) with kind `normal`,
/// `dev` or `build`, from `cargo metadata`.
fn edges(metadata: &Value) -> Result<Vec<(String, String, String)>> {
    let packages = metadata["packages"]
        .as_array()
        .context("cargo metadata has no packages")?;
    let ours: Vec<&str> = packages.iter().filter_map(|p| p["name"].as_str()).collect();
    let mut out = Vec::new();
    for p in packages {
        let from = p["name"].as_str().unwrap_or_default();
        for d in p["dependencies"].as_array().into_iter().flatten() {
            let to = d["name"].as_str().unwrap_or_default();
            if ours.contains(&to) && d["path"].is_string() {
                let kind = d["kind"].as_str().unwrap_or("normal").to_string();
                out.push((from.to_string(), to.to_string(), kind));
            }
        }
    }
    Ok(out)
}

/// Checks the workspace's dependencies against [`LAYERS`].
pub fn check(cargo: &str) -> Result<()> {
    let out = Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .output()
        .context("could not run `cargo metadata`")?;
    if !out.status.success() {
        bail!(
            "`cargo metadata` failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let metadata: Value =
        serde_json::from_slice(&out.stdout).context("`cargo metadata` printed no JSON")?;
    let edges = edges(&metadata)?;
    let bad = violations(&edges)?;
    if !bad.is_empty() {
        bail!(
            "the crate graph breaks its layers (xtask/src/layers.rs, docs/architecture.md):\n  {}",
            bad.join("\n  ")
        );
    }
    eprintln!(
        "layers: {} arrows between {} crates, all pointing down",
        edges.len(),
        LAYERS.iter().map(|l| l.len()).sum::<usize>()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn edge(a: &str, b: &str, kind: &str) -> (String, String, String) {
        (a.into(), b.into(), kind.into())
    }

    #[test]
    fn arrows_down_pass_and_arrows_up_fail() {
        assert!(violations(&[edge("host-cli", "jobs", "normal")])
            .unwrap()
            .is_empty());
        assert!(violations(&[edge("sim-target", "jobs", "dev")])
            .unwrap()
            .is_empty());
        let up = violations(&[edge("sim-target", "jobs", "normal")]).unwrap();
        assert_eq!(up.len(), 1, "{up:?}");
        let same = violations(&[edge("vectors", "fpgfx-capi", "normal")]).unwrap();
        assert_eq!(same.len(), 1, "{same:?}");
        let into_tool = violations(&[edge("fitkit-rtl-sim", "host-cli", "dev")]).unwrap();
        assert_eq!(into_tool.len(), 1, "{into_tool:?}");
        assert!(violations(&[edge("newcrate", "protocol", "normal")]).is_err());
    }
}
