// Periodic 2-D gradient (Perlin) noise and fBm, shared by the passes that need it.
//
// The files that name it in their `// import:` line get it before them
// (`relief::gpu::shader::source`); it declares no bindings. Its CPU twin, in f64, is
// `src/noise.rs`: every constant and every step here has its counterpart there, and the tests
// compare the two.
//
// Lattice coordinates are integers and hashed with PCG (Jarzynski & Olano 2020, "Hash
// Functions for GPU Rendering"), so a seed gives the same terrain on every GPU, in the browser
// and on the CPU. Octave `o` has period `frequency << o` lattice cells across the tile; corner
// indices wrap modulo that period, so one tile is exactly one period of every octave.

// Largest |noise| for unit gradients in 2-D: sqrt(2)/2, reached at a cell centre.
const NOISE_MAX_ABS: f32 = 0.70710678118654752;
const DIAG: f32 = 0.70710678118654752;

// Channels are independent fBm streams under one seed.
const CHANNEL_HEIGHT: u32 = 0u;
const CHANNEL_COLOR: u32 = 1u;

fn pcg(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// One hash stream per (seed, channel, octave), so octaves are uncorrelated.
fn noise_stream(seed: u32, channel: u32, octave: u32) -> u32 {
    return pcg(seed ^ pcg(channel * 64u + octave));
}

fn lattice_hash(x: u32, y: u32, stream: u32) -> u32 {
    return pcg(x ^ pcg(y ^ stream));
}

// Eight unit gradients: the axes and the diagonals.
fn gradient(h: u32) -> vec2<f32> {
    let s0 = select(1.0, -1.0, (h & 1u) != 0u);
    let s1 = select(1.0, -1.0, (h & 2u) != 0u);
    if (h & 4u) != 0u {
        return vec2<f32>(s0 * DIAG, s1 * DIAG);
    }
    if (h & 8u) != 0u {
        return vec2<f32>(s0, 0.0);
    }
    return vec2<f32>(0.0, s1);
}

fn fade(t: vec2<f32>) -> vec2<f32> {
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// The gradients at a cell's corners (x0 y0, x1 y0, x0 y1, x1 y1) for one hash stream, from the
// corners' coordinates as hashed (x0, y0, x1, y1).
struct CornerGradients {
    ga: vec2<f32>,
    gb: vec2<f32>,
    gc: vec2<f32>,
    gd: vec2<f32>,
}

fn corner_gradients(corners: vec4<u32>, stream: u32) -> CornerGradients {
    return CornerGradients(
        gradient(lattice_hash(corners.x, corners.y, stream)),
        gradient(lattice_hash(corners.z, corners.y, stream)),
        gradient(lattice_hash(corners.x, corners.w, stream)),
        gradient(lattice_hash(corners.z, corners.w, stream)),
    );
}

// The corners of lattice cell `cell` (already in 0..period) as hashed: the corner past the
// period's last cell is its first (no integer division).
fn periodic_corners(cell: vec2<u32>, period: u32) -> vec4<u32> {
    let x1 = select(cell.x + 1u, 0u, cell.x + 1u == period);
    let y1 = select(cell.y + 1u, 0u, cell.y + 1u == period);
    return vec4<u32>(cell, x1, y1);
}

// Gradient noise's value at offset `f` in [0,1)^2 of a cell with corner gradients `g`.
fn corner_value(g: CornerGradients, f: vec2<f32>) -> f32 {
    let n00 = dot(g.ga, f);
    let n10 = dot(g.gb, f - vec2<f32>(1.0, 0.0));
    let n01 = dot(g.gc, f - vec2<f32>(0.0, 1.0));
    let n11 = dot(g.gd, f - vec2<f32>(1.0, 1.0));
    let u = fade(f);
    return mix(mix(n00, n10, u.x), mix(n01, n11, u.x), u.y);
}

// Gradient noise at lattice cell `cell` (already in 0..period) and offset `f` in [0,1)^2.
fn periodic_noise(cell: vec2<u32>, f: vec2<f32>, period: u32, stream: u32) -> f32 {
    return corner_value(corner_gradients(periodic_corners(cell, period), stream), f);
}

// fBm of both channels (height, colour) at the centre of texel `texel` of a `size` x `size`
// tile, each normalised to [0, 1].
//
// The texel's lattice position (2x+1) * period / (2 size) is split into an integer cell and a
// fraction with integer arithmetic, so it is exact at any octave. Only octave 0 divides: each
// octave doubles the numerator, so the quotient doubles and takes the carry of the doubled
// remainder (integer division per octave and texel was the bake's largest cost). `offset` (in
// tiles, already reduced to [0,1) on the CPU in f64) is added in lattice units with one
// rounding. The channels share the split. Parameter validation keeps (2 size) * period below
// 2^32.
fn fbm_texel(
    texel: vec2<u32>,
    size: u32,
    frequency: u32,
    octaves: u32,
    gain: f32,
    offset: vec2<f32>,
    seed: u32,
) -> vec2<f32> {
    var sum = vec2<f32>(0.0);
    var amplitude = 1.0;
    var norm = 0.0;
    let den = 2u * size;
    let num = (2u * texel + vec2<u32>(1u)) * frequency;
    var quotient = num / den;
    var rem = num % den;
    for (var o = 0u; o < octaves; o++) {
        let period = frequency << o;
        var f = vec2<f32>(rem) / f32(den);
        let shift = offset * f32(period);
        let whole = floor(shift);
        f += shift - whole;
        let carry = f >= vec2<f32>(1.0);
        f -= select(vec2<f32>(0.0), vec2<f32>(1.0), carry);
        // quotient < period and whole <= period, so the sum is under 2 period + 1: two
        // subtractions wrap it into the period, as `%` would.
        var cell = quotient + vec2<u32>(whole) + select(vec2<u32>(0u), vec2<u32>(1u), carry);
        cell = select(cell, cell - period, cell >= vec2<u32>(period));
        cell = select(cell, cell - period, cell >= vec2<u32>(period));
        sum.x += amplitude * periodic_noise(cell, f, period, noise_stream(seed, CHANNEL_HEIGHT, o));
        sum.y += amplitude * periodic_noise(cell, f, period, noise_stream(seed, CHANNEL_COLOR, o));
        norm += amplitude;
        amplitude *= gain;
        let next = next_octave_split(TexelSplit(quotient, rem), den);
        quotient = next.quotient;
        rem = next.rem;
    }
    return 0.5 + 0.5 * sum / (norm * NOISE_MAX_ABS);
}

// A texel's lattice position as quotient and remainder of numerator over `den`, per axis.
struct TexelSplit {
    quotient: vec2<u32>,
    rem: vec2<u32>,
}

// The next octave's split: the numerator doubles, so the quotient doubles and takes the carry
// of the doubled remainder.
fn next_octave_split(s: TexelSplit, den: u32) -> TexelSplit {
    let twice = 2u * s.rem;
    let over = twice >= vec2<u32>(den);
    return TexelSplit(
        2u * s.quotient + select(vec2<u32>(0u), vec2<u32>(1u), over),
        twice - select(vec2<u32>(0u), vec2<u32>(den), over),
    );
}

// fade'(t), for analytic gradients.
fn fade_derivative(t: vec2<f32>) -> vec2<f32> {
    return 30.0 * t * t * (t - 1.0) * (t - 1.0);
}

// Gradient noise at any lattice position `p` with its derivative: (value, d/dpx, d/dpy).
fn periodic_noise_grad(p: vec2<f32>, period: u32, stream: u32) -> vec3<f32> {
    let fl = floor(p);
    let f = p - fl;
    let per = i32(period);
    let c = vec2<i32>(fl);
    let x0 = u32(((c.x % per) + per) % per);
    let y0 = u32(((c.y % per) + per) % per);
    let x1 = (x0 + 1u) % period;
    let y1 = (y0 + 1u) % period;
    let ga = gradient(lattice_hash(x0, y0, stream));
    let gb = gradient(lattice_hash(x1, y0, stream));
    let gc = gradient(lattice_hash(x0, y1, stream));
    let gd = gradient(lattice_hash(x1, y1, stream));
    let a = dot(ga, f);
    let b = dot(gb, f - vec2<f32>(1.0, 0.0));
    let cc = dot(gc, f - vec2<f32>(0.0, 1.0));
    let d = dot(gd, f - vec2<f32>(1.0, 1.0));
    let u = fade(f);
    let du = fade_derivative(f);
    let k = a - b - cc + d;
    let value = a + u.x * (b - a) + u.y * (cc - a) + u.x * u.y * k;
    var grad = ga + u.x * (gb - ga) + u.y * (gc - ga) + u.x * u.y * (ga - gb - gc + gd);
    grad += du * vec2<f32>((b - a) + u.y * k, (cc - a) + u.x * k);
    return vec3<f32>(value, grad);
}

// Normalised fBm at continuous tile position `u` (one tile = [0,1)^2, before the offset) and
// its gradient with respect to u: (h, dh/du.x, dh/du.y). Sums the first `octaves` octaves but
// normalises by `norm_octaves` of them, so truncating octaves (as the seed's ray marcher does
// while stepping) keeps the same height scale.
fn fbm_grad(
    u: vec2<f32>,
    frequency: u32,
    octaves: u32,
    norm_octaves: u32,
    gain: f32,
    offset: vec2<f32>,
    seed: u32,
    channel: u32,
) -> vec3<f32> {
    // The noise is periodic in the tile, so wrapping keeps f32 lattice positions small.
    let q = fract(u + offset);
    var sum = vec3<f32>(0.0);
    var amplitude = 1.0;
    var norm = 0.0;
    for (var o = 0u; o < norm_octaves; o++) {
        if o < octaves {
            let period = frequency << o;
            let n = periodic_noise_grad(q * f32(period), period, noise_stream(seed, channel, o));
            sum += amplitude * vec3<f32>(n.x, n.yz * f32(period));
        }
        norm += amplitude;
        amplitude *= gain;
    }
    let scale = 0.5 / (norm * NOISE_MAX_ABS);
    return vec3<f32>(0.5 + scale * sum.x, scale * sum.yz);
}
