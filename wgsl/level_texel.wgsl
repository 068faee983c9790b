// A level texel of the endless world's (and the tile's) clipmap in 64 bits, rg32uint: 12 bytes
// a texel with the light's 4 where rgba32float took 20 (src/gpu/landscape.rs packs and unpacks
// the same on the CPU).
//   x: the height (in [0, 1] of the peak) as a 24-bit fixed-point number, as fine as a 32-bit
//      float near the peak, above the colour channel's 8 bits (the shaded albedo moves by less
//      than an 8-bit output step between two codes);
//   y: the gradient per sample (dh/dx, dh/dz times the level's spacing, bounded by about 1
//      whatever the octaves, since a level keeps only octaves whose cells span two samples),
//      times LEVEL_GRADIENT_SCALE, as two 16-bit floats: the normal is good to ~0.03 degrees.

const LEVEL_HEIGHT_ONE: f32 = 16777215.0;
const LEVEL_GRADIENT_SCALE: f32 = 64.0;

// Packs (height, dh/dx, dh/dz, colour) of a level spaced 2^spacing_log2 metres.
fn pack_level_texel(s: vec4<f32>, spacing_log2: i32) -> vec2<u32> {
    let h = u32(round(clamp(s.x, 0.0, 1.0) * LEVEL_HEIGHT_ONE));
    let c = u32(round(clamp(s.w, 0.0, 1.0) * 255.0));
    let g = ldexp(s.yz, vec2<i32>(spacing_log2)) * LEVEL_GRADIENT_SCALE;
    return vec2<u32>((h << 8u) | c, pack2x16float(g));
}

// The height alone of a packed texel.
fn level_texel_height(x: u32) -> f32 {
    return f32(x >> 8u) / LEVEL_HEIGHT_ONE;
}

// (height, dh/dx, dh/dz, colour) of a packed texel of a level spaced `spacing` metres.
fn unpack_level_texel(t: vec2<u32>, spacing: f32) -> vec4<f32> {
    let g = unpack2x16float(t.y) / (LEVEL_GRADIENT_SCALE * spacing);
    return vec4<f32>(level_texel_height(t.x), g, f32(t.x & 255u) / 255.0);
}
