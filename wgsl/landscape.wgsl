// import: noise
// The endless world's terrain function (composed after noise.wgsl, whose hash, gradients and
// fade it uses). Its CPU twin, in f64, is `src/landscape.rs`.
//
// World units are metres. Octave `o` has lattice cells 2^(feature_log2 - o) metres wide, hashed
// on wrapping 32-bit integer cell coordinates. A sample grid spaced 2^level_log2 metres is
// addressed by integer sample coordinates; each octave's cell and fraction are taken from them
// with integer shifts, so every sample is exact wherever it lies (no f32 world positions).

struct LandscapeUniforms {
    // World sample coordinates of the first texel of the rectangle baked.
    origin: vec2<i32>,
    // Size of the rectangle baked, in samples.
    extent: vec2<u32>,
    // Where the rectangle's first texel goes in the (toroidal) texture, and its side.
    dest_origin: vec2<u32>,
    wrap: u32,
    // Texture-array layer written.
    layer: u32,
    seed: u32,
    // Octaves this grid keeps, and all octaves (the normalisation).
    octaves: u32,
    total_octaves: u32,
    // 0: fBm, 1: derivative-damped ("eroded") fBm.
    terrain: u32,
    gain: f32,
    feature_log2: i32,
    level_log2: i32,
    // 0: endless; else octave 0's lattice cells per period (octave o wraps at period << o).
    period: u32,
}

// The cell's corners (x0, y0, x1, y1) as hashed: wrapping 32-bit integers, or wrapped into
// `period` cells when it is not 0 (the tile). Without a branch or an integer division (both
// slow on CPU rasterisers such as lavapipe, even where the period is uniform): the quotient
// comes from a float division, off by at most one for the tile's cells (a few periods from
// the origin), and is corrected.
fn lattice_corners(cell: vec2<i32>, period: u32) -> vec4<u32> {
    if period == 0u {
        let c = bitcast<vec2<u32>>(cell);
        return vec4<u32>(c, c + 1u);
    }
    let p = i32(max(period, 1u));
    let q = vec2<i32>(floor(vec2<f32>(cell) / f32(p)));
    var r = cell - q * p;
    r = select(r, r + p, r < vec2<i32>(0));
    r = select(r, r - p, r >= vec2<i32>(p));
    let c = select(bitcast<vec2<u32>>(cell), vec2<u32>(r), vec2<bool>(period != 0u));
    // Past the period's last cell comes its first; for period 0 (2^32) the same is the
    // wrapping sum.
    return vec4<u32>(c, select(c + 1u, vec2<u32>(0u), c + 1u == vec2<u32>(period)));
}

// Octave `o`'s period in cells (0: endless).
fn octave_period(period: u32, o: u32) -> u32 {
    if o >= 32u {
        return 0u;
    }
    return period << o;
}

// Gradient noise's value, gradient and, for the eroded terrain, Hessian (xx, xy, yy), all in
// lattice units.
struct NoiseD {
    value: f32,
    grad: vec2<f32>,
    hess: vec3<f32>,
}

fn fade2(t: vec2<f32>) -> vec2<f32> {
    return 60.0 * t * (2.0 * t * t - 3.0 * t + 1.0);
}

// Gradient noise at cell `cell` (wrapping at 2^32) and offset `f`.
fn cell_noise_d(cell: vec2<i32>, f: vec2<f32>, stream: u32) -> NoiseD {
    let c = bitcast<vec2<u32>>(cell);
    return corner_noise_d(vec4<u32>(c, c + 1u), f, stream);
}

// The noise in the cell whose corners hash as (x0, y0, x1, y1).
fn corner_noise_d(corners: vec4<u32>, f: vec2<f32>, stream: u32) -> NoiseD {
    return gradient_noise_d(corner_gradients(corners, stream), f);
}

// The noise at offset `f` in a cell with corner gradients `g`.
fn gradient_noise_d(g: CornerGradients, f: vec2<f32>) -> NoiseD {
    let ga = g.ga;
    let gb = g.gb;
    let gc = g.gc;
    let gd = g.gd;
    let a = dot(ga, f);
    let b = dot(gb, f - vec2<f32>(1.0, 0.0));
    let c = dot(gc, f - vec2<f32>(0.0, 1.0));
    let d = dot(gd, f - vec2<f32>(1.0, 1.0));
    let bb = b - a;
    let cc = c - a;
    let k = a - b - c + d;
    let db = gb - ga;
    let dc = gc - ga;
    let dk = ga - gb - gc + gd;
    let u = fade(f);
    let u1 = fade_derivative(f);
    let u2 = fade2(f);
    var out: NoiseD;
    out.value = a + u.x * bb + u.y * cc + u.x * u.y * k;
    out.grad = vec2<f32>(
        ga.x + u1.x * (bb + u.y * k) + u.x * db.x + u.y * dc.x + u.x * u.y * dk.x,
        ga.y + u1.y * (cc + u.x * k) + u.x * db.y + u.y * dc.y + u.x * u.y * dk.y,
    );
    out.hess = vec3<f32>(
        u2.x * (bb + u.y * k) + 2.0 * u1.x * (db.x + u.y * dk.x),
        u1.x * db.y + u1.y * dc.x + u1.x * u1.y * k + u1.x * u.y * dk.y + u.x * u1.y * dk.x,
        u2.y * (cc + u.x * k) + 2.0 * u1.y * (dc.y + u.x * dk.y),
    );
    return out;
}

// Sample `s` of a grid spaced 2^level_log2 metres in the lattice of an octave whose cells are
// 2^cell_log2 metres (cell_log2 > level_log2): cell = s >> shift, fraction = low bits / 2^shift.
struct Split {
    cell: vec2<i32>,
    frac: vec2<f32>,
}

fn lattice_split(s: vec2<i32>, shift: u32) -> Split {
    let mask = (1 << shift) - 1;
    var out: Split;
    out.cell = s >> vec2<u32>(shift);
    out.frac = vec2<f32>(s & vec2<i32>(mask)) / f32(1u << shift);
    return out;
}

// A running sum of octaves: plain or derivative-damped ("eroded"), with its gradient per
// metre. `acc` is the sum of the lattice-unit gradients so far (eroded only) and `dacc_x`,
// `dacc_y` its derivatives per metre (rows acc.x and acc.y).
struct Octaves {
    sum: f32,
    grad: vec2<f32>,
    acc: vec2<f32>,
    dacc_x: vec2<f32>,
    dacc_y: vec2<f32>,
}

// Adds one octave's noise `n` (lattice units), of lattice frequency `freq` per metre, at
// `amplitude`. The same operations in the same order wherever the terrain is evaluated.
fn add_octave(st: Octaves, n: NoiseD, freq: f32, amplitude: f32, eroded: bool) -> Octaves {
    var out = st;
    if eroded {
        out.acc += n.grad;
        out.dacc_x += vec2<f32>(n.hess.x, n.hess.y) * freq;
        out.dacc_y += vec2<f32>(n.hess.y, n.hess.z) * freq;
        // One division: the damping 1/q, its square in the derivative's second term (3.5%
        // faster region bakes on the H100 than dividing by q three times).
        let inv = 1.0 / (1.0 + dot(out.acc, out.acc));
        let damped = amplitude * inv;
        out.sum += damped * n.value;
        let dq = 2.0 * (out.acc.x * out.dacc_x + out.acc.y * out.dacc_y);
        out.grad += damped * (n.grad * freq - n.value * dq * inv);
    } else {
        out.sum += amplitude * n.value;
        out.grad += amplitude * n.grad * freq;
    }
    return out;
}

// Octave `o`'s cell at sample `s` of grid `level_log2` offset by `f` samples: its corners as
// hashed, the fraction within it, and the octave's lattice frequency per metre (a power of
// two, so exact).
struct OctaveCell {
    corners: vec4<u32>,
    frac: vec2<f32>,
    freq: f32,
}

fn octave_cell(s: vec2<i32>, f: vec2<f32>, u: LandscapeUniforms, o: u32) -> OctaveCell {
    let cell_log2 = u.feature_log2 - i32(o);
    let shift = u32(cell_log2 - u.level_log2);
    let split = lattice_split(s, shift);
    let frac = split.frac + f * ldexp(1.0, -i32(shift));
    let whole = floor(frac);
    var out: OctaveCell;
    out.corners = lattice_corners(split.cell + vec2<i32>(whole), octave_period(u.period, o));
    out.frac = frac - whole;
    out.freq = ldexp(1.0, -cell_log2);
    return out;
}

// The channel `f` samples of grid `level_log2` (a small offset, either sign) from world sample
// `s`: (value in [0,1], d/dx, d/dz per metre). Each octave's cell comes from the integer sample
// and only the fraction takes the offset, so the point is exact far from the origin; an
// offset of 0 gives the bake's value (landscape_samples_quad).
fn landscape_sample_at(s: vec2<i32>, f: vec2<f32>, u: LandscapeUniforms, channel: u32) -> vec3<f32> {
    let eroded = u.terrain == 1u && channel == CHANNEL_HEIGHT;
    var st = Octaves();
    var amplitude = 1.0;
    var norm = 0.0;
    for (var o = 0u; o < u.total_octaves; o++) {
        if o < u.octaves {
            let c = octave_cell(s, f, u, o);
            let n = corner_noise_d(c.corners, c.frac, noise_stream(u.seed, channel, o));
            st = add_octave(st, n, c.freq, amplitude, eroded);
        }
        norm += amplitude;
        amplitude *= u.gain;
    }
    let scale = 0.5 / (norm * NOISE_MAX_ABS);
    return vec3<f32>(0.5 + scale * st.sum, scale * st.grad);
}

// Both channels at the 2x2 samples from `s` (even on both axes), in the order (0, 0), (1, 0),
// (0, 1), (1, 1), in one pass over the octaves. Every octave a grid keeps has cells at least
// two samples wide (`Landscape::octaves_for_level`), so the four samples lie in one cell of
// every octave: they share its split and its corner gradients, the integer hashing that
// each sample would otherwise do alone. Each channel takes the operations landscape_sample_at
// takes at offset 0 (the same bits on lavapipe; a driver may fuse multiply-adds differently).
// Written out for the four samples, not as arrays: indexed arrays of sums ran 36% slower than
// a sample an invocation on the H100, these 2.3x faster (docs/results/bakes.md).
fn landscape_samples_quad(s: vec2<i32>, u: LandscapeUniforms) -> array<vec4<f32>, 4> {
    let eroded = u.terrain == 1u;
    var h0 = Octaves();
    var h1 = Octaves();
    var h2 = Octaves();
    var h3 = Octaves();
    var t0 = Octaves();
    var t1 = Octaves();
    var t2 = Octaves();
    var t3 = Octaves();
    var amplitude = 1.0;
    var norm = 0.0;
    for (var o = 0u; o < u.total_octaves; o++) {
        if o < u.octaves {
            let c = octave_cell(s, vec2<f32>(0.0), u, o);
            let gh = corner_gradients(c.corners, noise_stream(u.seed, CHANNEL_HEIGHT, o));
            let gt = corner_gradients(c.corners, noise_stream(u.seed, CHANNEL_COLOR, o));
            let shift = u32(u.feature_log2 - i32(o) - u.level_log2);
            let f0 = lattice_split(s, shift).frac;
            let f1 = lattice_split(s + quad_offset(1u), shift).frac;
            let f2 = lattice_split(s + quad_offset(2u), shift).frac;
            let f3 = lattice_split(s + quad_offset(3u), shift).frac;
            h0 = add_octave(h0, gradient_noise_d(gh, f0), c.freq, amplitude, eroded);
            h1 = add_octave(h1, gradient_noise_d(gh, f1), c.freq, amplitude, eroded);
            h2 = add_octave(h2, gradient_noise_d(gh, f2), c.freq, amplitude, eroded);
            h3 = add_octave(h3, gradient_noise_d(gh, f3), c.freq, amplitude, eroded);
            t0 = add_octave(t0, gradient_noise_d(gt, f0), c.freq, amplitude, false);
            t1 = add_octave(t1, gradient_noise_d(gt, f1), c.freq, amplitude, false);
            t2 = add_octave(t2, gradient_noise_d(gt, f2), c.freq, amplitude, false);
            t3 = add_octave(t3, gradient_noise_d(gt, f3), c.freq, amplitude, false);
        }
        norm += amplitude;
        amplitude *= u.gain;
    }
    let scale = 0.5 / (norm * NOISE_MAX_ABS);
    let m = 0.5 + scale * vec4<f32>(h0.sum, h1.sum, h2.sum, h3.sum);
    let n = 0.5 + scale * vec4<f32>(t0.sum, t1.sum, t2.sum, t3.sum);
    return array<vec4<f32>, 4>(
        vec4<f32>(m.x, scale * h0.grad, n.x),
        vec4<f32>(m.y, scale * h1.grad, n.y),
        vec4<f32>(m.z, scale * h2.grad, n.z),
        vec4<f32>(m.w, scale * h3.grad, n.w),
    );
}

// Sample `k` of a 2x2 quad, from its first: (0, 0), (1, 0), (0, 1), (1, 1).
fn quad_offset(k: u32) -> vec2<i32> {
    return vec2<i32>(i32(k & 1u), i32(k >> 1u));
}
