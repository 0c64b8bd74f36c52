//! The FITkit gallery scene (examples/raster/fitkit.toml, parsed as `fpgfx raster` parses
//! it) through both sides, and its pixels read back over the SPI read channel.

use std::path::Path;

use crate::harness::{Pair, MODEL_TRAVERSAL};
use crate::tally::Tally;

fn job() -> jobs::raster::RasterJob {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../examples/raster/fitkit.toml");
    let text = std::fs::read_to_string(&file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    jobs::raster::parse(&text, "fitkit.toml").expect("the gallery file parses")
}

#[test]
fn the_fitkit_scene_matches_the_model() {
    let job = job();
    let mut setup = job.setup;
    setup.traversal = MODEL_TRAVERSAL;
    let mut pair = Pair::new(setup);
    let mut t = Tally::default();
    for (k, cmd) in job.cmds.iter().enumerate() {
        let step = pair.step(&format!("fitkit.toml cmd {k}"), cmd, false);
        let case = || format!("fitkit.toml cmd {k}: {cmd:?}");
        t.add("gallery", case, &step);
    }
    t.assert_exact();
    // The read channel gives what the backdoor sees, row by row.
    let (w, h) = (u32::from(setup.width), u32::from(setup.height));
    let backdoor = pair.rtl.borrow().frame(w, h).expect("inside");
    for y in (0..h).step_by(7) {
        let row = pair.read_pixels(0, y, w as usize);
        assert_eq!(
            row,
            backdoor[(y * w) as usize..((y + 1) * w) as usize],
            "row {y}"
        );
    }
    let s = pair.status();
    assert_eq!(s.error, None, "read-back latched {s:?}");
}
