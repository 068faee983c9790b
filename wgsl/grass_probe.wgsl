// import: grass
// The blades and the cover at given cells and surfaces (src/gpu/grass.rs), for the tests that
// hold the GPU's grass to its CPU twin (src/grass.rs).

@group(0) @binding(0) var<uniform> g: GrassUniforms;
@group(0) @binding(1) var<uniform> r: RenderUniforms;
// Cells relative to the eye's.
@group(1) @binding(0) var<storage, read> probe_cells: array<vec2<i32>>;
// Ten numbers a blade: offset x, z, height, facing, lean, curve, width, shade, keep, far.
@group(1) @binding(1) var<storage, read_write> probe_blades: array<f32>;
// Surfaces: the normal's y, normalised height, colour channel.
@group(1) @binding(2) var<storage, read> probe_surfaces: array<vec4<f32>>;
@group(1) @binding(3) var<storage, read_write> probe_cover: array<f32>;

@compute @workgroup_size(64, 1, 1)
fn blades_cs(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&probe_cells) {
        return;
    }
    let b = blade_at(g, probe_cells[id.x]);
    let o = 10u * id.x;
    probe_blades[o] = b.offset.x;
    probe_blades[o + 1u] = b.offset.y;
    probe_blades[o + 2u] = b.height;
    probe_blades[o + 3u] = b.facing;
    probe_blades[o + 4u] = b.lean;
    probe_blades[o + 5u] = b.curve;
    probe_blades[o + 6u] = b.width;
    probe_blades[o + 7u] = b.shade;
    probe_blades[o + 8u] = b.keep;
    probe_blades[o + 9u] = b.far;
}

@compute @workgroup_size(64, 1, 1)
fn cover_cs(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= arrayLength(&probe_surfaces) {
        return;
    }
    let s = probe_surfaces[id.x];
    probe_cover[id.x] = grass_cover(r, s.x, s.y, s.z);
}
