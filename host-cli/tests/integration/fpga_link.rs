//! The controller with its FPGA behind the serial FPGA link (`protocol::fpga_link` over
//! `protocol::link`, as on a QEMU board) must produce exactly the images of the in-process
//! bus: the link changes the transport, never a bit.

use std::path::Path;

use host_cli::run::render::{Aovs, Packing, Renderer};
use host_cli::session::{Session, Transport};
use sim_board::in_process::{sim_target, sim_target_via_fpga_link};

use crate::common;

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn raster_image<T: Transport>(target: T, file: &Path) -> (Vec<u8>, u64) {
    let name = file.display().to_string();
    let job = jobs::raster::parse(&read(file), &name).expect("example parses");
    let mut session = Session::new(target);
    session.handshake().expect("handshake");
    let out = host_cli::run::raster::run(&mut session, &job, &name).expect("draws");
    (out.image.into_raw(), out.stats.device.fragments)
}

#[test]
fn raster_gallery_over_the_fpga_link_is_identical() {
    for path in common::raster_gallery() {
        let file = path.display();
        let want = raster_image(sim_target(), &path);
        let got = raster_image(sim_target_via_fpga_link().expect("link up"), &path);
        assert_eq!(want.1, got.1, "{file}: fragment counts differ");
        let diff = want.0.iter().zip(&got.0).filter(|(a, b)| a != b).count();
        assert_eq!(want.0.len(), got.0.len());
        assert_eq!(diff, 0, "{file}: {diff} bytes differ");
    }
}

#[test]
fn render_over_the_fpga_link_is_identical_and_sends_only_changes() {
    let text = read(Path::new(&common::example("reference.toml")));
    let mut scene = jobs::scene::parse(&text, "reference.toml").expect("parses");
    scene.width = 64;
    scene.height = 36;
    let regs = jobs::scene::to_regs(&scene).expect("fits");
    let numeric = protocol::frame::Numeric::Q16_16;
    let aovs = Aovs {
        depth: true,
        normal: true,
    };

    let mut direct = Session::new(sim_target());
    direct.handshake().expect("handshake");
    let (want, _) = Renderer::new()
        .frame(&mut direct, &regs, numeric, Packing::Rgb888, aovs)
        .expect("renders");

    let mut session = Session::new(sim_target_via_fpga_link().expect("link up"));
    session.handshake().expect("handshake");
    let mut renderer = Renderer::new();
    let (got, words) = renderer
        .frame(&mut session, &regs, numeric, Packing::Rgb888, aovs)
        .expect("renders over the link");
    assert_eq!(got.image.as_raw(), want.image.as_raw(), "colour differs");
    assert_eq!(got.depth, want.depth, "depth AOV differs");
    assert_eq!(got.normal, want.normal, "normal AOV differs");
    assert!(words > 200, "first frame sends the scene ({words} words)");

    scene.objects[1].translate[1] += 0.25;
    let moved = jobs::scene::to_regs(&scene).expect("fits");
    let words = common::words_for_next_frame(&mut renderer, &mut session, &moved, numeric);
    assert_eq!(words, 1, "one register changed");
}
