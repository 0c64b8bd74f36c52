//! Regression tests for what the `scene_file` cargo-fuzz target found (fuzz/README.md).

/// Found by `cargo fuzz run scene_file`: a NUL byte inside a comment made toml report an
/// error with an empty message, so the user saw "`?`: " and nothing else.
#[test]
fn control_character_in_a_comment_gets_a_message() {
    let text = "# a comment with a \u{0} in it\n[camera]\nposition = [0.0, 0.0, 1.0]\n";
    let e = jobs::scene::parse(text, "nul.toml").expect_err("NUL is not valid TOML");
    assert!(!e.message.trim().is_empty(), "{e:?}");
    assert_eq!(e.line, 1, "{e:?}");
    assert!(e.to_string().starts_with("nul.toml:1:"), "{e}");
}

/// Also found by the fuzz target (the input as it found it): an array cut off by a
/// comment gave the same empty message.
#[test]
fn array_cut_off_by_a_comment_gets_a_message() {
    let text = include_str!("data/fuzz_cut_array.toml");
    let e = jobs::scene::parse(text, "cut.toml").expect_err("unterminated array");
    assert!(!e.message.trim().is_empty(), "{e:?}");
    assert_eq!(e.line, 9, "{e:?}");
}
