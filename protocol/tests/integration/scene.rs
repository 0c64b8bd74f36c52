//! Ray-tracer register image: golden offsets and words for the example scene of
//! docs/requirements.md §4.11, Q16.16 conversion limits, and the diff (identical scenes
//! give nothing, one field gives one one-word write, diff + apply reproduces the new scene
//! for arbitrary images), and the binary32 value format.

use proptest::prelude::*;
use protocol::frame::{RegWrite, REG_WRITE_WORDS};
use protocol::scene::{
    apply, cam, diff, diff_with_gap, hdr, light, obj, q16_from_f64, q16_to_f64, At, CameraRegs,
    DiffuseModel, LightKind, LightRegs, Mapping, MaterialRegs, ObjectRegs, ReflectionMode,
    RenderRegs, SceneError, SceneRegs, Shape, SpecularModel, TermRegs, TexFilter, TextureKind,
    TextureRegs, ValueFormat, DEFAULT_MERGE_GAP, FLAG_SHADOWS, MAGIC,
};

type Regs = SceneRegs; // the seed's defaults: 8 objects, 2 lights

/// The example scene of docs/requirements.md §4.11 ("Scene file and AOVs").
fn example() -> Regs {
    example_in(ValueFormat::Q16_16)
}

/// [`example`] with its reals in `format`.
fn example_in(format: ValueFormat) -> Regs {
    let mut s = Regs::with_format(format);
    s.set_render(&RenderRegs {
        width: 1920,
        height: 1080,
        depth: 2,
        bias: 0.001,
        max_distance: 1e6,
        background: [0.0; 3],
        spp: 1,
        flags: FLAG_SHADOWS,
        seed: 7,
    })
    .unwrap();
    s.set_camera(&CameraRegs {
        position: [0.0, 1.0, 6.0],
        look_at: [0.0; 3],
        up: [0.0, 1.0, 0.0],
        fov_y: 45.0,
        u: [1.0, 0.0, 0.0],
        v: [0.0, 1.0, 0.0],
        w: [0.0, 0.0, 1.0],
        near_plane: 1.0,
        pitch: 0x1922_956E,
    })
    .unwrap();
    s.set_light(
        0,
        &LightRegs {
            kind: LightKind::Ambient,
            color: [0.1; 3],
            ..Default::default()
        },
    )
    .unwrap();
    s.set_light(
        1,
        &LightRegs {
            kind: LightKind::Spot,
            position: [3.0, 5.0, 4.0],
            color: [30.0; 3],
            direction: [-0.4, -1.0, -0.6],
            cos_outer: 0.70,
            cos_inner: 0.85,
        },
    )
    .unwrap();
    s.set_object(0, &floor()).unwrap();
    s.set_counts(1, 2).unwrap();
    s
}

fn floor() -> ObjectRegs {
    ObjectRegs {
        shape: Shape::Disk,
        translate: [0.0, -2.0, 0.0],
        scale: [20.0; 3],
        rotate: [0.0; 3],
        minv: [[0.05, 0.0, 0.0], [0.0, 0.05, 0.0], [0.0, 0.0, 1e-6]],
        material: MaterialRegs {
            ambient: TermRegs {
                k: 1.0,
                color: [0.9; 3],
            },
            diffuse: TermRegs {
                k: 0.8,
                color: [0.9; 3],
            },
            diffuse_model: DiffuseModel::Lambert,
            sigma2: 0.0,
            specular: TermRegs {
                k: 0.2,
                color: [1.0; 3],
            },
            specular_model: SpecularModel::BlinnPhong,
            exponent: 32,
            reflection: ReflectionMode::Fresnel,
            eta: 1.33,
            kappa: 0.0,
            spec_eta: 0.0,
            spec_kappa: 0.0,
            reflectance: 0.0,
            texture: TextureRegs {
                kind: TextureKind::Checkerboard,
                mapping: Mapping::Planar,
                scale: [6.0, 6.0],
                offset: [0.0, 0.0],
                color2: [0.1; 3],
                filter: TexFilter::Bilinear,
                seed: 0,
                base: 0,
                width_log2: 8,
                height_log2: 8,
            },
        },
    }
}

#[test]
fn golden_offsets() {
    assert_eq!(hdr::WORDS, 16);
    assert_eq!(cam::OFFSET, 16);
    assert_eq!(light::OFFSET, 38);
    assert_eq!(Regs::light_offset(1), 50);
    assert_eq!(Regs::OBJECTS_OFFSET, 62);
    assert_eq!(Regs::object_offset(7), 62 + 7 * 54);
    // 16 header + 22 camera + 2 × 12 lights + 8 × 54 objects.
    assert_eq!(Regs::WORDS, 494);
    assert_eq!(SceneRegs::<4, 3>::WORDS, 16 + 22 + 36 + 216);
    assert_eq!(SceneRegs::<4, 3>::OBJECTS_OFFSET, 74);
    assert_eq!(Regs::VERSION_WORD, 0x0208_0002);
}

#[test]
fn golden_words() {
    let s = example();
    let w: Vec<u32> = s.words().collect();
    assert_eq!(w.len(), 494);
    assert_eq!(w[hdr::MAGIC], MAGIC);
    assert_eq!(w[hdr::MAGIC].to_be_bytes(), *b"FPRT");
    assert_eq!(w[hdr::VERSION], 0x0208_0002);
    assert_eq!(w[hdr::OBJECT_COUNT], 1);
    assert_eq!(w[hdr::LIGHT_COUNT], 2);
    assert_eq!(w[hdr::WIDTH], 1920);
    // 0.001 × 65536 = 65.536 → 66.
    assert_eq!(w[hdr::BIAS], 66);
    // 1e6 = 1.9073486328125 × 2^19: sign 0, exponent 127 + 19 = 0x92, mantissa
    // 0.9073486328125 × 2^23 = 0x742400 → 0 10010010 1110100001001… = 0x4974_2400.
    assert_eq!(w[hdr::MAX_DISTANCE], 0x4974_2400);
    assert_eq!(w[hdr::FLAGS], FLAG_SHADOWS);
    // Q16.16, code 0: the word that was "reserved, 0" before the value format existed.
    assert_eq!(w[hdr::VALUE_FORMAT], 0);
    // Camera position (0, 1, 6) and fov 45°.
    assert_eq!(
        &w[cam::OFFSET..cam::OFFSET + 3],
        &[0, 0x0001_0000, 0x0006_0000]
    );
    assert_eq!(w[cam::OFFSET + cam::FOV_Y], 45 << 16);
    // The pitch, a u64 in two words, low first.
    assert_eq!(w[cam::OFFSET + cam::PITCH], 0x1922_956E);
    assert_eq!(w[cam::OFFSET + cam::PITCH + 1], 0);
    // Ambient light colour 0.1 → 6553.6 → 6554 = 0x199A.
    assert_eq!(w[38 + light::KIND], 0);
    assert_eq!(w[38 + light::COLOR], 0x199A);
    // The spot light at 50: kind 2, colour 30 = 0x1E_0000,
    // direction −0.4 → −26214.4 → −26214 = 0xFFFF_999A, −1 → 0xFFFF_0000,
    // cos_outer 0.70 → 45875.2 → 0xB333, cos_inner 0.85 → 55705.6 → 55706 = 0xD99A.
    assert_eq!(w[50 + light::KIND], 2);
    assert_eq!(w[50 + light::COLOR], 0x001E_0000);
    assert_eq!(
        &w[50 + light::DIRECTION..50 + light::DIRECTION + 2],
        &[0xFFFF_999A, 0xFFFF_0000]
    );
    assert_eq!(w[50 + light::COS_OUTER], 0xB333);
    assert_eq!(w[50 + light::COS_INNER], 0xD99A);
    // The floor at 60: disk = 2, translate y −2 = 0xFFFE_0000, scale 20 = 0x14_0000,
    // η 1.33 → 87162.88 → 87163 = 0x1_547B, exponent 32, Fresnel = 2, checkerboard = 2,
    // texture scale 6 = 0x6_0000, size 8 | 8 << 8 = 0x808; M⁻¹ 0.05 = 3276.8 → 0xCCD,
    // and 10⁻⁶ (below Q16.16's resolution) saturates to 0 instead of being refused.
    let o = 62;
    assert_eq!(w[o + obj::SHAPE], 2);
    assert_eq!(w[o + obj::TRANSLATE + 1], 0xFFFE_0000);
    assert_eq!(w[o + obj::SCALE], 0x0014_0000);
    assert_eq!(w[o + obj::ETA], 0x0001_547B);
    assert_eq!(w[o + obj::EXPONENT], 32);
    assert_eq!(w[o + obj::REFLECTION_MODE], 2);
    assert_eq!(w[o + obj::TEX_KIND], 2);
    assert_eq!(w[o + obj::TEX_SCALE], 0x0006_0000);
    assert_eq!(w[o + obj::TEX_FILTER], 1);
    assert_eq!(w[o + obj::TEX_SIZE], 0x808);
    assert_eq!(w[o + obj::MINV], 0xCCD);
    assert_eq!(w[o + obj::MINV + 4], 0xCCD);
    assert_eq!(w[o + obj::MINV + 8], 0);
    // Unused objects stay zero.
    assert!(w[Regs::object_offset(1)..].iter().all(|&x| x == 0));
    // Typed read-back gives the Q16.16-rounded values.
    let l = s.light(1).unwrap();
    assert_eq!(l.kind, LightKind::Spot);
    assert_eq!(l.direction[0], -26214.0 / 65536.0);
    let f = s.object(0).unwrap();
    assert_eq!(f.shape, Shape::Disk);
    assert_eq!(
        f.material.texture,
        floor().material.texture.with_color2(0x199A)
    );
    assert_eq!(s.render().max_distance, 1e6);
    assert_eq!(s.camera().fov_y, 45.0);
}

trait WithColor2 {
    fn with_color2(self, q: i32) -> Self;
}
impl WithColor2 for TextureRegs {
    fn with_color2(mut self, q: i32) -> Self {
        self.color2 = [q16_to_f64(q); 3];
        self
    }
}

#[test]
fn binary32_images_carry_ieee_words() {
    let q = example();
    let s = example_in(ValueFormat::Binary32);
    assert_eq!(s.value_format(), ValueFormat::Binary32);
    let w: Vec<u32> = s.words().collect();
    assert_eq!(w[hdr::VALUE_FORMAT], 1);
    // Integers, codes and the always-f32 max_distance are the Q16.16 image's words.
    for i in [
        hdr::VERSION,
        hdr::WIDTH,
        hdr::MAX_DISTANCE,
        hdr::FLAGS,
        hdr::SEED,
    ] {
        assert_eq!(Some(w[i]), q.word(i), "word {i}");
    }
    assert_eq!(w[hdr::BIAS], 0.001f32.to_bits());
    assert_eq!(
        &w[cam::OFFSET..cam::OFFSET + 3],
        &[0, 1.0f32.to_bits(), 6.0f32.to_bits()]
    );
    assert_eq!(w[cam::OFFSET + cam::FOV_Y], 0x4234_0000); // 45.0
    assert_eq!(w[50 + light::DIRECTION], (-0.4f32).to_bits());
    assert_eq!(w[62 + obj::ETA], 1.33f32.to_bits());
    assert_eq!(w[62 + obj::EXPONENT], 32);
    // Read back: the f32-rounded values, not the Q16.16-quantised ones.
    assert_eq!(s.render().bias, f64::from(0.001f32));
    assert_eq!(s.light(1).unwrap().direction[0], f64::from(-0.4f32));
    assert_eq!(s.object(0).unwrap().material.eta, f64::from(1.33f32));
    let mut buf = vec![0u32; Regs::WORDS];
    s.to_words(&mut buf).unwrap();
    assert_eq!(Regs::from_words(&buf).unwrap(), s);
    // Beyond Q16.16 is fine in binary32; beyond f32 is refused naming the field and block.
    let mut o = floor();
    o.scale[1] = 40000.0;
    let mut t = Regs::with_format(ValueFormat::Binary32);
    t.set_object(3, &o).unwrap();
    assert_eq!(t.object(3).unwrap().scale[1], 40000.0);
    for v in [1e39, -1e39, f64::NAN, f64::INFINITY] {
        o.scale[1] = v;
        let e = t.set_object(3, &o).unwrap_err();
        assert!(
            matches!(
                e,
                SceneError::F32 {
                    at: At::Object(3),
                    field: "scale",
                    ..
                }
            ),
            "{v}: {e}"
        );
        assert!(e.to_string().starts_with("object 3: `scale`"), "{e}");
    }
    assert_eq!(
        ValueFormat::Binary32.encode("x", 3.0e38),
        Ok(3.0e38f32.to_bits())
    );
}

#[test]
fn unknown_value_formats_are_refused_naming_the_field() {
    let mut buf = vec![0u32; Regs::WORDS];
    example().to_words(&mut buf).unwrap();
    buf[hdr::VALUE_FORMAT] = 2;
    let refused = SceneError::Code {
        at: At::Global,
        field: "value_format",
        value: 2,
    };
    assert_eq!(Regs::from_words(&buf), Err(refused));
    assert!(refused.to_string().contains("value_format"));
    // A register write that would set it changes nothing, alone or inside a run.
    let mut s = example();
    assert_eq!(s.write(hdr::VALUE_FORMAT, &[2]), Err(refused));
    assert_eq!(s.write(hdr::SEED, &[9, 2, 5]), Err(refused));
    assert_eq!(s, example());
    // A known code is taken: the image's reals are then read in that format.
    s.write(hdr::VALUE_FORMAT, &[1]).unwrap();
    assert_eq!(s.value_format(), ValueFormat::Binary32);
}

#[test]
fn the_format_follows_the_targets_caps() {
    use protocol::frame::{Caps, Numeric, NumericSet};
    let caps = Caps {
        float_regs: NumericSet::default().with(Numeric::F32).with(Numeric::F64),
        rt_build: protocol::frame::RtBuild::FULL,
        link_payload: 0,
        ..Default::default()
    };
    for n in Numeric::ALL {
        let want = if matches!(n, Numeric::F32 | Numeric::F64) {
            ValueFormat::Binary32
        } else {
            ValueFormat::Q16_16
        };
        assert_eq!(ValueFormat::for_caps(&caps, n), want, "{n:?}");
        assert_eq!(
            ValueFormat::for_caps(&Caps::default(), n),
            ValueFormat::Q16_16
        );
    }
}

#[test]
fn words_round_trip_and_checks() {
    let s = example();
    let mut buf = vec![0u32; Regs::WORDS];
    assert_eq!(s.to_words(&mut buf), Ok(494));
    assert_eq!(Regs::from_words(&buf).unwrap(), s);
    let mut bad = buf.clone();
    bad[0] = 0;
    assert_eq!(Regs::from_words(&bad), Err(SceneError::Magic { found: 0 }));
    assert!(matches!(
        Regs::from_words(&buf[..395]),
        Err(SceneError::Length {
            expected: 494,
            got: 395
        })
    ));
    // A 4-object map is refused by the 8-object decoder even at the right length.
    let small = SceneRegs::<4, 2>::new();
    let mut sw: Vec<u32> = small.words().collect();
    sw.resize(494, 0);
    assert!(matches!(
        Regs::from_words(&sw),
        Err(SceneError::Version { .. })
    ));
}

#[test]
fn q16_limits() {
    assert_eq!(q16_from_f64("x", 1.0), Ok(0x1_0000));
    assert_eq!(q16_from_f64("x", -1.0), Ok(-0x1_0000));
    assert_eq!(q16_from_f64("x", -32768.0), Ok(i32::MIN));
    assert_eq!(q16_from_f64("x", 32768.0 - 1.0 / 65536.0), Ok(i32::MAX));
    // Ties away from zero.
    assert_eq!(q16_from_f64("x", 0.5 / 65536.0), Ok(1));
    assert_eq!(q16_from_f64("x", -0.5 / 65536.0), Ok(-1));
    for v in [
        32768.0,
        -32768.0 - 1.0 / 65536.0,
        1e6,
        f64::NAN,
        f64::INFINITY,
    ] {
        let e = q16_from_f64("bias", v).unwrap_err();
        assert!(matches!(e, SceneError::Q16 { field: "bias", .. }), "{v}");
        assert!(e.to_string().contains("bias"));
    }
    // Errors from a block name the block.
    let mut s = Regs::new();
    let mut o = floor();
    o.scale[1] = 40000.0;
    let e = s.set_object(3, &o).unwrap_err();
    assert_eq!(
        e,
        SceneError::Q16 {
            at: At::Object(3),
            field: "scale",
            value: 40000.0
        }
    );
    assert!(e.to_string().starts_with("object 3: `scale` = 40000"));
    o = floor();
    o.material.exponent = 1024;
    assert!(matches!(
        s.set_object(0, &o),
        Err(SceneError::Int {
            field: "material.specular.exponent",
            value: 1024,
            ..
        })
    ));
    assert!(matches!(
        s.set_object(8, &floor()),
        Err(SceneError::Index { index: 8, .. })
    ));
    assert!(matches!(
        s.set_light(1, &LightRegs::default()),
        Err(SceneError::Code {
            at: At::Light(1),
            field: "kind",
            ..
        })
    ));
    assert!(s.set_counts(9, 1).is_err());
    let mut r = example().render();
    r.max_distance = 1e300;
    assert!(matches!(
        s.set_render(&r),
        Err(SceneError::F32 {
            field: "max_distance",
            ..
        })
    ));
    // Invalid codes in raw words are reported by the typed getter.
    s.write(Regs::object_offset(2) + obj::SHAPE, &[99]).unwrap();
    assert_eq!(
        s.object(2),
        Err(SceneError::Code {
            at: At::Object(2),
            field: "shape",
            value: 99
        })
    );
}

#[test]
fn identical_scenes_diff_to_nothing() {
    let a = example();
    assert_eq!(diff(&a, &a.clone()).count(), 0);
    assert_eq!(diff(&Regs::new(), &Regs::new()).count(), 0);
}

#[test]
fn one_changed_field_is_one_one_word_write() {
    let a = example();
    let mut b = a.clone();
    let mut l = b.light(1).unwrap();
    l.cos_inner = 0.9;
    b.set_light(1, &l).unwrap();
    let writes: Vec<RegWrite> = diff(&a, &b).collect();
    assert_eq!(writes.len(), 1);
    assert_eq!(usize::from(writes[0].offset), 50 + light::COS_INNER);
    assert_eq!(
        writes[0].words.as_slice(),
        &[q16_from_f64("", 0.9).unwrap() as u32]
    );
}

#[test]
fn runs_merge_small_gaps_only() {
    let a = Regs::new();
    let mut b = a.clone();
    // Changes at 20 and 23: a gap of two unchanged words is bridged.
    b.write(20, &[1]).unwrap();
    b.write(23, &[1]).unwrap();
    // Changes at 40 and 44: a gap of three starts a new run.
    b.write(40, &[1]).unwrap();
    b.write(44, &[1]).unwrap();
    let w: Vec<(u16, usize)> = diff(&a, &b).map(|w| (w.offset, w.words.len())).collect();
    assert_eq!(w, [(20, 4), (40, 1), (44, 1)]);
    assert_eq!(DEFAULT_MERGE_GAP, 2);
    // With no merging every changed word stands alone.
    let w: Vec<(u16, usize)> = diff_with_gap(&a, &b, 0)
        .map(|w| (w.offset, w.words.len()))
        .collect();
    assert_eq!(w, [(20, 1), (23, 1), (40, 1), (44, 1)]);
    // A long change is cut into REG_WRITE_WORDS-word runs.
    let mut c = a.clone();
    c.write(100, &[7; 100]).unwrap();
    let w: Vec<(u16, usize)> = diff(&a, &c).map(|w| (w.offset, w.words.len())).collect();
    assert_eq!(w, [(100, 40), (140, 40), (180, 20)]);
}

#[test]
fn apply_checks_bounds() {
    let mut s = example();
    let before = s.clone();
    let w = RegWrite {
        offset: 493,
        words: heapless::Vec::from_slice(&[1, 2]).unwrap(),
    };
    assert_eq!(
        apply(&mut s, &w),
        Err(SceneError::Bounds {
            offset: 493,
            len: 2,
            size: 494
        })
    );
    assert_eq!(s, before);
    let w = RegWrite {
        offset: 493,
        words: heapless::Vec::from_slice(&[1]).unwrap(),
    };
    apply(&mut s, &w).unwrap();
    assert_eq!(s.word(493), Some(1));
    assert_eq!(s.word(494), None);
}

fn image(words: Vec<u32>) -> Regs {
    let mut w = words;
    w[0] = MAGIC;
    w[1] = Regs::VERSION_WORD;
    // Either value format: other codes are refused (`unknown_value_formats_…`).
    w[hdr::VALUE_FORMAT] %= 2;
    Regs::from_words(&w).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// For arbitrary images and arbitrary sparse edits, applying the diff to the old
    /// image gives the new one; every run is bounded, starts and ends on a changed word
    /// and bridges no gap wider than the merge gap.
    #[test]
    fn diff_then_apply_reproduces(
        base in proptest::collection::vec(any::<u32>(), 494),
        edits in proptest::collection::vec((2usize..494, any::<u32>()), 0..60),
        gap in 0usize..4,
    ) {
        let old = image(base);
        let mut new = old.clone();
        for (off, v) in edits {
            let v = if off == hdr::VALUE_FORMAT { v % 2 } else { v };
            new.write(off, &[v]).unwrap();
        }
        let mut patched = old.clone();
        for w in diff_with_gap(&old, &new, gap) {
            prop_assert!(!w.words.is_empty() && w.words.len() <= REG_WRITE_WORDS);
            let start = usize::from(w.offset);
            let end = start + w.words.len() - 1;
            prop_assert_ne!(old.word(start), new.word(start));
            prop_assert_ne!(old.word(end), new.word(end));
            let mut run = 0;
            for i in start..=end {
                if old.word(i) == new.word(i) { run += 1; prop_assert!(run <= gap); } else { run = 0; }
            }
            apply(&mut patched, &w).unwrap();
        }
        prop_assert_eq!(patched, new);
    }

    /// Typed objects survive the registers up to Q16.16 rounding (values on a 1/64 grid
    /// are exact).
    #[test]
    fn objects_round_trip(
        t in proptest::array::uniform3(-32768i32..32767),
        k in 0i32..64,
        shape in 0u32..7,
        e in 0u32..1024,
        i in 0usize..8,
    ) {
        let mut o = floor();
        o.translate = t.map(|v| f64::from(v) / 64.0);
        o.material.diffuse.k = f64::from(k) / 64.0;
        o.shape = Shape::from_code(shape).unwrap();
        o.material.exponent = e;
        let mut s = Regs::new();
        s.set_object(i, &o).unwrap();
        let back = s.object(i).unwrap();
        prop_assert_eq!(back.translate, o.translate);
        prop_assert_eq!(back.material.diffuse.k, o.material.diffuse.k);
        prop_assert_eq!(back.shape, o.shape);
        prop_assert_eq!(back.material.exponent, e);
        // And exactly one object block changed.
        let writes: Vec<RegWrite> = diff(&Regs::new(), &s).collect();
        let lo = Regs::object_offset(i);
        for w in &writes {
            prop_assert!(usize::from(w.offset) >= lo && usize::from(w.offset) + w.words.len() <= lo + obj::WORDS);
        }
    }
}

proptest! {
    /// Every Q16.16 word survives the trip through f64 and back.
    #[test]
    fn q16_words_round_trip(q: i32) {
        prop_assert_eq!(q16_from_f64("x", q16_to_f64(q)), Ok(q));
    }

    /// Conversion is within half an ulp (2^-17) of the value.
    #[test]
    fn q16_rounds_to_nearest(v in -32768.0f64..32767.99) {
        let q = q16_from_f64("x", v).unwrap();
        prop_assert!((q16_to_f64(q) - v).abs() <= 0.5 / 65536.0);
    }
}

/// The committed `hw/rt-core/rtl/rt_map.vh` is what `protocol::scene` writes today.
#[test]
fn rt_map_header_matches_the_rust_map() {
    let mut text = String::new();
    protocol::scene::write_verilog_header(&mut text).expect("writes to a String");
    super::generated::matches_committed("../hw/rt-core/rtl/rt_map.vh", &text, "protocol::scene");
    for s in protocol::scene::Shape::ALL {
        let want = format!(
            "`define RT_SHAPE_{} 3'd{}\n",
            format!("{s:?}").to_uppercase(),
            s.code()
        );
        assert!(text.contains(&want), "{want}");
    }
}

/// The committed `hw/rt-core/rtl/rt_axi_map.vh` is what `protocol::axi_lite` writes today.
#[test]
fn rt_axi_map_header_matches_the_rust_map() {
    let mut text = String::new();
    protocol::axi_lite::write_verilog_header(&mut text).expect("writes to a String");
    super::generated::matches_committed(
        "../hw/rt-core/rtl/rt_axi_map.vh",
        &text,
        "protocol::axi_lite",
    );
    assert!(text.contains("`define RT_AXI_SCENE_BASE 32'h00000800\n"));
    assert!(text.contains("`define RT_AXI_AUTO_RESTART 7\n"));
    assert!(text.contains("`define RT_AXI_COUNTER_SATURATIONS 3\n"));
}
