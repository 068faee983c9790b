// import: grass_blade
// part of: raster_ids (calls raster.wgsl's clip and setup, and the ids' `keep`)
// The grass's blades in the compute raster with ids (src/gpu/raster.rs; the visibility method
// where the device has a 64-bit atomic maximum): after the terrain's raster, a thread a
// triangle of each blade the scatter kept (grass_scatter.wgsl) builds it from the blade's strip
// (grass_blade.wgsl, in the segments the scatter chose) and rasterises it into the same depth
// buffer with ids, so each pixel keeps the nearest of terrain and blades; big triangles go to
// the same list as the terrain's (dispatch mode 1, after the terrain's list was drawn). `resolve_blades` then stores each pixel that a blade kept: its
// normal and how far up the blade (interpolated, as the surface attributes), and the blade's
// shade and occlusion (packed, as the valley), which visibility.wgsl shades as a blade.
//
// Why: on the H100 only two TPCs run vertex and pixel shaders; the blades drawn by the GPU's
// rasteriser after the terrain cost over 1.6 ms for 20k blades at 1080p, here about 0.35 ms.

// The blades (4 vec4s each, grass_scatter.wgsl's layout), the scatter's counts (the fourth:
// how many `blades` holds; the sixth: how many `blade_triangles` holds), and the list of their
// triangles (a blade's number times 8 plus its triangle's number in the strip).
@group(2) @binding(0) var<storage, read> blades: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read> blade_counts: array<u32, 8>;
@group(2) @binding(2) var<storage, read> blade_triangles: array<u32>;
// How far each pixel's point moved since the last frame (camera-relative metres; w 1 where it
// is a blade's), for the temporal service: only the wind moves a blade, and nothing else moves.
@group(1) @binding(11) var motion_out: texture_storage_2d<rgba16float, write>;

// The grass's layer in a visibility-buffer id: a blade's number times 16, plus its
// triangle's number in the strip times 2, plus 1 for the second triangle of its cut to the
// near plane.
const LAYER_GRASS: u32 = 1u;
// The segments blade `i` is drawn in, as the scatter chose them (its level of detail).
fn blade_segments(i: u32) -> u32 {
    return clamp(u32(blades[4u * i + 3u].z), 1u, BLADE_SEGMENTS);
}

// Vertex `vi` of blade `i` drawn in `segments`: its clip position, and its normal and how far
// up the blade as the attributes the resolve interpolates.
fn blade_vertex(i: u32, segments: u32, vi: u32) -> RasterVertex {
    let q = blade_point(blades[4u * i], blades[4u * i + 1u], blades[4u * i + 3u].xy, segments, vi);
    return RasterVertex(r.view_proj * vec4<f32>(q.p, 1.0), vec4<f32>(q.n, q.t), 0.0);
}

// A thread a triangle of the scatter's list. A thread a blade, looping over all its pixels,
// took 0.65 ms for 20k blades on the H100 (the terrain's whole raster takes 0.85 ms); a thread
// a triangle, 0.25 ms.
@compute @workgroup_size(128)
fn raster_blades(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= blade_counts[5] {
        return;
    }
    let e = blade_triangles[id.x];
    if e == 0xffffffffu {
        // Its blade was past the capacity, not stored.
        return;
    }
    let i = e >> 3u;
    let k = e & 7u;
    let segments = blade_segments(i);
    raster_clipped(
        blade_vertex(i, segments, k),
        blade_vertex(i, segments, k + 1u),
        blade_vertex(i, segments, k + 2u),
        (LAYER_GRASS << LAYER_SHIFT) | (i << 4u) | (k << 1u),
    );
}

// A blade's shade and the sun's and sky's occlusion, 8 bits each, as an integer below 2^24
// (exact in the valley's f32); visibility.wgsl's `blade_look` unpacks it.
fn pack_look(look: vec3<f32>) -> f32 {
    let q = vec3<u32>(round(clamp(look, vec3<f32>(0.0), vec3<f32>(1.0)) * 255.0));
    return f32((q.x << 16u) | (q.y << 8u) | q.z);
}

// Each pixel a blade kept, a thread a pixel: its triangle set up again from the id, its normal
// and height up the blade interpolated at the pixel's centre, its look packed, its motion; every
// other pixel still.
@compute @workgroup_size(8, 8)
fn resolve_blades(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= ras.size.x || id.y >= ras.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    textureStore(motion_out, px, vec4<f32>(0.0));
    let kept = raster_ids[id.y * ras.size.x + id.x];
    if kept.y == 0u || (kept.x >> LAYER_SHIFT) != LAYER_GRASS {
        return;
    }
    let p = kept.x & PRIMITIVE_MASK;
    let i = p >> 4u;
    let k = (p >> 1u) & 7u;
    let segments = blade_segments(i);
    let c = clip_near(blade_vertex(i, segments, k), blade_vertex(i, segments, k + 1u), blade_vertex(i, segments, k + 2u));
    if c.n < 3u {
        return;
    }
    var t: Setup;
    if (p & 1u) == 1u && c.n == 4u {
        t = setup_triangle(c.poly[0], c.poly[2], c.poly[3], kept.x);
    } else {
        t = setup_triangle(c.poly[0], c.poly[1], c.poly[2], kept.x);
    }
    let x = f32(id.x);
    let y = f32(id.y);
    let e = pixel_edges(t, x, y);
    let q = e / vec3<f32>(t.v0.clip.w, t.v1.clip.w, t.v2.clip.w);
    let w3 = q / (q.x + q.y + q.z);
    let surface = w3.x * t.v0.surface + w3.y * t.v1.surface + w3.z * t.v2.surface;
    textureStore(surface_out, px, surface);
    let look = blades[4u * i + 2u];
    textureStore(valley_out, px, vec4<f32>(pack_look(look.xyz), 0.0, 0.0, 0.0));
    let tip = blades[4u * i + 3u];
    let moved = blade_motion(blades[4u * i + 1u].x, tip.xy, vec2<f32>(look.w, tip.w), surface.w);
    textureStore(motion_out, px, vec4<f32>(moved, 1.0));
}
