//! The kinds' tapes compiled into WGSL at load: a function a kind of straight-line code (each
//! instruction's transform, shape and parameters written as constants, the stack as local
//! values), and `kind_distance` choosing among them, in place of the interpreter of
//! `wgsl/props.wgsl` that reads the tapes from a buffer. Same arithmetic, same order: the two
//! agree to a rounding (tested). And the tapes and kinds in the buffers that interpreter reads.

use crate::props::place::cumulative;
use crate::props::{Combine, Op, Scene, Shape, Tape};
use std::fmt::Write as _;

/// Mirrors `PropKind` in `wgsl/props.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct PropKind {
    pub(crate) first: u32,
    pub(crate) count: u32,
    pub(crate) lipschitz: f32,
    pub(crate) weight: f32,
    pub(crate) lo: [f32; 4],
    pub(crate) hi: [f32; 4],
    pub(crate) scale: [f32; 4],
    pub(crate) sphere: [f32; 4],
}

/// Mirrors `PropOp` in `wgsl/props.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct PropOp {
    pub(crate) head: [f32; 4],
    pub(crate) params: [f32; 4],
    pub(crate) rows: [[f32; 4]; 3],
}

/// The kinds' tapes as the GPU reads them: the instructions and the kinds.
pub(crate) fn gpu_tapes(scene: &Scene, tapes: &[Tape]) -> (Vec<PropOp>, Vec<PropKind>) {
    let weights = cumulative(&scene.kinds);
    let mut code = Vec::new();
    let mut kinds = Vec::new();
    for ((kind, tape), weight) in scene.kinds.iter().zip(tapes).zip(weights) {
        let first = code.len() as u32;
        for ins in &tape.code {
            let (op, params) = op_code(&ins.op);
            code.push(PropOp {
                head: [op as f32, ins.material as f32, ins.scale as f32, 0.0],
                params,
                rows: ins.to_local.map(|r| r.map(|v| v as f32)),
            });
        }
        let [lo, hi] = tape.bounds.map(|b| b.map(|v| v as f32));
        kinds.push(PropKind {
            first,
            count: tape.code.len() as u32,
            lipschitz: tape.lipschitz as f32,
            weight,
            lo: [lo[0], lo[1], lo[2], tape.radius() as f32],
            hi: [hi[0], hi[1], hi[2], f32::from(u8::from(kind.on_rock))],
            scale: [
                kind.scale.0,
                kind.scale.1,
                tape.roughness() as f32,
                tape.lipschitz_undisplaced as f32,
            ],
            sphere: {
                let c = [0, 1, 2].map(|a| 0.5 * (lo[a] + hi[a]));
                let r = [0, 1, 2].map(|a| 0.5 * (hi[a] - lo[a]));
                [
                    c[0],
                    c[1],
                    c[2],
                    (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt(),
                ]
            },
        });
    }
    (code, kinds)
}

/// The instruction's code in `wgsl/props.wgsl` and its parameters.
pub(crate) fn op_code(op: &Op) -> (u32, [f32; 4]) {
    match *op {
        Op::Shape(s) => match s {
            Shape::Sphere { radius } => (0, [radius, 0.0, 0.0, 0.0]),
            Shape::Box { half } => (1, [half[0], half[1], half[2], 0.0]),
            Shape::RoundBox { half, radius } => (2, [half[0], half[1], half[2], radius]),
            Shape::Torus { major, minor } => (3, [major, minor, 0.0, 0.0]),
            Shape::Cylinder {
                radius,
                half_height,
            } => (4, [radius, half_height, 0.0, 0.0]),
            Shape::Capsule {
                radius,
                half_height,
            } => (5, [radius, half_height, 0.0, 0.0]),
            Shape::Plane { normal, offset } => (6, [normal[0], normal[1], normal[2], offset]),
        },
        Op::Combine(c, k) => {
            let code = match c {
                Combine::Union => 10,
                Combine::Intersection => 11,
                Combine::Subtraction => 12,
            };
            (code, [k, 0.0, 0.0, 0.0])
        }
        Op::Displace {
            amplitude,
            frequency,
        } => (20, [amplitude, frequency, 0.0, 0.0]),
    }
}

/// A WGSL float literal that reads back as `v`.
fn float(v: f32) -> String {
    let s = format!("{v:?}");
    if s.contains(['.', 'e']) {
        s
    } else {
        format!("{s}.0")
    }
}

fn vec4(v: [f32; 4]) -> String {
    format!(
        "vec4<f32>({}, {}, {}, {})",
        float(v[0]),
        float(v[1]),
        float(v[2]),
        float(v[3])
    )
}

/// The WGSL of one kind's function, `kind_<index>` (`rough`: with its displacements) or
/// `kind_smooth_<index>` (without).
fn kind_function(index: usize, tape: &Tape, rough: bool) -> String {
    let name = if rough { "kind" } else { "kind_smooth" };
    let mut out = format!("fn {name}_{index}(p: vec3<f32>, seed: u32) -> vec2<f32> {{\n");
    let mut stack: Vec<String> = Vec::new();
    for (i, ins) in tape.code.iter().enumerate() {
        let (code, params) = op_code(&ins.op);
        let rows = ins.to_local.map(|r| r.map(|v| v as f32));
        let point = format!(
            "vec3<f32>(dot({}, vec4<f32>(p, 1.0)), dot({}, vec4<f32>(p, 1.0)), dot({}, vec4<f32>(p, 1.0)))",
            vec4(rows[0]),
            vec4(rows[1]),
            vec4(rows[2])
        );
        let name = format!("v{i}");
        let line = match ins.op {
            Op::Shape(_) => format!(
                "vec2<f32>(shape_distance({code}u, {}, {point}) * {}, {})",
                vec4(params),
                float(ins.scale as f32),
                float(ins.material as f32)
            ),
            Op::Combine(..) => {
                let b = stack.pop().unwrap_or_default();
                let a = stack.pop().unwrap_or_default();
                format!("prop_combine({code}u, {a}, {b}, {})", float(params[0]))
            }
            Op::Displace { .. } if !rough => continue,
            Op::Displace { .. } => {
                let a = stack.pop().unwrap_or_default();
                format!(
                    "vec2<f32>({a}.x + {} * value_noise({point} * {}, seed), {a}.y)",
                    float(params[0]),
                    float(params[1])
                )
            }
        };
        let _ = writeln!(out, "    let {name} = {line};");
        stack.push(name);
    }
    let result = stack
        .pop()
        .unwrap_or_else(|| "vec2<f32>(3.0e38, 0.0)".into());
    let _ = writeln!(out, "    return {result};\n}}");
    out
}

/// The WGSL that defines `kind_distance` and `kind_undisplaced` by the kinds' compiled
/// functions, to follow a module whose own (the interpreter's) were renamed `*_tape`.
pub(crate) fn compiled_kinds(tapes: &[Tape]) -> String {
    let mut out = String::from("// The kinds' tapes compiled at load (src/gpu/props_wgsl.rs).\n");
    for (i, tape) in tapes.iter().enumerate() {
        out.push_str(&kind_function(i, tape, true));
        out.push_str(&kind_function(i, tape, false));
    }
    for (name, call, ret, rough) in [
        (
            "kind_distance(k: u32, p: vec3<f32>, seed: u32) -> vec2<f32>",
            "kind",
            "",
            true,
        ),
        (
            "kind_undisplaced(k: u32, p: vec3<f32>) -> f32",
            "kind_smooth",
            ".x",
            false,
        ),
    ] {
        let _ = writeln!(out, "fn {name} {{\n    switch k {{");
        let seed = if rough { "seed" } else { "0u" };
        for i in 0..tapes.len() {
            let _ = writeln!(
                out,
                "        case {i}u: {{ return {call}_{i}(p, {seed}){ret}; }}"
            );
        }
        let none = if rough {
            "vec2<f32>(3.0e38, 0.0)"
        } else {
            "3.0e38"
        };
        let _ = writeln!(out, "        default: {{ return {none}; }}\n    }}\n}}");
    }
    out
}

/// The march's module source: `wgsl/props_march.wgsl` composed, its kinds' tapes compiled in
/// (`compiled`) or read from the buffer.
pub(crate) fn march_source(tapes: &[Tape], compiled: bool) -> String {
    let source = super::shader::source("props_march");
    if !compiled {
        return source;
    }
    let renamed = source
        .replace("fn kind_distance(", "fn kind_distance_tape(")
        .replace("fn kind_undisplaced(", "fn kind_undisplaced_tape(");
    debug_assert_ne!(renamed, source, "props.wgsl defines kind_distance");
    renamed + &compiled_kinds(tapes)
}
