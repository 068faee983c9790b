use super::kinds::{self, landscape};
use super::place::{self, Placed};
use super::sdf;
use super::*;

fn sphere(r: f32) -> Node {
    Node::Shape {
        shape: Shape::Sphere { radius: r },
        transform: Transform::default(),
        material: 0,
    }
}

fn kind(root: Node) -> Kind {
    Kind {
        name: "k".into(),
        root,
        weight: 1.0,
        scale: (1.0, 1.0),
        on_rock: true,
    }
}

fn error(k: &Kind) -> String {
    k.compile(1).unwrap_err().to_string()
}

#[test]
fn the_shipped_scene_compiles_within_its_limits() {
    let scene = landscape();
    let tapes = scene.compile(&Props::default()).unwrap();
    assert_eq!(tapes.len(), 5);
    for (k, t) in scene.kinds.iter().zip(&tapes) {
        let prims = t
            .code
            .iter()
            .filter(|i| matches!(i.op, Op::Shape(_)))
            .count();
        let smooth = t
            .code
            .iter()
            .filter(|i| matches!(i.op, Op::Combine(_, r) if r > 0.0))
            .count();
        assert!(prims >= 3 && smooth >= 1, "{}: {prims} primitives", k.name);
        assert!(t.code.len() <= MAX_TAPE && t.stack <= STACK);
        assert!(
            t.lipschitz >= 1.0 && t.lipschitz < 4.0,
            "{}: {}",
            k.name,
            t.lipschitz
        );
        // Buried below the origin: the foot is sunk.
        assert!(t.bounds[0][1] < -0.1, "{}: {:?}", k.name, t.bounds);
    }
    kinds::demo().compile(5).unwrap();
}

#[test]
fn bad_trees_are_refused_naming_the_key_the_value_and_the_limit() {
    let mut deep = sphere(1.0);
    for _ in 0..40 {
        deep = Node::Transform {
            transform: Transform::default(),
            child: Box::new(deep),
        };
    }
    let e = error(&kind(deep));
    assert!(
        e.contains("prop_kinds.k") && e.contains("33 deep") && e.contains("at most 32"),
        "{e}"
    );
    let e = error(&kind(sphere(0.0)));
    assert!(e.contains("root.sphere.radius") && e.contains(": 0"), "{e}");
    let e = error(&kind(sphere(f32::NAN)));
    assert!(e.contains("radius") && e.contains("NaN"), "{e}");
    let scaled = Node::Transform {
        transform: Transform {
            scale: [1.0, 0.0, 1.0],
            ..Transform::default()
        },
        child: Box::new(sphere(1.0)),
    };
    let e = error(&kind(scaled));
    assert!(e.contains("root.scale") && e.contains("> 0"), "{e}");
    let soft = Node::Combine {
        op: Combine::Union,
        smooth: Some(-0.5),
        children: vec![sphere(1.0), sphere(0.5)],
    };
    let e = error(&kind(soft));
    assert!(e.contains("root.smooth") && e.contains("-0.5"), "{e}");
    let wide = Node::Combine {
        op: Combine::Union,
        smooth: None,
        children: (0..70).map(|_| sphere(1.0)).collect(),
    };
    assert!(error(&kind(wide)).contains("at most 64"));
    let plane = Node::Shape {
        shape: Shape::Plane {
            normal: [0.0, 1.0, 0.0],
            offset: 0.0,
        },
        transform: Transform::default(),
        material: 0,
    };
    assert!(error(&kind(plane)).contains("unbounded"));
    let bad_material = Node::Shape {
        shape: Shape::Sphere { radius: 1.0 },
        transform: Transform::default(),
        material: 3,
    };
    assert!(error(&kind(bad_material)).contains("material"));
}

#[test]
fn a_prop_wider_than_half_its_cell_or_taller_than_its_band_is_refused() {
    let scene = landscape();
    let small = Props {
        cell: 4.0,
        ..Props::default()
    };
    let e = scene.compile(&small).unwrap_err().to_string();
    assert!(
        e.contains("prop_kinds.") && e.contains("half the cell, 2 m"),
        "{e}"
    );
    let low = Props {
        band: 2.0,
        ..Props::default()
    };
    let e = scene.compile(&low).unwrap_err().to_string();
    assert!(e.contains("tall") && e.contains("props_band"), "{e}");
    let mut scene = landscape();
    scene.placed.push(Placed {
        kind: 9,
        at: [0.0, 0.0],
        turn: 0.0,
        scale: 1.0,
    });
    let e = scene.compile(&Props::default()).unwrap_err().to_string();
    assert!(e.contains("prop_place[0].kind"), "{e}");
}

#[test]
fn primitives_are_exact_distances() {
    // Against closed forms at points outside, inside and on each.
    let b = Shape::Box {
        half: [1.0, 2.0, 3.0],
    };
    assert!((sdf::shape(&b, [3.0, 0.0, 0.0]) - 2.0).abs() < 1e-12);
    assert!((sdf::shape(&b, [2.0, 3.0, 0.0]) - 2f64.sqrt()).abs() < 1e-12);
    assert!((sdf::shape(&b, [0.5, 0.0, 0.0]) + 0.5).abs() < 1e-12);
    let t = Shape::Torus {
        major: 2.0,
        minor: 0.5,
    };
    assert!((sdf::shape(&t, [2.0, 1.0, 0.0]) - 0.5).abs() < 1e-12);
    let c = Shape::Capsule {
        radius: 0.5,
        half_height: 1.0,
    };
    assert!((sdf::shape(&c, [0.0, 3.0, 0.0]) - 1.5).abs() < 1e-12);
    let y = Shape::Cylinder {
        radius: 1.0,
        half_height: 1.0,
    };
    assert!((sdf::shape(&y, [3.0, 0.0, 0.0]) - 2.0).abs() < 1e-12);
    assert!((sdf::shape(&y, [0.0, 0.0, 0.0]) + 1.0).abs() < 1e-12);
    let r = Shape::RoundBox {
        half: [1.0; 3],
        radius: 0.25,
    };
    assert!((sdf::shape(&r, [2.0, 0.0, 0.0]) - 1.0).abs() < 1e-12);
}

#[test]
fn the_tapes_field_never_steps_through_its_surface() {
    // Sample each shipped kind's field along random segments: the field changes by at most its
    // Lipschitz constant times the distance (so a march dividing by it never oversteps).
    let scene = landscape();
    let tapes = scene.compile(&Props::default()).unwrap();
    let mut h = 12345u32;
    let mut next = || {
        h = crate::noise::pcg(h);
        f64::from(h >> 8) / 16_777_216.0
    };
    for (k, tape) in scene.kinds.iter().zip(&tapes) {
        // And the field without its displacements against its own, smaller constant.
        let smooth: Vec<_> = tape
            .code
            .iter()
            .filter(|i| !matches!(i.op, Op::Displace { .. }))
            .cloned()
            .collect();
        let mut worst = [0.0f64; 2];
        for _ in 0..4000 {
            let p = [next() * 8.0 - 4.0, next() * 6.0 - 1.0, next() * 8.0 - 4.0];
            let d = [next() - 0.5, next() - 0.5, next() - 0.5];
            let e = 1e-3;
            let q = [0, 1, 2].map(|a| p[a] + e * d[a]);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() * e;
            let change = (sdf::distance(tape, p, 7).0 - sdf::distance(tape, q, 7).0).abs();
            worst[0] = worst[0].max(change / len);
            let change =
                (sdf::distance_of(&smooth, p, 7).0 - sdf::distance_of(&smooth, q, 7).0).abs();
            worst[1] = worst[1].max(change / len);
        }
        assert!(
            worst[0] <= tape.lipschitz && worst[1] <= tape.lipschitz_undisplaced,
            "{}: slopes {worst:?} over {} and {}",
            k.name,
            tape.lipschitz,
            tape.lipschitz_undisplaced
        );
        assert!(tape.lipschitz_undisplaced >= 1.0 && tape.lipschitz_undisplaced <= tape.lipschitz);
    }
}

#[test]
fn a_march_meets_a_sphere_where_the_closed_form_does() {
    let tape = kind(Node::Shape {
        shape: Shape::Sphere { radius: 1.0 },
        transform: Transform::at([0.0, 1.0, 5.0]),
        material: 0,
    })
    .compile(1)
    .unwrap();
    let t = sdf::march(
        &tape,
        ([0.0, 1.2, 0.0], [0.0, 0.0, 1.0]),
        0,
        20.0,
        1e-9,
        200,
    )
    .unwrap();
    let exact = 5.0 - (1.0f64 - 0.04).sqrt();
    assert!((t - exact).abs() < 1e-6, "{t} {exact}");
    let n = sdf::normal(&tape, [0.0, 1.2, t], 0, 1e-5);
    assert!((n[1] - 0.2).abs() < 1e-4 && n[2] < 0.0, "{n:?}");
}

#[test]
fn smooth_union_blends_and_keeps_the_nearer_material() {
    let (d, h) = sdf::smooth_min(1.0, 1.0, 0.4);
    assert!((d - 0.9).abs() < 1e-12 && (h - 0.5).abs() < 1e-12);
    assert_eq!(sdf::smooth_min(0.0, 5.0, 0.4), (0.0, 1.0));
}

#[test]
fn props_are_the_same_in_every_cell_far_from_the_origin() {
    let scene = landscape();
    let w = place::cumulative(&scene.kinds);
    let near = place::prop_at(&w, 7, [3, -4]);
    assert_eq!(near, place::prop_at(&w, 7, [3, -4]));
    assert_ne!(near, place::prop_at(&w, 7, [3, -5]));
    assert_ne!(near, place::prop_at(&w, 8, [3, -4]));
    // 10^9 m out, cells are exact integers.
    let far = Props::default().cell_at(1e9 + 4.0, -1e9);
    assert_eq!(far, [125_000_000, -125_000_000]);
    let counts = (0..20_000).fold([0u32; 5], |mut c, i| {
        c[place::prop_at(&w, 7, [i, 1]).kind as usize] += 1;
        c
    });
    let total: f32 = scene.kinds.iter().map(|k| k.weight).sum();
    for (k, n) in scene.kinds.iter().zip(counts) {
        let share = n as f32 / 20_000.0;
        assert!(
            (share - k.weight / total).abs() < 0.02,
            "{}: {share}",
            k.name
        );
    }
}

#[test]
fn no_prop_stands_under_water_and_few_on_rock() {
    let p = Props::default();
    let prop = place::Prop {
        chance: 0.01,
        ..Default::default()
    };
    assert!(!place::keeps(&p, &prop, true, (1.0, 0.5, 0.1), Some(0.2)));
    assert!(place::keeps(&p, &prop, true, (1.0, 0.5, 0.3), Some(0.2)));
    let rocky = place::Prop {
        chance: 0.2,
        ..Default::default()
    };
    assert!(place::keeps(&p, &rocky, true, (1.0, 0.5, 0.3), None));
    assert!(!place::keeps(&p, &rocky, true, (0.4, 0.5, 0.3), None));
}

#[test]
fn the_noise_rises_no_faster_than_its_bound() {
    let mut h = 99u32;
    let mut next = || {
        h = crate::noise::pcg(h);
        f64::from(h >> 8) / 16_777_216.0
    };
    let mut worst = 0.0f64;
    let e = 1e-4;
    for _ in 0..100_000 {
        let p = [
            next() * 20.0 - 10.0,
            next() * 20.0 - 10.0,
            next() * 20.0 - 10.0,
        ];
        let g = [0, 1, 2].map(|a| {
            let (mut lo, mut hi) = (p, p);
            lo[a] -= e;
            hi[a] += e;
            (sdf::value_noise(hi, 5) - sdf::value_noise(lo, 5)) / (2.0 * e)
        });
        worst = worst.max((g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt());
    }
    eprintln!("the noise's steepest slope sampled: {worst:.3} (bound {NOISE_GRADIENT})");
    assert!(worst < NOISE_GRADIENT && worst > 2.0, "{worst}");
}
