// import: noise
// Bake pass: writes normalised height (r) and the albedo-mix channel (g) into an rg32float
// storage texture, one texel an invocation (`bake_main`) or, where every octave's lattice cells
// hold whole pairs of texels, a 2x2 quad of texels an invocation (`bake_quads`).
// Composed after noise.wgsl.

struct BakeUniforms {
    size: u32,
    frequency: u32,
    octaves: u32,
    seed: u32,
    gain: f32,
    _pad: u32,
    // Scroll offset in tiles, reduced to [0, 1) on the CPU in f64.
    offset: vec2<f32>,
}

@group(0) @binding(0) var<uniform> bake: BakeUniforms;
@group(0) @binding(1) var terrain_out: texture_storage_2d<rg32float, write>;

@compute @workgroup_size(8, 8, 1)
fn bake_main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= bake.size || id.y >= bake.size {
        return;
    }
    let t = fbm_texel(id.xy, bake.size, bake.frequency, bake.octaves, bake.gain, bake.offset, bake.seed);
    textureStore(terrain_out, vec2<i32>(id.xy), vec4<f32>(t, 0.0, 1.0));
}

// Both channels at the 2x2 texels from `texel` (even on both axes), in the order (0, 0), (1, 0),
// (0, 1), (1, 1), for a bake without offset whose every octave has an even number of texels to
// a lattice cell (src/gpu/bake.rs checks both): the four texels lie in one cell of every octave,
// so they share its corners' hashes and gradients, the integer work each texel would otherwise
// do alone. Each texel takes the operations fbm_texel takes at offset 0 (its fraction from its
// own remainder), so the texels are fbm_texel's. Written out for the four texels, not as indexed
// arrays (which ran slower than a sample an invocation in the landscape's bake on the H100).
fn fbm_texel_quad(texel: vec2<u32>, size: u32, frequency: u32, octaves: u32, gain: f32, seed: u32) -> array<vec2<f32>, 4> {
    var s0 = vec2<f32>(0.0);
    var s1 = vec2<f32>(0.0);
    var s2 = vec2<f32>(0.0);
    var s3 = vec2<f32>(0.0);
    var amplitude = 1.0;
    var norm = 0.0;
    let den = 2u * size;
    // Per axis, the quad's first texel (a) and its second (b).
    let num_a = (2u * texel + vec2<u32>(1u)) * frequency;
    let num_b = num_a + 2u * frequency;
    var a = TexelSplit(num_a / den, num_a % den);
    var b = TexelSplit(num_b / den, num_b % den);
    for (var o = 0u; o < octaves; o++) {
        let period = frequency << o;
        let fa = vec2<f32>(a.rem) / f32(den);
        let fb = vec2<f32>(b.rem) / f32(den);
        // a.quotient == b.quotient: the quad's texels share the cell.
        let corners = periodic_corners(a.quotient, period);
        let gh = corner_gradients(corners, noise_stream(seed, CHANNEL_HEIGHT, o));
        let gc = corner_gradients(corners, noise_stream(seed, CHANNEL_COLOR, o));
        let f1 = vec2<f32>(fb.x, fa.y);
        let f2 = vec2<f32>(fa.x, fb.y);
        s0 += amplitude * vec2<f32>(corner_value(gh, fa), corner_value(gc, fa));
        s1 += amplitude * vec2<f32>(corner_value(gh, f1), corner_value(gc, f1));
        s2 += amplitude * vec2<f32>(corner_value(gh, f2), corner_value(gc, f2));
        s3 += amplitude * vec2<f32>(corner_value(gh, fb), corner_value(gc, fb));
        norm += amplitude;
        amplitude *= gain;
        a = next_octave_split(a, den);
        b = next_octave_split(b, den);
    }
    let k = norm * NOISE_MAX_ABS;
    return array<vec2<f32>, 4>(0.5 + 0.5 * s0 / k, 0.5 + 0.5 * s1 / k, 0.5 + 0.5 * s2 / k, 0.5 + 0.5 * s3 / k);
}

@compute @workgroup_size(8, 8, 1)
fn bake_quads(@builtin(global_invocation_id) id: vec3<u32>) {
    let texel = 2u * id.xy;
    if texel.x >= bake.size || texel.y >= bake.size {
        return;
    }
    let t = fbm_texel_quad(texel, bake.size, bake.frequency, bake.octaves, bake.gain, bake.seed);
    let p = vec2<i32>(texel);
    textureStore(terrain_out, p, vec4<f32>(t[0], 0.0, 1.0));
    textureStore(terrain_out, p + vec2<i32>(1, 0), vec4<f32>(t[1], 0.0, 1.0));
    textureStore(terrain_out, p + vec2<i32>(0, 1), vec4<f32>(t[2], 0.0, 1.0));
    textureStore(terrain_out, p + vec2<i32>(1, 1), vec4<f32>(t[3], 0.0, 1.0));
}
