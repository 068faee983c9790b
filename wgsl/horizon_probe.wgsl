// import: world_rays_io
// The terrain's horizon towards the sun at given points of the endless world's continuous
// surface, as the ray casters shade them (`world_horizon` in world_rays.wgsl, by `ray.method`:
// the reference's conservative march or the seed's shadow march). Composed after
// world_rays.wgsl and rays.wgsl; `relief stability` measures the shadow rays' tunnelling with
// it (src/stability/shadow.rs).

// Points (x, z) in metres from the reference sample, as the casters' positions are.
@group(1) @binding(0) var<storage, read> probe_points: array<vec2<f32>>;
// The horizon at each point, radians above the horizontal.
@group(1) @binding(1) var<storage, read_write> probe_horizons: array<f32>;

@compute @workgroup_size(64, 1, 1)
fn horizon_cs(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&probe_points) {
        return;
    }
    let q = probe_points[id.x];
    let h0 = world_height(q, ray.octaves);
    probe_horizons[id.x] = world_horizon(vec3<f32>(q.x, h0, q.y), h0);
}
