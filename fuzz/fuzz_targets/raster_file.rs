//! Any text through the raster command-file parser, read as TOML and as JSON. Beyond
//! "never panics":
//! - an accepted job satisfies the parser's promises (sides 1..=4096, sub-pixel bits
//!   ≤ 8, 1..=64 AA samples, every point inside the guard band on the sub-pixel grid,
//!   polygons of at most 16 points), every command fits one wire frame and survives the
//!   batcher's encode → decode unchanged, and it draws (clipped to 8 × 8, which keeps the
//!   target fast; the parser's coordinates still span the whole guard band);
//! - a refused text gets a non-empty message naming the file and a key or command index
//!   (and the line, for a TOML command).
#![no_main]
use jobs::raster::{RasterFileError, RasterJob, GUARD_BAND};
use libfuzzer_sys::fuzz_target;
use protocol::frame::{decode, HostFrame, RasterBatcher};
use protocol::raster::{AaPattern, Point, RasterCmd, MAX_POLYGON, MAX_SUBPIXEL_BITS};
use protocol::MAX_FRAME_SIDE;
use sim_target::raster::Raster;

fn check(job: &RasterJob) {
    let s = &job.setup;
    assert!((1..=MAX_FRAME_SIDE).contains(&u32::from(s.width)));
    assert!((1..=MAX_FRAME_SIDE).contains(&u32::from(s.height)));
    assert!(s.subpixel_bits <= MAX_SUBPIXEL_BITS);
    // Without an `[aa]` table the set-up is `Aa::default()` (pattern None, samples 0):
    // the sample count only means something for a real pattern.
    if s.aa.pattern != AaPattern::None {
        assert!((1..=64).contains(&s.aa.samples), "{:?}", s.aa);
    }
    let unit = f64::from(1u32 << s.subpixel_bits);
    // Snapping rounds half up, so a point at the band's open end may land on it.
    let inside = |p: &Point| {
        let (x, y) = (f64::from(p.x) / unit, f64::from(p.y) / unit);
        (-GUARD_BAND..=f64::from(s.width) + GUARD_BAND).contains(&x)
            && (-GUARD_BAND..=f64::from(s.height) + GUARD_BAND).contains(&y)
    };
    for c in &job.cmds {
        let pts: Vec<Point> = match c {
            RasterCmd::Triangle(t) => t.v.to_vec(),
            RasterCmd::Line(l) => vec![l.from, l.to],
            RasterCmd::Circle(c) => vec![c.center],
            RasterCmd::Polygon(p) => {
                assert!(p.points.len() <= MAX_POLYGON);
                p.points.to_vec()
            }
            RasterCmd::Bezier(b) => b.points.to_vec(),
            RasterCmd::Patch(p) => p.points.to_vec(),
            _ => Vec::new(),
        };
        assert!(pts.iter().all(inside), "{c:?} beyond the guard band");
    }
    // Ready for the wire: the batcher takes every command and the batches decode back.
    let mut b = RasterBatcher::new();
    let mut sent = Vec::new();
    for c in &job.cmds {
        let full = b.push(c).unwrap_or_else(|e| panic!("{c:?}: {e}"));
        sent.extend(full);
    }
    sent.extend(b.finish());
    let mut back = Vec::new();
    for batch in &sent {
        match decode::<HostFrame>(batch.as_bytes()) {
            Ok(HostFrame::Raster(v)) => back.extend(v),
            other => panic!("batch decodes to {other:?}"),
        }
    }
    assert_eq!(back, job.cmds);
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    for name in ["fuzz.toml", "fuzz.json"] {
        match jobs::raster::parse(text, name) {
            Ok(job) => {
                check(&job);
                let w = u32::from(job.setup.width).min(8);
                let h = u32::from(job.setup.height).min(8);
                if let Ok(mut block) = Raster::new(w, h, &job.setup) {
                    for c in &job.cmds {
                        let _ = block.draw(c);
                    }
                }
            }
            Err(e) => {
                let shown = e.to_string();
                assert!(shown.starts_with(name), "{shown}");
                match &e {
                    RasterFileError::Syntax { message, .. } => assert!(!message.is_empty()),
                    RasterFileError::Setting { key, message, .. } => {
                        assert!(!key.is_empty() && !message.is_empty())
                    }
                    RasterFileError::Command {
                        line, message, op, ..
                    } => {
                        assert!(!message.is_empty() && !op.is_empty());
                        if name.ends_with(".toml") {
                            let lines = text.lines().count().max(1);
                            let l = line.expect("a TOML command error has a line");
                            assert!(l >= 1 && l <= lines + 1, "{shown}");
                        }
                    }
                    // The enum is non-exhaustive: a variant added later must get its own
                    // check here rather than pass unexamined.
                    other => panic!("a RasterFileError this target does not check: {other}"),
                }
            }
        }
    }
});
