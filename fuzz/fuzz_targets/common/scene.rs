//! The scene-file parser's promises, shared by `scene_file` (parse alone) and
//! `scene_render` (parse, then render what it accepts).
use sim_target::rt::{DiffuseModel, Reflection, Scene};

/// Parses `text` as the CLI does and checks the outcome: an accepted scene satisfies every
/// rule the parser promises; a refused text gets a message that names the file, a line
/// inside the text and a key. Returns the accepted scene.
pub fn parse_checked(text: &str) -> Option<Scene> {
    match jobs::scene::parse(text, "fuzz.toml") {
        Ok(scene) => {
            check(&scene);
            Some(scene)
        }
        Err(e) => {
            let lines = text.lines().count().max(1);
            assert!(
                e.line >= 1 && e.line <= lines + 1,
                "{e}: line outside 1..={lines}"
            );
            assert!(!e.key.is_empty() && !e.message.is_empty(), "{e:?}");
            let shown = e.to_string();
            assert!(
                shown.starts_with(&format!("fuzz.toml:{}:", e.line)),
                "{shown}"
            );
            None
        }
    }
}

fn finite(xs: &[f64]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

fn check(s: &Scene) {
    let limits = jobs::scene::Limits::default();
    assert!(s.width > 0 && s.height > 0 && s.depth >= 1 && s.spp >= 1);
    assert!(s.camera.fov_y > 0.0 && s.camera.fov_y < 180.0);
    assert!(finite(&[s.bias, s.max_distance, s.camera.fov_y]));
    assert!(finite(&s.background) && finite(&s.ambient));
    assert!(finite(&s.camera.position) && finite(&s.camera.look_at) && finite(&s.camera.up));
    assert!(
        s.lights.len() < limits.max_lights,
        "ambient + {} lights",
        s.lights.len()
    );
    for l in &s.lights {
        assert!(finite(&l.position) && finite(&l.color));
        if let Some(sp) = &l.spot {
            assert!(finite(&sp.direction) && finite(&[sp.cos_outer, sp.cos_inner]));
            assert!(sp.cos_inner >= sp.cos_outer);
        }
    }
    for m in &s.materials {
        assert!(finite(&[m.diffuse.k]) && finite(&m.diffuse.color));
        if let Some(a) = &m.ambient {
            assert!(finite(&[a.k]) && finite(&a.color));
        }
        if let DiffuseModel::OrenNayar { sigma2 } = m.diffuse_model {
            assert!(sigma2.is_finite() && sigma2 >= 0.0);
        }
        if let Some(sp) = &m.specular {
            assert!(sp.exponent <= 1023 && finite(&[sp.k]) && finite(&sp.color));
        }
        match m.reflection {
            Reflection::None => {}
            Reflection::Constant(r) => assert!(r.is_finite()),
            Reflection::Fresnel { eta, k } => {
                assert!(eta > 0.0 && eta.is_finite() && k.is_finite())
            }
            Reflection::Glass { eta } => assert!(eta > 0.0 && eta.is_finite()),
        }
        if let Some(t) = &m.texture {
            assert!(finite(&t.scale) && finite(&t.offset) && finite(&t.color2));
        }
    }
    assert!(s.objects.len() <= limits.max_objects);
    for o in &s.objects {
        assert!(o.material < s.materials.len());
        assert!(o.scale.iter().all(|x| x.is_finite() && *x > 0.0));
        assert!(finite(&o.translate) && finite(&o.rotate));
    }
}
