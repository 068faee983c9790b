// instead of: terrain_air (in the ray casters' modules, whose top file names it in `// with:`)
// The terrain's shadow in the air by a march of the continuous surface towards the sun from the
// point itself (`world_horizon`, world_rays.wgsl, as the casters shadow the ground): the
// reference's way, and the truth the shadow-height map is measured against: the margin is how
// far the sun stands above the terrain's horizon there, radians, and a point sees as much of
// the sun's disc as the ground does (`occlusion`, shade.wgsl). `ray.eye` is the eye less the
// reference sample (x, z) and its altitude (y).
fn terrain_air_margin(r: RenderUniforms, rel: vec3<f32>) -> f32 {
    let p = ray.eye.xyz + rel;
    return r.sun_elevation - world_horizon(p, p.y);
}

fn terrain_air_step(margin: f32) -> f32 {
    return smoothstep(-SUN_RADIUS, SUN_RADIUS, margin);
}

// Points a ray marches the terrain from: two a cloud's point (`cloud_shaft_steps`), a march
// each.
fn terrain_air_points() -> u32 {
    return 12u;
}
