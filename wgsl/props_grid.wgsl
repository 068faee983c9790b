// import: props
// The frame's placed props (props_scatter.wgsl writes them, props_march.wgsl reads them): a
// record a cell of the grid around the eye, then one a prop put at a given place; the heights
// each cell's prop spans; the same for each dual cell (the 2x2 cells around a grid corner: the
// props a point in it can touch) and for each block of BLOCK x BLOCK dual cells.

// Four vectors a record: the prop's foot (camera-relative metres) and its scale (0: none);
// the cosine and sine of its turn, its kind and its noise's seed (bits); its shade, the
// terrain's horizon and valley at its foot (the light bake's) and the foot's normalised height;
// the centre (camera-relative) and radius of a sphere that holds it.
@group(1) @binding(4) var<storage, read_write> prop_grid: array<vec4<f32>>;
@group(1) @binding(5) var<storage, read_write> prop_cell_range: array<vec2<f32>>;
@group(1) @binding(6) var<storage, read_write> prop_dual_range: array<vec2<f32>>;
// Per block; then, past the last block, the heights every prop spans.
@group(1) @binding(7) var<storage, read_write> prop_block_range: array<vec2<f32>>;

const BLOCK: u32 = 8u;
// Vectors a record.
const RECORD: u32 = 4u;
// The range of a cell with no prop: empty.
const EMPTY_RANGE: vec2<f32> = vec2<f32>(3.0e38, -3.0e38);

fn union_range(a: vec2<f32>, b: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(min(a.x, b.x), max(a.y, b.y));
}

// The dual cells on a side of the grid (the corners of its cells) and the blocks of them.
fn dual_side() -> u32 {
    return pf.side + 1u;
}
