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
// and a blade narrower than a pixel widened to one and thinned to keep the cover. A workgroup's
// block of cells is skipped whole where it lies outside the distance or the view.

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
// appended clamped to the capacity by `finish`), and the triangles of those appended.
@group(1) @binding(2) var<storage, read_write> counts: array<atomic<u32>, 8>;
// The indirect draw's arguments: vertices, instances, first vertex, first instance; then the
// compute raster's indirect dispatch of a thread a triangle of `triangles`
// (raster_blades.wgsl): workgroups of 128 in x, 1, 1, and 0.
@group(1) @binding(3) var<storage, read_write> draw_args: array<u32, 8>;
// The compute raster's list of the kept blades' triangles: the blade's number times 8 plus the
// triangle's in its strip. A triangle past the list's end is not drawn.
@group(1) @binding(4) var<storage, read_write> triangles: array<u32>;

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

// Whether the workgroup's block can show a blade; its counts of cells considered, blades kept
// and their triangles; and where its blades and triangles begin in `blades` and `triangles`:
// one global atomic a workgroup for each (an atomic a blade cost the scatter more than the list
// of triangles saves the raster).
var<workgroup> block_visible: u32;
var<workgroup> block_counts: array<atomic<u32>, 3>;
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

@compute @workgroup_size(8, 8)
fn scatter(
    @builtin(global_invocation_id) id: vec3<u32>,
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    if lane == 0u {
        block_visible = u32(block_in_view(group.xy));
    }
    let visible = workgroupUniformLoad(&block_visible) != 0u;
    let half = i32(gf.side / 2u);
    let rel_cell = vec2<i32>(id.xy) - vec2<i32>(half);
    let in_square = id.x < gf.side && id.y < gf.side;
    // Considered: the cells whose centre lies within the draw distance (each holds a blade),
    // in blocks culled or not.
    let centre = (vec2<f32>(rel_cell) + 0.5) * gf.g.cell - gf.eye_in_cell;
    if in_square && length(centre) <= gf.distance {
        atomicAdd(&block_counts[0], 1u);
    }
    var k = Kept();
    if visible && in_square {
        k = scatter_cell(rel_cell);
    }
    var own = vec2<u32>(0u);
    if k.kept {
        own = vec2<u32>(atomicAdd(&block_counts[1], 1u), atomicAdd(&block_counts[2], k.triangles));
    }
    workgroupBarrier();
    if lane == 0u {
        // The counters are shared by every workgroup: a block that keeps no blade (most of
        // them: outside the view, or off the grass) leaves them alone.
        let considered = atomicLoad(&block_counts[0]);
        if considered > 0u {
            atomicAdd(&counts[0], considered);
        }
        let kept = atomicLoad(&block_counts[1]);
        if kept > 0u {
            atomicAdd(&counts[1], kept);
            let first_blade = atomicAdd(&counts[2], kept);
            block_base = vec2<u32>(first_blade, atomicAdd(&counts[4], atomicLoad(&block_counts[2])));
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
