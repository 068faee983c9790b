// import: world
// part of: raster_depth, raster_ids (each defines `keep` and `drawn_bits` for it)
// The visibility method's raster pass in compute (src/gpu/raster.rs; one sample a pixel): the
// same patches and vertices as the hardware raster pass (world.wgsl's `place`), one thread a
// cell, its two triangles clipped to the near plane, projected, and rasterised at pixel centres.
// What a covered pixel keeps is the next file's (`keep`):
//
// - raster_depth.wgsl (any device, the page): the nearest depth, by an atomic maximum of the
//   depth's complemented bits (non-negative floats order as their bits do, so the complement
//   orders them nearest first, and a cleared buffer's 0 reads as no terrain). The endless
//   world's shading also needs each pixel's attributes (world.wgsl's `fs_attributes`): a second
//   dispatch of the same pipeline (`mode` 1) rasterises again, and where a triangle's depth is
//   the pixel's nearest, bit for bit (the same code computed it), stores its attributes;
// - raster_ids.wgsl (devices with 64-bit atomic maximum): the same depth bits above the
//   triangle's id in one 64-bit atomic maximum, so one raster finds the nearest triangle of
//   every pixel, and a dispatch a pixel (`raster_resolve`) sets that one triangle up again from
//   its id and stores its attributes. A tie in depth goes to the greater id, the same every
//   frame.
//
// The depth's raster runs in passes, nearest levels first (src/gpu/raster.rs's PASS_LEVELS);
// a pass after the first skips the blocks of cells wholly behind what the passes before it
// drew (`block_hidden`, against `hiz`).
//
// Why: the H100 has few raster units; its depth-only raster of the tile's 131k triangles took
// 0.50 ms at 1080p, a pass that shades nothing. A thread a cell does the same in compute; the
// second raster of the attributes cost as much again as the first.
//
// Watertight: an edge shared by two triangles is evaluated with its end points in one order
// (the lesser point first) by both, so the two see exactly opposite values; a pixel centre
// exactly on the edge goes to the triangle that runs along it from the lesser point. Composed
// after shade.wgsl, level_texel.wgsl and world.wgsl (their uniforms, `place`), and before
// raster_depth.wgsl or raster_ids.wgsl.

struct RasterUniforms {
    // The image's size in pixels.
    size: vec2<u32>,
    // Whole patches (first in `patches`), then sub-patches.
    whole: u32,
    subs: u32,
    // Cells per side of a whole patch and of a sub-patch.
    patch_cells: u32,
    sub_cells: u32,
    // Workgroups per row of `raster_cells`' dispatch (its x extent).
    row_groups: u32,
    // raster_depth.wgsl's: 0 the nearest depth, 1 the attributes of the triangles that are
    // nearest. raster_ids.wgsl's: 0.
    mode: u32,
    // This dispatch's blocks of cells: `first_group` up to `end_group` (`block_of`'s order).
    first_group: u32,
    end_group: u32,
    // 1 where a block hidden behind `hiz` is skipped (`block_hidden`).
    cull: u32,
    _pad: u32,
}

@group(1) @binding(0) var<uniform> ras: RasterUniforms;
@group(1) @binding(1) var<storage, read> patches: array<vec4<u32>>;
// Binding 2, the depth buffer, is raster_depth.wgsl's or raster_ids.wgsl's.
// Per HIZ_TILE x HIZ_TILE tile of pixels, row by row, the farthest depth's complemented bits
// drawn so far (`raster_hiz`; 0 where a pixel has none): a raster in passes, nearest levels
// first, skips a block of cells wholly behind what the passes before it drew.
@group(1) @binding(10) var<storage, read_write> hiz: array<u32>;
// The endless world's attributes (1x1 stand-ins for the tile): as `fs_attributes` writes them.
@group(1) @binding(3) var surface_out: texture_storage_2d<rgba16float, write>;
@group(1) @binding(4) var valley_out: texture_storage_2d<r32float, write>;
// Triangles whose bounding box is over BIG_PIXELS, left by `raster_cells` for `raster_big`;
// their tiles of pixels as (triangle, tile) entries, a workgroup's work each; for each
// dispatch mode the counts of both (triangles at `mode`, tiles at 2 + `mode`); and the
// arguments of `raster_big`'s indirect dispatch for each mode (workgroups at 3 `mode`, then
// 1, 1): as many as there are tiles, at most BIG_GROUPS, none where nothing is big. The last
// is bound to `raster_cells` only: `raster_big` is dispatched from it.
@group(1) @binding(5) var<storage, read_write> big: array<BigTriangle>;
@group(1) @binding(6) var<storage, read_write> big_count: array<atomic<u32>, 4>;
@group(1) @binding(7) var<storage, read_write> big_tiles: array<vec2<u32>>;
@group(1) @binding(8) var<storage, read_write> big_args: array<atomic<u32>, 6>;

// A triangle's bounding box over this many pixels is rasterised by a workgroup
// (`raster_big`), not by the one thread that placed it: a camera near the ground sees
// triangles spanning much of the screen, and one thread looping over them held the pass.
const BIG_PIXELS: f32 = 256.0;
// Threads of a `raster_big` workgroup, and the side of the square of pixels it takes at once.
const BIG_GROUP: u32 = 64u;
const BIG_TILE: u32 = 16u;
// Most workgroups of `raster_big` (src/gpu/raster.rs's BIG_GROUPS).
const BIG_GROUPS: u32 = 4096u;

// A RasterVertex as stored for `raster_big` (the valley in `extra.x`).
struct BigVertex {
    clip: vec4<f32>,
    surface: vec4<f32>,
    extra: vec4<f32>,
}

struct BigTriangle {
    v0: BigVertex,
    v1: BigVertex,
    v2: BigVertex,
    // Its id (`Setup`'s).
    id: u32,
}

fn to_big(v: RasterVertex) -> BigVertex {
    return BigVertex(v.clip, v.surface, vec4<f32>(v.valley, 0.0, 0.0, 0.0));
}

fn from_big(v: BigVertex) -> RasterVertex {
    return RasterVertex(v.clip, v.surface, v.extra.x);
}

// A vertex: its clip position and the attributes `fs_attributes` writes (slope in x and z,
// colour channel, horizon; valley depth).
struct RasterVertex {
    clip: vec4<f32>,
    surface: vec4<f32>,
    valley: f32,
}

fn raster_vertex(vi: u32, patch_instance: vec4<u32>) -> RasterVertex {
    let v = place(vi, patch_instance);
    return RasterVertex(v.clip, vec4<f32>(v.sample.yz * w.peak, v.sample.w, v.light.x), v.light.y);
}

fn mix_vertex(a: RasterVertex, b: RasterVertex, t: f32) -> RasterVertex {
    return RasterVertex(mix(a.clip, b.clip, t), mix(a.surface, b.surface, t), mix(a.valley, b.valley, t));
}

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

// A triangle set up for its pixels: screen points (x, y, depth) turned to face forward, its
// vertices in the same order, 1 / twice its area, and its pixels' bounding box (pixel
// indices, inclusive); `valid` false where it covers no pixel centre.
struct Setup {
    s0: vec3<f32>,
    s1: vec3<f32>,
    s2: vec3<f32>,
    v0: RasterVertex,
    v1: RasterVertex,
    v2: RasterVertex,
    inv: f32,
    lo: vec2<f32>,
    hi: vec2<f32>,
    valid: bool,
    // The triangle's id: its cell's number (`cell_of`) times 4, plus 2 for the cell's second
    // triangle, plus 1 for the second triangle of its cut to the near plane. The terrain's
    // layer is 0, so its ids are their primitives (`LAYER_SHIFT`).
    id: u32,
}

// A visibility-buffer id: the layer (0 the terrain, then the frame's list of layers) in the
// bits from LAYER_SHIFT up, the layer's own primitive below them (PRIMITIVE_MASK): a terrain
// triangle, later a blade or a prop instance. Rust's `raster::LAYER_SHIFT` agrees.
const LAYER_SHIFT: u32 = 28u;
const PRIMITIVE_MASK: u32 = 0x0fffffffu;
const LAYER_TERRAIN: u32 = 0u;

fn setup_triangle(v0: RasterVertex, v1_in: RasterVertex, v2_in: RasterVertex, id: u32) -> Setup {
    var t: Setup;
    t.valid = false;
    t.id = id;
    t.v0 = v0;
    t.v1 = v1_in;
    t.v2 = v2_in;
    t.s0 = to_screen(v0.clip);
    t.s1 = to_screen(v1_in.clip);
    t.s2 = to_screen(v2_in.clip);
    var area = edge(t.s0.xy, t.s1.xy, t.s2.xy);
    if !(abs(area) > 0.0) {
        return t;
    }
    // Back faces are drawn too (the raster pass culls nothing): turn them to face forward.
    if area < 0.0 {
        let s = t.s1;
        t.s1 = t.s2;
        t.s2 = s;
        let u = t.v1;
        t.v1 = t.v2;
        t.v2 = u;
        area = -area;
    }
    let size = vec2<f32>(ras.size);
    t.lo = max(ceil(min(t.s0.xy, min(t.s1.xy, t.s2.xy)) - 0.5), vec2<f32>(0.0));
    t.hi = min(floor(max(t.s0.xy, max(t.s1.xy, t.s2.xy)) - 0.5), size - 1.0);
    t.valid = t.lo.x <= t.hi.x && t.lo.y <= t.hi.y;
    t.inv = 1.0 / area;
    return t;
}

// The edge values of pixel (x, y) for triangle `t` (each the area opposite one vertex).
fn pixel_edges(t: Setup, x: f32, y: f32) -> vec3<f32> {
    let p = vec2<f32>(x + 0.5, y + 0.5);
    return vec3<f32>(edge(t.s1.xy, t.s2.xy, p), edge(t.s2.xy, t.s0.xy, p), edge(t.s0.xy, t.s1.xy, p));
}

// Stores the attributes of triangle `t` at pixel (x, y) with edge values `e`, interpolated
// perspective-correct: the screen weights over each vertex's clip w.
fn store_attributes(t: Setup, e: vec3<f32>, x: f32, y: f32) {
    let q = e / vec3<f32>(t.v0.clip.w, t.v1.clip.w, t.v2.clip.w);
    let k = q / (q.x + q.y + q.z);
    let px = vec2<i32>(i32(x), i32(y));
    textureStore(surface_out, px, k.x * t.v0.surface + k.y * t.v1.surface + k.z * t.v2.surface);
    let valley = k.x * t.v0.valley + k.y * t.v1.valley + k.z * t.v2.valley;
    textureStore(valley_out, px, vec4<f32>(valley, 0.0, 0.0, 0.0));
}

// The pixel (x, y) of triangle `t`: where it is covered and in front of the far plane, `keep`
// (raster_depth.wgsl or raster_ids.wgsl) is given its depth's complemented bits.
fn raster_pixel(t: Setup, x: f32, y: f32) {
    let e = pixel_edges(t, x, y);
    if !(inside(e.x, t.s1.xy, t.s2.xy) && inside(e.y, t.s2.xy, t.s0.xy) && inside(e.z, t.s0.xy, t.s1.xy)) {
        return;
    }
    // A blend of the corners' depths: in exact arithmetic never nearer than the nearest. The
    // edge values' rounding can take a long thin triangle's blend nearer by some 1e-5 (their
    // sum is not quite the area), poking it through nearer ground; held at the nearest corner
    // it cannot, and a block of cells is hidden exactly when its nearest corner is
    // (`block_hidden`).
    let z = max((e.x * t.s0.z + e.y * t.s1.z + e.z * t.s2.z) * t.inv, min(t.s0.z, min(t.s1.z, t.s2.z)));
    if !(z >= 0.0 && z < 1.0) {
        return;
    }
    keep(t, e, x, y, u32(y) * ras.size.x + u32(x), ~bitcast<u32>(abs(z)));
}

// The least and greatest x of triangle `t` between the lines y = `ya` and y = `yb` (screen
// pixels; empty, lo > hi, where it has no point there): of its corners between them and of its
// edges' crossings of them.
fn slab_span(t: Setup, ya: f32, yb: f32) -> vec2<f32> {
    let p = array<vec2<f32>, 3>(t.s0.xy, t.s1.xy, t.s2.xy);
    var span = vec2<f32>(3.0e38, -3.0e38);
    for (var k = 0u; k < 3u; k++) {
        let a = p[k];
        let b = p[(k + 1u) % 3u];
        if a.y >= ya && a.y <= yb {
            span = vec2<f32>(min(span.x, a.x), max(span.y, a.x));
        }
        for (var j = 0u; j < 2u; j++) {
            let yc = select(ya, yb, j == 1u);
            if (a.y - yc) * (b.y - yc) < 0.0 {
                let x = a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x);
                span = vec2<f32>(min(span.x, x), max(span.y, x));
            }
        }
    }
    return span;
}

// Lists the tiles of big triangle `t` (entry `i` of `big`) that it can cover for `raster_big`:
// a row of tiles at a time, the tiles under the triangle's span across the row's pixel
// centres, grown by half a pixel (so no rounding of the span loses a covered pixel; a long
// thin triangle, a blade of grass near the eye, touches few of its bounding box's tiles).
// False where the list ran out of room (the caller then draws the triangle itself).
fn list_tiles(t: Setup, i: u32) -> bool {
    let size = vec2<u32>(t.hi - t.lo + 1.0);
    let across = (size.x + BIG_TILE - 1u) / BIG_TILE;
    let down = (size.y + BIG_TILE - 1u) / BIG_TILE;
    let room = arrayLength(&big_tiles);
    let tile = f32(BIG_TILE);
    var complete = true;
    for (var ty = 0u; ty < down; ty++) {
        let y0 = t.lo.y + f32(ty) * tile;
        let y1 = min(y0 + tile - 1.0, t.hi.y);
        // Pixel centres y + 0.5 for the rows y0..y1, grown by half a pixel.
        let span = slab_span(t, y0, y1 + 1.0);
        if span.x > span.y {
            continue;
        }
        // Pixels x whose centre, grown by half a pixel, meets the span.
        let first = u32(clamp(floor((span.x - 1.0 - t.lo.x) / tile), 0.0, f32(across - 1u)));
        let last = u32(clamp(floor((span.y - t.lo.x) / tile), 0.0, f32(across - 1u)));
        let count = last - first + 1u;
        let at = atomicAdd(&big_count[2u + ras.mode], count);
        let listed = min(count, room - min(at, room));
        for (var k = 0u; k < listed; k++) {
            big_tiles[at + k] = vec2<u32>(i, ty * across + first + k);
        }
        atomicMax(&big_args[3u * ras.mode], min(at + listed, BIG_GROUPS));
        complete = complete && listed == count;
    }
    return complete;
}

fn raster_triangle(v0: RasterVertex, v1: RasterVertex, v2: RasterVertex, id: u32) {
    let t = setup_triangle(v0, v1, v2, id);
    if !t.valid {
        return;
    }
    let extent = t.hi - t.lo + 1.0;
    if extent.x * extent.y > BIG_PIXELS {
        // Listed with its tiles for `raster_big`, which sets it up again from the same
        // vertices. Where a list is full it is drawn here too (drawing a pixel twice keeps the
        // same depth and stores the same attributes).
        let i = atomicAdd(&big_count[ras.mode], 1u);
        if i < arrayLength(&big) {
            big[i] = BigTriangle(to_big(v0), to_big(v1), to_big(v2), id);
            if list_tiles(t, i) {
                return;
            }
        }
    }
    for (var y = t.lo.y; y <= t.hi.y; y += 1.0) {
        for (var x = t.lo.x; x <= t.hi.x; x += 1.0) {
            raster_pixel(t, x, y);
        }
    }
}

// The point where the edge from `a` (in front of the near plane) to `b` (behind it) meets it:
// computed from the point in front, so two triangles sharing the edge find the same point.
fn near_crossing(a: RasterVertex, b: RasterVertex) -> RasterVertex {
    return mix_vertex(a, b, a.clip.z / (a.clip.z - b.clip.z));
}

// A triangle cut to the near plane (clip z >= 0, where w > 0): `n` points of `poly`, 0 (none
// in front), 3 (the triangle, whole or cut) or 4 (a quadrilateral, drawn as the triangles
// (0, 1, 2) and (0, 2, 3)).
struct Clipped {
    poly: array<RasterVertex, 4>,
    n: u32,
}

fn clip_near(c0: RasterVertex, c1: RasterVertex, c2: RasterVertex) -> Clipped {
    let v = array<RasterVertex, 3>(c0, c1, c2);
    var out: Clipped;
    var front = 0u;
    for (var i = 0u; i < 3u; i++) {
        front += u32(v[i].clip.z >= 0.0);
    }
    if front == 3u {
        out.poly[0] = c0;
        out.poly[1] = c1;
        out.poly[2] = c2;
        out.n = 3u;
        return out;
    }
    out.n = 0u;
    if front == 0u {
        return out;
    }
    for (var i = 0u; i < 3u; i++) {
        let a = v[i];
        let b = v[(i + 1u) % 3u];
        let a_in = a.clip.z >= 0.0;
        if a_in {
            out.poly[out.n] = a;
            out.n += 1u;
        }
        if a_in != (b.clip.z >= 0.0) {
            if a_in {
                out.poly[out.n] = near_crossing(a, b);
            } else {
                out.poly[out.n] = near_crossing(b, a);
            }
            out.n += 1u;
        }
    }
    return out;
}

// The triangle with id `id` (its last bit clear) cut to the near plane and drawn.
fn raster_clipped(c0: RasterVertex, c1: RasterVertex, c2: RasterVertex, id: u32) {
    let c = clip_near(c0, c1, c2);
    if c.n >= 3u {
        raster_triangle(c.poly[0], c.poly[1], c.poly[2], id);
    }
    if c.n == 4u {
        raster_triangle(c.poly[0], c.poly[2], c.poly[3], id | 1u);
    }
}

// The side of the square block of cells a workgroup of `raster_cells` draws: its threads
// place the block's corners once each, into `corners`, where a thread a cell would place
// each corner four times (once for each cell that shares it).
const BLOCK: u32 = 8u;
var<workgroup> corners: array<RasterVertex, 81>;

// A workgroup's block of cells: its patch instance, the patch's side in cells, the first cell
// of the patch in `cell_of`'s numbering, and the block's first cell (column, row) in the
// patch; `valid` false past the last block.
struct Block {
    instance: u32,
    side: u32,
    first: u32,
    origin: vec2<u32>,
    valid: bool,
}

// The block of workgroup `group` (row by row over the dispatch): whole patches' blocks first.
fn block_of(group: u32) -> Block {
    var out: Block;
    out.valid = true;
    let whole_across = (ras.patch_cells + BLOCK - 1u) / BLOCK;
    let sub_across = (ras.sub_cells + BLOCK - 1u) / BLOCK;
    let whole_blocks = whole_across * whole_across;
    let sub_blocks = sub_across * sub_across;
    var g = group;
    var across = whole_across;
    if g < ras.whole * whole_blocks {
        out.instance = g / whole_blocks;
        out.side = ras.patch_cells;
        out.first = out.instance * ras.patch_cells * ras.patch_cells;
        g = g % whole_blocks;
    } else {
        g -= ras.whole * whole_blocks;
        if sub_blocks == 0u || g >= ras.subs * sub_blocks {
            out.valid = false;
            return out;
        }
        let sub = g / sub_blocks;
        out.instance = ras.whole + sub;
        out.side = ras.sub_cells;
        out.first = ras.whole * ras.patch_cells * ras.patch_cells + sub * ras.sub_cells * ras.sub_cells;
        g = g % sub_blocks;
        across = sub_across;
    }
    out.origin = vec2<u32>(g % across, g / across) * BLOCK;
    return out;
}

// The side of the tiles of pixels `hiz` keeps a depth for, and the most tiles a block's
// pixels may span to be tested (a block nearer the eye is drawn untested).
const HIZ_TILE: u32 = 8u;
const HIZ_MOST_TILES: u32 = 16u;
// Whether the workgroup's block is skipped (`block_hidden`, by its first thread).
var<workgroup> hidden: u32;
// Its corners' bounds on screen, gathered by the threads that place them (`bound_corner`):
// the least x and y, the greatest x and y, the least depth, and 1 where one is behind the
// near plane. Each kept by an atomic maximum of a code that orders as the value does
// (`ordered`), complemented for the least: workgroup memory starts at 0, less than any.
var<workgroup> block_bounds: array<atomic<u32>, 6>;

// A float's bits as a u32 that orders as the float does.
fn ordered(f: f32) -> u32 {
    let bits = bitcast<u32>(f);
    return select(bits | 0x80000000u, ~bits, (bits >> 31u) == 1u);
}

fn unordered(o: u32) -> f32 {
    return bitcast<f32>(select(~o, o & 0x7fffffffu, (o >> 31u) == 1u));
}

// Gathers a corner of the workgroup's block (its clip position) into `block_bounds`.
fn bound_corner(c: vec4<f32>) {
    let s = to_screen(c);
    // Behind the near plane (cut there), or not a finite point on screen: the block is drawn.
    if !(c.z >= 0.0 && c.w > 0.0 && abs(s.x) < 1.0e30 && abs(s.y) < 1.0e30) {
        atomicMax(&block_bounds[5], 1u);
        return;
    }
    atomicMax(&block_bounds[0], ~ordered(s.x));
    atomicMax(&block_bounds[1], ~ordered(s.y));
    atomicMax(&block_bounds[2], ordered(s.x));
    atomicMax(&block_bounds[3], ordered(s.y));
    atomicMax(&block_bounds[4], ~ordered(s.z));
}

// Whether no triangle of the workgroup's block (its corners gathered in `block_bounds`) can be
// the nearest at any pixel: it covers no pixel centre, or each tile of pixels its corners'
// bounding box touches was drawn, all of it, strictly nearer than the nearest corner. A
// triangle's depth at a pixel is a blend of its corners' held at the nearest (`raster_pixel`),
// so none is nearer than the nearest corner (the margin of a millionth is to spare). A block
// with a corner behind the near plane (cut there) or over HIZ_MOST_TILES tiles is drawn.
fn block_hidden() -> bool {
    if atomicLoad(&block_bounds[5]) != 0u {
        return false;
    }
    let lo = vec2<f32>(unordered(~atomicLoad(&block_bounds[0])), unordered(~atomicLoad(&block_bounds[1])));
    let hi = vec2<f32>(unordered(atomicLoad(&block_bounds[2])), unordered(atomicLoad(&block_bounds[3])));
    let nearest = unordered(~atomicLoad(&block_bounds[4]));
    // The pixel centres of the bounding box, as `setup_triangle` finds them.
    let first = max(ceil(lo - 0.5), vec2<f32>(0.0));
    let last = min(floor(hi - 0.5), vec2<f32>(ras.size) - 1.0);
    if first.x > last.x || first.y > last.y {
        return true;
    }
    let t0 = vec2<u32>(first) / HIZ_TILE;
    let t1 = vec2<u32>(last) / HIZ_TILE;
    let tiles = t1 - t0 + 1u;
    if tiles.x * tiles.y > HIZ_MOST_TILES {
        return false;
    }
    let across = (ras.size.x + HIZ_TILE - 1u) / HIZ_TILE;
    let bound = nearest - abs(nearest) * 1.0e-6;
    for (var y = t0.y; y <= t1.y; y++) {
        for (var x = t0.x; x <= t1.x; x++) {
            let bits = hiz[y * across + x];
            if bits == 0u || !(bitcast<f32>(~bits) < bound) {
                return false;
            }
        }
    }
    return true;
}

// `hiz` from the depth drawn so far, a thread a tile: the farthest of its pixels (the least of
// their complemented bits; 0 where one has none). `drawn_bits` is raster_depth.wgsl's or
// raster_ids.wgsl's.
@compute @workgroup_size(8, 8)
fn raster_hiz(@builtin(global_invocation_id) id: vec3<u32>) {
    let across = (ras.size.x + HIZ_TILE - 1u) / HIZ_TILE;
    let down = (ras.size.y + HIZ_TILE - 1u) / HIZ_TILE;
    if id.x >= across || id.y >= down {
        return;
    }
    let origin = id.xy * HIZ_TILE;
    let end = min(origin + HIZ_TILE, ras.size);
    var farthest = 0xffffffffu;
    for (var y = origin.y; y < end.y; y++) {
        for (var x = origin.x; x < end.x; x++) {
            farthest = min(farthest, drawn_bits(y * ras.size.x + x));
        }
    }
    hiz[id.y * across + id.x] = farthest;
}

// A workgroup a block of BLOCK x BLOCK cells, a thread a cell: the block's corners placed once
// into `corners`, then each thread's two triangles, split as the index buffer splits its cell
// (world.rs `patch_indices`): (a, b, d) and (a, d, c), a the cell's first corner, b the next
// in its row, c and d the row after. A triangle's id is the cell's number in `cell_of`'s
// order times 4, plus 2 for the second (`Setup`).
@compute @workgroup_size(64)
fn raster_cells(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let number = ras.first_group + group.y * ras.row_groups + group.x;
    let b = block_of(number);
    if !b.valid || number >= ras.end_group {
        return;
    }
    let p = patches[b.instance];
    let row = ras.patch_cells + 1u;
    for (var k = lane; k < (BLOCK + 1u) * (BLOCK + 1u); k += BLOCK * BLOCK) {
        // Corners past the patch's last (a block over its edge) are never drawn: the last one
        // stands in.
        let v = min(b.origin + vec2<u32>(k % (BLOCK + 1u), k / (BLOCK + 1u)), vec2<u32>(b.side));
        let corner = raster_vertex(v.y * row + v.x, p);
        corners[k] = corner;
        if ras.cull != 0u {
            bound_corner(corner.clip);
        }
    }
    workgroupBarrier();
    if ras.cull != 0u {
        if lane == 0u {
            hidden = u32(block_hidden());
        }
        if workgroupUniformLoad(&hidden) != 0u {
            return;
        }
    }
    let local = vec2<u32>(lane % BLOCK, lane / BLOCK);
    let cell = b.origin + local;
    if cell.x >= b.side || cell.y >= b.side {
        return;
    }
    let a = local.y * (BLOCK + 1u) + local.x;
    let c = a + BLOCK + 1u;
    let id = (b.first + cell.y * b.side + cell.x) * 4u;
    raster_clipped(corners[a], corners[a + 1u], corners[c + 1u], id);
    raster_clipped(corners[a], corners[c + 1u], corners[c], id + 2u);
}

// The tiles of the triangles `raster_cells` listed as big, a workgroup each (strided over the
// dispatch), its threads sharing the tile's BIG_TILE x BIG_TILE pixels: the same setup and
// the same pixels as one thread would draw, so the same bits.
@compute @workgroup_size(64)
fn raster_big(
    @builtin(workgroup_id) group: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) lane: u32,
) {
    let count = min(atomicLoad(&big_count[2u + ras.mode]), arrayLength(&big_tiles));
    for (var e = group.x; e < count; e += groups.x) {
        let entry = big_tiles[e];
        let b = big[entry.x];
        let t = setup_triangle(from_big(b.v0), from_big(b.v1), from_big(b.v2), b.id);
        let size = vec2<u32>(t.hi - t.lo + 1.0);
        let across = (size.x + BIG_TILE - 1u) / BIG_TILE;
        let origin = vec2<u32>(entry.y % across, entry.y / across) * BIG_TILE;
        for (var k = lane; k < BIG_TILE * BIG_TILE; k += BIG_GROUP) {
            let at = origin + vec2<u32>(k % BIG_TILE, k / BIG_TILE);
            if at.x < size.x && at.y < size.y {
                raster_pixel(t, t.lo.x + f32(at.x), t.lo.y + f32(at.y));
            }
        }
    }
}
