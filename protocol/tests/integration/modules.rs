//! protocol's modules form no circle: reading the sources, every `crate::<module>` a
//! module's code names leads to a module that never names it back, directly or through
//! others. The order below is the one docs/architecture.md draws (leaves first).

use std::collections::BTreeMap;
use std::path::Path;

/// Every top-level module, leaves first: a module may name only those before it.
const ORDER: [&str; 12] = [
    "bytes",
    "names",
    "raster",
    "fitkit_spi",
    "bus",
    "frame",
    "link",
    "scene",
    "fpga_link",
    "axi_lite",
    "bootloader",
    "msp430_bsl",
];

/// The top-level modules a file's code (not its comments) names as `crate::<module>`.
fn named_modules(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        let mut rest = code;
        while let Some(i) = rest.find("crate::") {
            rest = &rest[i + "crate::".len()..];
            let name: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if ORDER.contains(&name.as_str()) && !out.contains(&name) {
                out.push(name);
            }
        }
    }
    out
}

#[test]
fn every_module_names_only_modules_below_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut uses: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for entry in walk(&src) {
        let rel = entry.strip_prefix(&src).expect("under src");
        let top = rel
            .components()
            .next()
            .and_then(|c| c.as_os_str().to_str())
            .map(|s| s.trim_end_matches(".rs").to_string())
            .expect("a file name");
        if top == "lib" {
            continue;
        }
        let text = std::fs::read_to_string(&entry).expect("readable source");
        uses.entry(top).or_default().extend(named_modules(&text));
    }
    let rank = |m: &str| ORDER.iter().position(|o| *o == m);
    for (module, named) in &uses {
        let me = rank(module).unwrap_or_else(|| panic!("module `{module}` is not in ORDER"));
        for n in named {
            if n == module {
                continue;
            }
            let them = rank(n).expect("filtered to ORDER");
            assert!(
                them < me,
                "protocol::{module} names crate::{n}, which is not below it: a circle in the making"
            );
        }
    }
    assert_eq!(
        uses.len(),
        ORDER.len(),
        "a module of ORDER has no file: {uses:?}"
    );
}

#[test]
fn a_circle_is_caught() {
    // The check reads code, not comments, and finds both `use` and inline paths.
    let named =
        named_modules("use crate::frame::Caps; // crate::link\nlet x = crate::bus::FITKIT;");
    assert_eq!(named, ["frame", "bus"]);
}

fn walk(dir: &Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).expect("src is a folder") {
        let p = e.expect("entry").path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}
