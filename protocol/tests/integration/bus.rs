//! Controller → FPGA bus words: golden FITkit records worked out by hand, field order,
//! efficiency figures, and properties (round trip of every in-range command on every
//! layout, errors for out-of-range values, decode → encode identity on arbitrary records).

#![allow(clippy::unusual_byte_groupings)] // RGB332 literals are grouped rrr_ggg_bb on purpose.
use heapless::Vec as HVec;
use proptest::prelude::*;
use protocol::bus::{
    self, channel, efficiency, efficiency_table, fields, pack, pack_fragment, pack_into,
    quantize_rgb332, rgb332_decode, rgb332_encode, unpack, unpack_fragment, BitReader, BitWriter,
    BusError, BusLayout, Decoded, Fragment, Kind, PackOptions, EXTENDED, FITKIT, LAYOUTS,
    MAX_RECORDS, WIDE,
};
use protocol::raster::{
    Bezier, BezierPatch, Circle, Connectivity, FillRule, Filter, Line, LineAlgo, Pixel, Point,
    Polygon, RasterCmd, Rgb, SeedFill, Shade, TexRef, Triangle, Wrap,
};

fn p(x: i32, y: i32) -> Point {
    Point { x, y }
}

fn thin_line(from: Point, to: Point, color: Rgb, sub: u8) -> RasterCmd {
    RasterCmd::Line(Line {
        from,
        to,
        color,
        color_to: None,
        width: 1 << sub,
        aa: false,
        algo: LineAlgo::Bresenham,
    })
}

fn flat_tri(v: [Point; 3], color: Rgb) -> RasterCmd {
    RasterCmd::Triangle(Triangle {
        v,
        shade: Shade::Flat(color),
        z: None,
        w: None,
        tex: None,
    })
}

const FIT: PackOptions = PackOptions {
    subpixel_bits: 0,
    clear: false,
};

// ------------------------------------------------------------------ golden FITkit words

#[test]
fn fitkit_line_golden() {
    // RGB332 0b101_010_01 = 0xA9 expands by bit replication to
    // r = 101·00000 | 101·00 | 10 = 182, g = 010·00000 | 010·00 | 01 = 73, b = 01 × 0x55 = 85.
    let color = Rgb::new(182, 73, 85);
    assert_eq!(rgb332_encode(color), Some(0xA9));
    let cmd = thin_line(p(1, 2), p(300, 400), color, 0);
    // 45 bits, bit 44 first: CB=1 | x0=1 | y0=2 | x1=300 | y1=400 | colour=0xA9
    //   1 000000001 000000010 100101100 110010000 10101001
    // Record 0 holds the first 36 bits (CB, x0, y0, x1 and the top 8 bits of y1):
    //   1000 0000 0100 0000 0101 0010 1100 1100 1000 = 0x8_0405_2CC8
    // Record 1 holds the last 9 bits (y1's low bit 0, colour 10101001 = 0x0A9) at its top,
    // followed by 27 zero bits: 0x0A9 << 27 = 0x5_4800_0000.
    let v: u64 = 1 << 44 | 1 << 35 | 2 << 26 | 300 << 17 | 400 << 8 | 0xA9;
    assert_eq!(v >> 9, 0x8_0405_2CC8);
    assert_eq!((v & 0x1FF) << 27, 0x5_4800_0000);
    let opts = PackOptions {
        subpixel_bits: 0,
        clear: true,
    };
    let recs = pack(&FITKIT, &cmd, opts).unwrap();
    assert_eq!(recs.as_slice(), &[0x8_0405_2CC8, 0x5_4800_0000]);
    assert_eq!(channel(&FITKIT, Kind::Line), Ok(0x01));
    let d = unpack(&FITKIT, 0x01, &recs, 0).unwrap();
    assert_eq!(d, Decoded { clear: true, cmd });
}

#[test]
fn fitkit_triangle_golden() {
    // White (0xFF), CB = 0, vertices (0,0), (511,511), (256,128). 63 bits:
    //   0 | 000000000 000000000 | 111111111 111111111 | 100000000 010000000 | 11111111
    // Record 0 = first 36 bits: 0, eighteen 0s, then seventeen 1s = 0x1FFFF.
    // Record 1 = last 27 bits, then 9 zero bits:
    //   1 100000000 010000000 11111111 000000000
    //   = 1100 0000 0001 0000 0001 1111 1110 0000 0000 = 0xC_0101_FE00.
    let cmd = flat_tri([p(0, 0), p(511, 511), p(256, 128)], Rgb::new(255, 255, 255));
    let recs = pack(&FITKIT, &cmd, FIT).unwrap();
    assert_eq!(recs.as_slice(), &[0x1FFFF, 0xC_0101_FE00]);
    assert_eq!(channel(&FITKIT, Kind::Triangle), Ok(0x02));
    assert_eq!(
        unpack(&FITKIT, 0x02, &recs, 0).unwrap(),
        Decoded { clear: false, cmd }
    );
}

#[test]
fn fitkit_fragment_and_clear_golden() {
    // Fragment x = 511, y = 0, pure green (RGB332 000_111_00 = 0x1C), right-aligned in one
    // 36-bit record (the seed leaves the top bits unused):
    //   111111111 000000000 00011100 = 511 << 17 | 0 << 8 | 0x1C = 0x3FE_001C.
    let f = Fragment {
        x: 511,
        y: 0,
        color: Rgb::new(0, 255, 0),
    };
    let recs = pack_fragment(&FITKIT, f).unwrap();
    assert_eq!(recs.as_slice(), &[0x3FE_001C]);
    assert_eq!(unpack_fragment(&FITKIT, &recs).unwrap(), f);
    // Clear to blue on the command channel: CB = 1, colour 000_000_11 = 0x03, nine bits at
    // the top of the record: 1_0000_0011 << 27 = 0x8_1800_0000.
    let clear = RasterCmd::Clear(Rgb::new(0, 0, 255));
    let recs = pack(&FITKIT, &clear, FIT).unwrap();
    assert_eq!(recs.as_slice(), &[0x8_1800_0000]);
    assert_eq!(channel(&FITKIT, Kind::Clear), Ok(0x03));
    assert_eq!(unpack(&FITKIT, 0x03, &recs, 0).unwrap().cmd, clear);
    // A clear record without CB means nothing and is refused.
    assert!(matches!(
        unpack(&FITKIT, 0x03, &[0x0_1800_0000], 0),
        Err(BusError::InvalidCode { field: "cb", .. })
    ));
}

#[test]
fn extended_line_golden() {
    // CB 0 | opcode 0001 | gradient 0, aa 0, algo 0 | x0 = −1.5 px = −24/16 → 0xFFE8 |
    // y0 0x0000 | x1 = 2 px → 0x0020 | y1 = 3 px → 0x0030 | width 1 px → 0x0010 |
    // colour 0x123456: 112 bits in four 36-bit records, 32 zero bits of padding.
    //   r0 = 0 0001 000 1111111111101000 000000000000          = 0x0_8FFE_8000
    //   r1 = 0000 0000000000100000 0000000000110000             = 0x0_0020_0030
    //   r2 = 0000000000010000 0001_0010_0011_0100_0101          = 0x0_0101_2345
    //   r3 = 0110 then 32 zeros                                 = 0x6_0000_0000
    let cmd = thin_line(p(-24, 0), p(32, 48), Rgb::new(0x12, 0x34, 0x56), 4);
    let opts = PackOptions {
        subpixel_bits: 4,
        clear: false,
    };
    let recs = pack(&EXTENDED, &cmd, opts).unwrap();
    assert_eq!(
        recs.as_slice(),
        &[0x0_8FFE_8000, 0x0_0020_0030, 0x0_0101_2345, 0x6_0000_0000]
    );
    assert_eq!(channel(&EXTENDED, Kind::Line), Ok(bus::CHANNEL_STREAM));
    assert_eq!(
        unpack(&EXTENDED, bus::CHANNEL_STREAM, &recs, 4)
            .unwrap()
            .cmd,
        cmd
    );
}

#[test]
fn fitkit_field_order() {
    let names = |k| {
        fields(&FITKIT, k)
            .unwrap()
            .iter()
            .map(|f| (f.name, f.bits))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        names(Kind::Line),
        [
            ("cb", 1),
            ("x0", 9),
            ("y0", 9),
            ("x1", 9),
            ("y1", 9),
            ("color", 8)
        ]
    );
    assert_eq!(
        names(Kind::Triangle),
        [
            ("cb", 1),
            ("x0", 9),
            ("y0", 9),
            ("x1", 9),
            ("y1", 9),
            ("x2", 9),
            ("y2", 9),
            ("color", 8)
        ]
    );
    assert_eq!(names(Kind::Fragment), [("x", 9), ("y", 9), ("color", 8)]);
    assert!(matches!(
        fields(&FITKIT, Kind::Circle),
        Err(BusError::UnsupportedCommand { .. })
    ));
}

#[test]
fn efficiency_figures() {
    let pct = |l: &BusLayout, k| efficiency(l, k).unwrap().percent();
    let near = |a: f64, b: f64| (a - b).abs() < 0.05;
    let e = efficiency(&FITKIT, Kind::Triangle).unwrap();
    assert_eq!((e.used_bits, e.records), (63, 2));
    assert!(near(pct(&FITKIT, Kind::Triangle), 87.5));
    let e = efficiency(&FITKIT, Kind::Line).unwrap();
    assert_eq!((e.used_bits, e.records), (45, 2));
    assert!(near(pct(&FITKIT, Kind::Line), 62.5));
    let e = efficiency(&FITKIT, Kind::Fragment).unwrap();
    assert_eq!((e.used_bits, e.records), (26, 1));
    assert!(near(pct(&FITKIT, Kind::Fragment), 72.2));
    // Extended line: 1 + 4 + 3 + 4·16 + 16 + 24 = 112 bits in 4 records.
    let e = efficiency(&EXTENDED, Kind::Line).unwrap();
    assert_eq!((e.used_bits, e.records), (112, 4));
    // Wide fragment: 2·15 + 24 = 54 bits in one 64-bit record.
    let e = efficiency(&WIDE, Kind::Fragment).unwrap();
    assert_eq!((e.used_bits, e.records), (54, 1));
    let table = efficiency_table();
    // FITkit: clear, line, triangle, fragment; the others: all nine kinds.
    assert_eq!(table.len(), 4 + 9 + 9);
    for row in &table {
        println!(
            "{:9} {:9} {:4} bits {:2} × {:2} = {:5.1} %",
            row.layout,
            row.kind.name(),
            row.used_bits,
            row.records,
            row.record_bits,
            row.percent()
        );
        assert!(row.ratio() > 0.0 && row.ratio() <= 1.0);
    }
}

// ------------------------------------------------------------------ errors name the field

#[test]
fn out_of_range_values_are_named_errors() {
    let white = Rgb::new(255, 255, 255);
    let e = pack(&FITKIT, &thin_line(p(0, 0), p(512, 0), white, 0), FIT).unwrap_err();
    assert_eq!(
        e,
        BusError::OutOfRange {
            layout: "fitkit",
            field: "x1",
            value: 512,
            min: 0,
            max: 511
        }
    );
    assert!(e.to_string().contains("x1") && e.to_string().contains("512"));
    let e = pack(&FITKIT, &flat_tri([p(0, 0), p(0, -1), p(3, 3)], white), FIT).unwrap_err();
    assert!(matches!(
        e,
        BusError::OutOfRange {
            field: "y1",
            value: -1,
            ..
        }
    ));
    let e = pack(
        &FITKIT,
        &thin_line(p(0, 0), p(1, 1), Rgb::new(1, 2, 3), 0),
        FIT,
    )
    .unwrap_err();
    assert!(matches!(
        e,
        BusError::ColorNotRepresentable {
            field: "color",
            value: 0x010203,
            ..
        }
    ));
    let q = quantize_rgb332(Rgb::new(1, 2, 3));
    assert_eq!(q, Rgb::new(0, 0, 0));
    assert!(pack(&FITKIT, &thin_line(p(0, 0), p(1, 1), q, 0), FIT).is_ok());
    // Half a pixel on a whole-pixel layout.
    let opts = PackOptions {
        subpixel_bits: 1,
        clear: false,
    };
    let e = pack(&FITKIT, &thin_line(p(1, 0), p(2, 2), white, 1), opts).unwrap_err();
    assert!(matches!(
        e,
        BusError::SubpixelPrecision {
            field: "x0",
            value: 1,
            ..
        }
    ));
    // …but whole pixels in finer units are fine.
    let recs = pack(&FITKIT, &thin_line(p(2, 0), p(4, 2), white, 1), opts).unwrap();
    assert_eq!(
        unpack(&FITKIT, 1, &recs, 1).unwrap().cmd,
        thin_line(p(2, 0), p(4, 2), white, 1)
    );
    // Commands and features the FITkit lacks.
    let circle = RasterCmd::Circle(Circle {
        center: p(1, 1),
        radius: 1,
        color: white,
        fill: false,
    });
    assert!(matches!(
        pack(&FITKIT, &circle, FIT),
        Err(BusError::UnsupportedCommand {
            command: "circle",
            ..
        })
    ));
    let mut g = flat_tri([p(0, 0), p(1, 0), p(0, 1)], white);
    if let RasterCmd::Triangle(t) = &mut g {
        t.z = Some([1, 2, 3]);
    }
    assert!(matches!(
        pack(&FITKIT, &g, FIT),
        Err(BusError::UnsupportedFeature { field: "z", .. })
    ));
    // z beyond 24 bits on the extended layout.
    if let RasterCmd::Triangle(t) = &mut g {
        t.z = Some([1, 1 << 24, 3]);
    }
    let e = pack(&EXTENDED, &g, PackOptions::default()).unwrap_err();
    assert!(matches!(
        e,
        BusError::OutOfRange {
            field: "z1",
            value: 16_777_216,
            ..
        }
    ));
    // Coordinates beyond ±2048 px on the extended layout.
    let e = pack(
        &EXTENDED,
        &thin_line(p(0, 0), p(2048 * 16, 0), white, 4),
        PackOptions {
            subpixel_bits: 4,
            clear: false,
        },
    )
    .unwrap_err();
    assert!(matches!(e, BusError::OutOfRange { field: "x1", .. }));
    // Too small an output buffer.
    let mut small = [0u64; 1];
    assert!(matches!(
        pack_into(
            &FITKIT,
            &thin_line(p(0, 0), p(1, 1), white, 0),
            FIT,
            &mut small
        ),
        Err(BusError::BufferTooSmall { .. })
    ));
    // Fragments beyond 9 bits.
    assert!(matches!(
        pack_fragment(
            &FITKIT,
            Fragment {
                x: 512,
                y: 0,
                color: white
            }
        ),
        Err(BusError::OutOfRange { field: "x", .. })
    ));
}

#[test]
fn malformed_records_are_refused() {
    // Record wider than 36 bits.
    assert!(matches!(
        unpack(&FITKIT, 1, &[1 << 36, 0], 0),
        Err(BusError::RecordTooWide { index: 0, .. })
    ));
    // Padding bit set in the last line record.
    assert!(matches!(
        unpack(&FITKIT, 1, &[0, 1], 0),
        Err(BusError::NonZeroPadding { bits: 27, value: 1 })
    ));
    // Too few and too many records.
    assert!(matches!(
        unpack(&FITKIT, 1, &[0], 0),
        Err(BusError::Truncated { .. })
    ));
    assert!(matches!(
        unpack(&FITKIT, 1, &[0, 0, 0], 0),
        Err(BusError::TrailingRecords { used: 2, given: 3 })
    ));
    assert!(matches!(
        unpack(&FITKIT, 9, &[0, 0], 0),
        Err(BusError::UnknownChannel { channel: 9, .. })
    ));
    // Opcode 15 is unused on the extended layout.
    assert!(matches!(
        unpack(&EXTENDED, bus::CHANNEL_STREAM, &[0x7_8000_0000], 0),
        Err(BusError::InvalidCode {
            field: "opcode",
            value: 15,
            ..
        })
    ));
}

#[test]
fn rgb332_helpers() {
    for q in 0..=255u8 {
        assert_eq!(rgb332_encode(rgb332_decode(q)), Some(q));
        assert_eq!(quantize_rgb332(rgb332_decode(q)), rgb332_decode(q));
    }
    assert_eq!(rgb332_decode(0xFF), Rgb::new(255, 255, 255));
    assert_eq!(rgb332_decode(0x00), Rgb::new(0, 0, 0));
    assert_eq!(
        quantize_rgb332(Rgb::new(200, 100, 50)),
        rgb332_decode(0b101_011_01)
    );
    // Ties go to the darker level: 18 is 18 from 0 and 18 from 36.
    assert_eq!(quantize_rgb332(Rgb::new(18, 0, 0)), Rgb::new(0, 0, 0));
}

#[test]
fn worst_case_packets_fit() {
    // The largest packets: a textured, perspective, z-tested Gouraud triangle and a
    // 16-point polygon, on both rich layouts.
    let tri = RasterCmd::Triangle(Triangle {
        v: [p(0, 0); 3],
        shade: Shade::Gouraud([Rgb::default(); 3]),
        z: Some([0; 3]),
        w: Some([0; 3]),
        tex: Some(TexRef {
            base: 0,
            width_log2: 0,
            height_log2: 0,
            uv: [[0; 2]; 3],
            wrap: Wrap::Clamp,
            filter: Filter::Trilinear,
        }),
    });
    let poly = RasterCmd::Polygon(Polygon {
        points: HVec::from_slice(&[p(0, 0); 16]).unwrap(),
        rule: FillRule::EvenOdd,
        color: Rgb::default(),
    });
    let patch = RasterCmd::Patch(BezierPatch {
        points: [p(0, 0); 16],
        steps: 255,
        color: Rgb::default(),
    });
    for layout in [EXTENDED, WIDE] {
        for cmd in [&tri, &poly, &patch] {
            let n = pack(&layout, cmd, PackOptions::default()).unwrap().len();
            assert!(n <= MAX_RECORDS, "{} {n}", layout.name);
        }
    }
}

// ------------------------------------------------------------------ properties

fn color_for(layout: &BusLayout) -> BoxedStrategy<Rgb> {
    if layout.color_bits == 8 {
        any::<u8>().prop_map(rgb332_decode).boxed()
    } else {
        any::<(u8, u8, u8)>()
            .prop_map(|(r, g, b)| Rgb::new(r, g, b))
            .boxed()
    }
}

/// A point in range, in caller units with `sub` fraction bits (sub ≥ layout's).
fn point_for(layout: &BusLayout, sub: u8) -> BoxedStrategy<Point> {
    let (min, max) = layout.coord_range();
    let shift = sub - layout.subpixel_bits;
    (min..=max, min..=max)
        .prop_map(move |(x, y)| p((x << shift) as i32, (y << shift) as i32))
        .boxed()
}

fn length_for(layout: &BusLayout, sub: u8) -> BoxedStrategy<u32> {
    let max = (1u64 << layout.coord_bits) - 1;
    let shift = sub - layout.subpixel_bits;
    (0..=max).prop_map(move |v| (v << shift) as u32).boxed()
}

fn cmd_for(layout: BusLayout, sub: u8) -> BoxedStrategy<RasterCmd> {
    let pt = point_for(&layout, sub);
    let col = color_for(&layout);
    let len = length_for(&layout, sub);
    let one_px = 1u32 << sub;
    let clear = col.clone().prop_map(RasterCmd::Clear);
    if layout.opcode_bits == 0 {
        let line = (pt.clone(), pt.clone(), col.clone())
            .prop_map(move |(a, b, c)| thin_line(a, b, c, sub));
        let tri =
            ([pt.clone(), pt.clone(), pt.clone()], col.clone()).prop_map(|(v, c)| flat_tri(v, c));
        return prop_oneof![clear, line, tri].boxed();
    }
    let zmax = (1u32 << layout.z_bits) - 1;
    let pix = (1u16 << layout.pixel_bits()) - 1;
    let line = (
        pt.clone(),
        pt.clone(),
        col.clone(),
        proptest::option::of(col.clone()),
        len.clone(),
        any::<bool>(),
        any::<bool>(),
    )
        .prop_map(|(from, to, color, color_to, width, aa, dda)| {
            RasterCmd::Line(Line {
                from,
                to,
                color,
                color_to,
                width,
                aa,
                algo: if dda {
                    LineAlgo::Dda
                } else {
                    LineAlgo::Bresenham
                },
            })
        });
    let tex = (
        0..(1u32 << bus::TEX_BASE_BITS),
        0..16u8,
        0..16u8,
        any::<[[i32; 2]; 3]>(),
        any::<bool>(),
        0..3u8,
    )
        .prop_map(|(base, wl, hl, uv, clamp, f)| TexRef {
            base,
            width_log2: wl,
            height_log2: hl,
            uv,
            wrap: if clamp { Wrap::Clamp } else { Wrap::Repeat },
            filter: [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][f as usize],
        });
    let shade = prop_oneof![
        col.clone().prop_map(Shade::Flat),
        [col.clone(), col.clone(), col.clone()].prop_map(Shade::Gouraud)
    ];
    let tri = (
        [pt.clone(), pt.clone(), pt.clone()],
        shade,
        proptest::option::of([0..=zmax, 0..=zmax, 0..=zmax]),
        proptest::option::of(any::<[u32; 3]>()),
        proptest::option::of(tex),
    )
        .prop_map(|(v, shade, z, w, tex)| {
            RasterCmd::Triangle(Triangle {
                v,
                shade,
                z,
                w,
                tex,
            })
        });
    let circle = (pt.clone(), len.clone(), col.clone(), any::<bool>()).prop_map(
        |(center, radius, color, fill)| {
            RasterCmd::Circle(Circle {
                center,
                radius,
                color,
                fill,
            })
        },
    );
    let fill = (0..=pix, 0..=pix, col.clone(), any::<bool>()).prop_map(|(x, y, color, e)| {
        RasterCmd::Fill(SeedFill {
            seed: Pixel { x, y },
            color,
            connectivity: if e {
                Connectivity::Eight
            } else {
                Connectivity::Four
            },
        })
    });
    let poly = (
        proptest::collection::vec(pt.clone(), 3..=16),
        any::<bool>(),
        col.clone(),
    )
        .prop_map(|(pts, eo, color)| {
            RasterCmd::Polygon(Polygon {
                points: HVec::from_slice(&pts).unwrap(),
                rule: if eo {
                    FillRule::EvenOdd
                } else {
                    FillRule::NonZero
                },
                color,
            })
        });
    let bez = (
        proptest::collection::vec(pt.clone(), 3..=4),
        col.clone(),
        len,
    )
        .prop_map(|(pts, color, tolerance)| {
            RasterCmd::Bezier(Bezier {
                points: HVec::from_slice(&pts).unwrap(),
                color,
                tolerance,
            })
        });
    let patch =
        (proptest::collection::vec(pt, 16), any::<u8>(), col).prop_map(|(pts, steps, color)| {
            let mut points = [p(0, 0); 16];
            points.copy_from_slice(&pts);
            RasterCmd::Patch(BezierPatch {
                points,
                steps,
                color,
            })
        });
    let _ = one_px;
    prop_oneof![clear, line, tri, circle, fill, poly, bez, patch].boxed()
}

fn round_trip(layout: &BusLayout, cmd: &RasterCmd, sub: u8, cb: bool) -> Result<(), TestCaseError> {
    let opts = PackOptions {
        subpixel_bits: sub,
        clear: cb,
    };
    let recs = pack(layout, cmd, opts).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let ch = channel(layout, Kind::of(cmd)).unwrap();
    let d = unpack(layout, ch, &recs, sub).map_err(|e| TestCaseError::fail(e.to_string()))?;
    prop_assert_eq!(&d.cmd, cmd);
    prop_assert_eq!(d.clear, cb || matches!(cmd, RasterCmd::Clear(_)));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn fitkit_round_trips(cmd in cmd_for(FITKIT, 0), cb: bool) {
        round_trip(&FITKIT, &cmd, 0, cb)?;
    }

    #[test]
    fn fitkit_round_trips_in_finer_units(cmd in cmd_for(FITKIT, 8), cb: bool) {
        round_trip(&FITKIT, &cmd, 8, cb)?;
    }

    #[test]
    fn extended_round_trips(cmd in cmd_for(EXTENDED, 4), cb: bool) {
        round_trip(&EXTENDED, &cmd, 4, cb)?;
    }

    #[test]
    fn extended_round_trips_in_finer_units(cmd in cmd_for(EXTENDED, 8), cb: bool) {
        round_trip(&EXTENDED, &cmd, 8, cb)?;
    }

    #[test]
    fn wide_round_trips(cmd in cmd_for(WIDE, 8), cb: bool) {
        round_trip(&WIDE, &cmd, 8, cb)?;
    }

    #[test]
    fn fragments_round_trip(li in 0..3usize, x: u16, y: u16, r: u8, g: u8, b: u8) {
        let layout = &LAYOUTS[li];
        let m = (1u16 << layout.pixel_bits()) - 1;
        let color = if layout.color_bits == 8 { quantize_rgb332(Rgb::new(r, g, b)) } else { Rgb::new(r, g, b) };
        let f = Fragment { x: x & m, y: y & m, color };
        let recs = pack_fragment(layout, f).unwrap();
        prop_assert_eq!(unpack_fragment(layout, &recs).unwrap(), f);
        if x > m {
            let e = pack_fragment(layout, Fragment { x, y: 0, color }).unwrap_err();
            let is_x_out_of_range = matches!(e, BusError::OutOfRange { field: "x", .. });
            prop_assert!(is_x_out_of_range);
        }
    }

    /// Any coordinate beyond the layout's range is an error naming that coordinate.
    #[test]
    fn out_of_range_coordinates_error(li in 0..3usize, which in 0..4usize, excess in 1i64..1_000_000, below: bool) {
        let layout = &LAYOUTS[li];
        let (min, max) = layout.coord_range();
        let bad = if below { min - excess } else { max + excess };
        prop_assume!(bad >= i64::from(i32::MIN) && bad <= i64::from(i32::MAX));
        let sub = layout.subpixel_bits;
        let mut c = [0i32; 4];
        c[which] = bad as i32;
        let cmd = thin_line(p(c[0], c[1]), p(c[2], c[3]), Rgb::default(), sub);
        let e = pack(layout, &cmd, PackOptions { subpixel_bits: sub, clear: false }).unwrap_err();
        let field = ["x0", "y0", "x1", "y1"][which];
        prop_assert_eq!(e, BusError::OutOfRange { layout: layout.name, field, value: bad, min, max });
    }

    /// Colours that are not RGB332 are refused by the FITkit, never rounded.
    #[test]
    fn non_rgb332_colours_error(r: u8, g: u8, b: u8) {
        let c = Rgb::new(r, g, b);
        let cmd = flat_tri([p(0, 0), p(1, 0), p(0, 1)], c);
        let res = pack(&FITKIT, &cmd, FIT);
        if rgb332_encode(c).is_some() {
            prop_assert!(res.is_ok());
        } else {
            let is_colour_error = matches!(res, Err(BusError::ColorNotRepresentable { field: "color", .. }));
            prop_assert!(is_colour_error);
        }
    }

    /// Arbitrary records never panic the decoder, and whatever decodes re-encodes to the
    /// very same records (the encoding is canonical).
    #[test]
    fn decode_is_total_and_canonical(li in 0..3usize, ch in 0u8..6, raw in proptest::collection::vec(any::<u64>(), 0..8), narrow: bool) {
        let layout = &LAYOUTS[li];
        let m = u64::MAX >> (64 - layout.record_bits);
        let recs: Vec<u64> = raw.iter().map(|r| if narrow { r & m } else { *r }).collect();
        let sub = layout.subpixel_bits;
        if let Ok(d) = unpack(layout, ch, &recs, sub) {
            let again = pack(layout, &d.cmd, PackOptions { subpixel_bits: sub, clear: d.clear }).unwrap();
            prop_assert_eq!(again.as_slice(), recs.as_slice());
        }
    }

    /// BitWriter and BitReader agree for any field widths and record widths.
    #[test]
    fn bit_writer_reader_round_trip(rb in 1u8..=64, fields in proptest::collection::vec((1u8..=64, any::<u64>()), 1..20), start in 0usize..8) {
        let mut buf = vec![0u64; 20 * 64 + 8];
        let mut w = BitWriter::new(&mut buf, rb, start).unwrap();
        let masked: Vec<(u8, u64)> = fields.iter().map(|&(b, v)| (b, if b == 64 { v } else { v & ((1 << b) - 1) })).collect();
        for &(b, v) in &masked {
            w.write(v, b).unwrap();
        }
        let used = w.records_used();
        let mut r = BitReader::new(&buf[..used], rb, start).unwrap();
        for &(b, v) in &masked {
            prop_assert_eq!(r.read(b).unwrap(), v);
        }
        // A value wider than its field is refused, not cut.
        let mut buf2 = [0u64; 4];
        let mut w2 = BitWriter::new(&mut buf2, rb, 0).unwrap();
        prop_assert!(w2.write(2, 1).is_err());
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A valid packet with one bit flipped either is refused or decodes to a command that
    /// re-encodes to exactly the flipped records.
    #[test]
    fn bit_flips_decode_canonically(li in 0..3usize, seed in any::<u64>(), bit in any::<usize>()) {
        let layout = LAYOUTS[li];
        let sub = layout.subpixel_bits;
        let mut runner = proptest::test_runner::TestRunner::new_with_rng(
            ProptestConfig::default(),
            proptest::test_runner::TestRng::from_seed(
                proptest::test_runner::RngAlgorithm::ChaCha,
                &{ let mut s = [0u8; 32]; s[..8].copy_from_slice(&seed.to_le_bytes()); s },
            ),
        );
        let cmd = cmd_for(layout, sub).new_tree(&mut runner).unwrap().current();
        let opts = PackOptions { subpixel_bits: sub, clear: false };
        let mut recs = pack(&layout, &cmd, opts).unwrap();
        let total = recs.len() * usize::from(layout.record_bits);
        let b = bit % total;
        let rb = usize::from(layout.record_bits);
        recs[b / rb] ^= 1 << (rb - 1 - b % rb);
        let ch = channel(&layout, Kind::of(&cmd)).unwrap();
        if let Ok(d) = unpack(&layout, ch, &recs, sub) {
            let again = pack(&layout, &d.cmd, PackOptions { subpixel_bits: sub, clear: d.clear }).unwrap();
            prop_assert_eq!(again.as_slice(), recs.as_slice());
        }
    }
}

#[test]
fn layouts_are_validated() {
    for l in LAYOUTS {
        l.validate().unwrap();
    }
    let bad = BusLayout {
        coord_bits: 4,
        subpixel_bits: 4,
        ..FITKIT
    };
    assert!(matches!(
        bad.validate(),
        Err(BusError::BadLayout {
            layout: "fitkit",
            ..
        })
    ));
    assert!(pack(&bad, &RasterCmd::Clear(Rgb::default()), FIT).is_err());
    assert!(unpack(&bad, 3, &[0x8_0000_0000], 0).is_err());
    let no_channel = BusLayout {
        commands: EXTENDED.commands,
        ..FITKIT
    };
    assert!(no_channel.validate().is_err());
    let huge = PackOptions {
        subpixel_bits: 200,
        clear: false,
    };
    assert!(matches!(
        pack(&FITKIT, &RasterCmd::Clear(Rgb::default()), huge),
        Err(BusError::OutOfRange {
            field: "subpixel_bits",
            ..
        })
    ));
}

proptest! {
    /// Lengths and depths beyond their fields are errors naming the field, on every rich
    /// layout.
    #[test]
    fn out_of_range_lengths_and_depths_error(li in 1..3usize, excess in 1u32..1000, which in 0..3usize) {
        let layout = &LAYOUTS[li];
        let sub = layout.subpixel_bits;
        let opts = PackOptions { subpixel_bits: sub, clear: false };
        let radius = (1u32 << layout.coord_bits) - 1 + excess;
        let circle = RasterCmd::Circle(Circle { center: p(0, 0), radius, color: Rgb::default(), fill: false });
        let e = pack(layout, &circle, opts).unwrap_err();
        let radius_named = matches!(e, BusError::OutOfRange { field: "radius", .. });
        prop_assert!(radius_named);
        let mut z = [0u32; 3];
        z[which] = (1u32 << layout.z_bits) - 1 + excess;
        let mut t = flat_tri([p(0, 0); 3], Rgb::default());
        if let RasterCmd::Triangle(tri) = &mut t {
            tri.z = Some(z);
        }
        let e = pack(layout, &t, opts).unwrap_err();
        let field = ["z0", "z1", "z2"][which];
        let z_named = matches!(e, BusError::OutOfRange { field: f, .. } if f == field);
        prop_assert!(z_named);
    }
}
