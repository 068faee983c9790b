// import: fullscreen
// Shows a ray-cast image in a window or on the page: one full-screen triangle whose fragments
// average their `ss` x `ss` block of the cast (sRGB-encoded rgba8unorm, as the ray casters
// store it) in linear light, and encode it again where the target is not an sRGB format.

struct BlitUniforms {
    ss: u32,
    encode_srgb: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> blit: BlitUniforms;
@group(0) @binding(1) var image: texture_2d<f32>;

fn blit_decode(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

fn blit_encode(c: vec3<f32>) -> vec3<f32> {
    let lo = c * 12.92;
    let hi = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(hi, lo, c <= vec3<f32>(0.0031308));
}

@vertex
fn blit_vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_xy(i), 0.0, 1.0);
}

@fragment
fn blit_fs(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let n = i32(blit.ss);
    let base = vec2<i32>(floor(position.xy)) * n;
    var sum = vec3<f32>(0.0);
    for (var j = 0; j < n; j++) {
        for (var i = 0; i < n; i++) {
            sum += blit_decode(textureLoad(image, base + vec2<i32>(i, j), 0).rgb);
        }
    }
    var color = sum / f32(n * n);
    if blit.encode_srgb != 0u {
        color = blit_encode(color);
    }
    return vec4<f32>(color, 1.0);
}
