// import: world, ground, vis_common, props, props_grid, props_look
// The props' march (src/gpu/visibility/props.rs): a thread a pixel, after the raster and
// before the shading. Its ray walks the grid of placed props (props_grid.wgsl) from the eye up
// to the depth the raster kept (or the props' draw distance): block by block and dual cell by
// dual cell, skipping every one whose props' heights the ray does not cross, and in a dual cell
// whose props' boxes it enters, it sphere-traces the nearest of their fields (their tapes,
// props.wgsl), each step the distance over their Lipschitz constant, until the distance is
// under half a pixel's footprint. A hit leaves its depth, normal, albedo and the light on it
// (the sky's share from its own field's occlusion and the terrain's valley, the sun's from the
// terrain's horizon and a soft shadow marched through the props towards the sun); a pixel the
// ray crosses without a hit leaves the props' shadow on whatever the raster drew there.

// Per pixel (props_look.wgsl): depth (bits; 1: no prop), normal (two snorm16), albedo (its
// square root, rgb8) and the sky's share (a8), the sun's share (bits).
@group(1) @binding(9) var prop_hit_out: texture_storage_2d<rgba32uint, write>;

// The most dual cells and blocks a ray visits.
const MAX_VISITS: u32 = 1024u;
// A soft shadow's penumbra: the sun's share is at most this times distance over range.
const SHADOW_SOFTNESS: f32 = 8.0;
// How far a shadow is marched towards the sun, metres.
const SHADOW_REACH: f32 = 300.0;
// A shadow ray's least step, metres.
const SHADOW_STEP: f32 = 0.04;
// Nearer its sphere than this (metres), a prop's field is read.
const SPHERE_MARGIN: f32 = 0.25;
// Nearer its undisplaced surface than this less its displacements (metres), a view ray reads a
// prop's whole field.
const ROUGH_MARGIN: f32 = 0.05;

// Where a ray meets props: the distance along it (or the sun's share for a shadow) and the
// record it met (none: 0xffffffff).
struct Meet {
    t: f32,
    record: u32,
}

const NO_RECORD: u32 = 0xffffffffu;

// A placed prop's distance at camera-relative `p` and its material (as f32).
fn record_distance(i: u32, p: vec3<f32>) -> vec2<f32> {
    let a = prop_grid[i * RECORD];
    let b = prop_grid[i * RECORD + 1u];
    let q = p - a.xyz;
    let local = vec3<f32>(b.x * q.x - b.y * q.z, q.y, b.y * q.x + b.x * q.z) / a.w;
    let d = kind_distance(u32(b.z), local, bitcast<u32>(b.w));
    return vec2<f32>(d.x * a.w, d.y);
}

// Where the ray `o + t dir` is inside the box of record `i` (none: an empty interval).
fn record_span(i: u32, o: vec3<f32>, inv: vec3<f32>) -> vec2<f32> {
    let a = prop_grid[i * RECORD];
    if a.w <= 0.0 {
        return vec2<f32>(1.0, 0.0);
    }
    let k = prop_kinds[u32(prop_grid[i * RECORD + 1u].z)];
    let r = k.lo.w * a.w;
    let y = prop_cell_range[i];
    let lo = vec3<f32>(a.x - r, y.x, a.z - r);
    let hi = vec3<f32>(a.x + r, y.y, a.z + r);
    let t0 = (lo - o) * inv;
    let t1 = (hi - o) * inv;
    let near = min(t0, t1);
    let far = max(t0, t1);
    return vec2<f32>(max(near.x, max(near.y, near.z)), min(far.x, min(far.y, far.z)));
}

// A placed prop's distance at camera-relative `p` without its displacements: within their
// amplitudes (`roughness_of`) of its distance, and cheaper.
fn record_undisplaced(i: u32, p: vec3<f32>) -> f32 {
    let a = prop_grid[i * RECORD];
    let b = prop_grid[i * RECORD + 1u];
    let q = p - a.xyz;
    let local = vec3<f32>(b.x * q.x - b.y * q.z, q.y, b.y * q.x + b.x * q.z) / a.w;
    return kind_undisplaced(u32(b.z), local) * a.w;
}

fn lipschitz_of(i: u32) -> f32 {
    return prop_kinds[u32(prop_grid[i * RECORD + 1u].z)].lipschitz;
}

// The sum of record `i`'s displacements' amplitudes, metres.
fn roughness_of(i: u32) -> f32 {
    return prop_kinds[u32(prop_grid[i * RECORD + 1u].z)].scale.z * prop_grid[i * RECORD].w;
}

fn undisplaced_lipschitz_of(i: u32) -> f32 {
    return prop_kinds[u32(prop_grid[i * RECORD + 1u].z)].scale.w;
}

// Whether the ray's heights over [t0, t1] cross `range`.
fn crosses(o: vec3<f32>, dir: vec3<f32>, t0: f32, t1: f32, range: vec2<f32>) -> bool {
    let y0 = o.y + dir.y * t0;
    let y1 = o.y + dir.y * t1;
    return min(y0, y1) <= range.y && max(y0, y1) >= range.x;
}

// Where the ray leaves the square [lo, hi] (x, z) it is in.
fn square_exit(o: vec3<f32>, inv: vec3<f32>, lo: vec2<f32>, hi: vec2<f32>) -> f32 {
    let t0 = (lo - o.xz) * inv.xz;
    let t1 = (hi - o.xz) * inv.xz;
    let far = max(t0, t1);
    return min(far.x, far.y);
}

// Sphere-traces the nearest of the `n` records in `cands` along the ray over [t0, t1],
// spending `budget`'s steps. A view ray (`shadow` false) returns its hit; a shadow ray the
// sun's share (`t`: 1 unshadowed, down to 0), its record unused. Each step is the least over
// the records of the bound read for it over that bound's own Lipschitz constant: 1 for the
// distance to its sphere, the undisplaced field's for that field, the whole field's only near
// the surface (a cairn's is 2.47, its undisplaced field's 1.67).
fn trace(o: vec3<f32>, dir: vec3<f32>, span: vec2<f32>, cands: array<u32, 4>, n: u32, shadow: bool, budget: ptr<function, u32>, share: ptr<function, f32>) -> Meet {
    var t = span.x;
    // A view ray's distance a step ago: one that runs out of steps still nearing a surface
    // (grazing it) takes that surface as met, not seen through.
    var before = 3.0e38;
    var d_now = 3.0e38;
    var near = NO_RECORD;
    while t <= span.y && *budget > 0u {
        *budget -= 1u;
        let p = o + dir * t;
        let eps = max(1e-3, 0.5 * t / pf.pixels);
        var d = 3.0e38;
        var safe = 3.0e38;
        var best = NO_RECORD;
        for (var c = 0u; c < n; c++) {
            // Outside a prop's sphere by more than SPHERE_MARGIN, the distance to the sphere
            // bounds the distance to the prop: a view ray reads its field only near it. A
            // shadow ray reads it too where the bound would darken its penumbra. (A record
            // whose sphere is no nearer than `d` bounds no step: every constant is >= 1.)
            let sphere = prop_grid[cands[c] * RECORD + 3u];
            var dc = length(p - sphere.xyz) - sphere.w;
            if dc >= d {
                continue;
            }
            var lip = 1.0;
            let penumbra = shadow && SHADOW_SOFTNESS * dc < *share * max(t, 1e-3);
            if dc < SPHERE_MARGIN || penumbra {
                // Then the field without its displacements: a shadow reads it as the field, and
                // so does a view ray where their amplitude is under half the pixel's footprint
                // (the prop's level of detail: its surface is within that of the undisplaced
                // one; never in the reference, flag 64); else a view ray reads it less their
                // amplitude as a bound, and the whole field only near.
                dc = record_undisplaced(cands[c], p);
                lip = undisplaced_lipschitz_of(cands[c]);
                let rough = roughness_of(cands[c]);
                if !shadow && (rough >= eps || (pf.flags & 64u) != 0u) {
                    dc -= rough;
                    if dc < ROUGH_MARGIN {
                        dc = record_distance(cands[c], p).x;
                        lip = lipschitz_of(cands[c]);
                    }
                }
            }
            safe = min(safe, dc / lip);
            if dc < d {
                d = dc;
                best = cands[c];
            }
        }
        if shadow {
            // The distance at each step: estimating where between two steps the ray passed
            // nearest darkened the penumbra 3 to 10 times as much (`relief stability --axis
            // props`, the banding sweep).
            *share = min(*share, SHADOW_SOFTNESS * max(d, 0.0) / max(t, 1e-3));
            if *share < 0.01 {
                *share = 0.0;
                return Meet(t, best);
            }
        } else if d < eps {
            return Meet(t, best);
        }
        before = d_now;
        d_now = d;
        near = best;
        // A shadow ray steps at least SHADOW_STEP: its penumbra needs no finer.
        t += max(safe, select(eps, SHADOW_STEP, shadow));
    }
    if !shadow && *budget == 0u && t <= span.y && d_now < before {
        return Meet(t, near);
    }
    return Meet(span.y, NO_RECORD);
}

// Walks the ray `o + t dir` over [t_begin, t_end] through the props. A view ray returns its
// first hit (record NO_RECORD: none); a shadow ray the sun's share in `t`.
fn walk(o: vec3<f32>, dir: vec3<f32>, t_begin: f32, t_end: f32, shadow: bool) -> Meet {
    let inv = 1.0 / select(dir, vec3<f32>(1e-12), abs(dir) < vec3<f32>(1e-12));
    var budget = pf.steps;
    var share = 1.0;
    var best = Meet(t_end, NO_RECORD);
    // The props put at given places: each ray looks at each.
    let placed = pf.side * pf.side;
    for (var j = 0u; j < pf.placed; j++) {
        let s = record_span(placed + j, o, inv);
        let span = vec2<f32>(max(s.x, t_begin), min(s.y, best.t));
        if span.x <= span.y {
            var one = array<u32, 4>(placed + j, 0u, 0u, 0u);
            let m = trace(o, dir, span, one, 1u, shadow, &budget, &share);
            if shadow && share <= 0.0 {
                return Meet(0.0, m.record);
            }
            if !shadow && m.record != NO_RECORD {
                best = m;
            }
        }
    }
    let half = i32(pf.side / 2u);
    let m = i32(dual_side());
    let c = pf.cell;
    // Only where the ray is within the heights every prop spans.
    let all = prop_block_range[pf.blocks * pf.blocks];
    var t = t_begin;
    var t_last = best.t;
    if abs(dir.y) > 1e-6 {
        let ta = (all.x - o.y) / dir.y;
        let tb = (all.y - o.y) / dir.y;
        t = max(t, min(ta, tb));
        t_last = min(t_last, max(ta, tb));
    } else if o.y < all.x || o.y > all.y {
        t_last = t;
    }
    for (var visit = 0u; visit < MAX_VISITS; visit++) {
        if t >= t_last || budget == 0u {
            break;
        }
        let p = o + dir * t;
        // The dual cell holding p: the corner nearest it, counted from the grid's first.
        let g = vec2<i32>(floor((p.xz + pf.eye_in_cell) / c + 0.5)) + half;
        if any(g < vec2<i32>(0)) || any(g >= vec2<i32>(m)) {
            break;
        }
        let step = max(1e-4, 1e-6 * t);
        let bi = vec2<u32>(g) / BLOCK;
        let block_lo = (vec2<f32>(vec2<i32>(bi * BLOCK) - half) - 0.5) * c - pf.eye_in_cell;
        let block_exit = square_exit(o, inv, block_lo, block_lo + f32(BLOCK) * c);
        if !crosses(o, dir, t, min(block_exit, best.t), prop_block_range[bi.y * pf.blocks + bi.x]) {
            t = max(block_exit, t) + step;
            continue;
        }
        let lo = (vec2<f32>(g - half) - 0.5) * c - pf.eye_in_cell;
        let exit = square_exit(o, inv, lo, lo + c);
        let end = min(exit, best.t);
        if crosses(o, dir, t, end, prop_dual_range[u32(g.y * m + g.x)]) {
            var cands = array<u32, 4>(0u, 0u, 0u, 0u);
            var n = 0u;
            var span = vec2<f32>(3.0e38, -3.0e38);
            for (var k = 0; k < 4; k++) {
                let cell = g - vec2<i32>(1) + vec2<i32>(k & 1, k >> 1u);
                if any(cell < vec2<i32>(0)) || any(cell >= vec2<i32>(i32(pf.side))) {
                    continue;
                }
                let i = u32(cell.y) * pf.side + u32(cell.x);
                let s = record_span(i, o, inv);
                let within = vec2<f32>(max(s.x, t), min(s.y, end));
                if within.x <= within.y {
                    cands[n] = i;
                    n += 1u;
                    span = vec2<f32>(min(span.x, within.x), max(span.y, within.y));
                }
            }
            if n > 0u {
                let hit = trace(o, dir, span, cands, n, shadow, &budget, &share);
                if shadow && share <= 0.0 {
                    return Meet(0.0, hit.record);
                }
                if !shadow && hit.record != NO_RECORD {
                    return hit;
                }
            }
        }
        t = max(exit, t) + step;
    }
    if shadow {
        return Meet(share, NO_RECORD);
    }
    return best;
}

// The seed's way, for the benchmark's peer (`PropsFrame::flags` bit 16): from the eye, every
// step reads the whole fields of the props of the 3x3 cells around the point, steps at most
// half a cell (so no prop beyond them is stepped into), up to the draw distance: no band, no
// bounds, no depth the raster kept; `pf.peer_steps` steps at most.
fn seed_walk(dir: vec3<f32>, t_end: f32) -> Meet {
    let half = i32(pf.side / 2u);
    var t = 0.05;
    for (var s = 0u; s < pf.peer_steps; s++) {
        let p = dir * t;
        let cell = vec2<i32>(floor((p.xz + pf.eye_in_cell) / pf.cell)) + half;
        // The nearest field's value (the hit test, relief's) and the safe step (each field
        // over its Lipschitz constant).
        var d = 3.0e38;
        var step = 3.0e38;
        var best = NO_RECORD;
        for (var k = 0; k < 9; k++) {
            let c = cell + vec2<i32>(k % 3 - 1, k / 3 - 1);
            if any(c < vec2<i32>(0)) || any(c >= vec2<i32>(i32(pf.side))) {
                continue;
            }
            let i = u32(c.y) * pf.side + u32(c.x);
            if prop_grid[i * RECORD].w <= 0.0 {
                continue;
            }
            let dc = record_distance(i, p).x;
            step = min(step, dc / max(lipschitz_of(i), 1.0));
            if dc < d {
                d = dc;
                best = i;
            }
        }
        if d < max(1e-3, 0.5 * t / pf.pixels) {
            return Meet(t, best);
        }
        t += min(step, 0.5 * pf.cell);
        if t > t_end {
            break;
        }
    }
    return Meet(t_end, NO_RECORD);
}

// The props' shadow at camera-relative `p` (the sun's share, 0 to 1).
fn props_shadow(p: vec3<f32>) -> f32 {
    let l = r.sun_dir.xyz;
    if l.y <= 0.0 {
        return 1.0;
    }
    return walk(p, l, 0.0, SHADOW_REACH, true).t;
}

// The props' shadow on the surface the raster drew at distance `t` along `dir`, from a little
// towards the eye.
fn surface_shadow(dir: vec3<f32>, t: f32) -> f32 {
    return props_shadow(dir * (t - max(0.02, 2.0 * t / pf.pixels)));
}

// How high over the ground the props' occlusion of the sky reads their fields, metres (four
// heights up to this), and how strongly it darkens.
const GROUND_AO_REACH: f32 = 1.0;
const GROUND_AO_STRENGTH: f32 = 1.5;

// The props' occlusion of the sky over the ground at camera-relative `p` (the surface the
// raster drew), 0 to 1: their undisplaced fields read at four heights over it (straight up: the
// ground under props is gentle), as a prop's own occlusion reads its field along its normal.
fn ground_ao(p: vec3<f32>) -> f32 {
    var cands = array<u32, 4>(0u, 0u, 0u, 0u);
    var n = 0u;
    let half = i32(pf.side / 2u);
    let m = i32(dual_side());
    let g = vec2<i32>(floor((p.xz + pf.eye_in_cell) / pf.cell + 0.5)) + half;
    if all(g >= vec2<i32>(0)) && all(g < vec2<i32>(m)) {
        let range = prop_dual_range[u32(g.y * m + g.x)];
        if p.y + GROUND_AO_REACH >= range.x && p.y <= range.y {
            for (var k = 0; k < 4; k++) {
                let cell = g - vec2<i32>(1) + vec2<i32>(k & 1, k >> 1u);
                if all(cell >= vec2<i32>(0)) && all(cell < vec2<i32>(i32(pf.side))) {
                    let i = u32(cell.y) * pf.side + u32(cell.x);
                    if near_record(i, p) {
                        cands[n] = i;
                        n += 1u;
                    }
                }
            }
        }
    }
    // The props put at given places: each pixel looks at each.
    let placed = pf.side * pf.side;
    for (var j = 0u; j < pf.placed && n < 4u; j++) {
        if near_record(placed + j, p) {
            cands[n] = placed + j;
            n += 1u;
        }
    }
    if n == 0u {
        return 1.0;
    }
    var occ = 0.0;
    for (var s = 1u; s <= 4u; s++) {
        let h = 0.25 * f32(s) * GROUND_AO_REACH;
        var d = h;
        for (var k = 0u; k < n; k++) {
            d = min(d, record_undisplaced(cands[k], p + vec3<f32>(0.0, h, 0.0)));
        }
        occ += max(h - d, 0.0) / (h * f32(1u << s));
    }
    return clamp(1.0 - GROUND_AO_STRENGTH * occ, 0.0, 1.0);
}

// Whether record `i` holds a prop whose sphere comes within the ground's occlusion's reach of
// `p`.
fn near_record(i: u32, p: vec3<f32>) -> bool {
    let sphere = prop_grid[i * RECORD + 3u];
    return prop_grid[i * RECORD].w > 0.0 && length(p - sphere.xyz) < sphere.w + GROUND_AO_REACH;
}

// The props' shadow and occlusion on the surface the raster drew, marched a 2x2 block of
// pixels at a time (`props_shadows`) at the block's nearest pixel: the sun's share there, the
// point's distance (3e38: none) and the sky's share. A pixel of the block takes it where its own point is within this share
// of its distance of the block's.
@group(2) @binding(0) var quad_out: texture_storage_2d<rgba32float, write>;
@group(2) @binding(1) var quad_in: texture_2d<f32>;
const QUAD_DEPTH: f32 = 0.1;

@compute @workgroup_size(8, 8)
fn props_shadows(@builtin(global_invocation_id) id: vec3<u32>) {
    let blocks = (vis.size + 1u) / 2u;
    if id.x >= blocks.x || id.y >= blocks.y {
        return;
    }
    var best = vec3<f32>(1.0, 3.0e38, 1.0);
    var dir = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let px = id.xy * 2u + vec2<u32>(k & 1u, k >> 1u);
        if px.x >= vis.size.x || px.y >= vis.size.y {
            continue;
        }
        let d = rasterised_depth(px);
        if d < 1.0 {
            let v = sample_ray(vec2<f32>(px) + 0.5);
            let s = length(point_at(v, d));
            if s < best.y {
                best.y = s;
                dir = v;
            }
        }
    }
    if best.y < pf.distance + pf.cell {
        best.x = surface_shadow(dir, best.y);
        best.z = ground_ao(dir * best.y);
    } else {
        best.y = 3.0e38;
    }
    textureStore(quad_out, id.xy, vec4<f32>(best, 0.0));
}

// The props' shade map (props_map.wgsl reads it, src/gpu/props_map.rs bakes it): a thread a
// texel of a rectangle of one level, the props' shadow and occlusion on the drawn surface
// under its centre (ground.wgsl), marched as a pixel's are. Its own group 2, and a group 0 of
// the world's that binds no map (the map is written here).
struct MapRect {
    // The camera-relative x and z of the rectangle's first texel's corner, metres.
    origin: vec2<f32>,
    // That texel's column and row in the texture.
    first: vec2<u32>,
    size: vec2<u32>,
    level: u32,
    texel: f32,
}

@group(2) @binding(0) var props_map_out: texture_storage_2d_array<rgba8unorm, write>;
@group(2) @binding(1) var<uniform> map_rect: MapRect;

// How far over the drawn surface a texel's shadow ray leaves, metres.
const MAP_LIFT: f32 = 0.05;

@compute @workgroup_size(8, 8)
fn props_map_bake(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= map_rect.size.x || id.y >= map_rect.size.y {
        return;
    }
    let xz = map_rect.origin + (vec2<f32>(id.xy) + 0.5) * map_rect.texel;
    let p = ground_at(xz).rel;
    var shade = vec2<f32>(1.0);
    if length(p) < pf.distance + pf.cell {
        shade = vec2<f32>(props_shadow(p + vec3<f32>(0.0, MAP_LIFT, 0.0)), ground_ao(p));
    }
    let side = u32(textureDimensions(props_map_out).x);
    let t = (map_rect.first + id.xy) % side;
    textureStore(props_map_out, t, map_rect.level, vec4<f32>(shade, 0.0, 1.0));
}

@compute @workgroup_size(8, 8)
fn props_march(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    let dir = sample_ray(vec2<f32>(id.xy) + 0.5);
    // The overlay (flag 32) marches without the raster's depth: the host's depth test hides
    // what the terrain covers.
    var d = 1.0;
    if (pf.flags & 32u) == 0u {
        d = rasterised_depth(id.xy);
    }
    var t_end = pf.distance + pf.cell;
    var surface = false;
    if d < 1.0 {
        let s = length(point_at(dir, d));
        surface = s < t_end;
        t_end = min(t_end, s);
    }
    let origin = vec3<f32>(0.0);
    var hit: Meet;
    if (pf.flags & 16u) != 0u {
        hit = seed_walk(dir, pf.distance + pf.cell);
        if hit.t >= t_end {
            hit.record = NO_RECORD;
        }
    } else {
        hit = walk(origin, dir, 0.0, t_end, false);
    }
    if hit.record == NO_RECORD {
        var out = no_prop();
        if surface {
            // The props' shadow and occlusion on the surface the raster drew: its 2x2 block's,
            // where the block's point lies within QUAD_DEPTH of this pixel's; else its own.
            // The reference (flag 64) marches every sample's own.
            let quad = textureLoad(quad_in, id.xy / 2u, 0).xyz;
            if (pf.flags & 64u) == 0u && abs(quad.y - t_end) <= QUAD_DEPTH * t_end {
                out.w = bitcast<u32>(quad.x);
                out.y = bitcast<u32>(quad.z);
            } else {
                out.w = bitcast<u32>(surface_shadow(dir, t_end));
                out.y = bitcast<u32>(ground_ao(dir * t_end));
            }
        }
        textureStore(prop_hit_out, px, out);
        return;
    }
    let p = dir * hit.t;
    let i = hit.record;
    let e = max(2e-3, 0.5 * hit.t / pf.pixels);
    // The normal: the tetrahedron of four evaluations (four, not six, for central differences).
    let k0 = vec3<f32>(1.0, -1.0, -1.0);
    let k1 = vec3<f32>(-1.0, -1.0, 1.0);
    let k2 = vec3<f32>(-1.0, 1.0, -1.0);
    let k3 = vec3<f32>(1.0, 1.0, 1.0);
    var n = k0 * record_distance(i, p + e * k0).x + k1 * record_distance(i, p + e * k1).x
        + k2 * record_distance(i, p + e * k2).x + k3 * record_distance(i, p + e * k3).x;
    n = select(-dir, normalize(n), dot(n, n) > 0.0);
    let at = record_distance(i, p);
    // The sky's share: the field's occlusion over four steps out along the normal.
    var ao = 0.0;
    for (var s = 1; s <= 4; s++) {
        let h = 0.12 * f32(s);
        ao += (h - record_undisplaced(i, p + n * h)) / f32(1 << u32(s));
    }
    ao = clamp(1.0 - 2.5 * ao, 0.0, 1.0);
    let look = prop_grid[i * RECORD + 2u];
    let hn = (p.y + w.eye.y) / w.peak;
    let occl = occlusion(r, hn, look.y, look.z);
    // The shadow ray leaves from past the displacements: it reads the undisplaced fields.
    let b = prop_grid[i * RECORD + 1u];
    let rough = prop_kinds[u32(b.z)].scale.z * prop_grid[i * RECORD].w;
    let sun = occl.x * props_shadow(p + n * (max(0.02, 2.0 * e) + rough));
    let mat = prop_materials[u32(at.y)];
    let albedo = mat.rgb * (1.0 + mat.w * (look.x - 0.5));
    let clip_w = dot(vis.w_row.xyz, p) + vis.w_row.w;
    let depth = vis.depth.y / clip_w - vis.depth.x;
    textureStore(prop_hit_out, px, vec4<u32>(
        bitcast<u32>(depth),
        pack2x16snorm(oct_encode(n)),
        pack4x8unorm(vec4<f32>(sqrt(clamp(albedo, vec3<f32>(0.0), vec3<f32>(1.0))), ao * occl.y)),
        bitcast<u32>(sun),
    ));
}

// The grass's blades (grass_scatter.wgsl), for `props_grass`: four vectors a blade (its root
// camera-relative in the first; its height and width the second's x and w), and the scatter's
// counts (the blades drawn the fourth).
@group(2) @binding(0) var<storage, read_write> grass_blades: array<vec4<f32>>;
@group(2) @binding(1) var<storage, read> grass_counts: array<u32, 8>;

// Whether camera-relative `p` is inside a placed prop (the props of its dual cell and those put
// at given places; each read only where `p` is inside its box).
fn inside_props(p: vec3<f32>) -> bool {
    let half = i32(pf.side / 2u);
    let g = vec2<i32>(floor((p.xz + pf.eye_in_cell) / pf.cell + 0.5)) + half;
    for (var k = 0; k < 4; k++) {
        let cell = g - vec2<i32>(1) + vec2<i32>(k & 1, k >> 1u);
        if any(cell < vec2<i32>(0)) || any(cell >= vec2<i32>(i32(pf.side))) {
            continue;
        }
        if inside_record(u32(cell.y) * pf.side + u32(cell.x), p) {
            return true;
        }
    }
    let placed = pf.side * pf.side;
    for (var j = 0u; j < pf.placed; j++) {
        if inside_record(placed + j, p) {
            return true;
        }
    }
    return false;
}

fn inside_record(i: u32, p: vec3<f32>) -> bool {
    let a = prop_grid[i * RECORD];
    if a.w <= 0.0 {
        return false;
    }
    let y = prop_cell_range[i];
    let r = prop_kinds[u32(prop_grid[i * RECORD + 1u].z)].lo.w * a.w;
    if p.y < y.x || p.y > y.y || any(abs(p.xz - a.xz) > vec2<f32>(r)) {
        return false;
    }
    return record_distance(i, p).x < 0.0;
}

// No grass grows inside a prop: a blade whose root is inside one is flattened to nothing (its
// triangles empty), after both scatters. A fixed number of threads strides over the blades.
@compute @workgroup_size(64)
fn props_grass(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let drawn = grass_counts[3];
    for (var i = id.x; i < drawn; i += groups.x * 64u) {
        // A little over the root: a root on a prop's buried foot is inside it.
        if inside_props(grass_blades[4u * i].xyz + vec3<f32>(0.0, 0.01, 0.0)) {
            var b = grass_blades[4u * i + 1u];
            b.x = 0.0;
            b.w = 0.0;
            grass_blades[4u * i + 1u] = b;
        }
    }
}

// The reference's blades (grass_reference.wgsl, the same four vectors a blade; its lighting
// the third's y, the sun's share, and z, the sky's): a blade whose root is inside a prop is
// flattened as `props_grass` does; every other one takes the props' shadow at its middle into
// its sun's share and their occlusion of the sky at its root into its sky's (the reference
// lights a blade whole).
@compute @workgroup_size(64)
fn props_grass_reference(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let drawn = grass_counts[3];
    for (var i = id.x; i < drawn; i += groups.x * 64u) {
        let root = grass_blades[4u * i].xyz;
        var b = grass_blades[4u * i + 1u];
        if inside_props(root + vec3<f32>(0.0, 0.01, 0.0)) {
            b.x = 0.0;
            b.w = 0.0;
            grass_blades[4u * i + 1u] = b;
        } else {
            var lit = grass_blades[4u * i + 2u];
            lit.y *= props_shadow(root + vec3<f32>(0.0, 0.5 * b.x, 0.0));
            lit.z *= ground_ao(root);
            grass_blades[4u * i + 2u] = lit;
        }
    }
}
