//! The hybrid method (`--method hybrid`, the endless world): the clipmap mesh raised by each
//! level's error bound is rasterised, and each sample's ray is refined from it to the continuous
//! surface in compute. From a coarse mesh it draws the continuous surface: closer to the
//! reference ray cast than that mesh, silhouettes included.

#[path = "../../../tests/common/mod.rs"]
mod common;

use relief::gpu::headless::{self, Gpu, Offscreen, RENDER_SAMPLES};
use relief::noise::Channel;
use relief::{Method, Shading, Terrain, TerrainParams, WorldParams};
use relief_eval::metrics::{image_error, rgb};

const W: u32 = 256;
const H: u32 = 144;

fn world(gpu: &Gpu, params: WorldParams, method: Method) -> Vec<u8> {
    common::world_image(gpu, params, method, (W, H))
}

fn flip(a: &[u8], b: &[u8]) -> f64 {
    image_error(&rgb(a), &rgb(b), W, H).0
}

#[test]
fn from_a_coarse_mesh_the_hybrid_draws_the_continuous_surface() {
    let gpu = common::gpu();
    // A coarse mesh: 8 pixels of screen error.
    let params = WorldParams {
        pixel_error: 8.0,
        ..Default::default()
    };
    let mesh = world(&gpu, params, Method::Mesh);
    let hybrid = world(&gpu, params, Method::Hybrid);
    let reference = headless::render_world_rays(
        &gpu,
        &params,
        &Shading::default(),
        &common::world_view(&params, (W, H)),
        Method::Reference,
        None,
    )
    .unwrap();
    assert_eq!(reference.unresolved, 0);
    let mut other = params;
    other.land.seed += 1;
    let moved = world(&gpu, other, Method::Hybrid);
    let truth = &reference.rgba;
    let (h, m, control) = (
        flip(truth, &hybrid),
        flip(truth, &mesh),
        flip(&hybrid, &moved),
    );
    eprintln!("against the reference: hybrid {h:.4}, mesh {m:.4}; another seed {control:.4}");
    assert!(
        h < m,
        "the hybrid ({h:.4}) must be closer to the reference than its coarse mesh ({m:.4})"
    );
    assert!(
        control > 2.0 * h,
        "another seed ({control:.4}) must score far worse than the reference ({h:.4})"
    );
}

/// What the hybrid raises a level by ([`relief::clipmap::level_raise`]) bounds how far the
/// continuous surface rises above that level's mesh, at all but under 1% of points other than
/// those it was measured at: the raised mesh lies on or above the surface, so the refinement
/// starts in front of it.
#[test]
fn the_raise_bounds_the_surface_above_every_levels_mesh() {
    const POINTS: usize = 512;
    let land = WorldParams::default().land;
    let finest = relief::clipmap::finest_log2(&land);
    let mut state = 12345u32;
    let mut next = || {
        state = relief::noise::pcg(state);
        f64::from(state) / 4_294_967_296.0
    };
    for log2 in (finest..finest + 16).step_by(3) {
        let raise = relief::clipmap::level_raise(&land, log2);
        let s = 2f64.powi(log2);
        let kept = land.octaves_for_level(log2);
        let height =
            |x: f64, z: f64| land.peak_height * land.sample(Channel::Height, x, z, kept).value;
        let mut worst: f64 = 0.0;
        let mut through = 0;
        for _ in 0..POINTS {
            let (i, j) = ((next() * 4096.0).floor(), (next() * 4096.0).floor());
            let (u, v) = (next(), next());
            let [a, b, c, d] = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
                .map(|(di, dj)| height((i + di) * s, (j + dj) * s));
            // The triangle the GPU draws (the diagonal from (0, 0) to (1, 1)).
            let mesh = if u >= v {
                a + u * (b - a) + v * (d - b)
            } else {
                a + v * (c - a) + u * (d - c)
            };
            let above = land.height_at((i + u) * s, (j + v) * s) - mesh;
            worst = worst.max(above);
            through += usize::from(above > raise);
        }
        eprintln!(
            "spacing 2^{log2} m: raise {raise:.3} m; the surface rises up to {worst:.3} m above \
             the mesh, past the raise at {through} of {POINTS} points"
        );
        // A measured bound: the rare point where the surface pokes through is drawn at the
        // raised mesh's depth, a sliver in front of the surface.
        assert!(
            through * 100 <= POINTS,
            "spacing 2^{log2} m: the surface rises past the raise ({raise} m) at {through} of \
             {POINTS} points (up to {worst} m)"
        );
    }
}

#[test]
fn the_tile_refuses_the_hybrid_in_words() {
    let gpu = common::gpu();
    let mut terrain = Terrain::new(
        &gpu.device,
        &gpu.queue,
        Offscreen::targets(RENDER_SAMPLES),
        TerrainParams {
            size: 64,
            grid: 32,
            ..Default::default()
        },
    )
    .unwrap();
    let e = terrain.set_method(&gpu.device, Method::Hybrid).unwrap_err();
    assert!(e.to_string().contains("endless world"), "{e}");
    assert_eq!(terrain.method(), Method::Mesh);
}
