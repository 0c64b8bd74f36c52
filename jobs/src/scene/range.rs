//! What magnitudes a scene makes the ray tracer's datapath hold, named by the scene field
//! that causes them, against a number format's range.
//!
//! A fixed-point format saturates silently and a float one overflows to ∞: either draws a
//! wrong frame without a word. Knowing the demands before rendering lets the host warn
//! ("objects[2].scale: the squared ray reach in object space, 412, exceeds Q8.24's 128")
//! and lets the stress runner tell a format's limit from a bug.

use protocol::frame::Numeric;

use sim_target::rt::{f, Scene};

/// One magnitude the kernel forms, and the scene field that drives it.
#[derive(Debug, Clone, PartialEq)]
pub struct Demand {
    /// The scene field, as a scene file names it: `lights[1].color`, `objects[0].scale`.
    pub field: String,
    /// What the datapath computes from it.
    pub what: &'static str,
    /// The largest magnitude it reaches.
    pub value: f64,
}

/// Largest finite magnitude a format holds.
pub fn format_max(n: Numeric) -> f64 {
    match n {
        Numeric::F64 => f64::MAX,
        Numeric::F32 => f32::MAX as f64,
        Numeric::F16 => 65504.0,
        Numeric::Q16_16 => 32768.0,
        Numeric::Q8_24 => 128.0,
        Numeric::Q24_8 => 8_388_608.0,
        Numeric::Q32_32 => 2_147_483_648.0,
    }
}

/// Every magnitude the kernel must represent for `scene`: light intensities, distances
/// from the origin, the quadratic coefficients of each object (|d′|² = 1/s², |o′|² ≈
/// (2·far + s)²/s², since the ray's origin and direction are divided by the scale in
/// object space), the scale itself, and the squared distance across the scene.
/// MAX_DISTANCE is not a demand: the kernel clips it to the format's largest value.
pub fn demands(scene: &Scene) -> Vec<Demand> {
    let len = f::length;
    let mut out = Vec::new();
    // The farthest point from the origin, and which field it is.
    let mut far = (len(scene.camera.position), "camera.position".to_string());
    for (i, l) in scene.lights.iter().enumerate() {
        if len(l.position) > far.0 {
            far = (len(l.position), format!("lights[{i}].position"));
        }
        out.push(Demand {
            field: format!("lights[{i}].color"),
            what: "light intensity",
            value: l.color.iter().fold(0.0f64, |a, c| a.max(c.abs())),
        });
    }
    for (i, o) in scene.objects.iter().enumerate() {
        if len(o.translate) > far.0 {
            far = (len(o.translate), format!("objects[{i}].translate"));
        }
    }
    for (i, o) in scene.objects.iter().enumerate() {
        let smin = o.scale.iter().fold(f64::INFINITY, |a, s| a.min(*s));
        let smax = o.scale.iter().fold(0.0f64, |a, s| a.max(*s));
        let reach = (2.0 * far.0 + smax).max(1.0) / smin;
        out.push(Demand {
            field: format!("objects[{i}].scale"),
            what: "squared ray reach in object space",
            value: reach * reach,
        });
        out.push(Demand {
            field: format!("objects[{i}].scale"),
            what: "scale",
            value: smax,
        });
    }
    out.push(Demand {
        field: far.1,
        what: "squared distance across the scene (the farthest point from the origin, doubled)",
        value: 4.0 * far.0 * far.0,
    });
    out
}

/// The largest of [`demands`] (at least 1): a format whose [`format_max`] is below it
/// cannot hold the scene.
pub fn range_demand(scene: &Scene) -> f64 {
    demands(scene).iter().fold(1.0f64, |m, d| m.max(d.value))
}

/// The demands `n` cannot hold, largest first.
pub fn out_of_range(scene: &Scene, n: Numeric) -> Vec<Demand> {
    let max = format_max(n);
    let mut v: Vec<Demand> = demands(scene)
        .into_iter()
        .filter(|d| d.value > max)
        .collect();
    v.sort_by(|a, b| b.value.total_cmp(&a.value));
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference() -> Scene {
        let text = include_str!("../../../examples/reference.toml");
        super::super::parse(text, "reference.toml").expect("the reference scene parses")
    }

    #[test]
    fn the_reference_scene_fits_q16_16_but_not_q8_24() {
        let s = reference();
        assert!(out_of_range(&s, Numeric::Q16_16).is_empty());
        assert!(out_of_range(&s, Numeric::F32).is_empty());
        let over = out_of_range(&s, Numeric::Q8_24);
        assert!(!over.is_empty());
        assert!(over.iter().all(|d| d.value > 128.0));
        // Largest first, each naming a field of the file.
        assert!(over.windows(2).all(|w| w[0].value >= w[1].value));
        assert!(over.iter().all(|d| d.field.starts_with("objects[")
            || d.field.starts_with("lights[")
            || d.field.starts_with("camera")));
    }

    #[test]
    fn a_far_light_is_named() {
        let mut s = reference();
        s.lights[0].position = [0.0, 1000.0, 0.0];
        let over = out_of_range(&s, Numeric::Q16_16);
        let light = over
            .iter()
            .find(|d| d.field == "lights[0].position")
            .unwrap_or_else(|| panic!("the light is not named: {over:?}"));
        assert_eq!(light.value, 4.0e6);
        // Rays now reach 2000 units: every object's reach in object space grows with it.
        assert!(
            over.iter().any(|d| d.field == "objects[0].scale"),
            "{over:?}"
        );
    }
}
