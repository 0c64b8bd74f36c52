//! The spellings of the enums files and flags name: each value reads back from every one
//! of its spellings and from its `Display`, and a misspelling lists the choices.

use protocol::frame::Numeric;
use protocol::names::Named;
use protocol::raster::Traversal;

#[test]
fn numeric_formats_read_as_the_cli_has_always_taken_them() {
    for n in Numeric::ALL {
        assert_eq!(n.to_string().parse::<Numeric>(), Ok(n));
        for s in n.spellings() {
            assert_eq!(s.parse::<Numeric>(), Ok(n), "{s}");
            assert_eq!(s.to_ascii_uppercase().parse::<Numeric>(), Ok(n), "{s}");
        }
    }
    let names: Vec<String> = Numeric::ALL.iter().map(|n| n.to_string()).collect();
    assert_eq!(
        names,
        ["f64", "f32", "f16", "q16.16", "q8.24", "q24.8", "q32.32"]
    );
    assert_eq!("q32_32".parse::<Numeric>(), Ok(Numeric::Q32_32));
    assert_eq!("F32".parse::<Numeric>(), Ok(Numeric::F32));
    let e = "q7".parse::<Numeric>().unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown number format (expected f64, f32, f16, q16.16, q8.24, q24.8, q32.32)"
    );
}

#[test]
fn traversals_read_as_raster_files_spell_them() {
    let names: Vec<String> = Traversal::ALL.iter().map(|t| t.to_string()).collect();
    assert_eq!(names, ["bbox", "scanline", "zigzag", "tiles", "simd8"]);
    for t in Traversal::ALL {
        assert_eq!(t.to_string().parse::<Traversal>(), Ok(t));
    }
    // Case matters here, as it always has in raster files.
    assert!("Tiles".parse::<Traversal>().is_err());
    let e = "hilbert".parse::<Traversal>().unwrap_err();
    assert_eq!(
        e.expected().to_string(),
        "bbox, scanline, zigzag, tiles, simd8"
    );
}

/// Every spelling of every value of `T` reads back as that value, no spelling names two
/// values, and `VALUES` lists each value once: what `named!` promises for any table.
fn spellings_are_one_to_one<T: Named + PartialEq + core::fmt::Debug + core::str::FromStr>(
) -> Vec<String>
where
    <T as core::str::FromStr>::Err: core::fmt::Debug,
{
    let mut seen: Vec<&str> = Vec::new();
    for (i, v) in T::VALUES.iter().enumerate() {
        assert!(!T::VALUES[..i].contains(v), "{v:?} listed twice");
        for s in v.spellings() {
            assert!(!seen.contains(s), "{s:?} names two {}s", T::WHAT);
            seen.push(s);
            assert_eq!(s.parse::<T>().expect("spelling parses"), *v, "{s}");
        }
    }
    T::VALUES.iter().map(|v| v.name().to_string()).collect()
}

#[test]
fn raster_file_enums_read_as_raster_files_spell_them() {
    use protocol::raster::{AaPattern, Cull, FillRule, LineAlgo};
    assert_eq!(
        spellings_are_one_to_one::<AaPattern>(),
        ["none", "regular", "jitter", "rotated", "poisson", "coverage"]
    );
    assert_eq!(spellings_are_one_to_one::<Cull>(), ["none", "cw", "ccw"]);
    assert_eq!("clockwise".parse::<Cull>(), Ok(Cull::Clockwise));
    assert_eq!(
        "counter-clockwise".parse::<Cull>(),
        Ok(Cull::CounterClockwise)
    );
    assert_eq!(spellings_are_one_to_one::<LineAlgo>(), ["bresenham", "dda"]);
    assert_eq!(
        spellings_are_one_to_one::<FillRule>(),
        ["even-odd", "non-zero"]
    );
    spellings_are_one_to_one::<Traversal>();
    spellings_are_one_to_one::<Numeric>();
    // The lists are the enums' ALL tables, the numbering the C library and vectors use.
    assert_eq!(<AaPattern as Named>::VALUES, &AaPattern::ALL);
    assert_eq!(<Cull as Named>::VALUES, &Cull::ALL);
    let e = "diagonal".parse::<Cull>().unwrap_err();
    assert_eq!(e.to_string(), "unknown culling (expected none, cw, ccw)");
}
