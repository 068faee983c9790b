// import: raster, raster_blades
// The compute raster's depth with each pixel's triangle (raster.wgsl; src/gpu/raster.rs), for
// devices with a 64-bit atomic maximum (wgpu's SHADER_INT64_ATOMIC_MIN_MAX): per pixel, row by
// row, the nearest depth's complemented bits above the id of its triangle (`Setup`), 0 where
// nothing is drawn. Stored little-endian: read as two words, the depth's is the second.

@group(1) @binding(2) var<storage, read_write> raster_depth: array<atomic<u64>>;
// The same buffer read by `raster_resolve` and `raster_hiz` (bound to them alone, after the
// raster).
@group(1) @binding(9) var<storage, read> raster_ids: array<vec2<u32>>;

// Pixel (x, y), at index `at`, covered by triangle `t` with depth bits `bits`: nearest first,
// and of equal depths the greater id.
fn keep(t: Setup, e: vec3<f32>, x: f32, y: f32, at: u32, bits: u32) {
    atomicMax(&raster_depth[at], (u64(bits) << 32u) | u64(t.id));
}

// A cell of the mesh: its patch instance and its first corner in the patch's vertex numbering;
// `valid` false past the last cell.
struct Cell {
    instance: u32,
    corner: u32,
    valid: bool,
}

// The cell numbered `number`: whole patches' cells first, each patch's row by row.
fn cell_of(number: u32) -> Cell {
    var c = number;
    let whole_cells = ras.patch_cells * ras.patch_cells;
    let sub_cells = ras.sub_cells * ras.sub_cells;
    var out: Cell;
    out.valid = true;
    var side = ras.patch_cells;
    if c < ras.whole * whole_cells {
        out.instance = c / whole_cells;
        c = c % whole_cells;
    } else {
        c -= ras.whole * whole_cells;
        if sub_cells == 0u || c >= ras.subs * sub_cells {
            out.valid = false;
            return out;
        }
        out.instance = ras.whole + c / sub_cells;
        c = c % sub_cells;
        side = ras.sub_cells;
    }
    out.corner = (c / side) * (ras.patch_cells + 1u) + c % side;
    return out;
}

// The nearest depth's complemented bits drawn at index `at` so far (0: none).
fn drawn_bits(at: u32) -> u32 {
    return raster_ids[at].y;
}

// Each drawn pixel's attributes, a thread a pixel: its triangle set up again from the id (the
// same functions of the same cell and corners as `raster_cells`: its cut and setup agree but for
// rounding, which only interpolation sees), interpolated at its centre.
@compute @workgroup_size(8, 8)
fn raster_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= ras.size.x || id.y >= ras.size.y {
        return;
    }
    let kept = raster_ids[id.y * ras.size.x + id.x];
    if kept.y == 0u {
        return;
    }
    // Each layer sets up its own primitives; the terrain's are its triangles.
    if (kept.x >> LAYER_SHIFT) != LAYER_TERRAIN {
        return;
    }
    let triangle = kept.x & PRIMITIVE_MASK;
    let cell = cell_of(triangle >> 2u);
    if !cell.valid {
        return;
    }
    let row = ras.patch_cells + 1u;
    let a = cell.corner;
    let p = patches[cell.instance];
    let va = raster_vertex(a, p);
    let vd = raster_vertex(a + row + 1u, p);
    var c: Clipped;
    if (triangle & 2u) == 0u {
        c = clip_near(va, raster_vertex(a + 1u, p), vd);
    } else {
        c = clip_near(va, vd, raster_vertex(a + row, p));
    }
    if c.n < 3u {
        return;
    }
    // The second half of a cut, unless this pipeline's rounding cut the triangle into one
    // (a vertex within rounding of the near plane): then the one, so the pixel is stored.
    let second = (triangle & 1u) == 1u && c.n == 4u;
    var t: Setup;
    if second {
        t = setup_triangle(c.poly[0], c.poly[2], c.poly[3], triangle);
    } else {
        t = setup_triangle(c.poly[0], c.poly[1], c.poly[2], triangle);
    }
    let x = f32(id.x);
    let y = f32(id.y);
    store_attributes(t, pixel_edges(t, x, y), x, y);
}
