//! Test vectors for a hardware design, written from the golden model, so that an RTL (this
//! repository's or a user's) can be held to the model in its own simulator without Rust
//! in the loop: what `fpgfx vectors` writes, and what the C library's and the RTL's tests
//! read. docs/vectors.md describes every file.
//!
//! The FITkit raster block's self-checking Verilog testbench and its run scripts are
//! templates kept with the block's hardware (`hw/fitkit-raster/vectors/`) and compiled
//! into this crate.
//!
//! A vector set is a directory of files: `$readmemh` data ([`compare::memh`]), for the
//! ray tracer the same data as raw little-endian bytes, a manifest, and for the FITkit a
//! copy of the job and a self-checking Verilog testbench with its run scripts. Generation
//! is pure ([`raster::raster`] and [`render::render`] return a [`VectorSet`]); only
//! [`VectorSet::write_to`] touches the disk, so tests and other front ends can inspect the
//! files before (or instead of) writing them.

#![warn(missing_docs)]

pub mod raster;
pub mod render;

use std::path::{Path, PathBuf};

use serde::Serialize;

/// Why a vector set could not be made or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VectorsError {
    /// The job file does not parse.
    #[error(transparent)]
    Job(#[from] jobs::raster::RasterFileError),
    /// A command the layout cannot carry, named by its index.
    #[error(transparent)]
    Layout(#[from] jobs::raster::LayoutError),
    /// The scene does not fit the ray tracer's register image.
    #[error("the scene does not fit the ray tracer's registers")]
    Registers(#[from] sim_target::scene_regs::SceneRegsError),
    /// The emulated device refused the scene's registers or its frame.
    #[error("the golden model refused the frame")]
    Device(#[from] sim_target::DeviceError),
    /// A frame side the read-back cannot address (sides are 16-bit on the wire).
    #[error("frame size {0}x{1} is larger than a read-back can address")]
    Size(u32, u32),
    /// The device rendered the frame but has no such plane: a bug in the model.
    #[error("the golden model has no {0} plane for this frame")]
    Plane(&'static str),
    /// The device took the start but reported no finished frame: a bug in the model.
    #[error("the golden model rendered the frame but reported no end of frame")]
    NoFrameDone,
    /// The manifest could not be written as TOML.
    #[error("the manifest does not serialise as TOML")]
    Manifest(#[from] toml::ser::Error),
    /// The controller's driver refuses the job on this layout (anti-aliasing, sub-pixel
    /// coordinates or a background outside RGB332 on the FITkit).
    #[error("{file}: the FITkit controller refuses the job: {message}")]
    Controller {
        /// The job file as named.
        file: String,
        /// The controller's reason.
        message: String,
    },
    /// The golden model refused a packet the packer accepted: a bug in one of them,
    /// reported rather than written as vectors that would blame the RTL.
    #[error("{file}: the golden model refused the job: {message}")]
    Model {
        /// The job file as named.
        file: String,
        /// The model's complaint.
        message: String,
    },
    /// The output directory or a file in it could not be written.
    #[error("cannot write {}", path.display())]
    Write {
        /// The directory or file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
}

/// One file of a vector set.
#[derive(Debug, Clone)]
pub struct VectorFile {
    /// File name inside the set's directory.
    pub name: &'static str,
    /// The whole file: text for `$readmemh` data, scripts and manifests, little-endian
    /// words for the raw `.bin` copies.
    pub bytes: Vec<u8>,
    /// Whether the file is a script (written executable).
    pub executable: bool,
    /// What the manifest lists for it: data files have a word count and width.
    pub entry: Option<FileEntry>,
}

/// A data file as the manifest lists it: enough for a reader to size its memories
/// without parsing the file.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct FileEntry {
    /// File name inside the set's directory.
    pub name: &'static str,
    /// Words (lines that are not comments).
    pub words: usize,
    /// Bits per word (hex digits × 4).
    pub word_bits: u32,
    /// One line on what a word is (docs/vectors.md has the full format).
    pub content: &'static str,
}

/// A whole vector set, ready to write.
#[derive(Debug, Clone)]
pub struct VectorSet {
    /// Every file, the manifest included, in the order they are written.
    pub files: Vec<VectorFile>,
}

impl VectorFile {
    /// The file as text: empty for a binary file that is not UTF-8, which only the raw
    /// `.bin` copies are (and nobody reads those as text).
    pub fn text(&self) -> &str {
        std::str::from_utf8(&self.bytes).unwrap_or_default()
    }
}

impl VectorSet {
    /// The file called `name`, if the set has one.
    pub fn file(&self, name: &str) -> Option<&VectorFile> {
        self.files.iter().find(|f| f.name == name)
    }

    /// Writes every file into `dir`, creating it (and its parents) if needed. Existing
    /// files of the same names are replaced; others are left alone.
    pub fn write_to(&self, dir: &Path) -> Result<(), VectorsError> {
        let err = |path: &Path| {
            let path = path.to_path_buf();
            move |source| VectorsError::Write { path, source }
        };
        std::fs::create_dir_all(dir).map_err(err(dir))?;
        for f in &self.files {
            let path = dir.join(f.name);
            std::fs::write(&path, &f.bytes).map_err(err(&path))?;
            if f.executable {
                make_executable(&path).map_err(err(&path))?;
            }
        }
        Ok(())
    }
}

#[cfg(unix)]
fn make_executable(path: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
}

#[cfg(not(unix))]
fn make_executable(_path: &Path) -> std::io::Result<()> {
    Ok(())
}

/// The job's identity in a manifest: FNV-1a, 64 bits, over the job file's bytes exactly
/// as read, written `fnv1a64:` and 16 hex digits. Not cryptographic; it only has to tell
/// a reader that vectors and a job file belong together, with no dependency, and stay the
/// same across fpgfx versions and machines.
pub fn job_hash(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("fnv1a64:{h:016x}")
}

/// Replaces every `@NAME@` of `template` by its value, so the testbench and scripts live
/// in the repository as plain files and get the sizes of one vector set. An unknown or
/// unfilled placeholder is a bug in fpgfx, caught by the tests that build the templates.
fn fill(template: &str, values: &[(&str, String)]) -> String {
    let mut out = template.to_string();
    for (name, value) in values {
        out = out.replace(&format!("@{name}@"), value);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn job_hash_is_fnv1a64() {
        // The reference values of FNV-1a 64.
        assert_eq!(job_hash(b""), "fnv1a64:cbf29ce484222325");
        assert_eq!(job_hash(b"a"), "fnv1a64:af63dc4c8601ec8c");
    }

    #[test]
    fn fill_replaces_every_placeholder() {
        assert_eq!(
            fill("@A@ x @B@ @A@", &[("A", "1".into()), ("B", "2".into())]),
            "1 x 2 1"
        );
    }
}
