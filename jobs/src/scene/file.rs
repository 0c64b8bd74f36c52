//! The scene file (TOML) of docs/requirements.md §4.11: the contract shared by the CLI, the tests and other
//! tools. Unknown keys are errors (`deny_unknown_fields`) so that a typo never silently
//! renders a different scene; every error names the file, the line and the key.

use serde::Deserialize;
use sim_target::rt::{
    Camera, DiffuseModel, Filter, Light, Mapping, Material, Object, Reflection, Scene, Shape,
    Specular, SpecularModel, Spot, Term, Texture, TextureKind,
};
use std::collections::BTreeMap;
use toml::Spanned;

/// Capabilities a scene is checked against (the seed's OBJ_NUM and LIGHTS_NUM).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Most objects a scene may have (the register map's OBJ_NUM slots).
    pub max_objects: usize,
    /// Maximum lights, the ambient light included.
    pub max_lights: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_objects: 8,
            max_lights: 2,
        }
    }
}

/// A scene-file error, located.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: `{key}`: {message}")]
pub struct SceneFileError {
    /// File name as given to [`parse`].
    pub file: String,
    /// Line of the key in the file, counted from 1 as editors do.
    pub line: usize,
    /// Offending key (or the nearest one).
    pub key: String,
    /// What is wrong.
    pub message: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    render: Option<RenderToml>,
    camera: CameraToml,
    ambient: Option<AmbientToml>,
    #[serde(default)]
    light: Vec<Spanned<LightToml>>,
    #[serde(default)]
    // Not `Spanned`: toml cannot span a table that only exists implicitly (a material
    // written as `[material.clay.diffuse]` headers), and refuses the file instead.
    material: BTreeMap<String, MaterialToml>,
    #[serde(default)]
    object: Vec<Spanned<ObjectToml>>,
}

fn d_size() -> Spanned<[u32; 2]> {
    Spanned::new(0..0, [640, 480])
}
fn d_depth() -> u32 {
    2
}
fn d_bias() -> f64 {
    0.001
}
fn d_maxd() -> f64 {
    1e6
}
fn d_spp() -> Spanned<u32> {
    Spanned::new(0..0, 1)
}
fn d_one() -> f64 {
    1.0
}
fn d_white() -> [f64; 3] {
    [1.0; 3]
}
fn d_scale3() -> Spanned<[f64; 3]> {
    Spanned::new(0..0, [1.0; 3])
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RenderToml {
    #[serde(default = "d_size")]
    size: Spanned<[u32; 2]>,
    #[serde(default = "d_depth")]
    depth: u32,
    #[serde(default = "d_bias")]
    bias: f64,
    #[serde(default = "d_maxd")]
    max_distance: f64,
    #[serde(default)]
    background: [f64; 3],
    #[serde(default = "d_spp")]
    spp: Spanned<u32>,
    #[serde(default = "d_shadows")]
    shadows: bool,
}

fn d_shadows() -> bool {
    true
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraToml {
    position: [f64; 3],
    look_at: [f64; 3],
    up: [f64; 3],
    fov_y: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AmbientToml {
    color: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightToml {
    position: [f64; 3],
    color: [f64; 3],
    direction: Option<[f64; 3]>,
    cos_outer: Option<f64>,
    cos_inner: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TermToml {
    #[serde(default = "d_one")]
    k: f64,
    #[serde(default = "d_white")]
    color: [f64; 3],
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum DiffuseModelToml {
    Lambert,
    OrenNayar,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DiffuseToml {
    #[serde(default = "d_one")]
    k: f64,
    #[serde(default = "d_white")]
    color: [f64; 3],
    model: Option<DiffuseModelToml>,
    sigma2: Option<f64>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum SpecModelToml {
    BlinnPhong,
    TorranceSparrow,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecularToml {
    #[serde(default = "d_one")]
    k: f64,
    #[serde(default = "d_white")]
    color: [f64; 3],
    model: Option<SpecModelToml>,
    exponent: Option<Spanned<u32>>,
    eta: Option<f64>,
    extinction: Option<f64>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "kebab-case")]
enum ReflModeToml {
    None,
    Constant,
    Fresnel,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ReflectionToml {
    mode: ReflModeToml,
    r: Option<f64>,
    eta: Option<f64>,
    k: Option<f64>,
    transmit: Option<bool>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum TexKindToml {
    Xor,
    Checkerboard,
    RgbDots,
    Marble,
    Wood,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum MappingToml {
    Planar,
    Cylindrical,
    Spherical,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum FilterToml {
    Nearest,
    Bilinear,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TextureToml {
    kind: TexKindToml,
    mapping: Option<MappingToml>,
    scale: Option<[f64; 2]>,
    offset: Option<[f64; 2]>,
    color2: Option<[f64; 3]>,
    filter: Option<FilterToml>,
    cell: Option<u32>,
    seed: Option<u32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct MaterialToml {
    ambient: Option<TermToml>,
    diffuse: DiffuseToml,
    specular: Option<SpecularToml>,
    reflection: Option<ReflectionToml>,
    texture: Option<TextureToml>,
}

#[derive(Deserialize, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum ShapeToml {
    Sphere,
    Plane,
    Disk,
    Square,
    Cylinder,
    Cone,
    Cube,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectToml {
    shape: ShapeToml,
    #[serde(default)]
    translate: [f64; 3],
    #[serde(default = "d_scale3")]
    scale: Spanned<[f64; 3]>,
    #[serde(default)]
    rotate: [f64; 3],
    material: Spanned<String>,
}

fn line_of(text: &str, pos: usize) -> usize {
    let pos = pos.min(text.len());
    text.as_bytes()[..pos]
        .iter()
        .filter(|b| **b == b'\n')
        .count()
        + 1
}

/// The key an error is about. Why the source before the message: toml's message quotes
/// the offending token between backticks, which is the key for an unknown field but the
/// *value* for an unknown variant (and empty or cut short when the value itself holds a
/// backtick: found by fuzzing). Where the error's span points at a value, the key is the
/// token before that line's `=`.
fn key_from_message(msg: &str, text: &str, span: Option<core::ops::Range<usize>>) -> String {
    let key_like = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
    if let Some(r) = span.clone() {
        let line_start = text
            .get(..r.start)
            .map_or(0, |t| t.rfind('\n').map_or(0, |i| i + 1));
        if let Some(prefix) = text.get(line_start..r.start) {
            if let Some(eq) = prefix.rfind('=') {
                let before = prefix[..eq].trim_end();
                let start = before
                    .char_indices()
                    .rev()
                    .take_while(|(_, c)| key_like(*c))
                    .last()
                    .map_or(before.len(), |(i, _)| i);
                if start < before.len() {
                    return before[start..].to_string();
                }
            }
        }
    }
    if let Some(start) = msg.find('`') {
        if let Some(len) = msg[start + 1..].find('`') {
            let k = &msg[start + 1..start + 1 + len];
            if !k.is_empty() && k.chars().all(key_like) {
                return k.to_string();
            }
        }
    }
    if let Some(r) = span {
        if let Some(s) = text.get(r) {
            let k: String = s.chars().take_while(|c| key_like(*c)).collect();
            if !k.is_empty() {
                return k;
            }
        }
    }
    String::from("?")
}

/// Every number of a scene must be finite: TOML spells `nan` and `inf`, and an
/// overflowing literal such as `1e999` reads as ∞; any of them would reach the kernel as
/// a NaN position, colour or distance and poison every pixel it touches. The whole
/// document is walked once (not field by field, so that a field added later is covered);
/// the error names the key path and the line of the first such literal.
fn check_finite(text: &str, file_name: &str) -> Result<(), SceneFileError> {
    fn walk(v: &toml::Value, path: &mut String) -> bool {
        match v {
            toml::Value::Float(f) => !f.is_finite(),
            toml::Value::Array(a) => a.iter().enumerate().any(|(i, x)| {
                let n = path.len();
                path.push_str(&format!("[{i}]"));
                let bad = walk(x, path);
                if !bad {
                    path.truncate(n);
                }
                bad
            }),
            toml::Value::Table(t) => t.iter().any(|(k, x)| {
                let n = path.len();
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
                let bad = walk(x, path);
                if !bad {
                    path.truncate(n);
                }
                bad
            }),
            _ => false,
        }
    }
    let Ok(doc) = text.parse::<toml::Table>() else {
        return Ok(());
    };
    let mut path = String::new();
    if !walk(&toml::Value::Table(doc), &mut path) {
        return Ok(());
    }
    // The line: the first one holding a non-finite literal, preferring one that names the
    // key's last component.
    let last: String = path
        .rsplit('.')
        .next()
        .unwrap_or("")
        .split('[')
        .next()
        .unwrap_or("")
        .to_string();
    let non_finite = |line: &str| {
        let code = line.split('#').next().unwrap_or("");
        code.split(|c: char| !(c.is_ascii_alphanumeric() || "+-._".contains(c)))
            .any(|tok| {
                let t = tok.trim_start_matches(['+', '-']);
                t == "nan"
                    || t == "inf"
                    || (t.starts_with(|c: char| c.is_ascii_digit())
                        && t.replace('_', "")
                            .parse::<f64>()
                            .is_ok_and(|f| f.is_infinite()))
            })
    };
    let mut line = None;
    for (i, l) in text.lines().enumerate() {
        if non_finite(l) {
            if l.contains(last.as_str()) {
                line = Some(i + 1);
                break;
            }
            line.get_or_insert(i + 1);
        }
    }
    Err(SceneFileError {
        file: file_name.to_string(),
        line: line.unwrap_or(1),
        key: path,
        message: "not a finite number (NaN and infinity are not allowed)".into(),
    })
}

/// Parse a scene file with the seed's default limits.
pub fn parse(text: &str, file_name: &str) -> Result<Scene, SceneFileError> {
    parse_with_limits(text, file_name, Limits::default())
}

/// Parse a scene file against a target's limits.
pub fn parse_with_limits(
    text: &str,
    file_name: &str,
    limits: Limits,
) -> Result<Scene, SceneFileError> {
    let err = |pos: usize, key: &str, message: String| SceneFileError {
        file: file_name.to_string(),
        line: line_of(text, pos),
        key: key.to_string(),
        message,
    };
    let f: FileToml = toml::from_str(text).map_err(|e| {
        let span = e.span();
        // toml gives some errors (a control character such as NUL in a comment, found by
        // the scene_file fuzz target) an empty message; the error must still say something.
        let msg = match e.message().trim() {
            "" => "invalid TOML (a control character or malformed text here)".to_string(),
            m => m.to_string(),
        };
        SceneFileError {
            file: file_name.to_string(),
            line: span.clone().map(|r| line_of(text, r.start)).unwrap_or(1),
            key: key_from_message(&msg, text, span),
            message: msg,
        }
    })?;
    check_finite(text, file_name)?;

    let r = f.render.unwrap_or(RenderToml {
        size: d_size(),
        depth: d_depth(),
        bias: d_bias(),
        max_distance: d_maxd(),
        background: [0.0; 3],
        spp: d_spp(),
        shadows: true,
    });
    let [width, height] = *r.size.get_ref();
    if width == 0 || height == 0 {
        return Err(err(
            r.size.span().start,
            "size",
            "frame size must be positive".into(),
        ));
    }
    if r.depth == 0 {
        return Err(err(0, "depth", "depth must be at least 1".into()));
    }
    if *r.spp.get_ref() == 0 {
        return Err(err(
            r.spp.span().start,
            "spp",
            "spp must be at least 1".into(),
        ));
    }
    let fov = *f.camera.fov_y.get_ref();
    if !(fov > 0.0 && fov < 180.0) {
        return Err(err(
            f.camera.fov_y.span().start,
            "fov_y",
            "must be in (0, 180) degrees".into(),
        ));
    }

    // lights: the ambient light is light 0
    let total_lights = 1 + f.light.len();
    if total_lights > limits.max_lights {
        let pos = f
            .light
            .get(limits.max_lights.saturating_sub(1))
            .map(|l| l.span().start)
            .unwrap_or(0);
        return Err(err(
            pos,
            "light",
            format!(
                "{total_lights} lights (ambient included), the target has {}",
                limits.max_lights
            ),
        ));
    }
    let mut lights = Vec::new();
    for l in &f.light {
        let pos = l.span().start;
        let l = l.get_ref();
        let spot = match (l.direction, l.cos_outer, l.cos_inner) {
            (None, None, None) => None,
            (Some(direction), Some(cos_outer), cos_inner) => {
                let cos_inner = cos_inner.unwrap_or(cos_outer);
                if cos_inner < cos_outer {
                    return Err(err(
                        pos,
                        "cos_inner",
                        "cos_inner must be ≥ cos_outer".into(),
                    ));
                }
                Some(Spot {
                    direction,
                    cos_outer,
                    cos_inner,
                })
            }
            _ => {
                return Err(err(
                    pos,
                    "direction",
                    "a spot light needs both direction and cos_outer".into(),
                ))
            }
        };
        lights.push(Light {
            position: l.position,
            color: l.color,
            spot,
        });
    }

    let mut names = Vec::new();
    let mut materials = Vec::new();
    for (name, m) in &f.material {
        // Errors point at the material's first header or dotted key.
        let pos = text.find(&format!("material.{name}")).unwrap_or(0);
        let diffuse_model = match m.diffuse.model.unwrap_or(DiffuseModelToml::Lambert) {
            DiffuseModelToml::Lambert => DiffuseModel::Lambert,
            DiffuseModelToml::OrenNayar => {
                let sigma2 = m.diffuse.sigma2.unwrap_or(0.25);
                if sigma2 < 0.0 {
                    return Err(err(pos, "sigma2", "must be ≥ 0".into()));
                }
                DiffuseModel::OrenNayar { sigma2 }
            }
        };
        let specular = match &m.specular {
            None => None,
            Some(s) => {
                let exponent = s.exponent.as_ref().map(|e| (*e.get_ref(), e.span().start));
                let (exponent, epos) = exponent.unwrap_or((32, pos));
                if exponent > sim_target::num::MAX_POW_EXPONENT {
                    return Err(err(epos, "exponent", "must be ≤ 1023".into()));
                }
                let model = match s.model.unwrap_or(SpecModelToml::BlinnPhong) {
                    SpecModelToml::BlinnPhong => SpecularModel::BlinnPhong,
                    SpecModelToml::TorranceSparrow => SpecularModel::TorranceSparrow {
                        eta: s.eta.unwrap_or(1.5),
                        k: s.extinction.unwrap_or(0.0),
                    },
                };
                Some(Specular {
                    k: s.k,
                    color: s.color,
                    model,
                    exponent,
                })
            }
        };
        let reflection = match &m.reflection {
            None => Reflection::None,
            Some(r) => match r.mode {
                ReflModeToml::None => Reflection::None,
                ReflModeToml::Constant => Reflection::Constant(
                    r.r.unwrap_or_else(|| specular.as_ref().map(|s| s.k).unwrap_or(0.0)),
                ),
                ReflModeToml::Fresnel => {
                    let eta = r.eta.unwrap_or(1.5);
                    if eta <= 0.0 {
                        return Err(err(pos, "eta", "must be positive".into()));
                    }
                    let k = r.k.unwrap_or(0.0);
                    if r.transmit.unwrap_or(false) {
                        if k != 0.0 {
                            return Err(err(
                                pos,
                                "transmit",
                                "only dielectrics (k = 0) transmit".into(),
                            ));
                        }
                        Reflection::Glass { eta }
                    } else {
                        Reflection::Fresnel { eta, k }
                    }
                }
            },
        };
        let texture = m.texture.as_ref().map(|t| Texture {
            kind: match t.kind {
                TexKindToml::Xor => TextureKind::Xor,
                TexKindToml::Checkerboard => TextureKind::Checkerboard {
                    cell: t.cell.unwrap_or(8),
                },
                TexKindToml::RgbDots => TextureKind::RgbDots,
                TexKindToml::Marble => TextureKind::Marble {
                    seed: t.seed.unwrap_or(1),
                },
                TexKindToml::Wood => TextureKind::Wood {
                    seed: t.seed.unwrap_or(2),
                },
            },
            mapping: match t.mapping.unwrap_or(MappingToml::Planar) {
                MappingToml::Planar => Mapping::Planar,
                MappingToml::Cylindrical => Mapping::Cylindrical,
                MappingToml::Spherical => Mapping::Spherical,
            },
            scale: t.scale.unwrap_or([1.0, 1.0]),
            offset: t.offset.unwrap_or([0.0, 0.0]),
            color2: t.color2.unwrap_or([0.0; 3]),
            filter: match t.filter.unwrap_or(FilterToml::Nearest) {
                FilterToml::Nearest => Filter::Nearest,
                FilterToml::Bilinear => Filter::Bilinear,
            },
        });
        names.push(name.clone());
        materials.push(Material {
            name: name.clone(),
            ambient: m.ambient.as_ref().map(|a| Term {
                k: a.k,
                color: a.color,
            }),
            diffuse: Term {
                k: m.diffuse.k,
                color: m.diffuse.color,
            },
            diffuse_model,
            specular,
            reflection,
            texture,
        });
    }

    if f.object.len() > limits.max_objects {
        let pos = f.object[limits.max_objects].span().start;
        return Err(err(
            pos,
            "object",
            format!(
                "{} objects, the target has {}",
                f.object.len(),
                limits.max_objects
            ),
        ));
    }
    let mut objects = Vec::new();
    for o in &f.object {
        let o = o.get_ref();
        let mname = o.material.get_ref();
        let Some(material) = names.iter().position(|n| n == mname) else {
            return Err(err(
                o.material.span().start,
                "material",
                format!("no material named `{mname}`"),
            ));
        };
        let scale = *o.scale.get_ref();
        if scale
            .iter()
            .any(|s| s.is_nan() || *s <= 0.0 || s.is_infinite())
        {
            return Err(err(
                o.scale.span().start,
                "scale",
                "scales (radii) must be positive and finite".into(),
            ));
        }
        objects.push(Object {
            shape: match o.shape {
                ShapeToml::Sphere => Shape::Sphere,
                ShapeToml::Plane => Shape::Plane,
                ShapeToml::Disk => Shape::Disk,
                ShapeToml::Square => Shape::Square,
                ShapeToml::Cylinder => Shape::Cylinder,
                ShapeToml::Cone => Shape::Cone,
                ShapeToml::Cube => Shape::Cube,
            },
            translate: o.translate,
            scale,
            rotate: o.rotate,
            material,
        });
    }

    Ok(Scene {
        width,
        height,
        depth: r.depth,
        bias: r.bias,
        max_distance: r.max_distance,
        background: r.background,
        spp: *r.spp.get_ref(),
        shadows: r.shadows,
        camera: Camera {
            position: f.camera.position,
            look_at: f.camera.look_at,
            up: f.camera.up,
            fov_y: fov,
        },
        ambient: f.ambient.map(|a| a.color).unwrap_or([0.0; 3]),
        lights,
        materials,
        objects,
    })
}
