//! The check every generated Verilog header shares: the committed file is what the Rust
//! map writes today, or, with `FPGFX_BLESS=1`, is rewritten from it.

/// Holds the header at `rel` (from the protocol crate's folder) to `text`, which `source`
/// (the Rust module that writes it) produced.
pub(crate) fn matches_committed(rel: &str, text: &str, source: &str) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(rel);
    if std::env::var_os("FPGFX_BLESS").is_some() {
        std::fs::write(&path, text).expect("writes the header");
    }
    let committed = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (FPGFX_BLESS=1 writes it)", path.display()));
    assert_eq!(
        committed,
        text,
        "{} differs from {source}; run with FPGFX_BLESS=1 to regenerate",
        path.display()
    );
}
