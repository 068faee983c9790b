// import: world_rays_io, grass, grass_blade
// The grass of the reference (src/gpu/grass_reference.rs): one thread a cell of the square of
// cells around the eye that the reference's distance (twice the draw distance) reaches. Each
// cell's blade (grass.wgsl, as the frame's scatter makes it) is kept where the continuous surface under it is grass enough, within the distance and inside the
// view; its root stands on the continuous surface the reference casts rays at (every octave,
// world_rays.wgsl), lit by that surface's horizon and valley as the cast shades the ground. No
// level of detail, no thinning, no widening: every blade at its full height in all its
// segments. Composed after world_rays.wgsl; `r` is the render uniforms of the layers' matrix.

struct ReferenceFrame {
    g: GrassUniforms,
    // The eye less its cell's first corner, metres (x, z); the distance, metres; the cells the
    // square spans on a side.
    eye_in_cell: vec2<f32>,
    distance: f32,
    side: u32,
    // The most blades `ref_blades` holds (0: count only).
    capacity: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
    // The wind and its gusts' phases at the eye, as grass_scatter.wgsl's `GrassFrame`.
    wind: vec4<f32>,
    gust_phase: vec4<f32>,
}

@group(1) @binding(0) var<uniform> rf: ReferenceFrame;
// Per blade, as grass_scatter.wgsl writes them for grass_draw.wgsl.
@group(1) @binding(1) var<storage, read_write> ref_blades: array<vec4<f32>>;
// Blades kept (stored while below the capacity).
@group(1) @binding(2) var<storage, read_write> ref_counts: array<atomic<u32>, 4>;

@compute @workgroup_size(8, 8)
fn scatter_reference(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= rf.side || id.y >= rf.side {
        return;
    }
    let half = i32(rf.side / 2u);
    let rel_cell = vec2<i32>(id.xy) - vec2<i32>(half);
    let b = blade_at(rf.g, rel_cell);
    let xz = (vec2<f32>(rel_cell) + b.offset) * rf.g.cell - rf.eye_in_cell;
    if length(xz) > rf.distance {
        return;
    }
    // Positions relative to the reference sample, as the cast's are.
    let q = xz + ray.eye.xz;
    let s = world_channel(q, ray.octaves, CHANNEL_HEIGHT, 0.0);
    let slope = s.yz * ray.peak;
    let n_y = inverseSqrt(1.0 + dot(slope, slope));
    let tint = world_channel(q, ray.octaves, CHANNEL_COLOR, 0.0).x;
    if b.keep >= grass_cover(r, n_y, s.x, tint) {
        return;
    }
    let h0 = s.x * ray.peak;
    let root = vec3<f32>(xz.x, h0 - ray.eye.y, xz.y);
    // The sphere holds the blade however far it leans (half its height) and is blown (0.6 of
    // it) from its middle, as the frame's scatter tests it (the cast's sub-pixel jitter moves
    // the frustum by far less).
    if !in_frustum(r.view_proj, root + vec3<f32>(0.0, 0.5 * b.height, 0.0), 1.25 * b.height) {
        return;
    }
    let at = atomicAdd(&ref_counts[0], 1u);
    if at >= rf.capacity {
        return;
    }
    var horizon = -1.5;
    if r.shadows != 0u {
        horizon = world_horizon(vec3<f32>(q.x, h0, q.y), h0);
    }
    var valley = 0.0;
    if r.palette != PALETTE_BLOG {
        valley = world_valley(q, h0);
    }
    let occl = occlusion(r, s.x, horizon, valley);
    ref_blades[4u * at] = vec4<f32>(root, b.facing);
    ref_blades[4u * at + 1u] = vec4<f32>(b.height, b.lean, b.curve, b.width);
    ref_blades[4u * at + 2u] = vec4<f32>(b.shade, occl, 0.0);
    let tip = wind_tip(rf.wind, rf.gust_phase.xy, xz, b.height);
    ref_blades[4u * at + 3u] = vec4<f32>(tip, f32(BLADE_SEGMENTS), 0.0);
}
