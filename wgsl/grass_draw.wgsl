// import: shade
// The grass's draw (src/gpu/grass.rs): each blade the scatter kept (grass_scatter.wgsl) is
// one instance of a strip of nine vertices, four segments and a tip, built here from the
// blade's root, facing, height, lean, curve and width: a curved, two-sided blade with a normal
// at every vertex. Lit as a thin leaf: the sun through either side (|N.L|, warmer where it
// shines through from behind), the sky's light, a little sheen, darker toward the root, the
// terrain's shadow and occlusion at the root; then through the air as the terrain is.

@group(0) @binding(0) var<uniform> r: RenderUniforms;
@group(0) @binding(1) var<storage, read> blades: array<vec4<f32>>;

struct BladeOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) rel: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // Up the blade (0 at the root, 1 at the tip), its shade, the sun's and the sky's
    // occlusion.
    @location(2) along: f32,
    @location(3) @interpolate(flat) look: vec3<f32>,
}

// Lush and dry blades (linear albedos), the lighter towards the tips.
const BLADE_LUSH: vec3<f32> = vec3<f32>(0.07, 0.16, 0.03);
const BLADE_DRY: vec3<f32> = vec3<f32>(0.22, 0.21, 0.08);
// What light through a blade takes on: yellower.
const THROUGH: vec3<f32> = vec3<f32>(0.9, 0.85, 0.35);
const SEGMENTS: f32 = 4.0;

@vertex
fn blade_vs(@builtin(vertex_index) vi: u32, @builtin(instance_index) ii: u32) -> BladeOut {
    let a = blades[4u * ii];
    let b = blades[4u * ii + 1u];
    let c = blades[4u * ii + 2u];
    let tip = blades[4u * ii + 3u].xy;
    let root = a.xyz;
    let facing = vec2<f32>(cos(a.w), sin(a.w));
    let across = vec2<f32>(-facing.y, facing.x);
    let height = b.x;
    let lean = b.y * height;
    // The lean grows as t^k: k = 1 a straight slant, larger an upright blade bent at the top.
    let k = 1.0 + 2.0 * b.z;
    let t = min(f32(vi / 2u) / SEGMENTS, 1.0);
    let side = select(-0.5, 0.5, (vi & 1u) == 1u && vi < 8u);
    let width = b.w * (1.0 - t) * select(1.0, 0.0, vi >= 8u);
    let bend = lean * pow(t, k);
    // The wind pushes the blade over more toward its tip; a bent blade stands lower.
    let pushed = tip * t * t;
    let droop = sqrt(max(1.0 - dot(tip, tip) / (height * height), 0.3));
    let p = root + vec3<f32>(
        facing.x * bend + across.x * side * width + pushed.x,
        height * t * droop,
        facing.y * bend + across.y * side * width + pushed.y,
    );
    // The tangent up the blade, and the normal across it in the plane of its bend.
    let dbend = lean * k * pow(max(t, 1e-3), k - 1.0);
    let n = normalize(vec3<f32>(facing.x * height, -dbend, facing.y * height));
    var out: BladeOut;
    out.clip = r.view_proj * vec4<f32>(p, 1.0);
    out.rel = p;
    out.normal = n;
    out.along = t;
    out.look = c.xyz;
    return out;
}

@fragment
fn blade_fs(in: BladeOut) -> @location(0) vec4<f32> {
    let l = r.sun_dir.xyz;
    let v = normalize(r.camera_pos.xyz - in.rel);
    // The side the eye sees, its normal bent towards the sky: a blade is rounded, and a
    // meadow's blades face every way, so more of it faces up than a flat strip does.
    var n = normalize(in.normal);
    n = select(n, -n, dot(n, v) < 0.0);
    let rounded = normalize(n + vec3<f32>(0.0, 0.8, 0.0));
    let shade = in.look.x;
    let sun = r.sun_color.rgb * in.look.y;
    let ao = in.look.z * mix(0.4, 1.0, in.along);
    let albedo = mix(BLADE_LUSH, BLADE_DRY, shade * shade) * mix(0.55, 1.2, in.along);
    // The sun on the side seen, and through the blade from the other side.
    let front = max(dot(rounded, l), 0.0);
    let back = 0.6 * max(dot(-n, l), 0.0);
    let sky = r.ambient_color.rgb * (0.75 + 0.25 * rounded.y);
    let half_vec = normalize(l + v);
    let sheen = 0.06 * pow(max(dot(rounded, half_vec), 0.0), 24.0) * in.along;
    let lit = albedo * (sky * ao + sun * (front + back * THROUGH)) + sun * sheen;
    let air = air_at(r, in.rel);
    return vec4<f32>(to_target(r, lit * air.keep + air.light), 1.0);
}
