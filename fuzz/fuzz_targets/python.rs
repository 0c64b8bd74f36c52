//! The Python package's entry points at the Rust boundary: the library calls
//! `fpgfx.raster`, `fpgfx.render` and `fpgfx.compare` make once PyO3 has turned their
//! arguments into text and arrays (`python/src/{raster,render,compare}.rs`), and the
//! TOML writing a dict argument goes through (`python/src/input.rs`). The conversion from
//! Python objects itself needs an interpreter and is left to the package's pytest suite.
//! Byte 0 picks the call; beyond "never panics":
//! - raster (`vectors::raster::trace` on the wide and FITkit layouts): a job it runs is
//!   the job `jobs::raster::parse` reads, with a frame of exactly width · height pixels
//!   (the binding shapes the array from it); a text the parser refuses is refused with
//!   the parser's message, naming the file;
//! - render (scene text → `jobs::scene::parse` → `vectors::render::render` at ≤ 8 × 8,
//!   1 spp, as `render(scene, size=…, spp=1)`): a frame has the size asked for, its
//!   planes the lengths the binding shapes, and its register image decodes to that size;
//! - compare (`compare::compare` on two RGB8 frames of fuzzed shapes, a whole tolerance
//!   0..=255 and `max_listed`): frames of different sizes are refused; otherwise the
//!   identical and the failing pixels are exactly the ones recounted here, the list
//!   holds the first `max_listed` failures in row-major order, and the mask is the frame's
//!   size;
//! - dict (text read as a TOML table, standing for the dict, and written back with
//!   `toml::to_string` as the binding writes a dict): the written text reads back as the
//!   same table, and the scene and raster parsers accept it exactly when they accept the
//!   original, reading the same scene or job.
#![no_main]
use libfuzzer_sys::fuzz_target;
use protocol::bus::LayoutId;
use protocol::frame::Numeric;
use sim_target::scene_regs::{from_regs, Regs};

mod common;
use common::Bytes;

fn same<T: std::fmt::Debug>(a: &T, b: &T) -> bool {
    format!("{a:?}") == format!("{b:?}")
}

fn raster(text: &str) {
    let name = "<raster job>";
    let parsed = jobs::raster::parse(text, name);
    // A big framebuffer is the parser's and the model's business (raster_file draws
    // clipped to 8 × 8); here every job that runs is at most 64 pixels.
    if let Ok(job) = &parsed {
        if u32::from(job.setup.width) * u32::from(job.setup.height) > 64 {
            return;
        }
    }
    for layout in [LayoutId::Wide, LayoutId::Fitkit] {
        match (vectors::raster::trace(text, name, layout), &parsed) {
            (Ok(t), Ok(job)) => {
                let s = &t.job.setup;
                assert_eq!(t.frame.len(), usize::from(s.width) * usize::from(s.height));
                assert_eq!(t.job.cmds, job.cmds);
                assert_eq!((s.width, s.height), (job.setup.width, job.setup.height));
                if layout == LayoutId::Wide {
                    assert_eq!(t.job.setup, job.setup);
                    assert!(t.spi.is_none());
                } else {
                    assert!(t.spi.is_some());
                }
            }
            (Ok(_), Err(e)) => panic!("trace ran a job the parser refuses: {e}"),
            (Err(e), Err(p)) => {
                assert_eq!(e.to_string(), p.to_string(), "not the parser's message");
                assert!(e.to_string().starts_with(name));
            }
            (Err(e), Ok(_)) => assert!(!e.to_string().is_empty()),
        }
    }
}

fn render(b: &mut Bytes) {
    let numeric = Numeric::ALL[usize::from(b.u8()) % Numeric::ALL.len()];
    let size = (u32::from(b.u8() % 8) + 1, u32::from(b.u8() % 8) + 1);
    let Ok(text) = std::str::from_utf8(b.rest()) else {
        return;
    };
    let Ok(mut scene) = jobs::scene::parse(text, "<scene>") else {
        return;
    };
    scene.spp = 1;
    // The warning the binding raises: its numbers must print.
    for d in jobs::scene::range::out_of_range(&scene, numeric) {
        assert!(
            d.value > jobs::scene::range::format_max(numeric),
            "{}",
            d.field
        );
    }
    let opts = vectors::render::Options {
        numeric,
        size: Some(size),
    };
    match vectors::render::render(&scene, &opts) {
        Ok(v) => {
            let (w, h) = size;
            let px = (w * h) as usize;
            assert_eq!((v.width, v.height), size);
            assert_eq!(v.rgb888.len(), 3 * px);
            assert_eq!(v.depth.len(), px);
            assert_eq!(v.normal.len(), 3 * px);
            let regs = Regs::from_words(&v.regs).expect("the frame's image decodes");
            let s = from_regs(&regs).expect("the frame's scene decodes");
            assert_eq!((s.width, s.height), size);
        }
        Err(e) => assert!(!e.to_string().is_empty()),
    }
}

fn compare(b: &mut Bytes) {
    let tolerance = b.u8();
    let max_listed = usize::from(b.u8() % 17);
    let (ew, eh) = (u32::from(b.u8() % 8) + 1, u32::from(b.u8() % 8) + 1);
    let differ = b.u8().is_multiple_of(8);
    let (aw, ah) = if differ {
        (u32::from(b.u8() % 8) + 1, u32::from(b.u8() % 8) + 1)
    } else {
        (ew, eh)
    };
    let src = b.rest();
    let byte = |i: usize| {
        if src.is_empty() {
            0
        } else {
            src[i % src.len()]
        }
    };
    let en = (ew * eh * 3) as usize;
    let e: Vec<u8> = (0..en).map(byte).collect();
    let a: Vec<u8> = (0..(aw * ah * 3) as usize).map(|i| byte(en + i)).collect();
    let opts = compare::Options {
        tolerance: f64::from(tolerance),
        coverage: None,
        max_listed,
    };
    let got = compare::compare(
        &compare::Frame::rgb8(ew, eh, e.clone()),
        &compare::Frame::rgb8(aw, ah, a.clone()),
        &opts,
    );
    let r = match got {
        Ok(r) => r,
        Err(err) => {
            assert_ne!((ew, eh), (aw, ah), "refused frames of one size: {err}");
            assert!(matches!(err, compare::CompareError::Size { .. }), "{err}");
            return;
        }
    };
    assert_eq!((ew, eh), (aw, ah), "compared frames of different sizes");
    assert_eq!(r.pixels(), u64::from(ew * eh));
    let (mut equal, mut failing) = (0u64, Vec::new());
    for (i, (pe, pa)) in e.chunks_exact(3).zip(a.chunks_exact(3)).enumerate() {
        let d = pe
            .iter()
            .zip(pa)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        if d == 0 {
            equal += 1;
        }
        if d > tolerance {
            failing.push(i as u32);
        }
    }
    assert_eq!(r.equal, equal);
    assert_eq!(r.failures(), failing.len() as u64);
    assert_eq!(r.near_edge, 0, "an allowance without coverage");
    assert_eq!(r.passed(), failing.is_empty());
    let listed: Vec<u32> = r.mismatches.iter().map(|m| m.y * ew + m.x).collect();
    let want: Vec<u32> = failing.iter().copied().take(max_listed).collect();
    assert_eq!(listed, want);
    assert_eq!(r.mask.len(), e.len());
}

fn dict(text: &str) {
    let Ok(table) = text.parse::<toml::Table>() else {
        return;
    };
    let Ok(written) = toml::to_string(&table) else {
        return;
    };
    let back: toml::Table = written
        .parse()
        .unwrap_or_else(|e| panic!("written TOML does not read back: {e}\n{written}"));
    assert!(
        same(&back, &table),
        "{table:?}\nwritten as\n{written}\nreads {back:?}"
    );
    let (s1, s2) = (
        jobs::scene::parse(text, "d"),
        jobs::scene::parse(&written, "d"),
    );
    match (&s1, &s2) {
        (Ok(a), Ok(b)) => assert!(same(a, b), "{a:?}\n{b:?}"),
        (Err(_), Err(_)) => {}
        _ => panic!("scene parser: {s1:?} for the text, {s2:?} written from its table"),
    }
    let (r1, r2) = (
        jobs::raster::parse(text, "d.toml"),
        jobs::raster::parse(&written, "d.toml"),
    );
    match (&r1, &r2) {
        (Ok(a), Ok(b)) => assert_eq!(a, b),
        (Err(_), Err(_)) => {}
        _ => panic!("raster parser: {r1:?} for the text, {r2:?} written from its table"),
    }
}

fuzz_target!(|data: &[u8]| {
    let mut b = Bytes(data);
    match b.u8() % 4 {
        0 => {
            if let Ok(t) = std::str::from_utf8(b.rest()) {
                raster(t)
            }
        }
        1 => render(&mut b),
        2 => compare(&mut b),
        _ => {
            if let Ok(t) = std::str::from_utf8(b.rest()) {
                dict(t)
            }
        }
    }
});
