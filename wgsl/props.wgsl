// import: noise
// Props (src/props/): the kinds' tapes evaluated from a buffer (src/props/sdf.rs is the f64
// twin), each cell's prop from a hash of its 64-bit coordinates (src/props/place.rs's
// `prop_at`), and the frame's grid of placed props around the eye that the scatter
// (props_scatter.wgsl) writes and the march (props_march.wgsl) reads. Cells reach the GPU
// relative to the eye's cell, which is 64-bit: the hash sees the same integers anywhere.

struct PropsFrame {
    // The eye's cell, 64-bit: x low and high words, z low and high words.
    eye_cell: vec4<u32>,
    // The eye less its cell's first corner, metres (x, z); a cell's side, metres; the cells
    // the grid spans on a side (the eye's cell is number side / 2).
    eye_in_cell: vec2<f32>,
    cell: f32,
    side: u32,
    // The chances a cell holds a prop on gentle ground and on rock; the draw distance, metres;
    // the screen-size cut-off, pixels.
    density: f32,
    rock_density: f32,
    distance: f32,
    cutoff: f32,
    // The landscape's seed; the kinds; the props at given places; the water's normalised
    // level (below every height where there is none).
    seed: u32,
    kinds: u32,
    placed: u32,
    water: f32,
    // Pixels a unit of tan(angle) spans on screen (the image's height over 2 tan(fov / 2));
    // the band, metres; the blocks of BLOCK dual cells on a side; the most steps a ray takes.
    pixels: f32,
    band: f32,
    blocks: u32,
    steps: u32,
    // 16: the benchmark's peer, the seed's way (props_march.wgsl's `seed_walk`); 32: no raster's
    // depth bounds the march (the props' overlay, props_overlay.wgsl); 64: the reference's
    // march (props_reference.wgsl), every sample's own shadow on the surface.
    flags: u32,
    // The seed's way's steps (flag 16): its view rays' budget; the shadows keep `steps`.
    peer_steps: u32,
    _pad1: u32,
    _pad2: u32,
}

// A kind: its tape's first instruction and length, its Lipschitz constant, its cumulative
// weight; the box of its surface (min xyz and the radius about its axis; max xyz and 1 where
// it stands on rock); its scale's range (min, max), the sum of its displacements' amplitudes
// (what its field may lie below its undisplaced field) and the undisplaced field's Lipschitz
// constant; a sphere that holds it.
struct PropKind {
    first: u32,
    count: u32,
    lipschitz: f32,
    weight: f32,
    lo: vec4<f32>,
    hi: vec4<f32>,
    scale: vec4<f32>,
    sphere: vec4<f32>,
}

// An instruction (src/props/mod.rs: Instruction): the op's code, the material, the scale its
// distances are multiplied by; the shape's or the op's parameters; the map from the kind's
// frame to its own (rows of a 3x4 matrix).
struct PropOp {
    head: vec4<f32>,
    params: vec4<f32>,
    m0: vec4<f32>,
    m1: vec4<f32>,
    m2: vec4<f32>,
}

@group(1) @binding(0) var<uniform> pf: PropsFrame;
@group(1) @binding(1) var<storage, read> prop_code: array<PropOp>;
@group(1) @binding(2) var<storage, read> prop_kinds: array<PropKind>;
// Per material: linear albedo and how much a prop's shade varies it.
@group(1) @binding(3) var<storage, read> prop_materials: array<vec4<f32>>;

// The codes of src/gpu/props.rs's `op_code`.
const OP_SPHERE: u32 = 0u;
const OP_BOX: u32 = 1u;
const OP_ROUND_BOX: u32 = 2u;
const OP_TORUS: u32 = 3u;
const OP_CYLINDER: u32 = 4u;
const OP_CAPSULE: u32 = 5u;
const OP_PLANE: u32 = 6u;
const OP_UNION: u32 = 10u;
const OP_INTERSECTION: u32 = 11u;
const OP_SUBTRACTION: u32 = 12u;
const OP_DISPLACE: u32 = 20u;
// The evaluation stack (src/props/mod.rs: STACK).
const PROP_STACK: u32 = 33u;
const PROP_STREAM: u32 = 0x70726f70u;
const PROP_TAU: f32 = 6.28318530717958648;

fn box_distance(p: vec3<f32>, half: vec3<f32>) -> f32 {
    let q = abs(p) - half;
    return length(max(q, vec3<f32>(0.0))) + min(max(q.x, max(q.y, q.z)), 0.0);
}

fn shape_distance(code: u32, a: vec4<f32>, p: vec3<f32>) -> f32 {
    switch code {
        case 0u: {
            return length(p) - a.x;
        }
        case 1u: {
            return box_distance(p, a.xyz);
        }
        case 2u: {
            return box_distance(p, a.xyz - a.w) - a.w;
        }
        case 3u: {
            return length(vec2<f32>(length(p.xz) - a.x, p.y)) - a.y;
        }
        case 4u: {
            let d = vec2<f32>(length(p.xz) - a.x, abs(p.y) - a.y);
            return min(max(d.x, d.y), 0.0) + length(max(d, vec2<f32>(0.0)));
        }
        case 5u: {
            let y = p.y - clamp(p.y, -a.y, a.y);
            return length(vec3<f32>(p.x, y, p.z)) - a.x;
        }
        default: {
            return dot(p, a.xyz) - a.w;
        }
    }
}

// The smooth minimum over radius k (0: the minimum) and how much of `a` it takes.
fn smooth_min(a: f32, b: f32, k: f32) -> vec2<f32> {
    if k <= 0.0 {
        return select(vec2<f32>(b, 0.0), vec2<f32>(a, 1.0), a <= b);
    }
    let h = clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
    return vec2<f32>(b + h * (a - b) - k * h * (1.0 - h), h);
}

fn prop_fade(t: vec3<f32>) -> vec3<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

fn prop_lattice(c: vec3<i32>, seed: u32) -> f32 {
    let h = pcg(bitcast<u32>(c.x) ^ pcg(bitcast<u32>(c.y) ^ pcg(bitcast<u32>(c.z) ^ seed)));
    return f32(h >> 8u) * (2.0 / 16777216.0) - 1.0;
}

// A value noise in [-1, 1] (src/props/sdf.rs: value_noise).
fn value_noise(q: vec3<f32>, seed: u32) -> f32 {
    let i = floor(q);
    let u = prop_fade(q - i);
    let c = vec3<i32>(i);
    let x00 = mix(prop_lattice(c, seed), prop_lattice(c + vec3<i32>(1, 0, 0), seed), u.x);
    let x10 = mix(prop_lattice(c + vec3<i32>(0, 1, 0), seed), prop_lattice(c + vec3<i32>(1, 1, 0), seed), u.x);
    let x01 = mix(prop_lattice(c + vec3<i32>(0, 0, 1), seed), prop_lattice(c + vec3<i32>(1, 0, 1), seed), u.x);
    let x11 = mix(prop_lattice(c + vec3<i32>(0, 1, 1), seed), prop_lattice(c + vec3<i32>(1, 1, 1), seed), u.x);
    return mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z);
}

fn op_point(op: PropOp, p: vec3<f32>) -> vec3<f32> {
    let h = vec4<f32>(p, 1.0);
    return vec3<f32>(dot(op.m0, h), dot(op.m1, h), dot(op.m2, h));
}

// The boolean `code` (OP_UNION, OP_INTERSECTION, OP_SUBTRACTION) of the distances and
// materials `a` and `b`, smooth over radius `k` (0: sharp).
fn prop_combine(code: u32, a: vec2<f32>, b: vec2<f32>, k: f32) -> vec2<f32> {
    var m: vec2<f32>;
    if code == OP_UNION {
        m = smooth_min(a.x, b.x, k);
    } else if code == OP_INTERSECTION {
        m = smooth_min(-a.x, -b.x, k);
        m.x = -m.x;
    } else {
        m = smooth_min(-a.x, b.x, k);
        m.x = -m.x;
    }
    return vec2<f32>(m.x, select(b.y, a.y, m.y >= 0.5));
}

// A kind's distance at `p` (its frame, metres) and the material there (as f32), for the prop
// whose noise is `seed`: its tape read from the buffer, run on a stack. (src/gpu/props_wgsl.rs
// compiles the tapes into WGSL at load in its place.)
fn kind_distance(k: u32, p: vec3<f32>, seed: u32) -> vec2<f32> {
    return run_tape(k, p, seed, true);
}

// The kind's distance without its noise's displacements: within the sum of their amplitudes
// (`PropKind::scale.z`) of the distance, and cheaper.
fn kind_undisplaced(k: u32, p: vec3<f32>) -> f32 {
    return run_tape(k, p, 0u, false).x;
}

fn run_tape(k: u32, p: vec3<f32>, seed: u32, rough: bool) -> vec2<f32> {
    let kind = prop_kinds[k];
    var stack: array<vec2<f32>, PROP_STACK>;
    var top = 0u;
    for (var i = 0u; i < kind.count; i++) {
        let op = prop_code[kind.first + i];
        let code = u32(op.head.x);
        if code < OP_UNION {
            stack[top] = vec2<f32>(shape_distance(code, op.params, op_point(op, p)) * op.head.z, op.head.y);
            top += 1u;
        } else if code < OP_DISPLACE {
            top -= 1u;
            stack[top - 1u] = prop_combine(code, stack[top - 1u], stack[top], op.params.x);
        } else if rough {
            let q = op_point(op, p) * op.params.y;
            stack[top - 1u].x += op.params.x * value_noise(q, seed);
        }
    }
    return stack[0];
}

// 64-bit integer (low, high words) plus a 32-bit one.
fn prop_add64(a: vec2<u32>, r: i32) -> vec2<u32> {
    let lo = a.x + bitcast<u32>(r);
    let carry = select(0u, 1u, lo < a.x);
    return vec2<u32>(lo, a.y + select(0u, 0xffffffffu, r < 0) + carry);
}

fn prop_unit(h: u32) -> f32 {
    return f32(h >> 8u) * (1.0 / 16777216.0);
}

// A cell's prop before the ground decides (src/props/place.rs: Prop).
struct Prop {
    kind: u32,
    offset: vec2<f32>,
    turn: f32,
    size: f32,
    shade: f32,
    chance: f32,
    cutoff: f32,
    seed: u32,
}

// The prop of the cell `rel` cells from the eye's.
fn prop_at(rel: vec2<i32>) -> Prop {
    let c = vec4<u32>(prop_add64(pf.eye_cell.xy, rel.x), prop_add64(pf.eye_cell.zw, rel.y));
    var h = pcg(pf.seed ^ pcg(c.x ^ pcg(c.y ^ pcg(c.z ^ pcg(c.w ^ PROP_STREAM)))));
    var p: Prop;
    h = pcg(h);
    p.chance = prop_unit(h);
    h = pcg(h);
    let pick = prop_unit(h);
    p.kind = pf.kinds - 1u;
    for (var k = 0u; k < pf.kinds; k++) {
        if pick < prop_kinds[k].weight {
            p.kind = k;
            break;
        }
    }
    h = pcg(h);
    p.offset.x = prop_unit(h);
    h = pcg(h);
    p.offset.y = prop_unit(h);
    h = pcg(h);
    p.turn = prop_unit(h) * PROP_TAU;
    h = pcg(h);
    p.size = prop_unit(h);
    h = pcg(h);
    p.shade = prop_unit(h);
    h = pcg(h);
    p.cutoff = 0.7 + 0.6 * prop_unit(h);
    p.seed = pcg(h ^ 0x5eedu);
    return p;
}

// The share of gentle ground (src/props/place.rs: gentle).
fn prop_gentle(n_y: f32, tint: f32) -> f32 {
    return smoothstep(0.6, 0.95, n_y + 0.08 * (2.0 * (tint - 0.5)));
}
