// import: world, ground, grass, grass_blade
// The grass's scatter pass (src/gpu/grass.rs): one thread a cell of the square of cells around
// the eye that the draw distance reaches. Each cell's blade (grass.wgsl) is kept where the
// ground under it is grass enough (`grass_cover` against the blade's own `keep`), within its
// own distance (between half the draw distance and all of it, by `far`, shrinking to nothing
// over its last metres so that no ring of blades pops) and inside the view's frustum; its
// root stands on the triangle of the mesh the world draws there (the level that draws the
// point, its vertices placed as world.wgsl's `place` places them, morph and the hybrid's raise
// included). A kept blade is appended to `blades` for the draw (grass_draw.wgsl, or the compute
// raster's raster_blades.wgsl) with its level of detail: its segments by its length on screen,
// and a blade narrower than a pixel widened to one and thinned to keep the cover. A first pass
// (`cull`, a thread a block of 8 x 8 cells) counts the cells each block holds within the
// distance and lists the blocks that can show a blade (inside the distance and the view);
// `cull_finish` writes the scatter's indirect dispatch, a workgroup a listed block, so a block
// outside the view costs one thread, not a workgroup of 64 (on lavapipe the whole square's
// workgroups took over a second a frame at the default density, a view from high up keeping
// none).

struct GrassFrame {
    g: GrassUniforms,
    // The eye less its cell's first corner, metres (x, z); the draw distance, metres; the
    // cells the square spans on a side.
    eye_in_cell: vec2<f32>,
    distance: f32,
    side: u32,
    // The most blades `blades` holds; the image's height in pixels.
    capacity: u32,
    pixels_high: f32,
    // 1 for the benchmark's peer (src/grass.rs's Peer, Terra's way): every blade of the patch
    // kept, in all its segments, with no culling to the view and no widening.
    peer: u32,
    _pad2: u32,
    // The wind: the direction it blows towards (x, z), its speed (m/s); the gust waves' phases
    // at the eye, in turns (src/grass.rs: GUSTS), at this frame's clock (x, y) and at the last
    // frame's (z, w).
    wind: vec4<f32>,
    gust_phase: vec4<f32>,
}

@group(1) @binding(0) var<uniform> gf: GrassFrame;
// Per blade: root (camera-relative, metres) and facing; height, lean, curve, width; shade,
// the sun's and the sky's occlusion at the root, and how far the wind's push on the tip moved
// since the last frame along x; the wind's push on the tip (x, z), the segments it is drawn in,
// and how far the push moved along z (the temporal service's motion, grass_blade.wgsl's
// `blade_motion`).
@group(1) @binding(1) var<storage, read_write> blades: array<vec4<f32>>;
// Blades considered (cells the square holds within the distance), kept, appended, drawn (the
// appended clamped to the capacity by `finish`), the triangles of those appended, those in the
// compute raster's list, and the blocks `cull` listed.
@group(1) @binding(2) var<storage, read_write> counts: array<atomic<u32>, 8>;
// The indirect draw's arguments: vertices, instances, first vertex, first instance; then the
// compute raster's indirect dispatch of a thread a triangle of `triangles`
// (raster_blades.wgsl): workgroups of 128 in x, 1, 1, and 0.
@group(1) @binding(3) var<storage, read_write> draw_args: array<u32, 8>;
// The compute raster's list of the kept blades' triangles: the blade's number times 8 plus the
// triangle's in its strip. A triangle past the list's end is not drawn.
@group(1) @binding(4) var<storage, read_write> triangles: array<u32>;
// The blocks `cull` found can show a blade, a word each: the block's column, and its row times
// 65536 (the square spans at most 801 blocks a side); counts[6] says how many.
@group(1) @binding(5) var<storage, read_write> blocks: array<u32>;
// The scatter's indirect dispatch, written by `cull_finish`: a workgroup a listed block, in rows
// of at most MAX_GROUPS.
@group(2) @binding(0) var<storage, read_write> scatter_args: array<u32, 4>;

// The most workgroups a dispatch has along x (WebGPU's limit, maxComputeWorkgroupsPerDimension).
const MAX_GROUPS: u32 = 65535u;

// Vertices of a blade (grass_draw.wgsl): a strip of four segments and a tip.
const BLADE_VERTICES: u32 = 9u;

// Within this distance (metres) a blade has all its segments; beyond it one a this many
// pixels of its length on screen (at least one: a triangle).
const FULL_DETAIL: f32 = 10.0;
const SEGMENT_PIXELS: f32 = 12.0;

// The segments a blade `height` metres tall rooted at camera-relative `root` is drawn in: its
// level of detail, from its length on screen.
fn blade_segments(root: vec3<f32>, height: f32) -> u32 {
    let c = r.view_proj * vec4<f32>(root, 1.0);
    if length(root) < FULL_DETAIL || !(c.w > 0.0) {
        return BLADE_SEGMENTS;
    }
    let pixels = height * pixels_per_metre(c.w);
    return clamp(u32(ceil(pixels / SEGMENT_PIXELS)), 1u, BLADE_SEGMENTS);
}

// The tallest blade, as a multiple of the mean height (grass.wgsl's `blade_at`: 1.6 for
// clumps, 1.2 for a blade's own), and the steepest ground that grows grass (`grass_cover`: none
// where the normal's y is below 0.52, a slope of 1.65).
const TALLEST: f32 = 1.92;
const STEEPEST: f32 = 1.65;

// Whether any blade of the workgroup's block of 8 x 8 cells, numbered `group`, can be drawn:
// within the draw distance, and inside the view's frustum by a sphere holding the block's
// ground (its height at the block's centre, give or take the steepest slope that grows grass
// across the block) and its tallest blade, leaning or blown over. One ground read for 64
// cells; at the default density three blocks in four lie outside a level view.
fn block_in_view(group: vec2<u32>) -> bool {
    let first = vec2<f32>(vec2<i32>(group * 8u) - vec2<i32>(i32(gf.side / 2u)));
    let size = 8.0 * gf.g.cell;
    let centre = (first + 4.0) * gf.g.cell - gf.eye_in_cell;
    let radius = 0.7072 * size;
    if length(centre) - radius > gf.distance {
        return false;
    }
    if gf.peer != 0u {
        return true;
    }
    let top = TALLEST * gf.g.height;
    let ground = ground_at(centre).rel.y;
    let reach = radius * (1.0 + STEEPEST) + 2.0 * top;
    return in_frustum(r.view_proj, vec3<f32>(centre.x, ground, centre.y), reach);
}

// Pixels a metre at clip w `cw` (the projection's vertical scale: its row 1 is that times the
// view's up).
fn pixels_per_metre(cw: f32) -> f32 {
    let focal = length(vec3<f32>(r.view_proj[0][1], r.view_proj[1][1], r.view_proj[2][1]));
    return 0.5 * gf.pixels_high * focal / cw;
}

// The workgroup's block's counts of blades kept and their triangles, and where its blades and
// triangles begin in `blades` and `triangles`: one global atomic a workgroup for each (an atomic
// a blade cost the scatter more than the list of triangles saves the raster).
var<workgroup> block_counts: array<atomic<u32>, 2>;
var<workgroup> block_base: vec2<u32>;

// A cell's blade where it is kept: as the draw reads it (the layout of `blades`), and its
// triangles.
struct Kept {
    kept: bool,
    blade: array<vec4<f32>, 4>,
    triangles: u32,
}

// A triangle of the list whose blade was not stored (past the capacity): skipped.
const NO_TRIANGLE: u32 = 0xffffffffu;

// Blocks of 8 x 8 cells across the square.
fn blocks_across() -> u32 {
    return (gf.side + 7u) / 8u;
}

// A thread a block of the square: counts its cells within the draw distance (considered, culled
// or not: each holds a blade) and lists the block where it can show a blade.
@compute @workgroup_size(64)
fn cull(@builtin(global_invocation_id) id: vec3<u32>) {
    let across = blocks_across();
    if id.x >= across * across {
        return;
    }
    let group = vec2<u32>(id.x % across, id.x / across);
    let half = i32(gf.side / 2u);
    // The rectangle of the block's cells' centres: all 64 within the distance, or none, or
    // (a block across the circle or the square's edge) counted a cell at a time; a loop in
    // every thread cost lavapipe more than the scatter. A block within a cell of the circle
    // is counted a cell at a time too, so that rounding never tells the two ways apart.
    let lo = (vec2<f32>(vec2<i32>(group * 8u) - vec2<i32>(half)) + 0.5) * gf.g.cell - gf.eye_in_cell;
    let hi = lo + 7.0 * gf.g.cell;
    let near = max(max(lo, -hi), vec2<f32>(0.0));
    let far = max(abs(lo), abs(hi));
    let whole = group.x * 8u + 8u <= gf.side && group.y * 8u + 8u <= gf.side;
    var considered = 0u;
    if length(near) > gf.distance + gf.g.cell {
        considered = 0u;
    } else if whole && length(far) < gf.distance - gf.g.cell {
        considered = 64u;
    } else {
        for (var i = 0u; i < 64u; i++) {
            let cell = group * 8u + vec2<u32>(i % 8u, i / 8u);
            let rel_cell = vec2<i32>(cell) - vec2<i32>(half);
            let centre = (vec2<f32>(rel_cell) + 0.5) * gf.g.cell - gf.eye_in_cell;
            if cell.x < gf.side && cell.y < gf.side && length(centre) <= gf.distance {
                considered += 1u;
            }
        }
    }
    if considered > 0u {
        atomicAdd(&counts[0], considered);
    }
    if block_in_view(group) {
        blocks[atomicAdd(&counts[6], 1u)] = group.x | (group.y << 16u);
    }
}

// The scatter's dispatch: a workgroup a listed block.
@compute @workgroup_size(1)
fn cull_finish() {
    let listed = atomicLoad(&counts[6]);
    scatter_args[0] = min(listed, MAX_GROUPS);
    scatter_args[1] = (listed + MAX_GROUPS - 1u) / MAX_GROUPS;
    scatter_args[2] = 1u;
    scatter_args[3] = 0u;
}

// A listed block's word, or NO_BLOCK past the list's end (the last row's rest).
var<workgroup> block_word: u32;
const NO_BLOCK: u32 = 0xffffffffu;

@compute @workgroup_size(8, 8)
fn scatter(
    @builtin(local_invocation_id) local: vec3<u32>,
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    if lane == 0u {
        let listed = workgroup.y * MAX_GROUPS + workgroup.x;
        block_word = select(NO_BLOCK, blocks[listed], listed < atomicLoad(&counts[6]));
    }
    let word = workgroupUniformLoad(&block_word);
    if word == NO_BLOCK {
        return;
    }
    let id = vec2<u32>(word & 0xffffu, word >> 16u) * 8u + local.xy;
    let half = i32(gf.side / 2u);
    let rel_cell = vec2<i32>(id) - vec2<i32>(half);
    var k = Kept();
    if id.x < gf.side && id.y < gf.side {
        k = scatter_cell(rel_cell);
    }
    var own = vec2<u32>(0u);
    if k.kept {
        own = vec2<u32>(atomicAdd(&block_counts[0], 1u), atomicAdd(&block_counts[1], k.triangles));
    }
    workgroupBarrier();
    if lane == 0u {
        // The counters are shared by every workgroup: a block that keeps no blade (off the
        // grass) leaves them alone.
        let kept = atomicLoad(&block_counts[0]);
        if kept > 0u {
            atomicAdd(&counts[1], kept);
            let first_blade = atomicAdd(&counts[2], kept);
            block_base = vec2<u32>(first_blade, atomicAdd(&counts[4], atomicLoad(&block_counts[1])));
        }
    }
    let base = workgroupUniformLoad(&block_base);
    if !k.kept {
        return;
    }
    // Past the capacity a kept blade is counted, not stored, and its triangles skipped.
    let at = base.x + own.x;
    let stored = at < gf.capacity;
    if stored {
        for (var i = 0u; i < 4u; i++) {
            blades[4u * at + i] = k.blade[i];
        }
    }
    let first = base.y + own.y;
    for (var t = 0u; t < k.triangles && first + t < arrayLength(&triangles); t++) {
        triangles[first + t] = select(NO_TRIANGLE, (at << 3u) | t, stored);
    }
}

// The blade of cell `rel_cell` (relative to the eye's), where it is kept: on grass, inside the
// view (kept past the capacity too, though not stored).
fn scatter_cell(rel_cell: vec2<i32>) -> Kept {
    var out = Kept();
    let b = blade_at(gf.g, rel_cell);
    let xz = (vec2<f32>(rel_cell) + b.offset) * gf.g.cell - gf.eye_in_cell;
    let dist = length(xz);
    if dist > gf.distance {
        return out;
    }
    // Each blade's own distance, and the last metres over which it shrinks away.
    let own = gf.distance * (0.5 + 0.5 * b.far);
    let fade = 1.0 - smoothstep(own - 0.1 * gf.distance, own, dist);
    if fade <= 0.0 {
        return out;
    }
    let ground = ground_at(xz);
    let s = ground.sample;
    let slope = s.yz * w.peak;
    let n_y = inverseSqrt(1.0 + dot(slope, slope));
    if b.keep >= grass_cover(r, n_y, s.x, s.w) {
        return out;
    }
    let height = b.height * fade;
    let peer = gf.peer != 0u;
    // The sphere holds the blade however far it leans (half its height) and is blown (0.6 of
    // it) from its middle: 1.25 of its height.
    if !peer && !in_frustum(r.view_proj, ground.rel + vec3<f32>(0.0, 0.5 * height, 0.0), 1.25 * height) {
        return out;
    }
    // A blade narrower than a pixel: widened to one, and kept with a chance of its width in
    // pixels (its own number `thin`, independent of its others), so the field's cover stays
    // and a distant blade is not a sliver that flickers. It narrows to nothing as its width
    // nears its number, so none pops.
    var width = b.width * fade;
    let c = r.view_proj * vec4<f32>(ground.rel, 1.0);
    if c.w > 0.0 && !peer {
        let px = width * pixels_per_metre(c.w);
        if px < 1.0 {
            let thin = fract(b.facing * (16.0 / GRASS_TAU));
            if thin >= px {
                return out;
            }
            width *= clamp((px - thin) / (0.2 * px), 0.0, 1.0) / (0.9 * px);
        }
    }
    // The props' shadow on the ground at the root, where the frame overlays the props
    // (props_map.wgsl: 1 elsewhere; the marching method shades each blade's pixel with the
    // props' own march). Not their occlusion of the sky there: the map's is the ground's, and
    // a blade standing out of it takes it darker than the marching method and the reference do
    // (tests/props_truth.rs: 0.22 as bright in the props' shadow with it, 0.52 without, the
    // marching method 0.55).
    let occl = occlusion(r, s.x, ground.light.x, ground.light.y) * vec2<f32>(props_map_at(ground.rel).x, 1.0);
    let tip = wind_tip(gf.wind, gf.gust_phase.xy, xz, height);
    let moved = tip - wind_tip(gf.wind, gf.gust_phase.zw, xz, height);
    let segments = select(blade_segments(ground.rel, height), BLADE_SEGMENTS, peer);
    out.kept = true;
    out.blade = array<vec4<f32>, 4>(
        vec4<f32>(ground.rel, b.facing),
        vec4<f32>(height, b.lean, b.curve, width),
        vec4<f32>(b.shade, occl, moved.x),
        vec4<f32>(tip, f32(segments), moved.y),
    );
    out.triangles = 2u * segments - 1u;
    return out;
}

// The indirect draw of the blades the scatter kept (at most the capacity), and the compute
// raster's dispatch of them.
@compute @workgroup_size(1)
fn finish() {
    let drawn = min(atomicLoad(&counts[2]), gf.capacity);
    atomicStore(&counts[3], drawn);
    draw_args[0] = BLADE_VERTICES;
    draw_args[1] = drawn;
    draw_args[2] = 0u;
    draw_args[3] = 0u;
    let listed = min(atomicLoad(&counts[4]), arrayLength(&triangles));
    atomicStore(&counts[5], listed);
    draw_args[4] = (listed + 127u) / 128u;
    draw_args[5] = 1u;
    draw_args[6] = 1u;
    draw_args[7] = 0u;
}
