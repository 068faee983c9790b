// import: world_rays, rays
// with: terrain_air_rays
// The endless world's ray casters' bindings (src/gpu/raymarch.rs), composed after
// world_rays.wgsl, whose functions read `r` and `ray`.

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(1) var<uniform> ray: WorldRayUniforms;
@group(0) @binding(2) var color_out: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(3) var distance_out: texture_storage_2d<r32float, write>;
