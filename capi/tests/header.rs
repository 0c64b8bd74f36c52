//! The committed header (`include/fpgfx.h`) must be what cbindgen generates from the
//! sources: committed so that a C user reads and includes it without building anything,
//! checked here so that it never drifts from the library it declares.
//!
//! After changing the C API: `FPGFX_BLESS=1 cargo test -p fpgfx-capi --test header`
//! rewrites it; commit the result.

use std::path::Path;

#[test]
fn committed_header_is_what_cbindgen_generates() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml"))
        .unwrap_or_else(|e| panic!("capi/cbindgen.toml: {e}"));
    let bindings = cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .unwrap_or_else(|e| panic!("cbindgen cannot generate the header: {e}"));
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = dir.join("include/fpgfx.h");
    if std::env::var_os("FPGFX_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        return;
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "capi/include/fpgfx.h differs from what cbindgen generates from capi/src: \
         run `FPGFX_BLESS=1 cargo test -p fpgfx-capi --test header` and commit it"
    );
}
