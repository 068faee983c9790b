// import: noise, shade, rays
// Ray casting of the continuous fBm surface: no texture, no mesh. Composed after noise.wgsl
// and shade.wgsl. Two methods, chosen by `ray.method`:
//
//   0, the reference: conservative steps that can never pass through the surface (the step
//      is the vertical clearance divided by a bound on how fast the clearance can shrink,
//      from the Lipschitz bound of the height), then bisection to the crossing; all octaves;
//      normals from the analytic gradient. The ground truth the other methods are measured by.
//   1, the seed's march (a ShaderToy-style heightfield marcher): t += step_factor * h, a hit
//      when |h| < hit_k * t, `march_octaves` octaves while stepping and `normal_octaves` for the
//      normal. Fast, and wrong in known ways (it can tunnel through thin ridges).
//
// Each runs as a compute shader writing storage textures, or as a full-screen fragment shader
// (the entry points are in rays.wgsl, composed after this file).

struct RayUniforms {
    inv_view_proj: mat4x4<f32>,
    seed: u32,
    frequency: u32,
    octaves: u32,
    method: u32,
    march_octaves: u32,
    normal_octaves: u32,
    max_steps: u32,
    width: u32,
    height: u32,
    gain: f32,
    // Bound on |grad h_world| of the full fBm, for the reference's conservative steps.
    lipschitz: f32,
    step_factor: f32,
    hit_k: f32,
    // The seed's relaxation: steps multiplied by max(relax * t, 1); 0: off.
    relax: f32,
    offset: vec2<f32>,
}

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(1) var<uniform> ray: RayUniforms;
@group(0) @binding(2) var color_out: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(3) var distance_out: texture_storage_2d<r32float, write>;

// (normalised height, d h_world / dx, d h_world / dz) of the first `octaves` octaves.
fn surface(xz: vec2<f32>, octaves: u32) -> vec3<f32> {
    let u = xz / WORLD_SIZE + 0.5;
    let g = fbm_grad(u, ray.frequency, octaves, ray.octaves, ray.gain, ray.offset, ray.seed, CHANNEL_HEIGHT);
    return vec3<f32>(g.x, g.yz * (r.height_scale / WORLD_SIZE));
}

// What the seed's march (rays.wgsl) steps against.
fn march_height(xz: vec2<f32>, octaves: u32) -> f32 {
    return r.height_scale * surface(xz, octaves).x;
}

// Entry and exit distances of the ray through the terrain's bounding box, or (1, 0) if none.
fn clip_box(ro: vec3<f32>, rd: vec3<f32>) -> vec2<f32> {
    let lo = vec3<f32>(-0.5 * WORLD_SIZE, 0.0, -0.5 * WORLD_SIZE);
    let hi = vec3<f32>(0.5 * WORLD_SIZE, r.height_scale + 1e-4, 0.5 * WORLD_SIZE);
    let inv = 1.0 / rd;
    let a = (lo - ro) * inv;
    let b = (hi - ro) * inv;
    let tmin = min(a, b);
    let tmax = max(a, b);
    let t0 = max(max(tmin.x, tmin.y), max(tmin.z, 0.0));
    let t1 = min(min(tmax.x, tmax.y), tmax.z);
    return vec2<f32>(t0, t1);
}

// Distance along the unit ray to the surface, MISS or UNRESOLVED.
fn intersect(ro: vec3<f32>, rd: vec3<f32>) -> f32 {
    let span = clip_box(ro, rd);
    if span.x > span.y {
        return MISS;
    }
    var t = span.x;
    if ray.method == 0u {
        // The surface is a sheet, as the mesh is: a ray that enters the box's side below it
        // (under the terrain) hits where it first crosses the sheet from below.
        let below = ro.y + t * rd.y - r.height_scale * surface((ro + t * rd).xz, ray.octaves).x < 0.0;
        // How fast the clearance f(t) = y - h(xz) can approach zero: above the sheet it falls
        // no faster than lipschitz * |rd.xz| - rd.y; below, it rises no faster than
        // lipschitz * |rd.xz| + |rd.y|.
        let slope = ray.lipschitz * length(rd.xz);
        let rate = select(max(slope - rd.y, 1e-6), slope + abs(rd.y), below);
        var t_prev = t;
        for (var i = 0u; i < ray.max_steps; i++) {
            let p = ro + t * rd;
            let f = p.y - r.height_scale * surface(p.xz, ray.octaves).x;
            if (f <= 0.0) != below {
                return bisect(ro, rd, t_prev, t, below);
            }
            if t > span.y {
                return MISS;
            }
            t_prev = t;
            // A floor on the step keeps grazing rays moving; it can only skip slivers thinner
            // than 1e-6 world units plus 1e-5 of the distance.
            t += max(abs(f) / rate, 1e-6 + 1e-5 * t);
        }
        return UNRESOLVED;
    }
    return seed_march(ro, rd, span);
}

// (colour, distance) for the pixel whose centre is at `pixel` (in pixels from the top left).
fn cast_pixel(pixel: vec2<f32>) -> vec4<f32> {
    let ro = r.camera_pos.xyz;
    let rd = normalize(pixel_far(pixel) - ro);
    let t = intersect(ro, rd);
    if t < 0.0 {
        return vec4<f32>(sky_pixel(r, rd), t);
    }
    let p = ro + t * rd;
    let normal_octaves = select(ray.octaves, ray.normal_octaves, ray.method == 1u);
    let g = surface(p.xz, normal_octaves);
    let n = normalize(vec3<f32>(-g.y, 1.0, -g.z));
    let h = surface(p.xz, ray.octaves).x;
    let u = p.xz / WORLD_SIZE + 0.5;
    let tint = fbm_grad(u, ray.frequency, ray.octaves, ray.octaves, ray.gain, ray.offset, ray.seed, CHANNEL_COLOR).x;
    return vec4<f32>(shade(r, p, n, h, tint, unshadowed(r, h)), t);
}
