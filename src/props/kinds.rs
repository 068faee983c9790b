//! The shipped props: five kinds for the landscape (boulders, standing stones, arches, ruined
//! walls, cairns), each of at least three primitives joined by smooth booleans, the rocks
//! roughened by noise; and the SDF article's demo (a sphere and a box blended by a smooth
//! union).

use super::{Combine, Kind, Material, Node, Scene, Shape, Transform};

fn material(name: &str, albedo: [f32; 3], variation: f32) -> Material {
    Material {
        name: name.into(),
        albedo,
        variation,
    }
}

/// The landscape's materials: stone, sandstone, basalt, lichen, and the demo's white.
pub fn materials() -> Vec<Material> {
    vec![
        material("stone", [0.30, 0.29, 0.27], 0.35),
        material("sandstone", [0.46, 0.36, 0.25], 0.3),
        material("basalt", [0.12, 0.115, 0.11], 0.3),
        material("lichen", [0.22, 0.26, 0.14], 0.4),
        material("white", [0.8, 0.8, 0.8], 0.0),
    ]
}

const STONE: u32 = 0;
const SANDSTONE: u32 = 1;
const BASALT: u32 = 2;
const LICHEN: u32 = 3;
const WHITE: u32 = 4;

fn prim(shape: Shape, at: [f32; 3], material: u32) -> Node {
    Node::Shape {
        shape,
        transform: Transform::at(at),
        material,
    }
}

fn turned(shape: Shape, at: [f32; 3], rotate: [f32; 3], material: u32) -> Node {
    Node::Shape {
        shape,
        transform: Transform {
            translate: at,
            rotate,
            scale: [1.0; 3],
        },
        material,
    }
}

fn smooth(op: Combine, k: f32, children: Vec<Node>) -> Node {
    Node::Combine {
        op,
        smooth: Some(k),
        children,
    }
}

fn rough(amplitude: f32, frequency: f32, child: Node) -> Node {
    Node::Displace {
        amplitude,
        frequency,
        child: Box::new(child),
    }
}

fn kind(name: &str, root: Node, weight: f32, scale: (f32, f32), on_rock: bool) -> Kind {
    Kind {
        name: name.into(),
        root,
        weight,
        scale,
        on_rock,
    }
}

/// A boulder: three squashed spheres blended, roughened.
pub fn boulder() -> Kind {
    let body = smooth(
        Combine::Union,
        0.5,
        vec![
            Node::Shape {
                shape: Shape::Sphere { radius: 1.0 },
                transform: Transform {
                    translate: [0.0, 0.35, 0.0],
                    rotate: [0.0, 0.0, 0.0],
                    scale: [1.2, 0.8, 1.0],
                },
                material: STONE,
            },
            prim(Shape::Sphere { radius: 0.7 }, [0.8, 0.2, 0.3], STONE),
            prim(Shape::Sphere { radius: 0.55 }, [-0.5, 0.9, -0.2], LICHEN),
        ],
    );
    kind("boulder", rough(0.08, 2.5, body), 3.0, (0.6, 1.6), true)
}

/// A standing stone: a tall rounded slab on a rough foot, a worn top.
pub fn standing_stone() -> Kind {
    let body = smooth(
        Combine::Union,
        0.3,
        vec![
            turned(
                Shape::RoundBox {
                    half: [0.55, 1.7, 0.3],
                    radius: 0.15,
                },
                [0.0, 1.4, 0.0],
                [4.0, 0.0, 3.0],
                BASALT,
            ),
            prim(Shape::Sphere { radius: 0.5 }, [0.1, 3.0, 0.0], BASALT),
            prim(
                Shape::Cylinder {
                    radius: 0.8,
                    half_height: 0.25,
                },
                [0.0, 0.0, 0.0],
                STONE,
            ),
        ],
    );
    kind(
        "standing_stone",
        rough(0.04, 3.0, body),
        1.5,
        (0.8, 1.3),
        false,
    )
}

/// An arch: half a torus standing on two pillars.
pub fn arch() -> Kind {
    let ring = smooth(
        Combine::Intersection,
        0.1,
        vec![
            turned(
                Shape::Torus {
                    major: 1.7,
                    minor: 0.35,
                },
                [0.0, 2.0, 0.0],
                [90.0, 0.0, 0.0],
                SANDSTONE,
            ),
            prim(
                Shape::Plane {
                    normal: [0.0, -1.0, 0.0],
                    offset: -2.0,
                },
                [0.0, 0.0, 0.0],
                SANDSTONE,
            ),
        ],
    );
    let pillar = |x: f32| {
        prim(
            Shape::RoundBox {
                half: [0.4, 1.1, 0.4],
                radius: 0.1,
            },
            [x, 0.9, 0.0],
            SANDSTONE,
        )
    };
    let body = smooth(Combine::Union, 0.35, vec![ring, pillar(-1.7), pillar(1.7)]);
    kind("arch", rough(0.05, 2.0, body), 0.6, (0.8, 1.2), false)
}

/// A ruined wall: a wall with a window cut out and a broken top, a column at its end.
pub fn ruin() -> Kind {
    let wall = smooth(
        Combine::Subtraction,
        0.15,
        vec![
            prim(
                Shape::Box {
                    half: [2.2, 1.5, 0.3],
                },
                [0.0, 1.2, 0.0],
                SANDSTONE,
            ),
            prim(
                Shape::Box {
                    half: [0.5, 0.6, 0.5],
                },
                [-0.6, 1.4, 0.0],
                SANDSTONE,
            ),
            prim(Shape::Sphere { radius: 1.4 }, [1.6, 2.9, 0.0], SANDSTONE),
        ],
    );
    let body = smooth(
        Combine::Union,
        0.2,
        vec![
            wall,
            prim(
                Shape::Cylinder {
                    radius: 0.4,
                    half_height: 1.6,
                },
                [-2.3, 1.3, 0.0],
                STONE,
            ),
        ],
    );
    kind("ruin", body, 0.6, (0.8, 1.2), false)
}

/// A cairn: stones piled up, smaller towards the top.
pub fn cairn() -> Kind {
    let stones = [
        (0.75, [0.0, 0.15, 0.0]),
        (0.6, [0.1, 0.85, 0.05]),
        (0.45, [-0.05, 1.45, 0.0]),
        (0.32, [0.05, 1.9, 0.0]),
    ];
    let body = smooth(
        Combine::Union,
        0.15,
        stones
            .iter()
            .map(|&(r, at)| Node::Shape {
                shape: Shape::Sphere { radius: r },
                transform: Transform {
                    translate: at,
                    rotate: [0.0, 30.0, 0.0],
                    scale: [1.0, 0.6, 1.0],
                },
                material: STONE,
            })
            .collect(),
    );
    kind("cairn", rough(0.05, 4.0, body), 1.0, (0.7, 1.2), true)
}

/// The landscape's kinds, in order.
pub fn landscape_kinds() -> Vec<Kind> {
    vec![boulder(), standing_stone(), arch(), ruin(), cairn()]
}

/// The landscape's props: [`landscape_kinds`] with [`materials`], none at given places.
pub fn landscape() -> Scene {
    Scene {
        materials: materials(),
        kinds: landscape_kinds(),
        placed: Vec::new(),
    }
}

/// The SDF article's demo: a box and a sphere beside it blended by a smooth union of radius
/// 0.3 (the article's), at 2 m to the metre of its scene; its ground is the terrain.
pub fn demo() -> Kind {
    let body = smooth(
        Combine::Union,
        0.6,
        vec![
            prim(Shape::Sphere { radius: 1.0 }, [0.0, 2.0, 1.5], WHITE),
            prim(Shape::Box { half: [0.6; 3] }, [0.0, 2.0, 0.0], WHITE),
        ],
    );
    kind("demo", body, 0.0, (1.0, 1.0), true)
}
