//! Properties of the intersectors on random rays: a reported hit lies on the canonical
//! surface, inside [tmin, tmax] and inside the shape's limits; and no reported hit is
//! farther than the closest true one (checked by marching a dense set of samples).

use proptest::prelude::*;
use sim_target::rt::shapes;
use sim_target::rt::Math;
use sim_target::rt::Shape;
use sim_target::rt::V3;

fn on_surface(shape: Shape, p: V3<f64>) -> bool {
    let e = 1e-6;
    match shape {
        Shape::Sphere => (p.dot(p) - 1.0).abs() < e,
        Shape::Plane => p.y.abs() < e,
        Shape::Disk => p.y.abs() < e && p.x * p.x + p.z * p.z <= 1.0 + e,
        Shape::Square => p.y.abs() < e && p.x.abs() <= 1.0 + e && p.z.abs() <= 1.0 + e,
        Shape::Cylinder => (p.x * p.x + p.z * p.z - 1.0).abs() < e && p.y.abs() <= 1.0 + e,
        Shape::Cone => {
            (p.x * p.x + p.z * p.z - (1.0 - p.y) * (1.0 - p.y)).abs() < e
                && (-e..=1.0 + e).contains(&p.y)
        }
        Shape::Cube => {
            let m = p.x.abs().max(p.y.abs()).max(p.z.abs());
            (m - 1.0).abs() < e
        }
    }
}

fn shape_strategy() -> impl Strategy<Value = Shape> {
    prop_oneof![
        Just(Shape::Sphere),
        Just(Shape::Plane),
        Just(Shape::Disk),
        Just(Shape::Square),
        Just(Shape::Cylinder),
        Just(Shape::Cone),
        Just(Shape::Cube),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn hits_are_on_the_surface(
        shape in shape_strategy(),
        o in prop::array::uniform3(-4.0f64..4.0),
        d in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let d = V3::new(d[0], d[1], d[2]);
        prop_assume!(d.dot(d) > 1e-3);
        let o = V3::new(o[0], o[1], o[2]);
        let m = Math::default();
        if let Some(t) = shapes::intersect(shape, o, d, 0.001, 1e6, &m) {
            prop_assert!((0.001..=1e6).contains(&t));
            let p = o + d.scale(t);
            prop_assert!(on_surface(shape, p), "{:?} t={} p={:?}", shape, t, p);
        }
    }

    #[test]
    fn fn_pointer_and_match_dispatch_agree(
        shape in shape_strategy(),
        o in prop::array::uniform3(-4.0f64..4.0),
        d in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let (o, d) = (V3::new(o[0], o[1], o[2]), V3::new(d[0], d[1], d[2]));
        let m = Math::default();
        prop_assert_eq!(
            shapes::intersect(shape, o, d, 0.001, 1e6, &m),
            shapes::intersect_fn::<f64>(shape)(o, d, 0.001, 1e6, &m)
        );
    }

    #[test]
    fn sphere_hit_is_the_nearest(
        o in prop::array::uniform3(-3.0f64..3.0),
        d in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let d = V3::new(d[0], d[1], d[2]);
        prop_assume!(d.dot(d) > 1e-2);
        let d = d.scale(1.0 / d.dot(d).sqrt());
        let o = V3::new(o[0], o[1], o[2]);
        let hit = shapes::sphere(o, d, 0.001, 1e6, &Math::default());
        // march: the first sample whose inside/outside state differs from the start
        let inside = |t: f64| { let p = o + d.scale(t); p.dot(p) < 1.0 };
        let start = inside(0.001);
        let first = (1..20_000).map(|i| 0.001 + i as f64 * 0.0005).find(|t| inside(*t) != start);
        match (hit, first) {
            (Some(t), Some(f)) => prop_assert!(t <= f + 1e-9 && t >= f - 0.0005 - 1e-9, "{} vs {}", t, f),
            (None, Some(f)) => prop_assert!(false, "missed a crossing at {}", f),
            _ => {}
        }
    }
}
