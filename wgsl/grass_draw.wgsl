// import: grass_blade
// The grass's draw by the GPU's rasteriser (src/gpu/grass.rs): each blade the scatter kept
// (grass_scatter.wgsl) is one instance of a strip of nine vertices (four segments and a tip);
// a blade of fewer segments (its level of detail) puts the vertices past its tip on the tip,
// where their triangles have no area. Built and lit as grass_blade.wgsl builds and lights every
// blade.

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(1) var<storage, read> blades: array<vec4<f32>>;

struct BladeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) rel: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // Up the blade (0 at the root, 1 at the tip), its shade, the sun's and the sky's
    // occlusion.
    @location(2) along: f32,
    @location(3) @interpolate(flat) look: vec3<f32>,
}

@vertex
fn blade_vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> BladeOut {
    let d = blades[4u * ii + 3u];
    let segments = clamp(u32(d.z), 1u, BLADE_SEGMENTS);
    let q = blade_point(blades[4u * ii], blades[4u * ii + 1u], d.xy, segments, min(vi, 2u * segments));
    var out: BladeOut;
    out.clip = r.view_proj * vec4<f32>(q.p, 1.0);
    out.rel = q.p;
    out.normal = q.n;
    out.along = q.t;
    out.look = blades[4u * ii + 2u].xyz;
    return out;
}

@fragment
fn blade_fs(in: BladeOut) -> @location(0) vec4<f32> {
    return vec4<f32>(blade_light(r, in.rel, in.normal, in.along, in.look), 1.0);
}
