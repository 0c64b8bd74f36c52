//! `fpgfx animate`: a Rhai script moves a scene (or draws raster commands) frame by frame.
//!
//! The script works on the scene *file* (the TOML of docs/requirements.md §4.11 as a Rhai object map), not on
//! register words: it reads like the scene the user wrote, and every frame goes through
//! the same parser and validation as `fpgfx render`, so a script that breaks the scene
//! gets the parser's message with the frame number. The register diff of
//! [`crate::run::render::Renderer`] then sends only what changed between frames.
//!
//! A script defines one of
//! - `fn scene(s, frame, time)`: gets the base scene (the script's `const SCENE = "…"`,
//!   relative to the script, or `--scene`) and returns the frame's scene;
//! - `fn raster(frame, time)`: returns a raster job map (`size`, `background`, `cmd`: an
//!   array of command maps, as in a raster file).

use std::path::{Path, PathBuf};

use rhai::{Dynamic, Engine, Scope, AST};

/// What the script animates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `fn scene(s, frame, time)`.
    Scene,
    /// `fn raster(frame, time)`.
    Raster,
}

/// Errors of a script, with the file and what the script was doing.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnimateError {
    /// The file cannot be read.
    #[error("cannot read {path}")]
    Read {
        /// The script file, as given.
        path: String,
        /// The underlying error, reported as this one's `source()`.
        source: std::io::Error,
    },
    /// Syntax error; Rhai's message has line and position.
    #[error("{path}: {message}")]
    Compile {
        /// The script file, as given.
        path: String,
        /// Rhai's message.
        message: String,
    },
    /// The script defines neither entry point (or both).
    #[error(
        "{path}: define exactly one of `fn scene(s, frame, time)` or `fn raster(frame, time)`"
    )]
    NoEntry {
        /// The script file, as given.
        path: String,
    },
    /// A scene script without a base scene.
    #[error(
        "{path}: a scene script needs a base scene: `const SCENE = \"file.toml\";` or --scene"
    )]
    NoScene {
        /// The script file, as given.
        path: String,
    },
    /// The script failed while computing a frame.
    #[error("{path}: frame {frame}: {message}")]
    Run {
        /// The script file, as given.
        path: String,
        /// Frame the script was computing, counted from 0.
        frame: u32,
        /// Rhai's message (with line and position).
        message: String,
    },
    /// What the script returned is not a scene/job the tool can write as TOML.
    #[error(
        "{path}: frame {frame}: the script returned something that is not a {what}: {message}"
    )]
    Shape {
        /// The script file, as given.
        path: String,
        /// Frame the script was computing, counted from 0.
        frame: u32,
        /// "scene" or "raster job".
        what: &'static str,
        /// What the conversion said was wrong with the value (TOML or Rhai serde error).
        message: String,
    },
}

/// Why a GIF was not written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GifError {
    /// The file cannot be created.
    #[error("cannot create {}", .path.display())]
    Create {
        /// The GIF file.
        path: PathBuf,
        /// The underlying error, reported as this one's `source()`.
        source: std::io::Error,
    },
    /// Encoding or writing a frame failed.
    #[error("cannot write {}", .path.display())]
    Write {
        /// The GIF file.
        path: PathBuf,
        /// The underlying error, reported as this one's `source()`.
        source: image::ImageError,
    },
}

/// Writes `frames` as a GIF that loops forever, one frame every 1/`fps` s with `fps`
/// rounded to a whole number (the script's clock may run at any rate; the file's cannot).
pub fn write_gif(path: &Path, frames: &[image::RgbImage], fps: f64) -> Result<(), GifError> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let write = |source| GifError::Write {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(path).map_err(|source| GifError::Create {
        path: path.to_path_buf(),
        source,
    })?;
    let mut enc = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
    enc.set_repeat(Repeat::Infinite).map_err(write)?;
    let delay = image::Delay::from_numer_denom_ms(1000, (fps.round() as u32).max(1));
    for f in frames {
        let rgba = image::DynamicImage::ImageRgb8(f.clone()).into_rgba8();
        enc.encode_frame(image::Frame::from_parts(rgba, 0, 0, delay))
            .map_err(write)?;
    }
    Ok(())
}

/// A compiled animation script.
pub struct Script {
    engine: Engine,
    ast: AST,
    path: String,
    kind: Kind,
    /// The base scene the script names, resolved against its folder.
    pub scene_file: Option<PathBuf>,
    base: Option<Dynamic>,
}

/// Operations a script may spend per frame: enough for any honest animation, and a
/// runaway loop ends with an error instead of hanging the tool.
const MAX_OPERATIONS: u64 = 50_000_000;

impl Script {
    /// Reads and compiles `path`, and runs its top level once (constants).
    pub fn load(path: &Path) -> Result<Script, AnimateError> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| AnimateError::Read {
            path: name.clone(),
            source,
        })?;
        let mut engine = Engine::new();
        engine.set_max_operations(MAX_OPERATIONS);
        engine.set_max_call_levels(64);
        // A command list written as one nested literal (maps in arrays in maps) is deep.
        engine.set_max_expr_depths(256, 128);
        let ast = engine.compile(&text).map_err(|e| AnimateError::Compile {
            path: name.clone(),
            message: e.to_string(),
        })?;
        let has = |f: &str| ast.iter_functions().any(|m| m.name == f);
        let kind = match (has("scene"), has("raster")) {
            (true, false) => Kind::Scene,
            (false, true) => Kind::Raster,
            _ => return Err(AnimateError::NoEntry { path: name }),
        };
        let mut scope = Scope::new();
        engine
            .run_ast_with_scope(&mut scope, &ast)
            .map_err(|e| AnimateError::Run {
                path: name.clone(),
                frame: 0,
                message: e.to_string(),
            })?;
        let scene_file = scope
            .get_value::<rhai::ImmutableString>("SCENE")
            .map(|s| path.parent().unwrap_or(Path::new(".")).join(s.as_str()));
        Ok(Script {
            engine,
            ast,
            path: name,
            kind,
            scene_file,
            base: None,
        })
    }

    /// What the script animates.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// Sets the base scene from its TOML text (for [`Kind::Scene`]).
    pub fn set_base_scene(&mut self, toml_text: &str, file: &str) -> Result<(), AnimateError> {
        let value: toml::Value = toml::from_str(toml_text).map_err(|e| AnimateError::Shape {
            path: file.to_string(),
            frame: 0,
            what: "scene",
            message: e.to_string(),
        })?;
        let d = rhai::serde::to_dynamic(&value).map_err(|e| AnimateError::Shape {
            path: file.to_string(),
            frame: 0,
            what: "scene",
            message: e.to_string(),
        })?;
        self.base = Some(d);
        Ok(())
    }

    /// The TOML text of frame `frame` at `time` seconds: a scene file for
    /// [`Kind::Scene`], a raster command file for [`Kind::Raster`].
    pub fn frame(&self, frame: u32, time: f64) -> Result<String, AnimateError> {
        let run = |e: Box<rhai::EvalAltResult>| AnimateError::Run {
            path: self.path.clone(),
            frame,
            message: e.to_string(),
        };
        let mut scope = Scope::new();
        let (out, what): (Dynamic, &'static str) = match self.kind {
            Kind::Scene => {
                let base = self.base.clone().ok_or_else(|| AnimateError::NoScene {
                    path: self.path.clone(),
                })?;
                let out = self
                    .engine
                    .call_fn(
                        &mut scope,
                        &self.ast,
                        "scene",
                        (base, i64::from(frame), time),
                    )
                    .map_err(run)?;
                (out, "scene")
            }
            Kind::Raster => {
                let out = self
                    .engine
                    .call_fn(&mut scope, &self.ast, "raster", (i64::from(frame), time))
                    .map_err(run)?;
                (out, "raster job")
            }
        };
        let shape = |message: String| AnimateError::Shape {
            path: self.path.clone(),
            frame,
            what,
            message,
        };
        let value: toml::Value =
            rhai::serde::from_dynamic(&out).map_err(|e| shape(e.to_string()))?;
        if !value.is_table() {
            return Err(shape(format!("a {} instead of a map", out.type_name())));
        }
        toml::to_string(&value).map_err(|e| shape(e.to_string()))
    }
}

/// Where frames go: a GIF, or one PNG per frame from a pattern with `%0Nd` or `{}`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Output {
    /// An animated GIF at this path, all frames in one file.
    Gif(PathBuf),
    /// A PNG sequence: the pattern's placeholder becomes the frame number.
    Pngs(String),
}

impl Output {
    /// From `-o`: `.gif` is a GIF; a `.png` name must contain a frame-number placeholder.
    pub fn parse(o: &str) -> Result<Output, String> {
        let lower = o.to_ascii_lowercase();
        if lower.ends_with(".gif") {
            Ok(Output::Gif(PathBuf::from(o)))
        } else if lower.ends_with(".png") {
            if o.contains("{}") || percent_d(o).is_some() {
                Ok(Output::Pngs(o.to_string()))
            } else {
                Err(format!(
                    "-o {o}: a PNG sequence needs a frame-number placeholder, e.g. frame-%04d.png or frame-{{}}.png"
                ))
            }
        } else {
            Err(format!(
                "-o {o}: expected NAME.gif or a PNG pattern like frame-%04d.png"
            ))
        }
    }

    /// The PNG file of frame `n`.
    pub fn png_path(pattern: &str, n: u32) -> PathBuf {
        if let Some((start, end, width)) = percent_d(pattern) {
            PathBuf::from(format!(
                "{}{:0width$}{}",
                &pattern[..start],
                n,
                &pattern[end..]
            ))
        } else {
            PathBuf::from(pattern.replacen("{}", &n.to_string(), 1))
        }
    }
}

/// The `%0Nd` (or `%d`) in `s`: byte range and width.
fn percent_d(s: &str) -> Option<(usize, usize, usize)> {
    let start = s.find('%')?;
    let rest = &s[start + 1..];
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    if rest.as_bytes().get(digits) != Some(&b'd') {
        return None;
    }
    let width = rest[..digits].parse().unwrap_or(0);
    Some((start, start + 1 + digits + 1, width))
}

/// The user's camera moves in `--interactive`: an orbit about the scene's `look_at`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraMove {
    /// Turn about the world y axis, radians (← →).
    pub yaw: f64,
    /// Tilt up or down, radians (↑ ↓), kept away from the poles.
    pub pitch: f64,
    /// Distance factor (+ −).
    pub zoom: f64,
}

impl Default for CameraMove {
    fn default() -> Self {
        Self {
            yaw: 0.0,
            pitch: 0.0,
            zoom: 1.0,
        }
    }
}

impl CameraMove {
    /// Applies the move to the `[camera]` of a scene file: the eye orbits `look_at` by
    /// yaw and pitch and its distance scales by zoom (ViRAY's board buttons moved the
    /// observer the same way).
    pub fn apply(&self, scene_toml: &str) -> Result<String, String> {
        if *self == CameraMove::default() {
            return Ok(scene_toml.to_string());
        }
        let mut v: toml::Value = toml::from_str(scene_toml).map_err(|e| e.to_string())?;
        let cam = v
            .get_mut("camera")
            .and_then(toml::Value::as_table_mut)
            .ok_or("the scene has no [camera]")?;
        let vec3 = |t: &toml::Table, k: &str| -> Result<[f64; 3], String> {
            let a = t
                .get(k)
                .and_then(toml::Value::as_array)
                .filter(|a| a.len() == 3)
                .ok_or(format!("camera.{k} is not a 3-vector"))?;
            let f = |x: &toml::Value| {
                x.as_float()
                    .or_else(|| x.as_integer().map(|i| i as f64))
                    .ok_or(format!("camera.{k} has a non-number"))
            };
            Ok([f(&a[0])?, f(&a[1])?, f(&a[2])?])
        };
        let eye = vec3(cam, "position")?;
        let at = vec3(cam, "look_at")?;
        let d = [eye[0] - at[0], eye[1] - at[1], eye[2] - at[2]];
        let r = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if r == 0.0 {
            return Err("camera.position equals camera.look_at".into());
        }
        let yaw = d[0].atan2(d[2]) + self.yaw;
        let limit = 89f64.to_radians();
        let pitch = ((d[1] / r).asin() + self.pitch).clamp(-limit, limit);
        let r = r * self.zoom;
        let eye = [
            at[0] + r * pitch.cos() * yaw.sin(),
            at[1] + r * pitch.sin(),
            at[2] + r * pitch.cos() * yaw.cos(),
        ];
        cam.insert(
            "position".into(),
            toml::Value::Array(eye.iter().map(|&x| toml::Value::Float(x)).collect()),
        );
        toml::to_string(&v).map_err(|e| e.to_string())
    }
}
