//! The raster command file (`fpgfx raster CMDS.toml`): a contract other tools write, so
//! every mistake is reported with the command index, the field and (for TOML) the line,
//! and nothing is guessed or silently clamped.
//!
//! Geometry is given in pixel units as floats and snapped here, on the host, to the
//! sub-pixel grid with `floor(x · 2^b + 0.5)` (the coverage contract of docs/requirements.md §0 and §7.2): the wire and
//! everything after it is exact integer arithmetic.

use std::ops::Range;

use protocol::names::UnknownName;
use protocol::raster::{
    Aa, AaPattern, Bezier, BezierPatch, Circle, Connectivity, Cull, FillRule, Line, LineAlgo,
    Pixel, Point, Polygon, RasterCmd, RasterSetup, Rgb, SeedFill, Shade, Traversal, Triangle,
    MAX_POLYGON, MAX_SUBPIXEL_BITS,
};
use protocol::MAX_FRAME_SIDE;
use serde::Deserialize;

/// Geometry may reach this many pixels beyond the viewport on each side (a guard band);
/// the device clips it. Further out is a mistake in the file, reported as one.
pub const GUARD_BAND: f64 = 4096.0;

/// A parsed, validated command file, ready for the wire.
#[derive(Debug, Clone, PartialEq)]
pub struct RasterJob {
    /// Frame-wide state, sent first.
    pub setup: RasterSetup,
    /// Commands in file order.
    pub cmds: Vec<RasterCmd>,
}

/// What is wrong with a command file, and where.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RasterFileError {
    /// The text is not valid TOML/JSON or the top-level keys are wrong.
    #[error("{file}: {message}")]
    Syntax {
        /// File name as given.
        file: String,
        /// The parser's message (it includes line and column for TOML).
        message: String,
    },
    /// A top-level setting is out of range.
    #[error("{file}: `{key}`: {message}")]
    Setting {
        /// File name as given.
        file: String,
        /// The top-level key that is out of range (`width`, `subpixel_bits`, …).
        key: &'static str,
        /// What is wrong.
        message: String,
    },
    /// One command is wrong.
    #[error("{file}{line}: cmd[{index}] ({op}): {message}", line = line.map(|l| format!(":{l}")).unwrap_or_default())]
    Command {
        /// File name as given.
        file: String,
        /// 1-based line of the command's table, when known (TOML only).
        line: Option<usize>,
        /// 0-based index of the command in the file.
        index: usize,
        /// The command's `op` as written (`""` when empty), or `?` when it is missing or
        /// not a string.
        op: String,
        /// What is wrong, naming the field.
        message: String,
    },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileTop {
    size: [u32; 2],
    #[serde(default)]
    background: Option<String>,
    #[serde(default)]
    subpixel_bits: Option<u8>,
    #[serde(default)]
    aa: Option<AaTop>,
    #[serde(default)]
    cull: Option<String>,
    #[serde(default)]
    traversal: Option<String>,
    #[serde(default)]
    cmd: Vec<toml::Spanned<toml::Table>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AaTop {
    pattern: String,
    #[serde(default)]
    samples: Option<u8>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TriangleCmd {
    v: [[f64; 2]; 3],
    #[serde(default)]
    color: Option<String>,
    #[serde(default)]
    colors: Option<[String; 3]>,
    #[serde(default)]
    z: Option<[f64; 3]>,
    #[serde(default)]
    w: Option<[f64; 3]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LineCmd {
    from: [f64; 2],
    to: [f64; 2],
    color: String,
    #[serde(default)]
    color_to: Option<String>,
    #[serde(default)]
    width: Option<f64>,
    #[serde(default)]
    aa: bool,
    #[serde(default)]
    algorithm: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CircleCmd {
    center: [f64; 2],
    radius: f64,
    color: String,
    #[serde(default)]
    fill: bool,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FillCmd {
    seed: [i64; 2],
    color: String,
    #[serde(default)]
    connectivity: Option<u8>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BezierCmd {
    points: Vec<[f64; 2]>,
    color: String,
    #[serde(default)]
    tolerance: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PolygonCmd {
    points: Vec<[f64; 2]>,
    color: String,
    #[serde(default)]
    rule: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PatchCmd {
    points: Vec<[f64; 2]>,
    color: String,
    #[serde(default)]
    steps: Option<u8>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ClearCmd {
    color: String,
}

/// Parses a command file. `file` names it in errors; a name ending in `.json` is read as
/// JSON with the same structure, anything else as TOML.
pub fn parse(text: &str, file: &str) -> Result<RasterJob, RasterFileError> {
    let top: FileTop = if file.ends_with(".json") {
        // JSON has no spans; route it through toml's value model so both share one schema.
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| RasterFileError::Syntax {
                file: file.into(),
                message: e.to_string(),
            })?;
        let toml_text = json_to_toml(&value).map_err(|message| RasterFileError::Syntax {
            file: file.into(),
            message,
        })?;
        toml::from_str(&toml_text)
    } else {
        toml::from_str(text)
    }
    .map_err(|e| RasterFileError::Syntax {
        file: file.into(),
        message: e.to_string().trim_end().to_string(),
    })?;
    let is_toml = !file.ends_with(".json");
    let setting = |key: &'static str, message: String| RasterFileError::Setting {
        file: file.into(),
        key,
        message,
    };

    let [width, height] = top.size;
    for (key, v) in [("size[0]", width), ("size[1]", height)] {
        if v == 0 || v > MAX_FRAME_SIDE {
            return Err(setting(key, format!("{v} is outside 1..={MAX_FRAME_SIDE}")));
        }
    }
    let subpixel_bits = top.subpixel_bits.unwrap_or(8);
    if subpixel_bits > MAX_SUBPIXEL_BITS {
        return Err(setting(
            "subpixel_bits",
            format!("{subpixel_bits} is outside 0..={MAX_SUBPIXEL_BITS}"),
        ));
    }
    let background = match &top.background {
        Some(s) => parse_color(s).map_err(|m| setting("background", m))?,
        None => Rgb::new(0, 0, 0),
    };
    let aa = match &top.aa {
        None => Aa::default(),
        Some(a) => {
            let pattern = a.pattern.parse().map_err(|e: UnknownName<AaPattern>| {
                setting(
                    "aa.pattern",
                    format!("unknown pattern {:?} ({})", a.pattern, e.expected()),
                )
            })?;
            let samples = a
                .samples
                .unwrap_or(if pattern == AaPattern::None { 1 } else { 4 });
            if !(1..=64).contains(&samples) {
                return Err(setting(
                    "aa.samples",
                    format!("{samples} is outside 1..=64"),
                ));
            }
            Aa { pattern, samples }
        }
    };
    let cull = match top.cull.as_deref() {
        None => Cull::None,
        Some(name) => name.parse().map_err(|e: UnknownName<Cull>| {
            setting(
                "cull",
                format!("unknown culling {name:?} ({})", e.expected()),
            )
        })?,
    };
    let traversal = match top.traversal.as_deref() {
        None => Traversal::default(),
        Some(name) => name.parse().map_err(|e: UnknownName<Traversal>| {
            setting(
                "traversal",
                format!("unknown traversal {name:?} ({})", e.expected()),
            )
        })?,
    };
    let setup = RasterSetup {
        width: width as u16,
        height: height as u16,
        subpixel_bits,
        background,
        aa,
        cull,
        traversal,
    };

    let ctx = Ctx {
        scale: f64::from(1u32 << subpixel_bits),
        x_range: -GUARD_BAND..f64::from(width) + GUARD_BAND,
        y_range: -GUARD_BAND..f64::from(height) + GUARD_BAND,
        width,
        height,
    };
    let mut cmds = Vec::with_capacity(top.cmd.len());
    for (index, spanned) in top.cmd.iter().enumerate() {
        let line = is_toml.then(|| line_of(text, spanned.span().start));
        let table = spanned.get_ref();
        // The label the error shows: the op as written, `""` when it is empty (a message
        // naming no command would leave the reader to count), `?` when there is no string.
        let (op, label) = match table.get("op") {
            None => (Err("missing field `op`".to_string()), "?".to_string()),
            Some(toml::Value::String(s)) if s.is_empty() => (Ok(s.as_str()), "\"\"".into()),
            Some(toml::Value::String(s)) => (Ok(s.as_str()), s.clone()),
            Some(v) => (
                Err(format!("`op` must be a string naming the command, not {v}")),
                "?".to_string(),
            ),
        };
        let err = |message: String| RasterFileError::Command {
            file: file.into(),
            line,
            index,
            op: label.clone(),
            message,
        };
        let cmd = op.and_then(|op| ctx.command(op, table)).map_err(err)?;
        cmds.push(cmd);
    }
    Ok(RasterJob { setup, cmds })
}

/// Parses `#rrggbb`.
pub fn parse_color(s: &str) -> Result<Rgb, String> {
    let hex = s
        .strip_prefix('#')
        .filter(|h| h.len() == 6 && h.bytes().all(|b| b.is_ascii_hexdigit()))
        .ok_or_else(|| format!("colour {s:?} is not of the form \"#rrggbb\""))?;
    let byte = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).map_err(|e| e.to_string());
    Ok(Rgb::new(byte(0)?, byte(2)?, byte(4)?))
}

fn line_of(text: &str, offset: usize) -> usize {
    text.get(..offset).map_or(0, |t| t.matches('\n').count()) + 1
}

/// serde_json → TOML text, so JSON files go through exactly the TOML schema. `null`
/// has no TOML form and is reported rather than dropped.
fn json_to_toml(v: &serde_json::Value) -> Result<String, String> {
    fn conv(v: &serde_json::Value, path: &str) -> Result<toml::Value, String> {
        Ok(match v {
            serde_json::Value::Null => return Err(format!("{path}: null is not allowed")),
            serde_json::Value::Bool(b) => toml::Value::Boolean(*b),
            serde_json::Value::Number(n) => match n.as_i64() {
                Some(i) => toml::Value::Integer(i),
                None => toml::Value::Float(n.as_f64().ok_or_else(|| format!("{path}: {n}"))?),
            },
            serde_json::Value::String(s) => toml::Value::String(s.clone()),
            serde_json::Value::Array(a) => toml::Value::Array(
                a.iter()
                    .enumerate()
                    .map(|(i, x)| conv(x, &format!("{path}[{i}]")))
                    .collect::<Result<_, _>>()?,
            ),
            serde_json::Value::Object(o) => toml::Value::Table(
                o.iter()
                    .map(|(k, x)| Ok((k.clone(), conv(x, &format!("{path}.{k}"))?)))
                    .collect::<Result<_, String>>()?,
            ),
        })
    }
    match conv(v, "$")? {
        toml::Value::Table(t) => toml::to_string(&t).map_err(|e| e.to_string()),
        _ => Err("the top level must be an object".into()),
    }
}

struct Ctx {
    scale: f64,
    x_range: Range<f64>,
    y_range: Range<f64>,
    width: u32,
    height: u32,
}

impl Ctx {
    fn command(&self, op: &str, table: &toml::Table) -> Result<RasterCmd, String> {
        let mut fields = table.clone();
        fields.remove("op");
        let value = toml::Value::Table(fields);
        Ok(match op {
            "triangle" => self.triangle(typed(value)?)?,
            "line" => self.line(typed(value)?)?,
            "circle" => self.circle(typed(value)?)?,
            "fill" => self.fill(typed(value)?)?,
            "bezier" => self.bezier(typed(value)?)?,
            "polygon" => self.polygon(typed(value)?)?,
            "patch" => self.patch(typed(value)?)?,
            "clear" => {
                let c: ClearCmd = typed(value)?;
                RasterCmd::Clear(color("color", &c.color)?)
            }
            other => {
                return Err(format!(
                "unknown op {other:?} (triangle, line, circle, fill, bezier, polygon, patch, clear)"
            ))
            }
        })
    }

    /// Snaps a pixel-unit point to the sub-pixel grid, refusing non-finite values and
    /// points beyond the guard band.
    fn point(&self, field: &str, p: [f64; 2]) -> Result<Point, String> {
        let [x, y] = p;
        if !x.is_finite() || !y.is_finite() {
            return Err(format!("`{field}`: [{x}, {y}] is not finite"));
        }
        if !self.x_range.contains(&x) || !self.y_range.contains(&y) {
            return Err(format!(
                "`{field}`: [{x}, {y}] is beyond the guard band ({}..{} × {}..{})",
                self.x_range.start, self.x_range.end, self.y_range.start, self.y_range.end
            ));
        }
        Ok(Point {
            x: snap(x, self.scale),
            y: snap(y, self.scale),
        })
    }

    fn length(&self, field: &str, v: f64) -> Result<u32, String> {
        if !v.is_finite() || !(0.0..=2.0 * GUARD_BAND).contains(&v) {
            return Err(format!(
                "`{field}`: {v} is outside 0..={}",
                2.0 * GUARD_BAND
            ));
        }
        Ok(snap(v, self.scale) as u32)
    }

    fn triangle(&self, t: TriangleCmd) -> Result<RasterCmd, String> {
        let mut v = [Point::default(); 3];
        for (i, p) in t.v.iter().enumerate() {
            v[i] = self.point(&format!("v[{i}]"), *p)?;
        }
        let shade = match (&t.color, &t.colors) {
            (Some(c), None) => Shade::Flat(color("color", c)?),
            (None, Some(cs)) => Shade::Gouraud([
                color("colors[0]", &cs[0])?,
                color("colors[1]", &cs[1])?,
                color("colors[2]", &cs[2])?,
            ]),
            (Some(_), Some(_)) => return Err("give either `color` or `colors`, not both".into()),
            (None, None) => return Err("missing `color` (or `colors` for Gouraud)".into()),
        };
        let z =
            t.z.map(|z| -> Result<[u32; 3], String> {
                let mut out = [0u32; 3];
                for (i, &d) in z.iter().enumerate() {
                    if !(0.0..=1.0).contains(&d) {
                        return Err(format!("`z[{i}]`: {d} is outside 0..=1"));
                    }
                    out[i] = (d * f64::from((1u32 << 24) - 1)).round() as u32;
                }
                Ok(out)
            })
            .transpose()?;
        let w =
            t.w.map(|w| -> Result<[u32; 3], String> {
                let mut out = [0u32; 3];
                for (i, &d) in w.iter().enumerate() {
                    // Q16.16, strictly positive: w ≤ 0 is behind the eye and must be
                    // clipped before rasterization.
                    if !(d > 0.0 && d < 32768.0) {
                        return Err(format!("`w[{i}]`: {d} is outside (0, 32768)"));
                    }
                    out[i] = ((d * 65536.0).round() as u32).max(1);
                }
                Ok(out)
            })
            .transpose()?;
        Ok(RasterCmd::Triangle(Triangle {
            v,
            shade,
            z,
            w,
            tex: None,
        }))
    }

    fn line(&self, l: LineCmd) -> Result<RasterCmd, String> {
        let algo = match l.algorithm.as_deref() {
            None => LineAlgo::default(),
            Some(name) => name.parse().map_err(|e: UnknownName<LineAlgo>| {
                format!("`algorithm`: unknown {name:?} ({})", e.expected())
            })?,
        };
        Ok(RasterCmd::Line(Line {
            from: self.point("from", l.from)?,
            to: self.point("to", l.to)?,
            color: color("color", &l.color)?,
            color_to: l.color_to.map(|c| color("color_to", &c)).transpose()?,
            width: self.length("width", l.width.unwrap_or(1.0))?,
            aa: l.aa,
            algo,
        }))
    }

    fn circle(&self, c: CircleCmd) -> Result<RasterCmd, String> {
        if c.radius.is_nan() || c.radius <= 0.0 {
            return Err(format!("`radius`: {} must be positive", c.radius));
        }
        Ok(RasterCmd::Circle(Circle {
            center: self.point("center", c.center)?,
            radius: self.length("radius", c.radius)?,
            color: color("color", &c.color)?,
            fill: c.fill,
        }))
    }

    fn fill(&self, f: FillCmd) -> Result<RasterCmd, String> {
        let [x, y] = f.seed;
        if x < 0 || y < 0 || x >= i64::from(self.width) || y >= i64::from(self.height) {
            return Err(format!(
                "`seed`: [{x}, {y}] is outside the {}×{} framebuffer",
                self.width, self.height
            ));
        }
        let connectivity = match f.connectivity.unwrap_or(4) {
            4 => Connectivity::Four,
            8 => Connectivity::Eight,
            n => return Err(format!("`connectivity`: {n} is neither 4 nor 8")),
        };
        Ok(RasterCmd::Fill(SeedFill {
            seed: Pixel {
                x: x as u16,
                y: y as u16,
            },
            color: color("color", &f.color)?,
            connectivity,
        }))
    }

    fn bezier(&self, b: BezierCmd) -> Result<RasterCmd, String> {
        if !(3..=4).contains(&b.points.len()) {
            return Err(format!(
                "`points`: {} points given; a Bézier curve takes 3 (quadratic) or 4 (cubic)",
                b.points.len()
            ));
        }
        let mut points = heapless::Vec::new();
        for (i, p) in b.points.iter().enumerate() {
            // Capacity 4 was checked above.
            let _ = points.push(self.point(&format!("points[{i}]"), *p)?);
        }
        let tol = b.tolerance.unwrap_or(0.25);
        if tol.is_nan() || tol <= 0.0 {
            return Err(format!("`tolerance`: {tol} must be positive"));
        }
        Ok(RasterCmd::Bezier(Bezier {
            points,
            color: color("color", &b.color)?,
            tolerance: self.length("tolerance", tol)?.max(1),
        }))
    }

    fn polygon(&self, p: PolygonCmd) -> Result<RasterCmd, String> {
        if !(3..=MAX_POLYGON).contains(&p.points.len()) {
            return Err(format!(
                "`points`: {} points given; a polygon takes 3..={MAX_POLYGON}",
                p.points.len()
            ));
        }
        let rule = match p.rule.as_deref() {
            None => FillRule::EvenOdd,
            Some(name) => name.parse().map_err(|e: UnknownName<FillRule>| {
                format!("`rule`: unknown {name:?} ({})", e.expected())
            })?,
        };
        let mut points = heapless::Vec::new();
        for (i, q) in p.points.iter().enumerate() {
            let _ = points.push(self.point(&format!("points[{i}]"), *q)?);
        }
        Ok(RasterCmd::Polygon(Polygon {
            points,
            rule,
            color: color("color", &p.color)?,
        }))
    }

    fn patch(&self, p: PatchCmd) -> Result<RasterCmd, String> {
        if p.points.len() != 16 {
            return Err(format!(
                "`points`: {} points given; a bicubic patch takes 16 (4 × 4, row by row)",
                p.points.len()
            ));
        }
        let mut points = [Point::default(); 16];
        for (i, q) in p.points.iter().enumerate() {
            points[i] = self.point(&format!("points[{i}]"), *q)?;
        }
        let steps = p.steps.unwrap_or(8);
        if !(1..=32).contains(&steps) {
            return Err(format!("`steps`: {steps} is outside 1..=32"));
        }
        Ok(RasterCmd::Patch(BezierPatch {
            points,
            steps,
            color: color("color", &p.color)?,
        }))
    }
}

fn snap(v: f64, scale: f64) -> i32 {
    (v * scale + 0.5).floor() as i32
}

fn color(field: &str, s: &str) -> Result<Rgb, String> {
    parse_color(s).map_err(|m| format!("`{field}`: {m}"))
}

fn typed<T: for<'de> Deserialize<'de>>(value: toml::Value) -> Result<T, String> {
    value
        .try_into()
        .map_err(|e: toml::de::Error| e.message().trim_end().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = r##"
size = [320, 240]
background = "#000000"

[[cmd]]
op = "triangle"
v = [[10.5, 20.25], [200.0, 30.0], [50.0, 180.75]]
color = "#ff8000"

[[cmd]]
op = "line"
from = [3.0, 4.0]
to = [100.0, 50.0]
color = "#ffffff"
"##;

    #[test]
    fn snaps_half_up_and_keeps_order() {
        let job = parse(FILE, "t.toml").expect("valid file");
        assert_eq!(job.setup.width, 320);
        assert_eq!(job.cmds.len(), 2);
        let RasterCmd::Triangle(t) = &job.cmds[0] else {
            panic!("first command is the triangle")
        };
        // 10.5 · 256 = 2688, 20.25 · 256 = 5184, 180.75 · 256 = 46272.
        assert_eq!(t.v[0], Point { x: 2688, y: 5184 });
        assert_eq!(t.v[2], Point { x: 12800, y: 46272 });
        assert_eq!(t.shade, Shade::Flat(Rgb::new(0xff, 0x80, 0)));
        // Half rounds up, also for negatives: -0.5/256 px → floor(-0.5 + 0.5) = 0.
        assert_eq!(snap(-0.5 / 256.0, 256.0), 0);
        assert_eq!(snap(-1.5 / 256.0, 256.0), -1);
    }

    /// Found by fuzzing: an empty op was reported as `cmd[5] (): unknown op ""`, naming
    /// no command, and an op that was not a string, or the string `"?"`, as missing.
    #[test]
    fn op_errors_say_which_op() {
        let cases = [
            (
                "op = \"line\"",
                "op = \"\"",
                "cmd[1] (\"\"): unknown op \"\"",
            ),
            (
                "op = \"line\"",
                "op = \"?\"",
                "cmd[1] (?): unknown op \"?\"",
            ),
            (
                "op = \"line\"",
                "op = 3",
                "cmd[1] (?): `op` must be a string",
            ),
            ("op = \"line\"", "", "cmd[1] (?): missing field `op`"),
        ];
        for (from, to, want) in cases {
            let bad = FILE.replace(from, to);
            let e = parse(&bad, "t.toml").unwrap_err().to_string();
            assert!(e.contains(want), "{to:?}: {e}");
        }
        let json =
            r##"{"size": [8, 8], "cmd": [{"op": "clear", "color": "#000000"}, {"op": ""}]}"##;
        let e = parse(json, "t.json").unwrap_err().to_string();
        assert_eq!(
            e,
            "t.json: cmd[1] (\"\"): unknown op \"\" (triangle, line, circle, fill, bezier, \
             polygon, patch, clear)"
        );
    }

    #[test]
    fn errors_name_index_field_and_line() {
        let bad = FILE.replace("color = \"#ffffff\"", "color = \"white\"");
        let e = parse(&bad, "t.toml").unwrap_err().to_string();
        assert!(e.contains("t.toml:10: cmd[1] (line)"), "{e}");
        assert!(e.contains("`color`"), "{e}");

        let bad = FILE.replace("op = \"line\"", "op = \"spline\"");
        let e = parse(&bad, "t.toml").unwrap_err().to_string();
        assert!(e.contains("cmd[1] (spline): unknown op"), "{e}");

        let bad = FILE.replace("[50.0, 180.75]]", "]");
        let e = parse(&bad, "t.toml").unwrap_err().to_string();
        assert!(e.contains("cmd[0] (triangle)"), "{e}");

        let bad = FILE.replace("[3.0, 4.0]", "[3.0, 1e9]");
        let e = parse(&bad, "t.toml").unwrap_err().to_string();
        assert!(e.contains("`from`") && e.contains("guard band"), "{e}");

        let bad = FILE.replace("color = \"#ff8000\"", "color = \"#ff8000\"\nfoo = 1");
        let e = parse(&bad, "t.toml").unwrap_err().to_string();
        assert!(e.contains("cmd[0]") && e.contains("foo"), "{e}");

        let e = parse("size = [0, 10]", "t.toml").unwrap_err().to_string();
        assert!(e.contains("size[0]"), "{e}");
    }

    #[test]
    fn json_is_the_same_schema() {
        let json = r##"{"size":[320,240],"cmd":[{"op":"circle","center":[160.0,120.0],
            "radius":40.0,"color":"#00ff00","fill":true},{"op":"fill","seed":[1,2],"color":"#0000ff","connectivity":8}]}"##;
        let job = parse(json, "t.json").expect("valid json");
        assert_eq!(
            job.cmds[0],
            RasterCmd::Circle(Circle {
                center: Point {
                    x: 160 * 256,
                    y: 120 * 256
                },
                radius: 40 * 256,
                color: Rgb::new(0, 255, 0),
                fill: true
            })
        );
        let e = parse(r#"{"size":[1,1],"cmd":[{"op":"clear"}]}"#, "t.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("cmd[0] (clear)") && e.contains("color"), "{e}");
    }
}
