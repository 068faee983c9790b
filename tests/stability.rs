//! The boundaries `relief stability` finds, pinned on a software GPU at small sizes. A failure
//! names the axis and the value.

mod common;

use relief::stability::{grazing, Options};
use relief::TerrainParams;

#[test]
fn grazing_rays_tunnel_through_the_seed_march_on_steep_terrain_and_never_through_the_reference() {
    let gpu = common::gpu();
    let options = Options::quick();
    let rows = grazing(&gpu, &TerrainParams::default(), &options, |_, _| {}).unwrap();
    eprintln!("{}", relief::stability::table(&rows, &options));
    for r in &rows {
        let at = format!(
            "grazing axis, {} at {}° and height scale {}",
            r.marcher.label(),
            r.elevation_deg,
            r.height_scale
        );
        assert!(r.truth_hits > r.sampled / 4, "{at}: the view shows terrain");
        match r.marcher.step_factor {
            // relief's conservative cast: never through terrain, never out of steps.
            None => assert_eq!((r.tunnelled, r.capped), (0, 0), "{at}"),
            // The seed's march on the default terrain: no tunnel at any angle.
            Some(_) if r.height_scale == 0.5 => assert_eq!(r.tunnelled, 0, "{at}"),
            Some(_) => {}
        }
    }
    // The control: on steep terrain the seed's march at c = 0.8 steps through ridges, which
    // shows the test can see a tunnel.
    let worst = rows
        .iter()
        .filter(|r| r.marcher.step_factor == Some(0.8) && r.height_scale == 2.0)
        .map(|r| r.tunnelled_fraction())
        .fold(0.0, f64::max);
    assert!(
        worst > 0.02,
        "grazing axis, raymarch c=0.8 at height scale 2: tunnelled {worst}"
    );
}
