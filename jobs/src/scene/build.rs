//! Whether a target's ray tracer builds what a scene asks for ([`RtBuild`], from the
//! target's caps): a hardware core carries only the shapes and shading terms its scenes
//! need, so the host checks before anything is sent and names the scene field that asks
//! for more, instead of letting the core refuse the frame after the upload.

use protocol::frame::RtBuild;
use sim_target::rt::{DiffuseModel, Reflection, Scene, SpecularModel};
use sim_target::scene_regs::SceneRegsError;

/// Checks `scene` against `build`; the first field it asks for that is not built is named.
pub fn check_build(scene: &Scene, build: &RtBuild) -> Result<(), SceneRegsError> {
    let refuse = |what: String| Err(SceneRegsError::NotBuilt(what));
    for (i, o) in scene.objects.iter().enumerate() {
        if build.shapes & (1 << o.shape.code()) == 0 {
            let name = format!("{:?}", o.shape).to_lowercase();
            return refuse(format!(
                "object {i}: shape = \"{name}\" (the target builds shape codes {:#09b})",
                build.shapes
            ));
        }
    }
    if scene.spp > u32::from(build.max_spp) {
        return refuse(format!(
            "render.spp = {} (the target takes at most {})",
            scene.spp, build.max_spp
        ));
    }
    if scene.shadows && !build.has(RtBuild::SHADOWS) {
        return refuse("render.shadows = true (the target builds no shadow rays)".into());
    }
    if scene.lights.len() > usize::from(build.lights) {
        return refuse(format!(
            "{} lights besides the ambient one (the target shades {})",
            scene.lights.len(),
            build.lights
        ));
    }
    for (i, l) in scene.lights.iter().enumerate() {
        if l.spot.is_some() && !build.has(RtBuild::SPOT_LIGHTS) {
            return refuse(format!(
                "light {i}: a spot light (direction, cos_outer; the target builds point lights)"
            ));
        }
    }
    // only the materials an object uses: a scene may define more
    let mut used: Vec<usize> = scene.objects.iter().map(|o| o.material).collect();
    used.sort_unstable();
    used.dedup();
    for m in used.iter().filter_map(|&k| scene.materials.get(k)) {
        let name = &m.name;
        if m.texture.is_some() && !build.has(RtBuild::TEXTURES) {
            return refuse(format!(
                "material `{name}`: texture (the target builds none)"
            ));
        }
        if matches!(m.diffuse_model, DiffuseModel::OrenNayar { .. })
            && !build.has(RtBuild::OREN_NAYAR)
        {
            return refuse(format!(
                "material `{name}`: diffuse.model = \"oren-nayar\" (the target builds Lambert)"
            ));
        }
        if let Some(s) = &m.specular {
            if matches!(s.model, SpecularModel::TorranceSparrow { .. })
                && !build.has(RtBuild::TORRANCE_SPARROW)
            {
                return refuse(format!(
                    "material `{name}`: specular.model = \"torrance-sparrow\" (the target \
                     builds Blinn-Phong)"
                ));
            }
        }
        if m.reflection != Reflection::None && scene.depth > 1 && !build.has(RtBuild::REFLECTION) {
            return refuse(format!(
                "material `{name}`: reflection at render.depth = {} (the target traces \
                 primary rays only)",
                scene.depth
            ));
        }
    }
    Ok(())
}

/// Reduces `scene` to what `build` builds, so that a target carrying only part of the
/// ray tracer can still render it: objects of shapes not built are removed, samples
/// capped, shadows turned off, lights beyond the lanes dropped, spot lights made point
/// lights, textures removed, Oren–Nayar shaded as Lambert, Torrance–Sparrow as
/// Blinn–Phong with the same exponent, and without reflection the trace is cut to primary
/// rays (depth 1, every reflection off). Returns each change, naming the field as
/// [`check_build`] would, for the user to see what the picture lost.
pub fn fit_build(scene: &mut Scene, build: &RtBuild) -> Vec<String> {
    let mut changes = Vec::new();
    let before = scene.objects.len();
    let mut i = 0;
    scene.objects.retain(|o| {
        let keep = build.shapes & (1 << o.shape.code()) != 0;
        if !keep {
            let name = format!("{:?}", o.shape).to_lowercase();
            changes.push(format!("object {i}: shape = \"{name}\" removed"));
        }
        i += 1;
        keep
    });
    debug_assert!(scene.objects.len() + changes.len() == before);
    if scene.spp > u32::from(build.max_spp) {
        changes.push(format!("render.spp = {} → {}", scene.spp, build.max_spp));
        scene.spp = u32::from(build.max_spp);
    }
    if scene.shadows && !build.has(RtBuild::SHADOWS) {
        changes.push("render.shadows = true → false".into());
        scene.shadows = false;
    }
    if scene.lights.len() > usize::from(build.lights) {
        changes.push(format!(
            "lights {}..{} removed (the target shades {})",
            build.lights,
            scene.lights.len(),
            build.lights
        ));
        scene.lights.truncate(usize::from(build.lights));
    }
    for (i, l) in scene.lights.iter_mut().enumerate() {
        if l.spot.is_some() && !build.has(RtBuild::SPOT_LIGHTS) {
            changes.push(format!("light {i}: spot light → point light"));
            l.spot = None;
        }
    }
    let reflection = build.has(RtBuild::REFLECTION);
    if !reflection && scene.depth > 1 {
        changes.push(format!("render.depth = {} → 1", scene.depth));
        scene.depth = 1;
    }
    for m in &mut scene.materials {
        let name = m.name.clone();
        if m.texture.is_some() && !build.has(RtBuild::TEXTURES) {
            changes.push(format!("material `{name}`: texture removed"));
            m.texture = None;
        }
        if matches!(m.diffuse_model, DiffuseModel::OrenNayar { .. })
            && !build.has(RtBuild::OREN_NAYAR)
        {
            changes.push(format!(
                "material `{name}`: diffuse.model = \"oren-nayar\" → \"lambert\""
            ));
            m.diffuse_model = DiffuseModel::Lambert;
        }
        if let Some(sp) = &mut m.specular {
            if matches!(sp.model, SpecularModel::TorranceSparrow { .. })
                && !build.has(RtBuild::TORRANCE_SPARROW)
            {
                changes.push(format!(
                    "material `{name}`: specular.model = \"torrance-sparrow\" → \"blinn-phong\""
                ));
                sp.model = SpecularModel::BlinnPhong;
            }
        }
        if m.reflection != Reflection::None && !reflection {
            changes.push(format!("material `{name}`: reflection removed"));
            m.reflection = Reflection::None;
        }
    }
    changes
}

#[cfg(test)]
mod tests {
    use super::*;
    use sim_target::rt::Shape;

    fn reference() -> Scene {
        let text = include_str!("../../../examples/reference.toml");
        crate::scene::parse(text, "reference.toml").expect("reference parses")
    }

    fn refusal(scene: &Scene, build: &RtBuild) -> String {
        match check_build(scene, build) {
            Err(e) => e.to_string(),
            Ok(()) => panic!("{build:?} should refuse the scene"),
        }
    }

    #[test]
    fn the_full_build_takes_every_example_and_each_missing_term_is_named() {
        let s = reference();
        check_build(&s, &RtBuild::FULL).expect("the full build takes the reference");
        let without = |f: u16| RtBuild {
            features: RtBuild::FULL.features & !f,
            ..RtBuild::FULL
        };
        assert!(refusal(&s, &without(RtBuild::SHADOWS)).contains("render.shadows = true"));
        assert!(refusal(&s, &without(RtBuild::SPOT_LIGHTS)).contains("light 0: a spot light"));
        assert!(
            refusal(&s, &without(RtBuild::TEXTURES)).contains(": texture (the target builds none)")
        );
        assert!(refusal(&s, &without(RtBuild::OREN_NAYAR)).contains("\"oren-nayar\""));
        assert!(refusal(&s, &without(RtBuild::TORRANCE_SPARROW)).contains("\"torrance-sparrow\""));
        assert!(refusal(&s, &without(RtBuild::REFLECTION)).contains("render.depth = 2"));
        let no_cone = RtBuild {
            shapes: 0x7f & !(1 << Shape::Cone.code()),
            ..RtBuild::FULL
        };
        let cone = s
            .objects
            .iter()
            .position(|o| o.shape == Shape::Cone)
            .expect("the reference has a cone");
        assert!(refusal(&s, &no_cone).starts_with(&format!(
            "the target does not build this scene: object {cone}: shape = \"cone\""
        )));
        let no_lights = RtBuild {
            lights: 0,
            ..RtBuild::FULL
        };
        assert!(refusal(&s, &no_lights).contains("1 lights besides the ambient one"));
        let one_sample = RtBuild {
            max_spp: 1,
            ..RtBuild::FULL
        };
        let mut aa = s.clone();
        aa.spp = 4;
        assert!(refusal(&aa, &one_sample).contains("render.spp = 4"));
    }

    #[test]
    fn a_fitted_scene_passes_the_check_and_says_what_it_lost() {
        let builds = [
            sim_target::rt::core::BUILD,
            RtBuild {
                shapes: 0b11,
                lights: 0,
                max_spp: 1,
                features: 0,
            },
            RtBuild::FULL,
        ];
        for build in builds {
            let mut s = reference();
            let changes = fit_build(&mut s, &build);
            check_build(&s, &build).unwrap_or_else(|e| panic!("{build:?}: {e}"));
            assert_eq!(changes.is_empty(), build == RtBuild::FULL, "{changes:?}");
        }
        let mut s = reference();
        let changes = fit_build(&mut s, &sim_target::rt::core::BUILD);
        let text = changes.join("; ");
        for what in [
            "render.depth",
            "spot light → point light",
            "texture removed",
        ] {
            assert!(text.contains(what), "{what} not in: {text}");
        }
    }

    #[test]
    fn the_rt_core_build_takes_its_example() {
        let text = include_str!("../../../hw/rt-core/scenes/core.toml");
        let s = crate::scene::parse(text, "core.toml").expect("core.toml parses");
        // the default rt_cast: every shape, one point-light lane, one sample, shadows
        let core = sim_target::rt::core::BUILD;
        assert_eq!(
            (core.shapes, core.lights, core.max_spp, core.features),
            (0x7f, 1, 1, RtBuild::SHADOWS)
        );
        check_build(&s, &core).expect("the RTL core builds hw/rt-core/scenes/core.toml");
    }
}
