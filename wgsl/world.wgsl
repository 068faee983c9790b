// import: shade, level_texel, props_map
// with: terrain_air_map
// The endless world's render pass: the clipmap's patches (src/clipmap.rs) drawn as instances
// of one indexed (patch+1)^2 grid, displaced by the levels' baked heights, in camera-relative
// coordinates; shaded per pixel from the baked gradient by shade.wgsl (composed before this).
//
// Positions are exact where levels meet: a vertex's offset from the camera's reference sample
// is an integer count of finest-level samples (small: levels are camera-centred), times the
// finest spacing (a power of two), less the eye's offset from that sample. At a level's outer
// edge the morph is complete (alpha = 1): odd vertices sit on their even neighbours and take
// the coarser level's texels, so both levels produce the same vertices, bit for bit.
// The morph grows with the distance from the eye (not from the level's snapped square), so the
// geometry changes continuously as the camera moves and a level's snap does not pop.

struct Level {
    // Level origin, in finest samples, relative to the camera's reference sample.
    origin_rel: vec2<i32>,
    // This level's origin less twice the coarser level's, in this level's samples (even).
    delta: vec2<i32>,
    // Level origin modulo the texture side: the texel of the level's first sample.
    origin_mod: vec2<u32>,
    // log2 of this level's spacing over the finest level's.
    shift: u32,
    layer: u32,
    // Index of the coarser level, and whether there is one to morph towards.
    coarse: u32,
    has_coarse: u32,
    // The eye in this level's samples, from its first sample.
    eye_local: vec2<f32>,
    // The drawn bounds in this level's samples, from its first sample (x0, z0, x1, z1): vertices
    // are clamped into them (the tile's square; huge for the endless world).
    clip: vec4<f32>,
    // Metres the level's vertices are raised by: 0, or for the hybrid method a bound on how far
    // the continuous surface rises above the level's mesh, so the mesh lies on or above it.
    raise: f32,
    // The level whose light this one is drawn with: itself once its light is baked, before
    // that a coarser level's, or NO_LIGHT (unshadowed) while none has light
    // (src/gpu/light_queue.rs).
    light_from: u32,
    _pad1: u32,
    _pad2: u32,
}

const NO_LIGHT: u32 = 0xffffffffu;

struct WorldUniforms {
    // xz: eye position less the reference sample's, in metres; y: eye height; w: finest spacing.
    eye: vec4<f32>,
    // Cells per level side, cells per patch side, texture side.
    cells: u32,
    patch_cells: u32,
    side: u32,
    // 1 while morphing is on.
    morphing: u32,
    // Morph band: from and to this Chebyshev distance from the eye, in a level's cells.
    morph: vec2<f32>,
    // World height of normalised height 1.
    peak: f32,
    // How far the first active level is morphed as a whole (it reaches 1 where the eye is high
    // enough to drop it), and that level's index.
    fade: f32,
    first: u32,
    // The tile's: one over the tile's width (0: the endless world, which has no tile
    // textures), and the eye less the tile's first corner (metres, x and z).
    tile_inv: f32,
    tile_eye: vec2<f32>,
    levels: array<Level, 24>,
}

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(1) var<uniform> w: WorldUniforms;
// Per level texel: (height, dh/dx, dh/dz, colour) packed in 64 bits (level_texel.wgsl).
@group(0) @binding(2) var level_tex: texture_2d_array<u32>;
// Per level texel: the terrain's horizon towards the sun (radians) and the valley depth
// (metres), from the light bake (world_light.wgsl).
// Horizon elevation and valley depth, two 16-bit floats packed (src/gpu/world_light.rs).
@group(0) @binding(3) var light_tex: texture_2d_array<u32>;
// The tile's own textures (rg32float height and colour channel, rgba16float normals), read per
// pixel as the tile always shaded: its `size` and `normals` keys shade the mesh.
@group(0) @binding(4) var tile_terrain: texture_2d<f32>;
@group(0) @binding(5) var tile_normals: texture_2d<f32>;
@group(0) @binding(6) var tile_sampler: sampler;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    // Camera-relative position (the camera sits at the origin).
    @location(0) rel: vec3<f32>,
    // The vertex's sample (height, dh/dx, dh/dz, colour), morphed as its position is. Vertices
    // sit on the level's texels, so interpolating this across the triangle carries the same
    // information as reading the texture per pixel (piecewise linear instead of bilinear within
    // a cell) at a fraction of the cost: the fragment shader reads no texture.
    @location(1) sample: vec4<f32>,
    // The light bake's (horizon, valley), interpolated the same way: the horizon is continuous
    // over the ground, so the shadow's edge falls between vertices where it should.
    @location(2) light: vec2<f32>,
}

// The level's texel `ij` (clamped to the level), of the heights (light false) or the light.
fn texel(lv: Level, ij: vec2<i32>, light: bool) -> vec4<f32> {
    let c = clamp(ij, vec2<i32>(0), vec2<i32>(i32(w.cells)));
    let t = vec2<i32>((lv.origin_mod + vec2<u32>(c)) % vec2<u32>(w.side));
    if light {
        let packed = textureLoad(light_tex, t, i32(lv.layer), 0).x;
        return vec4<f32>(unpack2x16float(packed), 0.0, 0.0);
    }
    let spacing = w.eye.w * f32(1u << lv.shift);
    return unpack_level_texel(textureLoad(level_tex, t, i32(lv.layer), 0).xy, spacing);
}

// Bilinear by hand (32-bit float textures are not filterable in core WebGPU). At integer
// positions the weights are exactly 0, so the texel itself comes back unchanged.
fn sample_level(lv: Level, p: vec2<f32>, light: bool) -> vec4<f32> {
    let p0 = floor(p);
    let t = p - p0;
    let i = vec2<i32>(p0);
    let a = texel(lv, i, light);
    let b = texel(lv, i + vec2<i32>(1, 0), light);
    let c = texel(lv, i + vec2<i32>(0, 1), light);
    let d = texel(lv, i + vec2<i32>(1, 1), light);
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

// The light level `lv` borrows at `p` (its samples from its first) while its own is not baked
// (`lv.light_from` is not its index): that of a coarser level's texel nearest the same world
// point, or unshadowed while no level has light.
fn borrowed_light(lv: Level, p: vec2<f32>) -> vec2<f32> {
    if lv.light_from == NO_LIGHT {
        return vec2<f32>(-2.0, 0.0);
    }
    // The nearest texel: a stand-in for a frame or a few, kept small so that the frame's
    // shader barely grows for it.
    let lender = w.levels[lv.light_from];
    let finest = vec2<f32>(lv.origin_rel - lender.origin_rel) + p * f32(1u << lv.shift);
    let q = vec2<i32>(round(finest / f32(1u << lender.shift)));
    return texel(lender, q, true).xy;
}

// Blend towards the coarser level, exact at both ends.
fn morph_blend(fine: vec4<f32>, coarse: vec4<f32>, alpha: f32) -> vec4<f32> {
    if alpha <= 0.0 {
        return fine;
    }
    if alpha >= 1.0 {
        return coarse;
    }
    return mix(fine, coarse, alpha);
}

@vertex
fn vs_main(
    @builtin(vertex_index) vi: u32,
    @location(0) patch_instance: vec4<u32>,
) -> VertexOut {
    return place(vi, patch_instance);
}

// The vertex `vi` of the patch instance: where it lies and what it carries.
fn place(vi: u32, patch_instance: vec4<u32>) -> VertexOut {
    let level = patch_instance.x;
    let lv = w.levels[level];
    let row = w.patch_cells + 1u;
    // A sub-patch (the tile's edge) starts `w` cells into its patch: column low, row high.
    let sub = vec2<u32>(patch_instance.w & 0xffffu, patch_instance.w >> 16u);
    let local = patch_instance.yz * w.patch_cells + sub + vec2<u32>(vi % row, vi / row);
    // The morph towards the coarser level grows with the (Chebyshev) distance from the eye:
    // 0 at the hole's edge, exactly 1 at the level's outer edge, continuous as the eye moves.
    var alpha = 0.0;
    if lv.has_coarse != 0u && w.morphing != 0u {
        let d = abs(vec2<f32>(local) - lv.eye_local);
        alpha = clamp((max(d.x, d.y) - w.morph.x) / (w.morph.y - w.morph.x), 0.0, 1.0);
        if level == w.first {
            alpha = max(alpha, w.fade);
        }
    }
    let odd = vec2<f32>(local & vec2<u32>(1u));
    let p = clamp(vec2<f32>(local) - alpha * odd, lv.clip.xy, lv.clip.zw);
    let clv = w.levels[lv.coarse];
    let q = (vec2<f32>(lv.delta) + p) * 0.5;
    var s = sample_level(lv, p, false);
    // The level's own light, read beside its heights (the same texels); a level still
    // without it borrows a coarser level's (src/gpu/light_queue.rs), a branch the whole
    // patch takes alike.
    var light = sample_level(lv, p, true).xy;
    if lv.light_from != level {
        light = borrowed_light(lv, p);
    }
    var raise = lv.raise;
    if alpha > 0.0 {
        s = morph_blend(s, sample_level(clv, q, false), alpha);
        var coarse_light = sample_level(clv, q, true);
        if clv.light_from != lv.coarse {
            coarse_light = vec4<f32>(borrowed_light(clv, q), 0.0, 0.0);
        }
        light = morph_blend(vec4<f32>(light, 0.0, 0.0), coarse_light, alpha).xy;
        // Both levels' raised surfaces lie on or above the continuous one: so does their blend.
        raise = mix(lv.raise, clv.raise, alpha);
    }
    let scale = f32(1u << lv.shift);
    let xz = (vec2<f32>(lv.origin_rel) + p * scale) * w.eye.w - w.eye.xz;
    let rel = vec3<f32>(xz.x, s.x * w.peak + raise - w.eye.y, xz.y);
    var out: VertexOut;
    out.clip = r.view_proj * vec4<f32>(rel, 1.0);
    out.rel = rel;
    out.sample = s;
    out.light = light;
    return out;
}

fn wrap_texel(i: i32, n: i32) -> i32 {
    return ((i % n) + n) % n;
}

// Bilinear, wrap-around read of the tile's rg32float texture by hand (32-bit floats are not
// filterable in core WebGPU). Texel centres sit at (i + 0.5) / size, as the tile's bake writes.
fn tile_terrain_at(uv: vec2<f32>) -> vec2<f32> {
    let n = i32(r.tex_size);
    let s = uv * f32(n) - 0.5;
    let s0 = floor(s);
    let t = s - s0;
    let x0 = wrap_texel(i32(s0.x), n);
    let y0 = wrap_texel(i32(s0.y), n);
    let x1 = wrap_texel(x0 + 1, n);
    let y1 = wrap_texel(y0 + 1, n);
    let a = textureLoad(tile_terrain, vec2<i32>(x0, y0), 0).rg;
    let b = textureLoad(tile_terrain, vec2<i32>(x1, y0), 0).rg;
    let c = textureLoad(tile_terrain, vec2<i32>(x0, y1), 0).rg;
    let d = textureLoad(tile_terrain, vec2<i32>(x1, y1), 0).rg;
    return mix(mix(a, b, t.x), mix(c, d, t.x), t.y);
}

// The tile's fragments: normals, height (snow, AO) and colour channel per pixel from its
// textures. An entry point of its own, not a branch in `fs_main`: lavapipe paid for the unused
// path on every fragment (the tile's frame took 1.5x as long).
@fragment
fn fs_tile(in: VertexOut) -> @location(0) vec4<f32> {
    let uv = (in.rel.xz + w.tile_eye) * w.tile_inv + r.shift;
    let n = normalize(textureSampleLevel(tile_normals, tile_sampler, uv, 0.0).xyz);
    let t = tile_terrain_at(uv);
    return vec4<f32>(shade(r, in.rel, n, t.x, t.y, unshadowed(r, t.x)), 1.0);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let s = in.sample;
    // Gradient per metre of normalised height, to a unit normal in metres.
    let n = normalize(vec3<f32>(-s.y * w.peak, 1.0, -s.z * w.peak));
    let occl = occlusion(r, s.x, in.light.x, in.light.y) * props_map_at(in.rel);
    return vec4<f32>(shade(r, in.rel, n, s.x, s.w, occl), 1.0);
}

// The visibility method's raster pass (src/gpu/visibility.rs): the same vertices, their
// attributes interpolated at every MSAA sample rather than once a pixel, so the compute pass
// that shades them (wgsl/visibility.wgsl) sees each sample's own surface.
struct SampleOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(perspective, sample) sample: vec4<f32>,
    @location(1) @interpolate(perspective, sample) light: vec2<f32>,
}

@vertex
fn vs_samples(
    @builtin(vertex_index) vi: u32,
    @location(0) patch_instance: vec4<u32>,
) -> SampleOut {
    let v = place(vi, patch_instance);
    var out: SampleOut;
    out.clip = v.clip;
    out.sample = v.sample;
    out.light = v.light;
    return out;
}

// What the endless world's shading needs beyond the position (which the depth gives): the
// slope (dh/dx, dh/dz in metres per metre), the colour channel and the horizon towards the
// sun; and in a second target the valley depth (metres).
struct Attributes {
    @location(0) surface: vec4<f32>,
    @location(1) valley: f32,
}

@fragment
fn fs_attributes(in: SampleOut) -> Attributes {
    var out: Attributes;
    out.surface = vec4<f32>(in.sample.yz * w.peak, in.sample.w, in.light.x);
    out.valley = in.light.y;
    return out;
}
