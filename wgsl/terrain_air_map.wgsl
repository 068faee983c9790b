// instead of: terrain_air (in the modules whose top file names it in `// with:`)
// The terrain's shadow in the air from the shadow-height map (src/gpu/air_shadow.rs, baked by
// air_shadow.wgsl from the levels' heights): each texel of a square around the eye holds the
// altitude below which the air over its centre is in the terrain's shadow, read here between
// the four nearest (by hand: a 32-bit float texture is not filterable in core WebGPU): the
// margin is the point's altitude above that, metres. Outside the square, or where the frame
// bakes no map (`air_shadow.w` 0), the air is lit.
@group(0) @binding(39) var air_shadow_map: texture_2d<f32>;
// The shadow's edge, metres either side of the map's altitude.
const AIR_SHADOW_SOFT: f32 = 4.0;

fn terrain_air_margin(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    let n = r.air_shadow.w;
    if n <= 0.0 {
        return 1e30;
    }
    let p = (rel.xz - r.air_shadow.xy) / r.air_shadow.z - 0.5;
    if any(p < vec2<f32>(0.0)) || any(p > vec2<f32>(n - 1.0)) {
        return 1e30;
    }
    let i = vec2<i32>(floor(p));
    let f = p - floor(p);
    let last = vec2<i32>(i32(n) - 1);
    let a = textureLoad(air_shadow_map, i, 0).x;
    let b = textureLoad(air_shadow_map, min(i + vec2<i32>(1, 0), last), 0).x;
    let c = textureLoad(air_shadow_map, min(i + vec2<i32>(0, 1), last), 0).x;
    let d = textureLoad(air_shadow_map, min(i + vec2<i32>(1, 1), last), 0).x;
    let below = mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
    // The eye's altitude (`cloud_march.x`) plus the point's height above it.
    return r.cloud_march.x + rel.y - below;
}

fn terrain_air_step(margin: f32) -> f32 {
    return smoothstep(-AIR_SHADOW_SOFT, AIR_SHADOW_SOFT, margin);
}

// Points a ray reads the map at: two or four a cloud's point (`cloud_shaft_steps`), four
// loads each.
fn terrain_air_points() -> u32 {
    return 24u;
}
