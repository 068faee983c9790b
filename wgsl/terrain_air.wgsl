// part of: shade (through clouds.wgsl, which imports it)
// The terrain's shadow in the air, for the light shafts (`cloud_shafts`, clouds.wgsl): a
// margin at camera-relative `rel` (`terrain_air_margin`), above 0 where the sun reaches it past
// the terrain and below 0 where the terrain hides it, continuous across the shadow's edge (so
// the shafts can place the edge between their points), and how much of the sun a margin lets
// through at a point (`terrain_air_step`). This default sees no terrain: the modules that shade
// only what stands near the eye (props, the overlay's blades, the tile), whose air is too short
// for a shaft to show. A module that can tell names a stand-in in its top file's `// with:`
// line (shader::source): the levels' shadow-height map (terrain_air_map.wgsl) or a march of the
// continuous surface (terrain_air_rays.wgsl).
fn terrain_air_margin(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    return 1e30;
}

fn terrain_air_step(margin: f32) -> f32 {
    return 1.0;
}

// No terrain: as many as the clouds' points.
fn terrain_air_points() -> u32 {
    return 0u;
}
