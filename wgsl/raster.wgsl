// The visibility method's raster pass in compute (src/gpu/raster.rs; the tile at one sample a
// pixel): the same patches and vertices as the hardware raster pass (world.wgsl's `place`), one
// thread a cell, its two triangles clipped to the near plane, projected, and rasterised at pixel
// centres; each covered pixel keeps the nearest depth by an atomic maximum of the depth's
// complemented bits (non-negative floats order as their bits do, so the complement orders them
// nearest first, and a cleared buffer's 0 reads as no terrain).
//
// Why: the H100 has few raster units; its depth-only raster of the tile's 131k triangles took
// 0.50 ms at 1080p, a pass that shades nothing. A thread a cell does the same in compute.
//
// Watertight: an edge shared by two triangles is evaluated with its end points in one order
// (the lesser point first) by both, so the two see exactly opposite values; a pixel centre
// exactly on the edge goes to the triangle that runs along it from the lesser point. Composed
// after shade.wgsl, level_texel.wgsl and world.wgsl (their uniforms, `place`).

struct RasterUniforms {
    // The image's size in pixels.
    size: vec2<u32>,
    // Whole patches (first in `patches`), then sub-patches.
    whole: u32,
    subs: u32,
    // Cells per side of a whole patch and of a sub-patch.
    patch_cells: u32,
    sub_cells: u32,
    // Threads per row of the dispatch (its x extent times the workgroup's).
    row_threads: u32,
    _pad: u32,
}

@group(1) @binding(0) var<uniform> ras: RasterUniforms;
@group(1) @binding(1) var<storage, read> patches: array<vec4<u32>>;
@group(1) @binding(2) var<storage, read_write> raster_depth: array<atomic<u32>>;

// Whether screen point `a` comes before `b` (x, then y).
fn before(a: vec2<f32>, b: vec2<f32>) -> bool {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
}

// Twice the signed area of (a, b, p), with a and b taken in one order whichever way the edge is
// given, and the sign of the edge's direction: one expression for both orders, so the two
// triangles that share an edge compute the same value and differ only in its sign.
fn edge(a: vec2<f32>, b: vec2<f32>, p: vec2<f32>) -> f32 {
    let swap = before(b, a);
    let lo = select(a, b, swap);
    let hi = select(b, a, swap);
    let e = (hi.x - lo.x) * (p.y - lo.y) - (hi.y - lo.y) * (p.x - lo.x);
    return select(e, -e, swap);
}

// Whether a pixel centre with edge value `e` for the edge a -> b is inside (the triangle's
// area positive): strictly, or exactly on an edge that runs from its lesser point.
fn inside(e: f32, a: vec2<f32>, b: vec2<f32>) -> bool {
    return e > 0.0 || (e == 0.0 && before(a, b));
}

// Screen position (pixels from the top left) and depth of a clip-space point with w > 0.
fn to_screen(c: vec4<f32>) -> vec3<f32> {
    let n = c.xyz / c.w;
    let s = vec2<f32>(ras.size);
    return vec3<f32>((n.x * 0.5 + 0.5) * s.x, (0.5 - n.y * 0.5) * s.y, n.z);
}

fn raster_triangle(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>) {
    let s0 = to_screen(c0);
    var s1 = to_screen(c1);
    var s2 = to_screen(c2);
    var area = edge(s0.xy, s1.xy, s2.xy);
    if !(abs(area) > 0.0) {
        return;
    }
    // Back faces are drawn too (the raster pass culls nothing): turn them to face forward.
    if area < 0.0 {
        let t = s1;
        s1 = s2;
        s2 = t;
        area = -area;
    }
    let size = vec2<f32>(ras.size);
    let lo = max(ceil(min(s0.xy, min(s1.xy, s2.xy)) - 0.5), vec2<f32>(0.0));
    let hi = min(floor(max(s0.xy, max(s1.xy, s2.xy)) - 0.5), size - 1.0);
    if lo.x > hi.x || lo.y > hi.y {
        return;
    }
    let inv = 1.0 / area;
    for (var y = lo.y; y <= hi.y; y += 1.0) {
        for (var x = lo.x; x <= hi.x; x += 1.0) {
            let p = vec2<f32>(x + 0.5, y + 0.5);
            let e0 = edge(s1.xy, s2.xy, p);
            let e1 = edge(s2.xy, s0.xy, p);
            let e2 = edge(s0.xy, s1.xy, p);
            if !(inside(e0, s1.xy, s2.xy) && inside(e1, s2.xy, s0.xy) && inside(e2, s0.xy, s1.xy)) {
                continue;
            }
            let z = (e0 * s0.z + e1 * s1.z + e2 * s2.z) * inv;
            if !(z >= 0.0 && z < 1.0) {
                continue;
            }
            let at = u32(y) * ras.size.x + u32(x);
            atomicMax(&raster_depth[at], ~bitcast<u32>(abs(z)));
        }
    }
}

// The point where the edge from `a` (in front of the near plane) to `b` (behind it) meets it:
// computed from the point in front, so two triangles sharing the edge find the same point.
fn near_crossing(a: vec4<f32>, b: vec4<f32>) -> vec4<f32> {
    return mix(a, b, a.z / (a.z - b.z));
}

// The triangle cut to the near plane (clip z >= 0, where w > 0): none, one or two triangles.
fn raster_clipped(c0: vec4<f32>, c1: vec4<f32>, c2: vec4<f32>) {
    let v = array<vec4<f32>, 3>(c0, c1, c2);
    var front = 0u;
    for (var i = 0u; i < 3u; i++) {
        front += u32(v[i].z >= 0.0);
    }
    if front == 3u {
        raster_triangle(c0, c1, c2);
        return;
    }
    if front == 0u {
        return;
    }
    var poly: array<vec4<f32>, 4>;
    var n = 0u;
    for (var i = 0u; i < 3u; i++) {
        let a = v[i];
        let b = v[(i + 1u) % 3u];
        let a_in = a.z >= 0.0;
        if a_in {
            poly[n] = a;
            n += 1u;
        }
        if a_in != (b.z >= 0.0) {
            poly[n] = select(near_crossing(b, a), near_crossing(a, b), a_in);
            n += 1u;
        }
    }
    raster_triangle(poly[0], poly[1], poly[2]);
    if n == 4u {
        raster_triangle(poly[0], poly[2], poly[3]);
    }
}

@compute @workgroup_size(64)
fn raster_cells(@builtin(global_invocation_id) id: vec3<u32>) {
    var c = id.y * ras.row_threads + id.x;
    let whole_cells = ras.patch_cells * ras.patch_cells;
    let sub_cells = ras.sub_cells * ras.sub_cells;
    var instance = 0u;
    var side = ras.patch_cells;
    if c < ras.whole * whole_cells {
        instance = c / whole_cells;
        c = c % whole_cells;
    } else {
        c -= ras.whole * whole_cells;
        if sub_cells == 0u || c >= ras.subs * sub_cells {
            return;
        }
        instance = ras.whole + c / sub_cells;
        c = c % sub_cells;
        side = ras.sub_cells;
    }
    // The cell's corners in the patch's vertex numbering, split as the index buffer splits it
    // (world.rs `patch_indices`): (a, b, d) and (a, d, c).
    let row = ras.patch_cells + 1u;
    let a = (c / side) * row + c % side;
    let p = patches[instance];
    let va = place(a, p).clip;
    let vb = place(a + 1u, p).clip;
    let vc = place(a + row, p).clip;
    let vd = place(a + row + 1u, p).clip;
    raster_clipped(va, vb, vd);
    raster_clipped(va, vd, vc);
}
