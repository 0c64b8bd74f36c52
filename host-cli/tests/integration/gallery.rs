//! The raster gallery (`examples/raster/*.toml`) through the whole built-in path, compared
//! byte for byte with the golden PNGs in `examples/raster/golden/`, for every traversal.
//! `FPGFX_BLESS=1 cargo test -p host-cli --test integration gallery::` rewrites the goldens
//! after an intended change (look at them before committing).

use std::path::{Path, PathBuf};

use host_cli::session::Session;
use protocol::raster::{AaPattern, Traversal};

use crate::common;

fn examples() -> PathBuf {
    common::workspace().join("examples/raster")
}

fn draw(
    file: &Path,
    traversal: Traversal,
    layout: &'static protocol::bus::BusLayout,
) -> image::RgbImage {
    let name = file.display().to_string();
    let text = std::fs::read_to_string(file).expect("example readable");
    let mut job = jobs::raster::parse(&text, &name).expect("example parses");
    job.setup.traversal = traversal;
    let mut session = Session::new(sim_board::in_process::sim_target_with(layout));
    session.handshake().expect("handshake");
    host_cli::run::raster::run(&mut session, &job, &name)
        .expect("example draws")
        .image
}

#[test]
fn gallery_matches_golden_pngs_for_every_traversal() {
    let files = common::raster_gallery();
    let bless = std::env::var_os("FPGFX_BLESS").is_some();
    for file in files {
        let stem = file
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("?")
            .to_string();
        let golden = examples().join("golden").join(format!("{stem}.png"));
        let image = draw(&file, Traversal::Tiles, &protocol::bus::WIDE);
        if bless {
            image.save(&golden).expect("write golden");
        }
        let want = image::open(&golden)
            .unwrap_or_else(|e| panic!("{}: {e}", golden.display()))
            .to_rgb8();
        let diff = want
            .pixels()
            .zip(image.pixels())
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            diff,
            0,
            "{stem}: {diff} pixels differ from {}",
            golden.display()
        );
        // AA ignores the traversal; every other file must not depend on it.
        let text = std::fs::read_to_string(&file).expect("readable");
        let aa = jobs::raster::parse(&text, &stem)
            .expect("parses")
            .setup
            .aa
            .pattern
            != AaPattern::None;
        if !aa {
            for t in [
                Traversal::BoundingBox,
                Traversal::Scanline,
                Traversal::Zigzag,
                Traversal::Simd8,
            ] {
                assert!(
                    draw(&file, t, &protocol::bus::WIDE) == image,
                    "{stem}: {t:?} differs from tiles"
                );
            }
        }
    }
}

/// What the FITkit can draw comes out the same through its 36-bit FIFO layout.
#[test]
fn fitkit_layout_draws_the_same_picture() {
    let file = examples().join("fitkit.toml");
    let wide = draw(&file, Traversal::Tiles, &protocol::bus::WIDE);
    let fitkit = draw(&file, Traversal::Tiles, &protocol::bus::FITKIT);
    assert!(wide == fitkit, "FITkit layout changed the picture");
}
