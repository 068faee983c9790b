// import: raster
// The compute raster's depth on any device (raster.wgsl; src/gpu/raster.rs): per pixel, row by
// row, the nearest depth's complemented bits, 0 where nothing is drawn. The endless world's
// attributes come from a second dispatch (`mode` 1) that stores them where a triangle's depth
// is the pixel's nearest, bit for bit.

@group(1) @binding(2) var<storage, read_write> raster_depth: array<atomic<u32>>;

// Pixel (x, y), at index `at`, covered by triangle `t` with edge values `e` and depth bits
// `bits`.
fn keep(t: Setup, e: vec3<f32>, x: f32, y: f32, at: u32, bits: u32) {
    if ras.mode == 0u {
        atomicMax(&raster_depth[at], bits);
    } else if atomicLoad(&raster_depth[at]) == bits {
        store_attributes(t, e, x, y);
    }
}

// The nearest depth's complemented bits drawn at index `at` so far (0: none).
fn drawn_bits(at: u32) -> u32 {
    return atomicLoad(&raster_depth[at]);
}
