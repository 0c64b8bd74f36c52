//! Golden vectors and properties of the host <-> controller messages.
//!
//! The golden bytes were worked out by hand from postcard's wire format (varint integers,
//! zigzag for signed ones, enum variant index first, fields in declaration order) — a
//! change of any field's type, order or variant index breaks them, which is the point:
//! such a change must bump `PROTOCOL_VERSION` and the schema hash.

use heapless::{String, Vec};
use proptest::prelude::*;
use protocol::frame::*;
use protocol::raster::*;
use protocol::{MAX_PAYLOAD, PROTOCOL_VERSION};

fn vec<T: Clone, const N: usize>(items: &[T]) -> Vec<T, N> {
    Vec::from_slice(items).expect("test vector fits")
}

fn caps() -> Caps {
    Caps {
        raster: true,
        ray_trace: false,
        numeric: NumericSet(0b1001),
        pixel_formats: 0b11,
        max_width: 320,
        max_height: 240,
        max_subpixel_bits: 8,
        queue_depth: 16,
        fifo_depth: 512,
        max_objects: 8,
        max_lights: 2,
        texture_words: 65536,
        raster_layout: Some(protocol::bus::LayoutId::Fitkit),
        float_regs: NumericSet(0b11),
        rt_build: protocol::frame::RtBuild::FULL,
        link_payload: 16384,
    }
}

fn hello() -> Hello {
    Hello {
        protocol_version: 1,
        schema_hash: 0x0102_0304_0506_0708,
        caps: caps(),
        ident: String::try_from("fw").expect("short"),
    }
}

const HELLO: &[u8] = &[
    0x00, // variant Hello
    0x01, // protocol_version 1
    0x88, 0x8e, 0x98, 0xa8, 0xc0, 0xe0, 0x80, 0x81, 0x01, // schema_hash varint
    0x01, 0x00, // raster, ray_trace
    0x09, 0x03, // numeric mask, pixel formats
    0xc0, 0x02, 0xf0, 0x01, // 320, 240
    0x08, 0x10, 0x80, 0x04, // subpixel 8, queue 16, fifo 512
    0x08, 0x02, 0x80, 0x80, 0x04, // objects, lights, texture words 65536
    0x01, 0x00, // raster layout Some(Fitkit)
    0x03, // float_regs mask (f64, f32)
    0x7f, 0xff, // rt_build: every shape, any number of lights
    0xff, 0xff, 0x03, 0x3f, // max_spp 65535, every feature
    0x80, 0x80, 0x01, // link_payload 16384
    0x02, 0x66, 0x77, // "fw"
];

fn host_vectors() -> std::vec::Vec<(HostFrame, &'static [u8])> {
    let tri = Triangle {
        v: [
            Point { x: 2560, y: 5120 },
            Point { x: 51200, y: 7680 },
            Point { x: 12800, y: 46272 },
        ],
        shade: Shade::Flat(Rgb::new(255, 128, 0)),
        z: None,
        w: None,
        tex: None,
    };
    let line = Line {
        from: Point { x: 768, y: 1024 },
        to: Point { x: 25600, y: 12800 },
        color: Rgb::new(255, 255, 255),
        color_to: None,
        width: 256,
        aa: false,
        algo: LineAlgo::Dda,
    };
    let gouraud = Triangle {
        v: [Point::default(); 3],
        shade: Shade::Gouraud([Rgb::new(1, 2, 3), Rgb::new(4, 5, 6), Rgb::new(7, 8, 9)]),
        z: Some([0, 1 << 23, (1 << 24) - 1]),
        w: Some([65536; 3]),
        tex: Some(TexRef {
            base: 4096,
            width_log2: 6,
            height_log2: 5,
            uv: [[0, 0], [65536, 0], [0, -65536]],
            wrap: Wrap::Clamp,
            filter: Filter::Trilinear,
        }),
    };
    let mut patch = [Point::default(); 16];
    for (i, p) in patch.iter_mut().enumerate() {
        *p = Point {
            x: i as i32,
            y: -(i as i32),
        };
    }
    vec![
        (HostFrame::Hello(hello()), HELLO),
        (
            HostFrame::RasterSetup(RasterSetup {
                width: 320,
                height: 240,
                subpixel_bits: 8,
                background: Rgb::new(1, 2, 3),
                aa: Aa {
                    pattern: AaPattern::Rotated,
                    samples: 4,
                },
                cull: Cull::CounterClockwise,
                traversal: Traversal::Zigzag,
            }),
            &[
                0x01, 0xc0, 0x02, 0xf0, 0x01, 0x08, 0x01, 0x02, 0x03, 0x03, 0x04, 0x02, 0x02,
            ],
        ),
        (
            HostFrame::Raster(vec(&[
                RasterCmd::Clear(Rgb::new(0, 0, 0)),
                RasterCmd::Triangle(tri),
                RasterCmd::Line(line),
            ])),
            &[
                0x02, 0x03, // Raster, 3 commands
                0x00, 0x00, 0x00, 0x00, // Clear(0,0,0)
                0x02, 0x80, 0x28, 0x80, 0x50, 0x80, 0xa0, 0x06, 0x80, 0x78, 0x80, 0xc8, 0x01, 0x80,
                0xd3, 0x05, // Triangle vertices (zigzag varints)
                0x00, 0xff, 0x80, 0x00, // Flat(255,128,0)
                0x00, 0x00, 0x00, // z, w, tex: None
                0x01, 0x80, 0x0c, 0x80, 0x10, 0x80, 0x90, 0x03, 0x80, 0xc8, 0x01, // Line ends
                0xff, 0xff, 0xff, 0x00, // colour, color_to None
                0x80, 0x02, 0x00, 0x01, // width 256, aa false, Dda
            ],
        ),
        (
            HostFrame::Raster(vec(&[
                RasterCmd::Circle(Circle {
                    center: Point { x: -256, y: 300 },
                    radius: 10240,
                    color: Rgb::new(0, 255, 0),
                    fill: true,
                }),
                RasterCmd::Fill(SeedFill {
                    seed: Pixel { x: 10, y: 300 },
                    color: Rgb::new(0, 0, 255),
                    connectivity: Connectivity::Eight,
                }),
                RasterCmd::Polygon(Polygon {
                    points: vec(&[
                        Point { x: 0, y: 0 },
                        Point { x: 100, y: 0 },
                        Point { x: 0, y: -100 },
                    ]),
                    rule: FillRule::NonZero,
                    color: Rgb::new(9, 9, 9),
                }),
                RasterCmd::Bezier(Bezier {
                    points: vec(&[
                        Point { x: 1, y: 2 },
                        Point { x: 3, y: 4 },
                        Point { x: 5, y: 6 },
                    ]),
                    color: Rgb::new(7, 7, 7),
                    tolerance: 64,
                }),
            ])),
            &[
                0x02, 0x04, // Raster, 4 commands
                0x03, 0xff, 0x03, 0xd8, 0x04, 0x80, 0x50, 0x00, 0xff, 0x00, 0x01, // Circle
                0x04, 0x0a, 0xac, 0x02, 0x00, 0x00, 0xff, 0x01, // Fill
                0x05, 0x03, 0x00, 0x00, 0xc8, 0x01, 0x00, 0x00, 0xc7, 0x01, 0x01, 0x09, 0x09,
                0x09, // Polygon
                0x06, 0x03, 0x02, 0x04, 0x06, 0x08, 0x0a, 0x0c, 0x07, 0x07, 0x07,
                0x40, // Bezier
            ],
        ),
        (
            HostFrame::Raster(vec(&[RasterCmd::Patch(BezierPatch {
                points: patch,
                steps: 4,
                color: Rgb::new(1, 2, 3),
            })])),
            &[
                0x02, 0x01, 0x07, 0x00, 0x00, 0x02, 0x01, 0x04, 0x03, 0x06, 0x05, 0x08, 0x07, 0x0a,
                0x09, 0x0c, 0x0b, 0x0e, 0x0d, 0x10, 0x0f, 0x12, 0x11, 0x14, 0x13, 0x16, 0x15, 0x18,
                0x17, 0x1a, 0x19, 0x1c, 0x1b, 0x1e, 0x1d, 0x04, 0x01, 0x02, 0x03,
            ],
        ),
        (
            HostFrame::Raster(vec(&[RasterCmd::Triangle(gouraud)])),
            &[
                0x02, 0x01, 0x02, // Raster, 1 command, Triangle
                0x00, 0x00, 0x00, 0x00, 0x00, 0x00, // vertices
                0x01, 0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, // Gouraud
                0x01, 0x00, 0x80, 0x80, 0x80, 0x04, 0xff, 0xff, 0xff, 0x07, // z
                0x01, 0x80, 0x80, 0x04, 0x80, 0x80, 0x04, 0x80, 0x80, 0x04, // w
                0x01, 0x80, 0x20, 0x06, 0x05, // tex base, sizes
                0x00, 0x00, 0x80, 0x80, 0x08, 0x00, 0x00, 0xff, 0xff, 0x07, // uv
                0x01, 0x02, // Clamp, Trilinear
            ],
        ),
        (
            HostFrame::Texture(TextureWrite {
                offset: 1000,
                data: vec(&[0x11, 0x22, 0x33, 0x00]),
            }),
            &[0x03, 0xe8, 0x07, 0x04, 0x11, 0x22, 0x33, 0x00],
        ),
        (
            HostFrame::Regs(RegWrite {
                offset: 17,
                words: vec(&[0, 65536, u32::MAX]),
            }),
            &[
                0x04, 0x11, 0x03, 0x00, 0x80, 0x80, 0x04, 0xff, 0xff, 0xff, 0xff, 0x0f,
            ],
        ),
        (
            HostFrame::Start(StartFrame {
                frame_id: 7,
                block: Block::RayTrace,
                numeric: Numeric::Q16_16,
                auto_restart: true,
                aovs: false,
            }),
            &[0x05, 0x07, 0x01, 0x03, 0x01, 0x00],
        ),
        (HostFrame::Stop, &[0x06]),
        (HostFrame::Sync(300), &[0x07, 0xac, 0x02]),
        (
            HostFrame::Read(ReadRequest {
                plane: Plane::Color,
                rect: Rect {
                    x: 0,
                    y: 10,
                    w: 320,
                    h: 240,
                },
                format: PixelFormat::Rgb888,
            }),
            &[0x08, 0x00, 0x00, 0x0a, 0xc0, 0x02, 0xf0, 0x01, 0x00],
        ),
        (HostFrame::GetStats, &[0x09]),
        (HostFrame::Reset, &[0x0a]),
    ]
}

fn device_vectors() -> std::vec::Vec<(DeviceFrame, &'static [u8])> {
    vec![
        (DeviceFrame::Hello(hello()), HELLO),
        (
            DeviceFrame::Done(FrameDone {
                frame_id: 7,
                cycles: 16_765_083,
                work: 8_294_400,
            }),
            &[0x01, 0x07, 0x9b, 0xa1, 0xff, 0x07, 0x80, 0xa0, 0xfa, 0x03],
        ),
        (DeviceFrame::Synced(300), &[0x02, 0xac, 0x02]),
        (
            DeviceFrame::Chunk(ReadChunk {
                offset: 448,
                data: vec(&[1, 2, 3]),
            }),
            &[0x03, 0xc0, 0x03, 0x03, 0x01, 0x02, 0x03],
        ),
        (
            DeviceFrame::ReadDone(ReadDone {
                len: 230_400,
                crc32: 0xcbf4_3926,
            }),
            &[0x04, 0x80, 0x88, 0x0e, 0xa6, 0xf2, 0xd0, 0xdf, 0x0c],
        ),
        (
            DeviceFrame::Stats(Stats {
                link: LinkCounters {
                    sent: 100,
                    resent: 2,
                    delivered: 98,
                    crc_errors: 1,
                    framing_errors: 0,
                    duplicates: 3,
                    overflows: 4,
                    naks: 1,
                    timeouts: 5,
                    stale: 0,
                    resets: 300,
                },
                device: DeviceCounters {
                    commands: 5,
                    bus_words: 200,
                    fragments: 10,
                    cycles: 123_456,
                    fifo_stalls: 1_000_000,
                    frames: 17,
                    queue_free: 1,
                    saturations: 300,
                },
            }),
            &[
                0x05, // Stats
                0x64, 0x02, 0x62, 0x01, 0x00, 0x03, 0x04, 0x01, 0x05, 0x00, 0xac,
                0x02, // link counters
                0x05, 0xc8, 0x01, 0x0a, 0xc0, 0xc4, 0x07, 0xc0, 0x84, 0x3d, 0x11, 0x01, 0xac,
                0x02, // device counters
            ],
        ),
        (
            DeviceFrame::Error(ErrorReport {
                code: ErrorCode::OutOfRange,
                seq: 513,
                index: 2,
            }),
            &[0x06, 0x01, 0x81, 0x04, 0x02],
        ),
    ]
}

#[test]
fn host_frames_match_golden_bytes() {
    for (msg, bytes) in host_vectors() {
        let mut buf = [0u8; MAX_PAYLOAD];
        let got = encode(&msg, &mut buf).expect("fits");
        assert_eq!(got, bytes, "encoding of {msg:?}");
        assert_eq!(decode::<HostFrame>(bytes).expect("decodes"), msg);
    }
}

#[test]
fn device_frames_match_golden_bytes() {
    for (msg, bytes) in device_vectors() {
        let mut buf = [0u8; MAX_PAYLOAD];
        let got = encode(&msg, &mut buf).expect("fits");
        assert_eq!(got, bytes, "encoding of {msg:?}");
        assert_eq!(decode::<DeviceFrame>(bytes).expect("decodes"), msg);
    }
}

#[test]
fn every_variant_has_a_golden_vector() {
    // Variant indices are the first byte; a new variant without a vector fails here.
    let host: std::collections::BTreeSet<u8> = host_vectors().iter().map(|(_, b)| b[0]).collect();
    assert_eq!(host, (0..=10).collect());
    let dev: std::collections::BTreeSet<u8> = device_vectors().iter().map(|(_, b)| b[0]).collect();
    assert_eq!(dev, (0..=6).collect());
    let cmds: std::collections::BTreeSet<u8> = host_vectors()
        .iter()
        .filter(|(_, b)| b[0] == 2)
        .flat_map(|(m, _)| match m {
            HostFrame::Raster(cmds) => cmds
                .iter()
                .map(|c| {
                    let mut buf = [0u8; MAX_PAYLOAD];
                    encode(c, &mut buf).expect("fits")[0]
                })
                .collect::<std::vec::Vec<_>>(),
            _ => unreachable!(),
        })
        .collect();
    assert_eq!(cmds, (0..=7).collect());
}

#[test]
fn schema_hash_is_pinned() {
    // If this fails you changed the message schema. That is allowed, but do it on purpose:
    // update the constant below and bump PROTOCOL_VERSION if old peers must be refused
    // by version rather than by hash.
    assert_eq!(SCHEMA_HASH, schema_hash());
    println!("schema hash {SCHEMA_HASH:#018x}");
    assert_eq!(SCHEMA_HASH, 0xa32e_579f_563e_8418);
}

#[test]
fn handshake_names_both_sides() {
    let mut peer = Hello::new(Caps::default(), "peer");
    assert_eq!(peer.check(), Ok(()));
    peer.schema_hash ^= 1;
    let err = peer.check().expect_err("mismatch");
    let text = err.to_string();
    assert!(text.contains(&format!("{:#018x}", SCHEMA_HASH)), "{text}");
    assert!(
        text.contains(&format!("{:#018x}", SCHEMA_HASH ^ 1)),
        "{text}"
    );
    peer.protocol_version = 99;
    let text = peer.check().expect_err("mismatch").to_string();
    let ours = format!("v{PROTOCOL_VERSION}");
    assert!(text.contains("v99") && text.contains(&ours), "{text}");
}

#[test]
fn hello_ident_is_cut_not_refused() {
    let long = "x".repeat(100);
    assert_eq!(Hello::new(Caps::default(), &long).ident.len(), IDENT_LEN);
}

#[test]
fn trailing_bytes_are_an_error() {
    assert_eq!(
        decode::<HostFrame>(&[0x09, 0x00]),
        Err(CodecError::Trailing(1))
    );
    assert!(matches!(
        decode::<HostFrame>(&[0x0b]),
        Err(CodecError::Decode(_))
    ));
    assert!(matches!(
        decode::<HostFrame>(&[]),
        Err(CodecError::Decode(_))
    ));
}

/// The worst case of every bounded message must fit a frame: maximal counts and values
/// whose varints take the most bytes.
#[test]
fn worst_case_messages_fit_a_frame() {
    let far = Point {
        x: i32::MIN,
        y: i32::MIN,
    };
    let worst_cmds = [
        RasterCmd::Polygon(Polygon {
            points: Vec::from_slice(&[far; MAX_POLYGON]).expect("cap"),
            rule: FillRule::NonZero,
            color: Rgb::default(),
        }),
        RasterCmd::Patch(BezierPatch {
            points: [far; 16],
            steps: 255,
            color: Rgb::default(),
        }),
        RasterCmd::Triangle(Triangle {
            v: [far; 3],
            shade: Shade::Gouraud([Rgb::default(); 3]),
            z: Some([u32::MAX; 3]),
            w: Some([u32::MAX; 3]),
            tex: Some(TexRef {
                base: u32::MAX,
                width_log2: 255,
                height_log2: 255,
                uv: [[i32::MIN; 2]; 3],
                wrap: Wrap::Repeat,
                filter: Filter::Trilinear,
            }),
        }),
        RasterCmd::Bezier(Bezier {
            points: Vec::from_slice(&[far; 4]).expect("cap"),
            color: Rgb::default(),
            tolerance: u32::MAX,
        }),
    ];
    let mut buf = [0u8; MAX_PAYLOAD];
    for cmd in worst_cmds {
        let mut b = RasterBatcher::new();
        assert_eq!(b.push(&cmd), Ok(None));
        let msg = b.finish().expect("one batch");
        assert_eq!(
            msg.to_frame(),
            Ok(HostFrame::Raster(
                Vec::from_slice(std::slice::from_ref(&cmd)).expect("cap")
            ))
        );
        let len = encode(&msg.to_frame().expect("decodes"), &mut buf)
            .expect("worst-case command fits alone")
            .len();
        assert_eq!(len, msg.as_bytes().len());
        assert!(len <= MAX_PAYLOAD, "{cmd:?}: {len}");
    }
    let big: [HostFrame; 4] = [
        HostFrame::Regs(RegWrite {
            offset: u16::MAX,
            words: Vec::from_slice(&[u32::MAX; REG_WRITE_WORDS]).expect("cap"),
        }),
        HostFrame::Texture(TextureWrite {
            offset: u32::MAX,
            data: Vec::from_slice(&[0xff; TEXTURE_CHUNK]).expect("cap"),
        }),
        HostFrame::Hello(Hello::new(
            Caps {
                texture_words: u32::MAX,
                ..Default::default()
            },
            &"é".repeat(IDENT_LEN),
        )),
        HostFrame::Animate(protocol::frame::Animation {
            ramps: Vec::from_slice(
                &[protocol::frame::Ramp {
                    reg: u16::MAX,
                    step: i32::MIN,
                }; protocol::frame::MAX_RAMPS],
            )
            .expect("cap"),
            orbits: Vec::from_slice(
                &[protocol::frame::Orbit {
                    x_reg: u16::MAX,
                    z_reg: u16::MAX,
                    center: [i32::MIN; 2],
                    cos: i32::MIN,
                    sin: i32::MIN,
                }; protocol::frame::MAX_ORBITS],
            )
            .expect("cap"),
        }),
    ];
    for msg in big {
        assert!(encode(&msg, &mut buf).is_ok(), "{msg:?}");
    }
    let chunk = DeviceFrame::Chunk(ReadChunk {
        offset: u32::MAX,
        data: Vec::from_slice(&[0xff; READ_CHUNK]).expect("cap"),
    });
    assert!(encode(&chunk, &mut buf).is_ok());
    let stats = DeviceFrame::Stats(Stats {
        link: LinkCounters {
            sent: u32::MAX,
            resent: u32::MAX,
            delivered: u32::MAX,
            crc_errors: u32::MAX,
            framing_errors: u32::MAX,
            duplicates: u32::MAX,
            overflows: u32::MAX,
            naks: u32::MAX,
            timeouts: u32::MAX,
            stale: u32::MAX,
            resets: u32::MAX,
        },
        device: DeviceCounters {
            commands: u32::MAX,
            bus_words: u32::MAX,
            fragments: u64::MAX,
            cycles: u64::MAX,
            fifo_stalls: u64::MAX,
            frames: u32::MAX,
            queue_free: u16::MAX,
            saturations: u64::MAX,
        },
    });
    assert!(encode(&stats, &mut buf).is_ok());
}

#[test]
fn batcher_fills_by_count_and_by_bytes() {
    let tri = RasterCmd::Triangle(Triangle {
        v: [Point { x: 100, y: 100 }; 3],
        shade: Shade::Flat(Rgb::default()),
        z: None,
        w: None,
        tex: None,
    });
    let mut b = RasterBatcher::new();
    let mut batches = std::vec::Vec::new();
    for _ in 0..20 {
        batches.extend(b.push(&tri).expect("fits"));
    }
    batches.extend(b.finish());
    let sizes: std::vec::Vec<usize> = batches
        .iter()
        .map(|m| match m.to_frame() {
            Ok(HostFrame::Raster(c)) => c.len(),
            _ => 0,
        })
        .collect();
    assert_eq!(sizes, [8, 8, 4]);

    // Large polygons: the byte limit closes batches before the count does.
    let far = Point {
        x: i32::MIN,
        y: i32::MAX,
    };
    let poly = RasterCmd::Polygon(Polygon {
        points: Vec::from_slice(&[far; MAX_POLYGON]).expect("cap"),
        rule: FillRule::EvenOdd,
        color: Rgb::default(),
    });
    let mut n = 0;
    let mut buf = [0u8; MAX_PAYLOAD];
    for _ in 0..5 {
        if let Some(msg) = b.push(&poly).expect("fits") {
            n += 1;
            assert!(encode(&msg.to_frame().expect("decodes"), &mut buf).is_ok());
        }
    }
    assert_eq!(n, 4, "each 166-byte polygon needs a frame of its own");
}

// ---- property tests ----

fn rgb() -> impl Strategy<Value = Rgb> {
    any::<[u8; 3]>().prop_map(|[r, g, b]| Rgb { r, g, b })
}
fn point() -> impl Strategy<Value = Point> {
    any::<(i32, i32)>().prop_map(|(x, y)| Point { x, y })
}
fn triangle() -> impl Strategy<Value = Triangle> {
    let shade = prop_oneof![
        rgb().prop_map(Shade::Flat),
        [rgb(), rgb(), rgb()].prop_map(Shade::Gouraud)
    ];
    let tex = (
        any::<u32>(),
        any::<u8>(),
        any::<u8>(),
        any::<[[i32; 2]; 3]>(),
        any::<bool>(),
        0..3u8,
    )
        .prop_map(|(base, w, h, uv, clamp, f)| TexRef {
            base,
            width_log2: w,
            height_log2: h,
            uv,
            wrap: if clamp { Wrap::Clamp } else { Wrap::Repeat },
            filter: [Filter::Nearest, Filter::Bilinear, Filter::Trilinear][f as usize],
        });
    (
        [point(), point(), point()],
        shade,
        any::<Option<[u32; 3]>>(),
        any::<Option<[u32; 3]>>(),
        proptest::option::of(tex),
    )
        .prop_map(|(v, shade, z, w, tex)| Triangle {
            v,
            shade,
            z,
            w,
            tex,
        })
}
fn raster_cmd() -> impl Strategy<Value = RasterCmd> {
    prop_oneof![
        rgb().prop_map(RasterCmd::Clear),
        (
            point(),
            point(),
            rgb(),
            proptest::option::of(rgb()),
            any::<u32>(),
            any::<bool>(),
            any::<bool>()
        )
            .prop_map(
                |(from, to, color, color_to, width, aa, dda)| RasterCmd::Line(Line {
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
            ),
        triangle().prop_map(RasterCmd::Triangle),
        (point(), any::<u32>(), rgb(), any::<bool>()).prop_map(|(center, radius, color, fill)| {
            RasterCmd::Circle(Circle {
                center,
                radius,
                color,
                fill,
            })
        }),
        (any::<(u16, u16)>(), rgb(), any::<bool>()).prop_map(|((x, y), color, eight)| {
            RasterCmd::Fill(SeedFill {
                seed: Pixel { x, y },
                color,
                connectivity: if eight {
                    Connectivity::Eight
                } else {
                    Connectivity::Four
                },
            })
        }),
        (
            proptest::collection::vec(point(), 0..=MAX_POLYGON),
            any::<bool>(),
            rgb()
        )
            .prop_map(|(p, nz, color)| RasterCmd::Polygon(Polygon {
                points: Vec::from_slice(&p).expect("cap"),
                rule: if nz {
                    FillRule::NonZero
                } else {
                    FillRule::EvenOdd
                },
                color,
            })),
        (
            proptest::collection::vec(point(), 3..=4),
            rgb(),
            any::<u32>()
        )
            .prop_map(|(p, color, tolerance)| RasterCmd::Bezier(Bezier {
                points: Vec::from_slice(&p).expect("cap"),
                color,
                tolerance,
            })),
        (proptest::array::uniform16(point()), any::<u8>(), rgb()).prop_map(
            |(points, steps, color)| RasterCmd::Patch(BezierPatch {
                points,
                steps,
                color
            })
        ),
    ]
}
fn numeric() -> impl Strategy<Value = Numeric> {
    (0..Numeric::ALL.len()).prop_map(|i| Numeric::ALL[i])
}
fn pixel_format() -> impl Strategy<Value = PixelFormat> {
    prop_oneof![
        Just(PixelFormat::Rgb888),
        Just(PixelFormat::Rgb332),
        Just(PixelFormat::Kcu116),
        Just(PixelFormat::DepthF32),
        Just(PixelFormat::NormalF32),
    ]
}
fn hello_s() -> impl Strategy<Value = Hello> {
    (
        any::<u16>(),
        any::<u64>(),
        (
            any::<(bool, bool, u16, u8, u16, u16)>(),
            any::<(u8, u16, u16, u8, u8, u32)>(),
        ),
        "[a-z0-9 .]{0,32}",
        (
            proptest::option::of(prop_oneof![
                Just(protocol::bus::LayoutId::Fitkit),
                Just(protocol::bus::LayoutId::Extended),
                Just(protocol::bus::LayoutId::Wide),
            ]),
            any::<u16>(),
        ),
    )
        .prop_map(|(v, h, (a, b), ident, (raster_layout, float_regs))| {
            let c = (a.0, a.1, a.2, a.3, a.4, a.5, b.0, b.1, b.2, b.3, b.4, b.5);
            Hello {
                protocol_version: v,
                schema_hash: h,
                caps: Caps {
                    raster: c.0,
                    ray_trace: c.1,
                    numeric: NumericSet(c.2),
                    pixel_formats: c.3,
                    max_width: c.4,
                    max_height: c.5,
                    max_subpixel_bits: c.6,
                    queue_depth: c.7,
                    fifo_depth: c.8,
                    max_objects: c.9,
                    max_lights: c.10,
                    texture_words: c.11,
                    raster_layout,
                    float_regs: NumericSet(float_regs),
                    rt_build: protocol::frame::RtBuild::FULL,
                    link_payload: 0,
                },
                ident: String::try_from(ident.as_str()).expect("≤ 32 ASCII bytes"),
            }
        })
}
fn host_frame() -> impl Strategy<Value = HostFrame> {
    prop_oneof![
        hello_s().prop_map(HostFrame::Hello),
        (
            any::<(u16, u16, u8)>(),
            rgb(),
            0..6u8,
            any::<u8>(),
            0..3u8,
            0..5u8
        )
            .prop_map(
                |((width, height, subpixel_bits), background, p, samples, c, t)| {
                    HostFrame::RasterSetup(RasterSetup {
                        width,
                        height,
                        subpixel_bits,
                        background,
                        aa: Aa {
                            pattern: [
                                AaPattern::None,
                                AaPattern::Regular,
                                AaPattern::Jitter,
                                AaPattern::Rotated,
                                AaPattern::Poisson,
                                AaPattern::Coverage,
                            ][p as usize],
                            samples,
                        },
                        cull: [Cull::None, Cull::Clockwise, Cull::CounterClockwise][c as usize],
                        traversal: [
                            Traversal::BoundingBox,
                            Traversal::Scanline,
                            Traversal::Zigzag,
                            Traversal::Tiles,
                            Traversal::Simd8,
                        ][t as usize],
                    })
                }
            ),
        proptest::collection::vec(raster_cmd(), 0..=RASTER_BATCH)
            .prop_map(|c| HostFrame::Raster(Vec::from_slice(&c).expect("cap"))),
        (
            any::<u32>(),
            proptest::collection::vec(any::<u8>(), 0..=TEXTURE_CHUNK)
        )
            .prop_map(|(offset, d)| HostFrame::Texture(TextureWrite {
                offset,
                data: Vec::from_slice(&d).expect("cap")
            })),
        (
            any::<u16>(),
            proptest::collection::vec(any::<u32>(), 0..=REG_WRITE_WORDS)
        )
            .prop_map(|(offset, w)| HostFrame::Regs(RegWrite {
                offset,
                words: Vec::from_slice(&w).expect("cap")
            })),
        (
            any::<u32>(),
            any::<bool>(),
            numeric(),
            any::<bool>(),
            any::<bool>()
        )
            .prop_map(|(frame_id, rt, numeric, auto_restart, aovs)| {
                HostFrame::Start(StartFrame {
                    frame_id,
                    block: if rt { Block::RayTrace } else { Block::Raster },
                    numeric,
                    auto_restart,
                    aovs,
                })
            }),
        Just(HostFrame::Stop),
        any::<u32>().prop_map(HostFrame::Sync),
        (0..3u8, any::<(u16, u16, u16, u16)>(), pixel_format()).prop_map(
            |(p, (x, y, w, h), format)| {
                HostFrame::Read(ReadRequest {
                    plane: [Plane::Color, Plane::Depth, Plane::Normal][p as usize],
                    rect: Rect { x, y, w, h },
                    format,
                })
            }
        ),
        Just(HostFrame::GetStats),
        Just(HostFrame::Reset),
    ]
}
fn device_frame() -> impl Strategy<Value = DeviceFrame> {
    prop_oneof![
        hello_s().prop_map(DeviceFrame::Hello),
        any::<(u32, u64, u64)>().prop_map(|(frame_id, cycles, work)| DeviceFrame::Done(
            FrameDone {
                frame_id,
                cycles,
                work
            }
        )),
        any::<u32>().prop_map(DeviceFrame::Synced),
        (
            any::<u32>(),
            proptest::collection::vec(any::<u8>(), 0..=READ_CHUNK)
        )
            .prop_map(|(offset, d)| {
                DeviceFrame::Chunk(ReadChunk {
                    offset,
                    data: Vec::from_slice(&d).expect("cap"),
                })
            }),
        any::<(u32, u32)>().prop_map(|(len, crc32)| DeviceFrame::ReadDone(ReadDone { len, crc32 })),
        (
            any::<[u32; 11]>(),
            (any::<(u32, u32, u64)>(), any::<(u64, u64, u32, u16, u64)>())
                .prop_map(|(a, b)| (a.0, a.1, a.2, b.0, b.1, b.2, b.3, b.4))
        )
            .prop_map(|(l, d)| {
                DeviceFrame::Stats(Stats {
                    link: LinkCounters {
                        sent: l[0],
                        resent: l[1],
                        delivered: l[2],
                        crc_errors: l[3],
                        framing_errors: l[4],
                        duplicates: l[5],
                        overflows: l[6],
                        naks: l[7],
                        timeouts: l[8],
                        stale: l[9],
                        resets: l[10],
                    },
                    device: DeviceCounters {
                        commands: d.0,
                        bus_words: d.1,
                        fragments: d.2,
                        cycles: d.3,
                        fifo_stalls: d.4,
                        frames: d.5,
                        queue_free: d.6,
                        saturations: d.7,
                    },
                })
            }),
        (0..6u8, any::<(u16, u32)>()).prop_map(|(c, (seq, index))| {
            DeviceFrame::Error(ErrorReport {
                code: [
                    ErrorCode::Malformed,
                    ErrorCode::OutOfRange,
                    ErrorCode::Unsupported,
                    ErrorCode::BadState,
                    ErrorCode::Handshake,
                    ErrorCode::Device,
                ][c as usize],
                seq,
                index,
            })
        }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// Any command sequence survives the batcher: every batch decodes as a message and
    /// walks in place to the same commands, in order, none lost or split.
    #[test]
    fn batcher_preserves_every_command(cmds in proptest::collection::vec(raster_cmd(), 0..40)) {
        let mut b = RasterBatcher::new();
        let mut batches = std::vec::Vec::new();
        for c in &cmds {
            batches.extend(b.push(c).expect("every generated command fits alone"));
        }
        batches.extend(b.finish());
        let mut walked = std::vec::Vec::new();
        let mut decoded = std::vec::Vec::new();
        for batch in &batches {
            prop_assert!(batch.count() >= 1 && batch.count() <= RASTER_BATCH);
            prop_assert!(batch.as_bytes().len() <= MAX_PAYLOAD);
            for c in raster_commands(batch.as_bytes()).expect("a raster batch") {
                walked.push(c.expect("decodes"));
            }
            match batch.to_frame() {
                Ok(HostFrame::Raster(v)) => decoded.extend(v),
                other => prop_assert!(false, "{other:?}"),
            }
        }
        prop_assert_eq!(&walked, &cmds);
        prop_assert_eq!(&decoded, &cmds);
    }

    /// Every host message round-trips; one that is too large is refused, never cut.
    #[test]
    fn host_frames_round_trip(msg in host_frame()) {
        let mut buf = [0u8; 4096];
        let full = postcard::to_slice(&msg, &mut buf).expect("big buffer").len();
        let mut small = [0u8; MAX_PAYLOAD];
        match encode(&msg, &mut small) {
            Ok(bytes) => {
                prop_assert_eq!(bytes.len(), full);
                prop_assert_eq!(decode::<HostFrame>(bytes).expect("round trip"), msg);
            }
            Err(e) => {
                prop_assert!(full > MAX_PAYLOAD);
                prop_assert_eq!(e, CodecError::TooLarge);
            }
        }
    }

    #[test]
    fn device_frames_round_trip(msg in device_frame()) {
        let mut buf = [0u8; MAX_PAYLOAD];
        let bytes = encode(&msg, &mut buf).expect("every device frame fits");
        prop_assert_eq!(decode::<DeviceFrame>(bytes).expect("round trip"), msg);
    }

    /// Any bytes decode to a message or a clear error, never a panic; a message that
    /// decodes re-encodes to the same bytes (no two encodings of one value are accepted).
    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let mut buf = [0u8; 4096];
        if let Ok(msg) = decode::<HostFrame>(&bytes) {
            let again = postcard::to_slice(&msg, &mut buf).expect("fits");
            prop_assert_eq!(decode::<HostFrame>(again).expect("re-decodes"), msg);
        }
        if let Ok(msg) = decode::<DeviceFrame>(&bytes) {
            let again = postcard::to_slice(&msg, &mut buf).expect("fits");
            prop_assert_eq!(decode::<DeviceFrame>(again).expect("re-decodes"), msg);
        }
    }

    /// Truncating a valid message anywhere is an error, never a shorter valid message of
    /// the same variant with made-up fields.
    #[test]
    fn truncation_is_detected(msg in host_frame(), cut in 0usize..300) {
        let mut buf = [0u8; 4096];
        let bytes = postcard::to_slice(&msg, &mut buf).expect("big buffer");
        let cut = cut % bytes.len().max(1);
        prop_assert!(decode::<HostFrame>(&bytes[..cut]).is_err());
    }
}

mod animation {
    use protocol::frame::{Orbit, Ramp};

    fn orbit(angle: f64, center: [f64; 2]) -> Orbit {
        let q30 = |v: f64| (v * Orbit::ONE as f64).round() as i32;
        Orbit {
            x_reg: 0,
            z_reg: 1,
            center: center.map(|c| (c * 65536.0).round() as i32),
            cos: q30(angle.cos()),
            sin: q30(angle.sin()),
        }
    }

    fn q16(v: f64) -> u32 {
        (v * 65536.0).round() as i32 as u32
    }

    fn f(v: u32) -> f64 {
        v as i32 as f64 / 65536.0
    }

    /// A quarter turn about (1, 2) takes (4, 2) to (1, 5), exactly.
    #[test]
    fn orbit_quarter_turn_is_exact() {
        let o = orbit(std::f64::consts::FRAC_PI_2, [1.0, 2.0]);
        assert_eq!(o.apply(q16(4.0), q16(2.0)), (q16(1.0), q16(5.0)));
    }

    /// 360 steps of one degree come back to the start within 2⁻¹⁶ per step, and the radius
    /// stays within the same bound (rounding, not truncation, so it does not shrink).
    #[test]
    fn orbit_full_circle_drift_is_bounded() {
        let o = orbit(1f64.to_radians(), [0.5, -3.0]);
        let (x0, z0) = (q16(6.5), q16(-3.0));
        let (mut x, mut z) = (x0, z0);
        for _ in 0..360 {
            (x, z) = o.apply(x, z);
            let r = (f(x) - 0.5).hypot(f(z) + 3.0);
            assert!((r - 6.0).abs() < 360.0 / 65536.0, "radius {r}");
        }
        assert!(
            (f(x) - f(x0)).abs() < 0.01 && (f(z) - f(z0)).abs() < 0.01,
            "{} {}",
            f(x),
            f(z)
        );
    }

    #[test]
    fn ramp_wraps_instead_of_overflowing() {
        let r = Ramp { reg: 0, step: 1 };
        assert_eq!(r.apply(i32::MAX as u32), i32::MIN as u32);
        assert_eq!(
            Ramp {
                reg: 0,
                step: -65536
            }
            .apply(q16(1.5)),
            q16(0.5)
        );
    }
}

/// A chunk message as a controller writes it in place: the header, then the bytes.
fn chunk_in_place(offset: u32, data: &[u8]) -> std::vec::Vec<u8> {
    let (head, n) = chunk_header(offset, data.len() as u32);
    let mut out = head[..n].to_vec();
    out.extend_from_slice(data);
    out
}

#[test]
fn the_chunk_tag_is_the_variant_serde_gives_chunk() {
    let mut buf = [0u8; MAX_PAYLOAD];
    let empty = DeviceFrame::Chunk(ReadChunk {
        offset: 0,
        data: Vec::new(),
    });
    let bytes = encode(&empty, &mut buf).expect("fits");
    assert_eq!(bytes, [CHUNK_TAG as u8, 0, 0]);
}

#[test]
fn chunks_of_any_size_read_back_where_a_read_chunk_cannot() {
    for len in [0, 1, 127, 128, READ_CHUNK, 16_352, 70_000] {
        let data: std::vec::Vec<u8> = (0..len).map(|i| (i * 7) as u8).collect();
        let msg = chunk_in_place(0x1234_5678, &data);
        let (offset, bytes) = chunk_view(&msg).expect("a chunk").expect("decodes");
        assert_eq!((offset, bytes), (0x1234_5678, &data[..]), "len {len}");
        // Only a board-sized one is also a `DeviceFrame`.
        assert_eq!(
            decode::<DeviceFrame>(&msg).is_ok(),
            len <= READ_CHUNK,
            "len {len}"
        );
    }
}

#[test]
fn chunk_view_leaves_other_answers_and_refuses_a_chunk_whose_length_is_wrong() {
    let mut buf = [0u8; MAX_PAYLOAD];
    for msg in [
        DeviceFrame::Synced(7),
        DeviceFrame::ReadDone(ReadDone { len: 3, crc32: 9 }),
        DeviceFrame::Hello(hello()),
    ] {
        let bytes = encode(&msg, &mut buf).expect("fits");
        assert!(chunk_view(bytes).is_none(), "{msg:?}");
    }
    let msg = chunk_in_place(5, &[1, 2, 3, 4]);
    assert!(matches!(chunk_view(&msg[..msg.len() - 1]), Some(Err(_))));
    let mut long = msg.clone();
    long.push(0);
    assert_eq!(chunk_view(&long), Some(Err(CodecError::Trailing(1))));
    // The longest header is CHUNK_HEADER_MAX bytes.
    assert_eq!(chunk_header(u32::MAX, u32::MAX).1, CHUNK_HEADER_MAX);
    assert_eq!(chunk_header(0, 0).1, 3);
}

#[test]
fn a_board_sized_link_carries_read_chunk_bytes_and_larger_ones_the_same_margin() {
    assert_eq!(read_chunk_len(MAX_PAYLOAD), READ_CHUNK);
    assert_eq!(
        Caps::default().link_payload(),
        MAX_PAYLOAD,
        "an end that says nothing accepts MAX_PAYLOAD"
    );
    // The worst header (tag, a 5-byte offset, a 3-byte length) fits the margin.
    let len = read_chunk_len(protocol::link::BULK_PAYLOAD);
    let msg = chunk_in_place(u32::MAX, &std::vec![0xAB; len]);
    assert!(msg.len() <= protocol::link::BULK_PAYLOAD, "{}", msg.len());
}

proptest! {
    /// The header written in place is postcard's encoding of the same message.
    #[test]
    fn a_chunk_written_in_place_is_postcards_encoding(
        offset in any::<u32>(),
        data in proptest::collection::vec(any::<u8>(), 0..=READ_CHUNK),
    ) {
        let mut buf = [0u8; MAX_PAYLOAD];
        let msg = DeviceFrame::Chunk(ReadChunk { offset, data: Vec::from_slice(&data).expect("cap") });
        let serde = encode(&msg, &mut buf).expect("fits").to_vec();
        prop_assert_eq!(chunk_in_place(offset, &data), serde);
    }
}
