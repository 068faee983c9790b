// import: world, ground, props, props_grid
// The props' scatter (src/gpu/props.rs): a thread a cell of the square grid around the eye.
// Each cell's prop (props.wgsl's `prop_at`) stands where its chance is under the density its
// ground allows (gentle ground, rock for the kinds that stand there, none under water), within
// the draw distance, and not smaller on screen than its own cut-off: over the halving of its
// size below that it sinks into the ground, so no prop pops. It stands on the surface the world
// draws (ground.wgsl), at the lowest of five points under its foot, sunk 2 cm more; the kinds
// reach below their origin. A thread past the grid places a prop put at a given place.
// `props_ranges` then gives each dual cell (the 2x2 cells around a corner) the heights its
// props span, and `props_blocks` each block of them, which the march skips by.

// Props at given places, two vectors each: camera-relative x, z, the turn (radians), the
// scale; the kind, the shade, the noise's seed (bits), unused.
@group(1) @binding(8) var<storage, read> explicit_props: array<vec4<f32>>;

fn clear_record(i: u32) {
    prop_grid[i * RECORD] = vec4<f32>(0.0);
    prop_cell_range[i] = EMPTY_RANGE;
}

// Stands a prop of `kind` at camera-relative `xz`, turned by `turn` (radians) and scaled by
// `scale`, with the shade, seed, chance and cut-off of `p`, as record `i`; where `scattered`,
// the ground decides by the chance whether it stands (else it was put there).
fn stand(i: u32, kind: u32, xz: vec2<f32>, turn: f32, scale: f32, p: Prop, scattered: bool) {
    let k = prop_kinds[kind];
    let dist = length(xz);
    let centre = ground_at(xz);
    let s = centre.sample;
    if scattered {
        if dist > pf.distance || s.x < pf.water {
            clear_record(i);
            return;
        }
        let slope = s.yz * w.peak;
        let n_y = inverseSqrt(1.0 + dot(slope, slope));
        let g = prop_gentle(n_y, s.w);
        let rock = select(0.0, pf.rock_density, k.hi.w > 0.0);
        if p.chance >= pf.density * g + rock * (1.0 - g) {
            clear_record(i);
            return;
        }
    }
    let top = k.hi.y * scale;
    // Its height on screen against its own threshold: whole above it, sunk below half of it.
    let px = top * pf.pixels / max(length(vec3<f32>(xz.x, centre.rel.y, xz.y)), 1e-3);
    let shown = clamp(2.0 * px / (pf.cutoff * p.cutoff) - 1.0, 0.0, 1.0);
    if shown <= 0.0 {
        clear_record(i);
        return;
    }
    // The lowest of the drawn surface under its foot.
    let foot = 0.5 * k.lo.w * scale;
    var y = centre.rel.y;
    y = min(y, ground_at(xz + vec2<f32>(foot, 0.0)).rel.y);
    y = min(y, ground_at(xz - vec2<f32>(foot, 0.0)).rel.y);
    y = min(y, ground_at(xz + vec2<f32>(0.0, foot)).rel.y);
    y = min(y, ground_at(xz - vec2<f32>(0.0, foot)).rel.y);
    y -= 0.02 + (1.0 - shown) * top;
    let c = cos(turn);
    let sn = sin(turn);
    prop_grid[i * RECORD] = vec4<f32>(xz.x, y, xz.y, scale);
    prop_grid[i * RECORD + 1u] = vec4<f32>(c, sn, f32(kind), bitcast<f32>(p.seed));
    prop_grid[i * RECORD + 2u] = vec4<f32>(p.shade, centre.light, s.x);
    // The kind's sphere turned and scaled as the march's `record_distance` maps the prop.
    let o = k.sphere.xyz * scale;
    let centre_rel = vec3<f32>(xz.x, y, xz.y) + vec3<f32>(c * o.x + sn * o.z, o.y, -sn * o.x + c * o.z);
    prop_grid[i * RECORD + 3u] = vec4<f32>(centre_rel, k.sphere.w * scale);
    prop_cell_range[i] = vec2<f32>(y + k.lo.y * scale, y + top);
}

@compute @workgroup_size(8, 8)
fn props_scatter(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = pf.side;
    if id.y >= n || id.x >= n {
        // Threads past the grid: the props put at given places, a row of them.
        let j = id.x + (id.y - n) * n;
        if id.y >= n && id.x < n && j < pf.placed {
            let a = explicit_props[2u * j];
            let b = explicit_props[2u * j + 1u];
            var p: Prop;
            p.shade = b.y;
            p.seed = bitcast<u32>(b.z);
            p.cutoff = 1.0;
            stand(n * n + j, u32(b.x), a.xy, a.z, a.w, p, false);
        }
        return;
    }
    let rel = vec2<i32>(id.xy) - vec2<i32>(i32(n / 2u));
    let p = prop_at(rel);
    let xz = (vec2<f32>(rel) + p.offset) * pf.cell - pf.eye_in_cell;
    let k = prop_kinds[p.kind];
    stand(id.y * n + id.x, p.kind, xz, p.turn, k.scale.x + (k.scale.y - k.scale.x) * p.size, p, true);
}

// A thread a dual cell: the heights the props of its 2x2 cells span.
@compute @workgroup_size(8, 8)
fn props_ranges(@builtin(global_invocation_id) id: vec3<u32>) {
    let m = dual_side();
    if id.x >= m || id.y >= m {
        return;
    }
    var r = EMPTY_RANGE;
    let n = pf.side;
    for (var k = 0u; k < 4u; k++) {
        let c = vec2<i32>(id.xy) - vec2<i32>(1) + vec2<i32>(i32(k & 1u), i32(k >> 1u));
        if all(c >= vec2<i32>(0)) && all(c < vec2<i32>(i32(n))) {
            r = union_range(r, prop_cell_range[u32(c.y) * n + u32(c.x)]);
        }
    }
    prop_dual_range[id.y * m + id.x] = r;
}

// A thread a block: the heights its dual cells' props span.
@compute @workgroup_size(8, 8)
fn props_blocks(@builtin(global_invocation_id) id: vec3<u32>) {
    let b = pf.blocks;
    if id.x >= b || id.y >= b {
        return;
    }
    let m = dual_side();
    var r = EMPTY_RANGE;
    for (var j = 0u; j < BLOCK; j++) {
        for (var i = 0u; i < BLOCK; i++) {
            let c = id.xy * BLOCK + vec2<u32>(i, j);
            if c.x < m && c.y < m {
                r = union_range(r, prop_dual_range[c.y * m + c.x]);
            }
        }
    }
    prop_block_range[id.y * b + id.x] = r;
}

// One workgroup: the heights every block's props span (and the props put at given places),
// after the last block.
const SPAN_THREADS: u32 = 256u;
var<workgroup> span_part: array<vec2<f32>, SPAN_THREADS>;

@compute @workgroup_size(256)
fn props_span(@builtin(local_invocation_index) li: u32) {
    let n = pf.blocks * pf.blocks;
    var r = EMPTY_RANGE;
    for (var i = li; i < n; i += SPAN_THREADS) {
        r = union_range(r, prop_block_range[i]);
    }
    for (var j = li; j < pf.placed; j += SPAN_THREADS) {
        r = union_range(r, prop_cell_range[pf.side * pf.side + j]);
    }
    span_part[li] = r;
    workgroupBarrier();
    for (var half = SPAN_THREADS / 2u; half > 0u; half /= 2u) {
        if li < half {
            span_part[li] = union_range(span_part[li], span_part[li + half]);
        }
        workgroupBarrier();
    }
    if li == 0u {
        prop_block_range[n] = span_part[0];
    }
}
