// import: shade, world_rays, march, vis_common, props_look
// The props of the reference (src/gpu/props_reference.rs), at the cast's samples: after the
// cast of the continuous surface (world_rays.wgsl), `reference_depth` turns each sample's ray
// distance into the depth the props' march (props_march.wgsl) reads as a raster's; the march
// then leaves each sample's prop nearer than the surface, or the props' shadow and occlusion on
// the surface; `reference_props` shades each sample again where the march left something: a
// prop with its light (props_look.wgsl), or the surface with the props' shares of its sun and
// sky (`shade_cast`, the cast's own shading, so a sample the props leave alone keeps its bytes).

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(18) var<uniform> ray: WorldRayUniforms;
@group(0) @binding(2) var color_out: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(3) var distance_out: texture_storage_2d<r32float, write>;
@group(0) @binding(20) var distance_in: texture_2d<f32>;
@group(0) @binding(22) var prop_hit_in: texture_2d<u32>;
@group(1) @binding(0) var<storage, read_write> depth_out: array<u32>;

// Each sample's depth under the march's matrix (`vis`), as the compute raster leaves it: the
// bits of depth inverted, 0 where the cast met nothing.
@compute @workgroup_size(8, 8, 1)
fn reference_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let t = textureLoad(distance_in, vec2<i32>(id.xy), 0).x;
    var bits = 0u;
    if t > 0.0 {
        let p = sample_ray(vec2<f32>(id.xy) + 0.5) * t;
        let clip_w = dot(vis.w_row.xyz, p) + vis.w_row.w;
        bits = ~bitcast<u32>(clamp(vis.depth.y / clip_w - vis.depth.x, 0.0, 0.99999994));
    }
    depth_out[id.y * vis.size.x + id.x] = bits;
}

// Shades again each sample where the march left a prop or the props' shadow or occlusion.
@compute @workgroup_size(8, 8, 1)
fn reference_props(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= ray.width || id.y >= ray.height {
        return;
    }
    let px = vec2<i32>(id.xy);
    let hit = textureLoad(prop_hit_in, px, 0);
    let d = bitcast<f32>(hit.x);
    let pixel = vec2<f32>(id.xy) + 0.5;
    if d < 1.0 {
        let rel = point_at(sample_ray(pixel), d);
        textureStore(color_out, px, vec4<f32>(unorm8_exact(prop_color(r, rel, hit)), 1.0));
        textureStore(distance_out, px, vec4<f32>(length(rel), 0.0, 0.0, 0.0));
        return;
    }
    let props = vec2<f32>(bitcast<f32>(hit.w), bitcast<f32>(hit.y));
    let t = textureLoad(distance_in, px, 0).x;
    if t > 0.0 && any(props < vec2<f32>(1.0)) {
        let rd = normalize(pixel_far(pixel));
        textureStore(color_out, px, vec4<f32>(unorm8_exact(shade_cast(rd, t, props)), 1.0));
    }
}
