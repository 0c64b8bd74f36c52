//! Scene-file errors name file, line and key.

use jobs::scene::Limits;

const BASE: &str = r#"[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov_y = 45.0
[material.m]
diffuse = { k = 1.0, color = [1.0, 1.0, 1.0] }
"#;

fn obj(material: &str, scale: &str) -> String {
    format!("[[object]]\nshape = \"sphere\"\nscale = {scale}\nmaterial = \"{material}\"\n")
}

#[test]
fn parses_reference_and_examples() {
    let s = jobs::scene::parse(
        include_str!("../../../examples/reference.toml"),
        "reference.toml",
    )
    .expect("reference");
    assert_eq!((s.width, s.height, s.depth), (1920, 1080, 2));
    assert_eq!(s.objects.len(), 8);
    for entry in
        std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/rt")).expect("dir")
    {
        let p = entry.expect("entry").path();
        let text = std::fs::read_to_string(&p).expect("read");
        jobs::scene::parse(&text, &p.display().to_string()).expect("example parses");
    }
}

#[test]
fn unknown_key_is_located() {
    let text = format!("{BASE}{}", obj("m", "[1.0, 1.0, 1.0]"))
        .replace("fov_y = 45.0", "fov_y = 45.0\nzoom = 2.0");
    let e = jobs::scene::parse(&text, "a.toml").expect_err("unknown key");
    assert_eq!(
        (e.file.as_str(), e.line, e.key.as_str()),
        ("a.toml", 6, "zoom"),
        "{e}"
    );
}

#[test]
fn missing_material_is_located() {
    let text = format!("{BASE}{}", obj("nope", "[1.0, 1.0, 1.0]"));
    let e = jobs::scene::parse(&text, "b.toml").expect_err("missing material");
    assert_eq!((e.line, e.key.as_str()), (11, "material"), "{e}");
    assert!(e.to_string().starts_with("b.toml:11:"));
}

#[test]
fn non_positive_scale_is_located() {
    let text = format!("{BASE}{}", obj("m", "[1.0, 0.0, 1.0]"));
    let e = jobs::scene::parse(&text, "c.toml").expect_err("scale");
    assert_eq!((e.line, e.key.as_str()), (10, "scale"), "{e}");
}

#[test]
fn too_many_objects_and_lights() {
    let mut text = BASE.to_string();
    for _ in 0..3 {
        text += &obj("m", "[1.0, 1.0, 1.0]");
    }
    let lim = Limits {
        max_objects: 2,
        max_lights: 2,
    };
    let e = jobs::scene::parse_with_limits(&text, "d.toml", lim).expect_err("objects");
    assert_eq!((e.line, e.key.as_str()), (16, "object"), "{e}");
    let light = "[[light]]\nposition = [0.0, 5.0, 0.0]\ncolor = [1.0, 1.0, 1.0]\n";
    let text = format!("{BASE}{light}{light}");
    let e = jobs::scene::parse(&text, "e.toml").expect_err("lights");
    assert_eq!((e.line, e.key.as_str()), (11, "light"), "{e}");
}

#[test]
fn garbage_never_panics() {
    for text in [
        "",
        "[camera",
        "camera = 3",
        "[[object]]\nshape = \"torus\"",
        "\u{0}\u{1}",
    ] {
        assert!(jobs::scene::parse(text, "g.toml").is_err());
    }
}

/// Valid TOML that other tools write: a material defined only through dotted headers
/// (`[material.clay.diffuse]`) or dotted keys. toml's `Spanned` cannot span such an
/// implicit table, so the parser must not ask for one.
#[test]
fn materials_written_as_dotted_tables_parse() {
    let camera = "[camera]\nposition = [0.0, 1.0, 5.0]\nlook_at = [0.0, 0.0, 0.0]\n\
                  up = [0.0, 1.0, 0.0]\nfov_y = 45.0\n";
    let object = "[[object]]\nshape = \"sphere\"\nmaterial = \"clay\"\n";
    let headers =
        format!("{camera}[material.clay.diffuse]\ncolor = [0.7, 0.35, 0.3]\nk = 0.9\n{object}");
    let inline = format!(
        "{camera}[material.clay]\ndiffuse = {{ color = [0.7, 0.35, 0.3], k = 0.9 }}\n{object}"
    );
    let dotted = format!(
        "material.clay.diffuse.color = [0.7, 0.35, 0.3]\nmaterial.clay.diffuse.k = 0.9\n\
         {camera}{object}"
    );
    let a = jobs::scene::parse(&headers, "headers.toml").expect("dotted headers parse");
    let b = jobs::scene::parse(&inline, "inline.toml").expect("inline tables parse");
    let c = jobs::scene::parse(&dotted, "dotted.toml").expect("dotted keys parse");
    assert_eq!(a, b);
    assert_eq!(a, c);
    // An error inside such a material still names the file, line and key.
    let bad = headers.replace("k = 0.9", "k = 0.9\nsigma2 = -1.0\nmodel = \"oren-nayar\"");
    let e = jobs::scene::parse(&bad, "bad.toml").expect_err("negative sigma2");
    let text = e.to_string();
    assert!(text.starts_with("bad.toml:6:"), "{text}");
    assert!(text.contains("sigma2"), "{text}");
}
