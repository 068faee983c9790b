// import: shade
// part of: world, hybrid (each declares the uniforms `r`)
// The props' shade map as the terrain's shading reads it (src/gpu/props_map.rs bakes it): over
// the ground around the eye, in world space, the props' shadow (the sun's share) and their
// occlusion of the sky (the sky's share), in levels of PROPS_MAP_SIDE texels a side, each
// level's texel PROPS_MAP_TEXELS metres, addressed toroidally (a world texel's place in the
// texture is its index modulo the side: the sampler repeats, so its bilinear filter wraps
// with it). The methods that shade the terrain before the props are marched (the forward mesh,
// the hybrid, the visibility method rasterised by the GPU, the page's) read it; the marching
// method marches each pixel's own.

@group(0) @binding(23) var props_map_tex: texture_2d_array<f32>;
@group(0) @binding(24) var props_map_sampler: sampler;

const PROPS_MAP_SIDE: f32 = 512.0;
const PROPS_MAP_TEXELS: vec3<f32> = vec3<f32>(0.25, 1.0, 4.0);
// Texels over which a level fades out at its edge (into the next coarser level, the last into
// no props' shade).
const PROPS_MAP_FADE: f32 = 16.0;

// Level `l`'s shade at camera-relative `xz` and its weight there (0 outside the level, 1
// within it but for its fading edge); the level lies as `m` says (RenderUniforms.props_map).
fn props_map_level(l: i32, m: vec4<f32>, texel: f32, xz: vec2<f32>) -> vec3<f32> {
    let g = (xz - m.xy) / texel;
    let inset = min(min(g.x, g.y), PROPS_MAP_SIDE - max(g.x, g.y)) - 0.5;
    let weight = clamp(inset / PROPS_MAP_FADE, 0.0, 1.0);
    if weight <= 0.0 {
        return vec3<f32>(1.0, 1.0, 0.0);
    }
    let uv = (m.zw + g) / PROPS_MAP_SIDE;
    return vec3<f32>(textureSampleLevel(props_map_tex, props_map_sampler, uv, l, 0.0).xy, weight);
}

// The props' shade at camera-relative `rel` on the ground: (sun's share, sky's share), 1 where
// the map holds none. The finest level alone where it holds the point whole (most pixels: one
// filtered read).
fn props_map_at(rel: vec3<f32>) -> vec2<f32> {
    if r.props_map_levels == 0u {
        return vec2<f32>(1.0);
    }
    let fine = props_map_level(0, r.props_map[0], PROPS_MAP_TEXELS.x, rel.xz);
    if fine.z >= 1.0 {
        return fine.xy;
    }
    let mid = props_map_level(1, r.props_map[1], PROPS_MAP_TEXELS.y, rel.xz);
    var shade = vec2<f32>(1.0);
    if mid.z < 1.0 {
        let coarse = props_map_level(2, r.props_map[2], PROPS_MAP_TEXELS.z, rel.xz);
        shade = mix(shade, coarse.xy, coarse.z);
    }
    shade = mix(shade, mid.xy, mid.z);
    return mix(shade, fine.xy, fine.z);
}
