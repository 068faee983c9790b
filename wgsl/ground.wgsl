// import: world
// The surface the world draws at a camera-relative point (the grass's and the props' scatters
// stand their blades and props on it): the finest level drawn there, the triangle of its cell
// the index buffer draws, its vertices placed as world.wgsl's `place` places them.

// The mesh's vertex `v` (level-local) of level `l`, placed as the world draws it.
fn mesh_vertex(l: u32, v: vec2<i32>) -> VertexOut {
    let pc = i32(w.patch_cells);
    let last = i32(w.cells / w.patch_cells) - 1;
    let corner_patch = clamp(vec2<i32>(floor(vec2<f32>(v) / f32(pc))), vec2<i32>(0), vec2<i32>(last));
    let local = v - corner_patch * pc;
    let row = w.patch_cells + 1u;
    let vi = u32(local.y) * row + u32(local.x);
    return place(vi, vec4<u32>(l, u32(corner_patch.x), u32(corner_patch.y), 0u));
}

struct Ground {
    rel: vec3<f32>,
    // The sample there (height, slopes, colour channel) and the light (horizon, valley).
    sample: vec4<f32>,
    light: vec2<f32>,
}

// The drawn surface at camera-relative `xz`: the finest drawn level whose square holds it, the
// triangle of its cell that the index buffer draws (src/gpu/world/resources.rs: a to d is the
// diagonal), and the plane through that triangle's placed vertices at `xz`.
fn ground_at(xz: vec2<f32>) -> Ground {
    let f = (xz + w.eye.xz) / w.eye.w;
    var l = w.first;
    var p = vec2<f32>(0.0);
    for (var k = 0; k < 24; k++) {
        let lv = w.levels[l];
        p = (f - vec2<f32>(lv.origin_rel)) / f32(1u << lv.shift);
        let inside = all(p >= vec2<f32>(1.0)) && all(p <= vec2<f32>(f32(w.cells) - 1.0));
        if inside || lv.coarse == l {
            break;
        }
        l = lv.coarse;
    }
    let i = vec2<i32>(floor(p));
    let t = p - floor(p);
    let a = mesh_vertex(l, i);
    let d = mesh_vertex(l, i + vec2<i32>(1, 1));
    var b: VertexOut;
    if t.x >= t.y {
        b = mesh_vertex(l, i + vec2<i32>(1, 0));
    } else {
        b = mesh_vertex(l, i + vec2<i32>(0, 1));
    }
    // Barycentric weights of `xz` in the placed triangle (a, b, d).
    let e1 = b.rel.xz - a.rel.xz;
    let e2 = d.rel.xz - a.rel.xz;
    let q = xz - a.rel.xz;
    let det = e1.x * e2.y - e1.y * e2.x;
    var u = 0.0;
    var v = 0.0;
    if abs(det) > 1e-12 {
        u = (q.x * e2.y - q.y * e2.x) / det;
        v = (e1.x * q.y - e1.y * q.x) / det;
    }
    var g: Ground;
    g.rel = vec3<f32>(xz.x, a.rel.y + u * (b.rel.y - a.rel.y) + v * (d.rel.y - a.rel.y), xz.y);
    g.sample = a.sample + u * (b.sample - a.sample) + v * (d.sample - a.sample);
    g.light = a.light + u * (b.light - a.light) + v * (d.light - a.light);
    // The hybrid raises its levels to bound the surface from above and draws the continuous
    // surface under them: its ground is the levels' own, not raised.
    let lv = w.levels[l];
    if lv.raise != 0.0 || w.levels[lv.coarse].raise != 0.0 {
        g.rel.y = g.sample.x * w.peak - w.eye.y;
    }
    return g;
}
