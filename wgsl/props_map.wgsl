// import: shade
// The props' shade map as the terrain's shading reads it (src/gpu/props_map.rs bakes it): over
// the ground around the eye, in world space, the props' shadow (the sun's share) and their
// occlusion of the sky (the sky's share), in levels of PROPS_MAP_SIDE texels a side, each
// level's texel PROPS_MAP_TEXELS[l] metres, addressed toroidally (a world texel's place in the
// texture is its index modulo the side). The methods that shade the terrain before the props
// are marched (the forward mesh, the hybrid, the visibility method rasterised by the GPU, the
// page's) read it; the marching method marches each pixel's own.

@group(0) @binding(23) var props_map_tex: texture_2d_array<f32>;

const PROPS_MAP_SIDE: i32 = 512;
const PROPS_MAP_TEXELS: array<f32, 3> = array<f32, 3>(0.25, 1.0, 4.0);
// Texels over which a level fades out at its edge (into the next coarser level, the last into
// no props' shade).
const PROPS_MAP_FADE: f32 = 16.0;

// The props' shade at camera-relative `rel` on the ground: (sun's share, sky's share), 1 where
// the map holds none.
fn props_map_at(u: RenderUniforms, rel: vec3<f32>) -> vec2<f32> {
    var shade = vec2<f32>(1.0);
    var maps = u.props_map;
    var texels = PROPS_MAP_TEXELS;
    for (var l = i32(u.props_map_levels) - 1; l >= 0; l--) {
        let m = maps[l];
        // Texel centres at whole numbers.
        let g = (rel.xz - m.xy) / texels[l] - 0.5;
        let last = f32(PROPS_MAP_SIDE - 2);
        let inset = min(min(g.x, g.y), min(last - g.x, last - g.y));
        let weight = clamp(inset / PROPS_MAP_FADE, 0.0, 1.0);
        if weight <= 0.0 {
            continue;
        }
        let i0 = vec2<i32>(floor(g));
        let f = g - vec2<f32>(i0);
        let base = vec2<i32>(m.zw) + i0;
        var v: array<vec2<f32>, 4>;
        for (var k = 0; k < 4; k++) {
            let t = (base + vec2<i32>(k & 1, k >> 1u)) % PROPS_MAP_SIDE;
            v[k] = textureLoad(props_map_tex, t, l, 0).xy;
        }
        let here = mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
        shade = mix(shade, here, weight);
    }
    return shade;
}
