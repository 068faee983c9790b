//! The CPU twin of `wgsl/props.wgsl` in f64: a tape's distance, its normal, a march along a
//! ray. The GPU's hits are tested against these.

use super::{Combine, Instruction, Op, Shape, Tape, STACK};

type V3 = [f64; 3];

fn len(v: V3) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn len2(x: f64, y: f64) -> f64 {
    x.hypot(y)
}

/// A primitive's distance at `p` in its own frame (the formulas of the SDF literature: exact
/// for every primitive here).
pub fn shape(shape: &Shape, p: V3) -> f64 {
    match *shape {
        Shape::Sphere { radius } => len(p) - f64::from(radius),
        Shape::Box { half } => box_distance(p, half.map(f64::from)),
        Shape::RoundBox { half, radius } => {
            let r = f64::from(radius);
            box_distance(p, half.map(|h| f64::from(h) - r)) - r
        }
        Shape::Torus { major, minor } => {
            len2(len2(p[0], p[2]) - f64::from(major), p[1]) - f64::from(minor)
        }
        Shape::Cylinder {
            radius,
            half_height,
        } => {
            let dx = len2(p[0], p[2]) - f64::from(radius);
            let dy = p[1].abs() - f64::from(half_height);
            dx.max(dy).min(0.0) + len2(dx.max(0.0), dy.max(0.0))
        }
        Shape::Capsule {
            radius,
            half_height,
        } => {
            let h = f64::from(half_height);
            let y = p[1] - p[1].clamp(-h, h);
            len([p[0], y, p[2]]) - f64::from(radius)
        }
        Shape::Plane { normal, offset } => {
            let n = normal.map(f64::from);
            p[0] * n[0] + p[1] * n[1] + p[2] * n[2] - f64::from(offset)
        }
    }
}

fn box_distance(p: V3, half: V3) -> f64 {
    let q = [0, 1, 2].map(|a| p[a].abs() - half[a]);
    let outside = len(q.map(|v| v.max(0.0)));
    outside + q[0].max(q[1]).max(q[2]).min(0.0)
}

/// The smooth minimum of `a` and `b` over radius `k` (0: the minimum) and how much of `a` it
/// takes (for the material): the polynomial blend, which lowers the minimum by at most k / 4
/// and whose gradient is a convex combination of its arguments' (so it keeps their Lipschitz
/// constant).
pub fn smooth_min(a: f64, b: f64, k: f64) -> (f64, f64) {
    if k <= 0.0 {
        return if a <= b { (a, 1.0) } else { (b, 0.0) };
    }
    let h = (0.5 + 0.5 * (b - a) / k).clamp(0.0, 1.0);
    (b + h * (a - b) - k * h * (1.0 - h), h)
}

fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

fn lattice(c: [i32; 3], seed: u32) -> f64 {
    use crate::noise::pcg;
    let h = pcg(c[0] as u32 ^ pcg(c[1] as u32 ^ pcg(c[2] as u32 ^ seed)));
    f64::from(h >> 8) * (2.0 / 16_777_216.0) - 1.0
}

/// A value noise in [-1, 1] at `q` (lattice units) for `seed`: the lattice's hashed values
/// blended with a quintic fade (its gradient is bounded by [`super::NOISE_GRADIENT`]).
pub fn value_noise(q: V3, seed: u32) -> f64 {
    let i = q.map(|v| v.floor());
    let f = [0, 1, 2].map(|a| q[a] - i[a]);
    let c = i.map(|v| v as i32);
    let u = f.map(fade);
    let at = |dx: i32, dy: i32, dz: i32| lattice([c[0] + dx, c[1] + dy, c[2] + dz], seed);
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let x00 = lerp(at(0, 0, 0), at(1, 0, 0), u[0]);
    let x10 = lerp(at(0, 1, 0), at(1, 1, 0), u[0]);
    let x01 = lerp(at(0, 0, 1), at(1, 0, 1), u[0]);
    let x11 = lerp(at(0, 1, 1), at(1, 1, 1), u[0]);
    lerp(lerp(x00, x10, u[1]), lerp(x01, x11, u[1]), u[2])
}

fn apply(m: &[[f64; 4]; 3], p: V3) -> V3 {
    m.map(|r| r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3])
}

/// A tape's distance at `p` (the kind's frame, metres) and the material of the surface there;
/// `seed` varies the displacements' noise from one prop to the next.
pub fn distance(tape: &Tape, p: V3, seed: u32) -> (f64, u32) {
    distance_of(&tape.code, p, seed)
}

/// [`distance`] over bare instructions.
pub fn distance_of(code: &[Instruction], p: V3, seed: u32) -> (f64, u32) {
    let mut stack = [(0.0f64, 0u32); STACK];
    let mut top = 0usize;
    for ins in code {
        match ins.op {
            Op::Shape(s) => {
                stack[top] = (shape(&s, apply(&ins.to_local, p)) * ins.scale, ins.material);
                top += 1;
            }
            Op::Combine(op, k) => {
                top -= 1;
                let (b, mb) = stack[top];
                let (a, ma) = stack[top - 1];
                let k = f64::from(k);
                stack[top - 1] = match op {
                    Combine::Union => {
                        let (d, h) = smooth_min(a, b, k);
                        (d, if h >= 0.5 { ma } else { mb })
                    }
                    Combine::Intersection => {
                        let (d, h) = smooth_min(-a, -b, k);
                        (-d, if h >= 0.5 { ma } else { mb })
                    }
                    Combine::Subtraction => {
                        let (d, h) = smooth_min(-a, b, k);
                        (-d, if h >= 0.5 { ma } else { mb })
                    }
                };
            }
            Op::Displace {
                amplitude,
                frequency,
            } => {
                let q = apply(&ins.to_local, p).map(|v| v * f64::from(frequency));
                stack[top - 1].0 += f64::from(amplitude) * value_noise(q, seed);
            }
        }
    }
    stack[0]
}

/// The unit normal at `p`: the tetrahedron of four evaluations `e` apart.
pub fn normal(tape: &Tape, p: V3, seed: u32, e: f64) -> V3 {
    let ks: [V3; 4] = [
        [1.0, -1.0, -1.0],
        [-1.0, -1.0, 1.0],
        [-1.0, 1.0, -1.0],
        [1.0, 1.0, 1.0],
    ];
    let mut n = [0.0; 3];
    for k in ks {
        let d = distance(tape, [0, 1, 2].map(|a| p[a] + e * k[a]), seed).0;
        for a in 0..3 {
            n[a] += k[a] * d;
        }
    }
    let l = len(n).max(1e-300);
    n.map(|v| v / l)
}

/// Where a ray from `origin` along the unit `dir` (the kind's frame) first meets the surface
/// within `reach`, marched conservatively (each step the distance over the Lipschitz
/// constant) until the distance is under `eps`; `None` where it leaves or runs out of `steps`.
pub fn march(
    tape: &Tape,
    (origin, dir): (V3, V3),
    seed: u32,
    reach: f64,
    eps: f64,
    steps: u32,
) -> Option<f64> {
    let mut t = 0.0;
    for _ in 0..steps {
        let p = [0, 1, 2].map(|a| origin[a] + t * dir[a]);
        let d = distance(tape, p, seed).0;
        if d < eps {
            return Some(t);
        }
        t += d / tape.lipschitz;
        if t > reach {
            return None;
        }
    }
    None
}
