//! Frame files for `fpgfx compare`: PNG, PFM and `$readmemh` framebuffers, decoded into
//! the comparison kernel's [`Frame`] (I/O stays here, at the edge; the kernel reads no
//! files). The format is chosen by the file's extension, so a file that does not decode
//! as what its name says is reported as that, not guessed at.

use std::path::{Path, PathBuf};

use compare::memh::{self, MemhError};
use compare::Frame;
use sim_target::rt::PfmError;

/// The frame file formats, by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum FrameFormat {
    /// `.png`: 8-bit RGB (alpha dropped, 16-bit channels reduced to 8).
    Png,
    /// `.pfm`: float planes, one (`Pf`) or three (`PF`).
    Pfm,
    /// `.hex`, `.memh`, `.mem`: a framebuffer in `compare::memh` format (header `// fpgfx
    /// framebuffer WxH rgb332|rgb888`), as `fpgfx vectors` writes and `$writememh` dumps.
    Memh,
}

/// Extensions of a `$readmemh` framebuffer: `.hex` is what `fpgfx vectors` writes, the
/// others are the usual names for `$writememh` output.
const MEMH_EXTENSIONS: [&str; 3] = ["hex", "memh", "mem"];

impl FrameFormat {
    /// The format a path's extension names (case-insensitive), if any.
    pub fn of(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "png" => Some(FrameFormat::Png),
            "pfm" => Some(FrameFormat::Pfm),
            e if MEMH_EXTENSIONS.contains(&e) => Some(FrameFormat::Memh),
            _ => None,
        }
    }
}

/// A frame file that cannot be used, naming it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FrameFileError {
    /// The extension names no frame format.
    #[error("{}: unknown frame format (expected .png, .pfm, or a $readmemh framebuffer: .hex, .memh, .mem)", .path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file cannot be read.
    #[error("{}: cannot read", .path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// Not a decodable PNG.
    #[error("{}: not a readable PNG", .path.display())]
    Png {
        /// The file.
        path: PathBuf,
        /// The decoder's reason.
        #[source]
        source: image::ImageError,
    },
    /// Not a decodable PFM.
    #[error("{}: not a readable PFM", .path.display())]
    Pfm {
        /// The file.
        path: PathBuf,
        /// The reader's reason.
        #[source]
        source: PfmError,
    },
    /// Not a `$readmemh` framebuffer (no header, bad words, wrong length, …).
    #[error("{}: not a $readmemh framebuffer", .path.display())]
    Memh {
        /// The file.
        path: PathBuf,
        /// The parser's reason, with the line.
        #[source]
        source: MemhError,
    },
}

/// Reads a frame file in the format its extension names. RGB332 framebuffers are
/// expanded to 8 bits by [`memh::PixelFormat::to_rgb8`], so they compare with PNGs of the
/// same frame.
pub fn read(path: &Path) -> Result<Frame, FrameFileError> {
    let format = FrameFormat::of(path).ok_or_else(|| FrameFileError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let bytes = std::fs::read(path).map_err(|source| FrameFileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    decode(&bytes, format).map_err(|e| e.at(path))
}

/// What went wrong decoding, before the path is attached.
enum Decode {
    Png(image::ImageError),
    Pfm(PfmError),
    Memh(MemhError),
    Text(std::io::Error),
}

impl Decode {
    fn at(self, path: &Path) -> FrameFileError {
        let path = path.to_path_buf();
        match self {
            Decode::Png(source) => FrameFileError::Png { path, source },
            Decode::Pfm(source) => FrameFileError::Pfm { path, source },
            Decode::Memh(source) => FrameFileError::Memh { path, source },
            Decode::Text(source) => FrameFileError::Read { path, source },
        }
    }
}

fn decode(bytes: &[u8], format: FrameFormat) -> Result<Frame, Decode> {
    Ok(match format {
        FrameFormat::Png => {
            let img = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
                .map_err(Decode::Png)?
                .to_rgb8();
            Frame::rgb8(img.width(), img.height(), img.into_raw())
        }
        FrameFormat::Pfm => {
            let p = sim_target::rt::read_pfm(bytes).map_err(Decode::Pfm)?;
            // A PFM holds 1 or 3 planes, both within the kernel's limit.
            Frame::float(p.width, p.height, p.channels as u8, p.data)
        }
        FrameFormat::Memh => {
            let text = std::str::from_utf8(bytes).map_err(|e| {
                Decode::Text(std::io::Error::new(std::io::ErrorKind::InvalidData, e))
            })?;
            let (header, words) = memh::parse_frame(text).map_err(Decode::Memh)?;
            let rgb = words
                .iter()
                .flat_map(|&w| header.format.to_rgb8(w))
                .collect();
            Frame::rgb8(header.width, header.height, rgb)
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_by_extension() {
        assert_eq!(
            FrameFormat::of(Path::new("a/b.PNG")),
            Some(FrameFormat::Png)
        );
        assert_eq!(FrameFormat::of(Path::new("d.pfm")), Some(FrameFormat::Pfm));
        assert_eq!(
            FrameFormat::of(Path::new("expected_framebuffer.hex")),
            Some(FrameFormat::Memh)
        );
        assert_eq!(FrameFormat::of(Path::new("x.bmp")), None);
        assert_eq!(FrameFormat::of(Path::new("noext")), None);
    }

    #[test]
    fn rgb332_framebuffers_expand_to_rgb8() {
        let text = "// fpgfx framebuffer 2x1 rgb332\ne0\n03\n";
        let Ok(f) = decode(text.as_bytes(), FrameFormat::Memh) else {
            panic!("decodes")
        };
        assert_eq!(f, Frame::rgb8(2, 1, vec![255, 0, 0, 0, 0, 255]));
    }
}
