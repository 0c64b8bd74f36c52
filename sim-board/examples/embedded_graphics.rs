//! embedded-graphics drawing on the FPGA model: `cargo run -p sim-board --example
//! embedded_graphics -- out.ppm` draws a small dashboard with `firmware::Canvas`, one
//! FPGA command per primitive, prints what crossed the bus, and writes the framebuffer
//! read back from the model as a binary PPM.

use embedded_graphics::mono_font::{ascii::FONT_6X10, MonoTextStyle};
use embedded_graphics::pixelcolor::Rgb888;
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{Circle, Line, PrimitiveStyle, Rectangle, Triangle};
use embedded_graphics::text::Text;
use firmware::Canvas;
use sim_board::in_process::SimBus;
use sim_target::Device;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "embedded-graphics.ppm".into());
    let layout = &protocol::bus::WIDE;
    let (w, h) = (160u16, 100u16);
    let mut c = Canvas::new(
        SimBus(Device::new(layout)),
        layout,
        w,
        h,
        Rgb888::new(16, 16, 32),
    )
    .map_err(|e| format!("{e}"))?;
    let fill = PrimitiveStyle::with_fill;
    let draw = |c: &mut Canvas<SimBus>| -> Result<(), firmware::CanvasError<_>> {
        c.draw(
            &Rectangle::new(Point::new(4, 4), Size::new(152, 20))
                .into_styled(fill(Rgb888::new(40, 60, 120))),
        )?;
        c.draw(&Circle::new(Point::new(10, 34), 41).into_styled(fill(Rgb888::new(220, 180, 40))))?;
        c.draw(
            &Triangle::new(Point::new(70, 90), Point::new(110, 32), Point::new(150, 90))
                .into_styled(fill(Rgb888::new(60, 200, 90))),
        )?;
        for i in 0..8 {
            let y = 34 + i * 7;
            c.draw(
                &Line::new(Point::new(56, y), Point::new(150, 96 - i * 3))
                    .into_styled(PrimitiveStyle::with_stroke(Rgb888::WHITE, 1)),
            )?;
        }
        // Text has no FPGA unit: embedded-graphics draws it pixel by pixel.
        Text::new(
            "fpgfx",
            Point::new(10, 17),
            MonoTextStyle::new(&FONT_6X10, Rgb888::WHITE),
        )
        .draw(c)?;
        Ok(())
    };
    draw(&mut c).map_err(|e| format!("{e}"))?;
    c.finish().map_err(|e| format!("{e}"))?;
    let n = c.counters();
    println!(
        "{} commands, {} records, {} bytes on the bus",
        n.commands,
        n.records,
        n.bits / 8
    );
    let fb = c.bus().0.raster().ok_or("no raster block")?.framebuffer();
    let mut ppm = format!("P6\n{w} {h}\n255\n").into_bytes();
    ppm.extend_from_slice(fb.rgb());
    std::fs::write(&out, ppm)?;
    println!("wrote {out}");
    Ok(())
}
