// import: world, vis_common, composite, grass_blade, props_look
// with: terrain_air_map
// The visibility method (src/gpu/visibility.rs): the raster pass (world.wgsl's `vs_samples`
// and `fs_attributes`, or depth alone for the tile) leaves each MSAA sample's depth and, for the
// endless world, its surface attributes; this compute pass shades every sample with the
// shading every method shares (shade.wgsl) and averages the samples of a pixel in linear light;
// a full-screen pass composites the result, colour and depth, into the host's render pass.
// Composed after shade.wgsl, level_texel.wgsl, world.wgsl (their uniforms and the tile's
// texture reads) and vis_common.wgsl (its own uniforms and images).

// Where the props' march (props_march.wgsl) left each pixel's prop: its depth, normal, look
// and the sun's share, or the props' occlusion and shadow on what the raster drew
// (props_look.wgsl).
@group(0) @binding(22) var prop_hit: texture_2d<u32>;

fn props_at(px: vec2<i32>) -> vec4<u32> {
    if vis.props == 0u {
        return no_prop();
    }
    return textureLoad(prop_hit, px, 0);
}

// The colour (linear, tone-mapped) of one sample at `pixel` (pixels from the top left) whose
// depth is `d` (1: no terrain, the sky), with the endless world's attributes `s` and `valley`,
// the sun's and the sky's shares multiplied by `props` (the props' shadow and occlusion).
fn shade_sample(lin: RenderUniforms, pixel: vec2<f32>, d: f32, s: vec4<f32>, valley: f32, props: vec2<f32>) -> vec3<f32> {
    let dir = sample_ray(pixel);
    if d >= 1.0 {
        return sky_pixel(lin, dir);
    }
    let rel = point_at(dir, d);
    if vis.world != 0u {
        let h = (rel.y + w.eye.y) / w.peak;
        let n = normalize(vec3<f32>(-s.x, 1.0, -s.y));
        return shade(lin, rel, n, h, s.z, occlusion(lin, h, s.w, valley) * props * props_map_at(rel));
    }
    let uv = (rel.xz + w.tile_eye) * w.tile_inv + r.shift;
    let n = normalize(textureSampleLevel(tile_normals, tile_sampler, uv, 0.0).xyz);
    let t = tile_terrain_at(uv);
    return shade(lin, rel, n, t.x, t.y, unshadowed(lin, t.x));
}

@compute @workgroup_size(8, 8)
fn shade_samples(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    let lin = linear_uniforms();
    var sum = vec3<f32>(0.0);
    var covered = 0u;
    var nearest = 1.0;
    for (var i = 0; i < 4; i++) {
        let d = textureLoad(depth_ms, px, i);
        if d < 1.0 {
            covered += 1u;
            nearest = min(nearest, d);
        } else if vis.sky == 0u {
            continue;
        }
        let s = textureLoad(surface_ms, px, i);
        let valley = textureLoad(valley_ms, px, i).x;
        sum += shade_sample(lin, vec2<f32>(id.xy) + SAMPLES[i], d, s, valley, vec2<f32>(1.0));
    }
    store_pixel(px, sum, 4u, covered, nearest);
}

// A blade's shade and the sun's and sky's occlusion, as raster_blades.wgsl packs them into
// the valley's place.
fn blade_look(packed: f32) -> vec3<f32> {
    let q = u32(packed);
    return vec3<f32>(vec3<u32>(q >> 16u, (q >> 8u) & 255u, q & 255u)) / 255.0;
}

// Shades and stores the pixel `px` whose one sample has depth `d`, kept by the layer `layer`
// (`rasterised_layer`: 0 the terrain, 1 a blade of grass), or the prop the march found nearer.
fn shade_pixel(px: vec2<i32>, d: f32, layer: u32) {
    let pixel = vec2<f32>(px) + 0.5;
    let prop = props_at(px);
    let prop_depth = bitcast<f32>(prop.x);
    if prop_depth < d {
        let color = prop_color(linear_uniforms(), point_at(sample_ray(pixel), prop_depth), prop);
        store_pixel(px, color, 1u, 1u, prop_depth);
        return;
    }
    let sun = bitcast<f32>(prop.w);
    let sky = bitcast<f32>(prop.y);
    let covered = u32(d < 1.0);
    var color = vec3<f32>(0.0);
    if covered != 0u || vis.sky != 0u {
        let s = textureLoad(surface_1, px, 0);
        let valley = textureLoad(valley_1, px, 0).x;
        if layer == 1u && covered != 0u {
            let lin = linear_uniforms();
            let look = blade_look(valley) * vec3<f32>(1.0, sun, sky);
            color = blade_light(lin, point_at(sample_ray(pixel), d), s.xyz, s.w, look);
        } else {
            color = shade_sample(linear_uniforms(), pixel, d, s, valley, vec2<f32>(sun, sky));
        }
    }
    store_pixel(px, color, 1u, covered, d);
}

@compute @workgroup_size(8, 8)
fn shade_pixels(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let px = vec2<i32>(id.xy);
    shade_pixel(px, textureLoad(depth_1, px, 0), 0u);
}

@compute @workgroup_size(8, 8)
fn shade_rasterised(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    shade_pixel(vec2<i32>(id.xy), rasterised_depth(id.xy), rasterised_layer(id.xy));
}

// The composite (composite.wgsl) encodes where the host's target is not sRGB.
fn composite_encodes() -> bool {
    return vis.encode_srgb != 0u;
}

// The frame written without a render pass (Visibility::present), for an opaque image (the sky
// fills what no terrain covers): each pixel's colour sRGB-encoded to 8 bits a channel, packed
// in the byte order of the target's format, into rows of `presented` padded to 256 bytes (64
// pixels), which a copy then puts in the target. On a compute chip a full-screen draw costs
// what the whole shading pass does several times over (docs/bench/present in git history, up
// to a57006a).
@group(0) @binding(20) var<storage, read_write> presented: array<u32>;

fn present_pixel(id: vec2<u32>, bgra: bool) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let c = srgb_encode(clamp(textureLoad(shown, vec2<i32>(id), 0).rgb, vec3<f32>(0.0), vec3<f32>(1.0)));
    let ordered = select(c, c.bgr, bgra);
    let pitch = (vis.size.x + 63u) & ~63u;
    presented[id.y * pitch + id.x] = pack_unorm8(ordered);
}

// Straight into a target that takes storage writes (an RGBA8 texture, not sRGB, with
// STORAGE_BINDING: `relief render`'s offscreen image), with no buffer and no copy: the
// encoded colour a quarter step over its byte (`unorm8_exact`), so the store writes the bytes
// the packed frame holds (docs/bench/store-present in git history, up to a57006a).
@group(0) @binding(21) var presented_image: texture_storage_2d<rgba8unorm, write>;

@compute @workgroup_size(8, 8)
fn present_store(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= vis.size.x || id.y >= vis.size.y {
        return;
    }
    let c = srgb_encode(clamp(textureLoad(shown, vec2<i32>(id.xy), 0).rgb, vec3<f32>(0.0), vec3<f32>(1.0)));
    textureStore(presented_image, vec2<i32>(id.xy), vec4<f32>(unorm8_exact(c), 1.0));
}

// Into an RGBA8 target (sRGB or not: the bytes are the encoded values either way).
@compute @workgroup_size(8, 8)
fn present_rgba(@builtin(global_invocation_id) id: vec3<u32>) {
    present_pixel(id.xy, false);
}

// Into a BGRA8 target (a window's surface, often).
@compute @workgroup_size(8, 8)
fn present_bgra(@builtin(global_invocation_id) id: vec3<u32>) {
    present_pixel(id.xy, true);
}
