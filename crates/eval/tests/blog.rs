//! The method `blog` (the seed blog's pipeline, written again as a peer): it draws its own
//! terrain, its 8-bit normal map loses what rgba8unorm cannot hold, its exact surface converges,
//! and its frame is scored against that surface with an error that is neither nothing nor noise.

#[path = "../../../tests/common/mod.rs"]
mod common;

use relief::gpu::blog::{Blog, BLOG_SIZE};
use relief::gpu::headless::{self, render_blog, BlogImage, Offscreen};
use relief::{OrbitCamera, Shading, TerrainParams};

const W: u32 = 160;
const H: u32 = 90;

fn flip(a: &[u8], b: &[u8]) -> f64 {
    relief_eval::metrics::image_error(
        &relief_eval::metrics::rgb(a),
        &relief_eval::metrics::rgb(b),
        W,
        H,
    )
    .0
}

fn save(name: &str, rgba: &[u8]) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let _ = image::save_buffer(dir.join(name), rgba, W, H, image::ColorType::Rgba8);
}

#[test]
fn the_blog_frame_is_scored_against_its_own_converged_surface() {
    let gpu = common::gpu();
    let view = OrbitCamera::default().view(W as f32 / H as f32);
    let params = TerrainParams::default();
    let scene = (&params, &Shading::default());
    let draw = |what| {
        render_blog(&gpu, scene, &view, (W, H), what, None)
            .unwrap()
            .0
    };
    let blog = draw(BlogImage::Pipeline);
    let exact = |grid| {
        draw(BlogImage::Exact {
            grid,
            supersample: 2,
        })
    };
    let (coarse, fine) = (exact(512), exact(1024));
    save("blog.png", &blog);
    save("blog-exact.png", &fine);
    // Terrain, not the cleared sky: most pixels differ from the top-left corner's sky.
    let sky = &blog[..4];
    let terrain = blog.chunks(4).filter(|p| p != &sky).count();
    assert!(terrain > (W * H / 3) as usize, "{terrain} terrain pixels");
    // The exact surface has converged in its grid: a finer one barely moves it.
    let converged = flip(&coarse, &fine);
    assert!(converged < 0.01, "exact 512 against 1024: FLIP {converged}");
    // The blog's frame is its terrain (close to the exact one) with its own errors (8 bits,
    // normals, no anti-aliasing) well above the exact surface's own convergence.
    let error = flip(&fine, &blog);
    assert!(
        error > 3.0 * converged && error < 0.2,
        "blog against its exact surface: FLIP {error} (exact converged to {converged})"
    );
}

#[test]
fn the_blog_normal_map_cannot_hold_negative_components() {
    let gpu = common::gpu();
    let blog = Blog::new(&gpu.device, Offscreen::targets(1)).unwrap();
    let view = OrbitCamera::default().view(1.0);
    blog.prepare(
        &gpu.queue,
        &TerrainParams::default(),
        &Shading::default(),
        &view,
        0.0,
    );
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    blog.encode_bake(&mut encoder, None);
    gpu.queue.submit([encoder.finish()]);
    let maps = blog.maps.as_ref().unwrap();
    let heights = headless::read_texture(&gpu.device, &gpu.queue, &maps[0]).unwrap();
    let normals = headless::read_texture(&gpu.device, &gpu.queue, &maps[1]).unwrap();
    assert_eq!(heights.len(), (BLOG_SIZE * BLOG_SIZE * 4) as usize);
    // The blog's normalised noise keeps to the middle of its range: the whole relief is drawn
    // in fewer than half of the 256 codes (its terraces).
    let h: Vec<u8> = heights.chunks(4).map(|t| t[0]).collect();
    let (lo, hi) = (*h.iter().min().unwrap(), *h.iter().max().unwrap());
    assert!((40..128).contains(&(hi - lo)), "heights span {lo}..{hi}");
    // The slopes face every way, but rgba8unorm clamps the negative half of x and y to 0 (and
    // 8-bit heights make many differences exactly 0): at least half the texels store 0 in each.
    let texels = (BLOG_SIZE * BLOG_SIZE) as f64;
    for c in 0..2 {
        let zero = normals.chunks(4).filter(|t| t[c] == 0).count() as f64 / texels;
        assert!(zero > 0.45, "component {c}: {zero} of texels store 0");
        let high = normals.chunks(4).filter(|t| t[c] > 64).count() as f64 / texels;
        assert!(
            high > 0.01,
            "component {c}: {high} of texels lean its positive way"
        );
    }
    assert!(normals.chunks(4).all(|t| t[2] > 0), "z points up");
}
