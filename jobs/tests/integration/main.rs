//! jobs' integration tests: the two file parsers against the examples, hostile text and
//! what fuzzing found. One binary, so the dependency stack is linked once.

mod hostile_text;

mod raster_file_props;
mod scene_file;
mod scene_file_fuzz;
mod scene_file_props;

use std::path::PathBuf;

/// The repository's root (the examples live there).
pub fn workspace() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The raster example files, sorted.
pub fn raster_gallery() -> Vec<PathBuf> {
    let dir = workspace().join("examples/raster");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 3, "gallery files missing: {files:?}");
    files
}
