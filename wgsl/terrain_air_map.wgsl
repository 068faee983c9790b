// instead of: terrain_air (in the modules whose top file names it in `// with:`)
// The terrain's shadow in the air from the shadow-height map (src/gpu/air_shadow.rs, baked by
// air_shadow.wgsl from the levels' heights): each texel of a square around the eye holds the
// altitude below which the air over its centre is in the terrain's shadow, read here between
// the four nearest (one filtered sample): the margin is the point's altitude above that,
// metres. Outside the square, above the terrain's peak, or where the frame bakes no map
// (`air_shadow.w` 0), the air is lit.
@group(0) @binding(39) var air_shadow_map: texture_2d<f32>;
@group(0) @binding(40) var air_shadow_sampler: sampler;
// The shadow's edge, metres either side of the map's altitude.
const AIR_SHADOW_SOFT: f32 = 4.0;

fn terrain_air_margin(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    let n = r.air_shadow.w;
    if n <= 0.0 {
        return 1e30;
    }
    // The eye's altitude (`cloud_march.x`) plus the point's height above it. No terrain rises
    // above its peak (`height_scale`, metres): nothing to read up there.
    let alt = r.cloud_march.x + rel.y;
    if alt >= r.height_scale {
        return 1e30;
    }
    let uv = (rel.xz - r.air_shadow.xy) / (r.air_shadow.z * n);
    if any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) {
        return 1e30;
    }
    return alt - textureSampleLevel(air_shadow_map, air_shadow_sampler, uv, 0.0).x;
}

fn terrain_air_step(margin: f32) -> f32 {
    return smoothstep(-AIR_SHADOW_SOFT, AIR_SHADOW_SOFT, margin);
}

// Points a ray reads the map at, at most: two or four a cloud's point (`cloud_shaft_steps`).
fn terrain_air_points() -> u32 {
    return 24u;
}
