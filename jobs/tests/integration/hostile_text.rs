//! Hostile-text helpers shared by the two file parsers' property tests
//! (`raster_file_props.rs` for raster command files, `scene_file_props.rs` for scene
//! files): both parsers take the same kind of TOML, so the literal finder and the damage
//! model are one piece of code.

use proptest::prelude::*;

/// Byte ranges of float literals (with a `.` or an exponent) outside strings and comments.
pub fn float_literals(text: &str) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut offset = 0;
    for line in text.split_inclusive('\n') {
        let code = line.split('#').next().unwrap_or("");
        // `#rrggbb` colours live inside strings; a `#` in a string cuts `code` short,
        // which only loses literals, never invents one.
        let b = code.as_bytes();
        let mut i = 0;
        let mut in_str = false;
        while i < b.len() {
            if b[i] == b'"' {
                in_str = !in_str;
                i += 1;
                continue;
            }
            let starts = !in_str
                && (b[i].is_ascii_digit() || b[i] == b'-')
                && (i == 0
                    || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.'));
            if starts {
                let s = i;
                while i < b.len() && (b[i].is_ascii_digit() || b"-+.eE_".contains(&b[i])) {
                    i += 1;
                }
                let lit = &code[s..i];
                if lit.contains(['.', 'e', 'E']) && lit.bytes().any(|d| d.is_ascii_digit()) {
                    out.push((offset + s, offset + i));
                }
                continue;
            }
            i += 1;
        }
        offset += line.len();
    }
    out
}

/// One byte edit: (position, 0 overwrite / 1 insert / 2 delete, byte).
pub type Edit = (usize, u8, u8);

/// 1…7 edits with bytes from `alphabet` (the characters that matter to the syntax, so
/// that damage hits structure rather than only values).
pub fn edits(alphabet: &'static [u8]) -> impl Strategy<Value = Vec<Edit>> {
    proptest::collection::vec(
        (
            any::<usize>(),
            0u8..3,
            prop::sample::select(alphabet.to_vec()),
        ),
        1..8,
    )
}

/// `text` with `edits` applied in order (positions taken modulo the current length), as
/// text again (an edit may cut a UTF-8 sequence: lossily decoded).
pub fn damage(text: &str, edits: &[Edit]) -> String {
    let mut b = text.as_bytes().to_vec();
    for &(i, op, v) in edits {
        let n = b.len().max(1);
        match op {
            0 => {
                if let Some(x) = b.get_mut(i % n) {
                    *x = v;
                }
            }
            1 => b.insert(i % (b.len() + 1), v),
            _ => {
                if !b.is_empty() {
                    b.remove(i % n);
                }
            }
        }
    }
    String::from_utf8_lossy(&b).into_owned()
}
