//! Every WGSL module relief builds is valid (naga), and the Rust uniform structs have the
//! WGSL layouts. Unit tests, so the uniform mirrors stay private to the crate.

use super::bake::BakeUniforms;
use super::landscape::LandscapeUniforms;
use super::normals::NormalUniforms;
use super::{shader, RenderUniforms};
use std::mem::{offset_of, size_of};

pub(crate) fn parse(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}.wgsl does not parse:\n{}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}.wgsl does not validate: {e:?}"));
    module
}

/// The names of the files in `wgsl/` on disk.
fn files_on_disk() -> Vec<String> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/wgsl");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn every_file_on_disk_is_built_in_and_every_module_validates() {
    let on_disk = files_on_disk();
    let built_in: Vec<String> = shader::FILES.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(built_in, on_disk, "shader::FILES and wgsl/ differ");
    for name in &on_disk {
        // Every file is composed into some module: its own, or those it is part of, each of
        // which imports it.
        for whole in shader::part_of(name) {
            let mut todo = vec![whole];
            let mut visited = Vec::new();
            let mut found = false;
            while let Some(n) = todo.pop() {
                if visited.contains(&n) {
                    continue;
                }
                visited.push(n);
                let imports = shader::imports(n);
                found |= imports.contains(&name.as_str());
                todo.extend(imports);
            }
            assert!(
                found,
                "{name} says it is part of {whole}, which does not import it"
            );
        }
        for import in shader::imports(name) {
            assert!(
                on_disk.iter().any(|n| n == import),
                "{name} imports {import}: no such file"
            );
        }
    }
    let modules = shader::modules();
    let parts = on_disk
        .iter()
        .filter(|n| !shader::part_of(n).is_empty() || !shader::instead_of(n).is_empty())
        .count();
    assert_eq!(modules.len() + parts, on_disk.len());
    for (name, source) in modules {
        parse(name, &source);
    }
}

#[test]
fn a_stand_in_validates_in_every_module_its_file_is_in_and_changes_only_that() {
    // `shader::source_for`: the modules composed with the march are `source`'s; without the
    // clouds, every module that has the march has the stand-in instead, and validates; with
    // the clouds' image, so do the visibility method's modules (the only ones that read it).
    use shader::CloudCode;
    let mut replaced = 0;
    for (name, whole) in shader::modules() {
        assert_eq!(shader::source_for(name, CloudCode::March), whole, "{name}");
        let without = shader::source_for(name, CloudCode::Without);
        if whole.contains(shader::file("clouds").unwrap()) {
            assert!(without.len() < whole.len(), "{name}");
            assert!(
                without.contains(shader::file("clouds_none").unwrap())
                    && !without.contains(shader::file("clouds_seen").unwrap()),
                "{name}"
            );
            parse(name, &without);
            replaced += 1;
        } else {
            assert_eq!(without, whole, "{name}");
        }
    }
    assert!(replaced > 0);
    for name in ["visibility", "hybrid"] {
        let image = shader::source_for(name, CloudCode::Image);
        assert!(image.contains(shader::file("clouds_image").unwrap()));
        assert!(!image.contains(shader::file("clouds_seen").unwrap()));
        parse(name, &image);
    }
    assert_eq!(shader::instead_of("clouds_none"), ["clouds", "clouds_seen"]);
    assert_eq!(shader::instead_of("clouds_image"), ["clouds_seen"]);
}

#[test]
fn a_module_takes_the_stand_ins_its_own_file_names() {
    // `// with:` (shader::source): the shading of the mesh, the visibility and hybrid methods
    // and the sky reads the light shafts' shadow-height map, the ray casters march the terrain
    // for it; every other module with the clouds sees no terrain in the air (the default), and
    // a module importing one that names a stand-in does not take it.
    let default = shader::file("terrain_air").unwrap();
    let mut taken = Vec::new();
    for (name, source) in shader::modules() {
        let with = shader::with(name);
        for stand_in in &with {
            assert!(source.contains(shader::file(stand_in).unwrap()), "{name}");
            assert_eq!(shader::instead_of(stand_in), ["terrain_air"], "{stand_in}");
            assert!(!source.contains(default), "{name}");
            taken.push(name);
        }
        if with.is_empty() && source.contains(shader::file("clouds").unwrap()) {
            assert!(source.contains(default), "{name}");
        }
    }
    taken.sort_unstable();
    assert_eq!(
        taken,
        ["hybrid", "sky", "visibility", "world", "world_rays_io"]
    );
    assert!(shader::source("props_march").contains(default));
}

#[test]
fn a_part_alone_does_not_validate() {
    // What `// part of:` claims: the file calls what only its wholes define.
    for (name, _) in shader::FILES {
        if !shader::part_of(name).is_empty() {
            let source = shader::source(name);
            let valid = naga::front::wgsl::parse_str(&source).is_ok_and(|m| {
                naga::valid::Validator::new(
                    naga::valid::ValidationFlags::all(),
                    naga::valid::Capabilities::all(),
                )
                .validate(&m)
                .is_ok()
            });
            assert!(
                !valid,
                "{name} validates alone: drop its `// part of:` line"
            );
        }
    }
}

#[test]
fn only_the_raster_with_ids_needs_64_bit_integers() {
    // The page's WebGPU has no 64-bit integers: every other module builds without them.
    use naga::valid::Capabilities as C;
    let int64 = C::SHADER_INT64 | C::SHADER_INT64_ATOMIC_MIN_MAX | C::SHADER_INT64_ATOMIC_ALL_OPS;
    for (name, source) in shader::modules() {
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&source)));
        let without =
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), C::all() - int64)
                .validate(&module);
        assert_eq!(without.is_ok(), name != "raster_ids", "{name}: {without:?}");
    }
}

/// (size, member name -> offset) of a WGSL struct as naga lays it out.
pub(crate) fn layout(module: &naga::Module, name: &str) -> (u32, Vec<(String, u32)>) {
    for (_, ty) in module.types.iter() {
        if ty.name.as_deref() == Some(name) {
            if let naga::TypeInner::Struct { members, span } = &ty.inner {
                let m = members
                    .iter()
                    .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                    .collect();
                return (*span, m);
            }
        }
    }
    panic!("struct {name} not found");
}

pub(crate) fn offset(members: &[(String, u32)], name: &str) -> usize {
    members
        .iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no member {name}"))
        .1 as usize
}

#[test]
fn landscape_uniforms_match_wgsl() {
    let m = parse("landscape_bake", &shader::source("landscape_bake"));
    let (size, members) = layout(&m, "LandscapeUniforms");
    assert_eq!(size as usize, size_of::<LandscapeUniforms>());
    for (name, at) in [
        ("origin", offset_of!(LandscapeUniforms, origin)),
        ("extent", offset_of!(LandscapeUniforms, extent)),
        ("dest_origin", offset_of!(LandscapeUniforms, dest_origin)),
        ("wrap", offset_of!(LandscapeUniforms, wrap)),
        ("layer", offset_of!(LandscapeUniforms, layer)),
        ("seed", offset_of!(LandscapeUniforms, seed)),
        ("octaves", offset_of!(LandscapeUniforms, octaves)),
        (
            "total_octaves",
            offset_of!(LandscapeUniforms, total_octaves),
        ),
        ("terrain", offset_of!(LandscapeUniforms, terrain)),
        ("gain", offset_of!(LandscapeUniforms, gain)),
        ("feature_log2", offset_of!(LandscapeUniforms, feature_log2)),
        ("level_log2", offset_of!(LandscapeUniforms, level_log2)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
}

#[test]
fn visibility_uniforms_match_wgsl() {
    use crate::gpu::visibility::VisUniforms;
    let m = parse("visibility", &shader::source("visibility"));
    let (size, members) = layout(&m, "VisUniforms");
    assert_eq!(size as usize, size_of::<VisUniforms>());
    for (name, at) in [
        ("w_row", offset_of!(VisUniforms, w_row)),
        ("depth", offset_of!(VisUniforms, depth)),
        ("size", offset_of!(VisUniforms, size)),
        ("sky", offset_of!(VisUniforms, sky)),
        ("world", offset_of!(VisUniforms, world)),
        ("encode_srgb", offset_of!(VisUniforms, encode_srgb)),
        ("depth_stride", offset_of!(VisUniforms, depth_stride)),
    ] {
        assert_eq!(offset(&members, name), at, "VisUniforms.{name}");
    }
}

#[test]
fn uniform_structs_match_wgsl() {
    let bake = parse("bake", &shader::source("bake"));
    let (size, m) = layout(&bake, "BakeUniforms");
    assert_eq!(size as usize, size_of::<BakeUniforms>());
    assert_eq!(offset(&m, "gain"), offset_of!(BakeUniforms, gain));
    assert_eq!(offset(&m, "offset"), offset_of!(BakeUniforms, offset));

    let normals = parse("normals", &shader::source("normals"));
    let (size, m) = layout(&normals, "NormalUniforms");
    assert_eq!(size as usize, size_of::<NormalUniforms>());
    assert_eq!(
        offset(&m, "height_scale"),
        offset_of!(NormalUniforms, height_scale)
    );
    assert_eq!(
        offset(&m, "texel_world"),
        offset_of!(NormalUniforms, texel_world)
    );

    let render = parse("world", &shader::source("world"));
    let (size, m) = layout(&render, "RenderUniforms");
    assert_eq!(size as usize, size_of::<RenderUniforms>());
    assert_eq!(
        offset(&m, "camera_pos"),
        offset_of!(RenderUniforms, camera_pos)
    );
    assert_eq!(
        offset(&m, "snow_color"),
        offset_of!(RenderUniforms, snow_color)
    );
    assert_eq!(
        offset(&m, "height_scale"),
        offset_of!(RenderUniforms, height_scale)
    );
    assert_eq!(offset(&m, "grid"), offset_of!(RenderUniforms, grid));
    assert_eq!(offset(&m, "specular"), offset_of!(RenderUniforms, specular));
    for (name, rust) in [
        ("fog", offset_of!(RenderUniforms, fog)),
        ("fade_start", offset_of!(RenderUniforms, fade_start)),
        ("fade_end", offset_of!(RenderUniforms, fade_end)),
        ("sun_elevation", offset_of!(RenderUniforms, sun_elevation)),
        ("shadows", offset_of!(RenderUniforms, shadows)),
        ("water_level", offset_of!(RenderUniforms, water_level)),
        ("water_plane", offset_of!(RenderUniforms, water_plane)),
        ("clock", offset_of!(RenderUniforms, clock)),
        ("water_on", offset_of!(RenderUniforms, water_on)),
        ("ripple_origin", offset_of!(RenderUniforms, ripple_origin)),
        ("sand_band", offset_of!(RenderUniforms, sand_band)),
        ("palette", offset_of!(RenderUniforms, palette)),
        ("clouds", offset_of!(RenderUniforms, clouds)),
        ("cloud_origin", offset_of!(RenderUniforms, cloud_origin)),
        ("cloud_march", offset_of!(RenderUniforms, cloud_march)),
        ("cloud_sun", offset_of!(RenderUniforms, cloud_sun)),
        ("air_shadow", offset_of!(RenderUniforms, air_shadow)),
    ] {
        assert_eq!(offset(&m, name), rust, "RenderUniforms.{name}");
    }
}

#[test]
fn the_water_periods_agree_with_shade_wgsl() {
    let shade = shader::file("shade").unwrap();
    for (name, value) in [
        ("RIPPLE_PERIOD", crate::gpu::world::RIPPLE_PERIOD),
        ("CLOCK_PERIOD", crate::gpu::world::CLOCK_PERIOD),
    ] {
        let line = format!("const {name}: f32 = {value:.1};");
        assert!(shade.contains(&line), "shade.wgsl lacks `{line}`");
    }
}

#[test]
fn the_cloud_constants_agree_with_clouds_wgsl() {
    use crate::world::clouds;
    let text = shader::file("clouds").unwrap();
    for (name, value) in [
        ("CLOUD_PERIOD", clouds::CLOUD_PERIOD),
        ("EARTH_RADIUS", clouds::EARTH_RADIUS),
    ] {
        let line = format!("const {name}: f32 = {value:.1};");
        assert!(text.contains(&line), "clouds.wgsl lacks `{line}`");
    }
}

#[test]
fn each_ripple_makes_whole_cycles_in_a_clock_period_at_its_deep_water_frequency() {
    // `RIPPLES` in shade.wgsl: (cycles a ripple period in x and z, amplitude, cycles a clock
    // period); the last is sqrt(g k) rounded to whole cycles.
    let shade = shader::file("shade").unwrap();
    let at = shade.find("const RIPPLES").expect("RIPPLES");
    let body = &shade[at..at + shade[at..].find(");").unwrap()];
    let waves: Vec<[f64; 4]> = body
        .split("vec4<f32>(")
        .skip(1)
        .map(|w| {
            let nums: Vec<f64> = w
                .split(')')
                .next()
                .unwrap()
                .split(',')
                .map(|x| x.trim().parse().unwrap())
                .collect();
            [nums[0], nums[1], nums[2], nums[3]]
        })
        .collect();
    assert_eq!(waves.len(), 4, "{body}");
    let tau = std::f64::consts::TAU;
    for [x, z, _, cycles] in waves {
        let k = x.hypot(z) * tau / f64::from(crate::gpu::world::RIPPLE_PERIOD);
        let exact = (9.81 * k).sqrt() * f64::from(crate::gpu::world::CLOCK_PERIOD) / tau;
        assert_eq!(cycles, exact.round(), "({x}, {z}): {exact} cycles");
    }
}

#[test]
fn world_size_agrees_with_render_wgsl() {
    assert!(
        shader::file("shade").unwrap().contains(&format!(
            "const WORLD_SIZE: f32 = {:.1};",
            crate::WORLD_SIZE
        )),
        "shade.wgsl's WORLD_SIZE must equal crate::WORLD_SIZE"
    );
}

#[test]
fn world_uniforms_match_wgsl() {
    use crate::gpu::world::{LevelUniforms, WorldUniforms};
    let m = parse("world", &shader::source("world"));
    let (size, members) = layout(&m, "WorldUniforms");
    assert_eq!(size as usize, size_of::<WorldUniforms>());
    for (name, at) in [
        ("eye", offset_of!(WorldUniforms, eye)),
        ("cells", offset_of!(WorldUniforms, cells)),
        ("patch_cells", offset_of!(WorldUniforms, patch_cells)),
        ("side", offset_of!(WorldUniforms, side)),
        ("morphing", offset_of!(WorldUniforms, morphing)),
        ("morph", offset_of!(WorldUniforms, morph)),
        ("peak", offset_of!(WorldUniforms, peak)),
        ("fade", offset_of!(WorldUniforms, fade)),
        ("first", offset_of!(WorldUniforms, first)),
        ("levels", offset_of!(WorldUniforms, levels)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
    let (size, members) = layout(&m, "Level");
    assert_eq!(size as usize, size_of::<LevelUniforms>());
    for (name, at) in [
        ("origin_rel", offset_of!(LevelUniforms, origin_rel)),
        ("delta", offset_of!(LevelUniforms, delta)),
        ("origin_mod", offset_of!(LevelUniforms, origin_mod)),
        ("shift", offset_of!(LevelUniforms, shift)),
        ("layer", offset_of!(LevelUniforms, layer)),
        ("coarse", offset_of!(LevelUniforms, coarse)),
        ("has_coarse", offset_of!(LevelUniforms, has_coarse)),
        ("eye_local", offset_of!(LevelUniforms, eye_local)),
        ("clip", offset_of!(LevelUniforms, clip)),
        ("raise", offset_of!(LevelUniforms, raise)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
    // The level array holds every level a clipmap can have.
    assert_eq!(
        std::mem::size_of_val(&<WorldUniforms as bytemuck::Zeroable>::zeroed().levels)
            / size_of::<LevelUniforms>(),
        crate::clipmap::MAX_LEVELS
    );
}

#[test]
fn light_uniforms_match_wgsl() {
    use crate::gpu::world_light::{LightLevel, LightRect, LightUniforms};
    let m = parse("world_light", &shader::source("world_light"));
    let (size, members) = layout(&m, "LightUniforms");
    assert_eq!(size as usize, size_of::<LightUniforms>());
    for (name, at) in [
        ("sun", offset_of!(LightUniforms, sun)),
        ("cells", offset_of!(LightUniforms, cells)),
        ("side", offset_of!(LightUniforms, side)),
        ("levels", offset_of!(LightUniforms, levels)),
        ("peak", offset_of!(LightUniforms, peak)),
        ("steps", offset_of!(LightUniforms, steps)),
        ("valley_radius", offset_of!(LightUniforms, valley_radius)),
        ("seed", offset_of!(LightUniforms, seed)),
        ("total_octaves", offset_of!(LightUniforms, total_octaves)),
        ("terrain", offset_of!(LightUniforms, terrain)),
        ("gain", offset_of!(LightUniforms, gain)),
        ("feature_log2", offset_of!(LightUniforms, feature_log2)),
        ("entries", offset_of!(LightUniforms, entries)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
    let (size, members) = layout(&m, "LightLevel");
    assert_eq!(size as usize, size_of::<LightLevel>());
    for (name, at) in [
        ("origin", offset_of!(LightLevel, origin)),
        ("origin_mod", offset_of!(LightLevel, origin_mod)),
        ("spacing_log2", offset_of!(LightLevel, spacing_log2)),
        ("layer", offset_of!(LightLevel, layer)),
        ("usable", offset_of!(LightLevel, usable)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
    let (size, members) = layout(&m, "LightRect");
    assert_eq!(size as usize, size_of::<LightRect>());
    for (name, at) in [
        ("origin", offset_of!(LightRect, origin)),
        ("extent", offset_of!(LightRect, extent)),
        ("level", offset_of!(LightRect, level)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
}

#[test]
fn world_ray_uniforms_match_wgsl() {
    use crate::gpu::world_rays::WorldRayUniforms;
    let m = parse("world_rays", &shader::source("world_rays_io"));
    let (size, members) = layout(&m, "WorldRayUniforms");
    assert_eq!(size as usize, size_of::<WorldRayUniforms>());
    for (name, at) in [
        ("eye", offset_of!(WorldRayUniforms, eye)),
        ("reference", offset_of!(WorldRayUniforms, reference)),
        ("base_log2", offset_of!(WorldRayUniforms, base_log2)),
        ("feature_log2", offset_of!(WorldRayUniforms, feature_log2)),
        ("max_steps", offset_of!(WorldRayUniforms, max_steps)),
        ("gain", offset_of!(WorldRayUniforms, gain)),
        ("pixel_angle", offset_of!(WorldRayUniforms, pixel_angle)),
        ("relax", offset_of!(WorldRayUniforms, relax)),
        ("bounds", offset_of!(WorldRayUniforms, bounds)),
        ("prefix", offset_of!(WorldRayUniforms, prefix)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
}

#[test]
fn tile_ray_uniforms_match_wgsl() {
    use crate::gpu::raymarch::RayUniforms;
    let m = parse("raymarch", &shader::source("raymarch"));
    let (size, members) = layout(&m, "RayUniforms");
    assert_eq!(size as usize, size_of::<RayUniforms>());
    for (name, at) in [
        ("seed", offset_of!(RayUniforms, seed)),
        ("max_steps", offset_of!(RayUniforms, max_steps)),
        ("lipschitz", offset_of!(RayUniforms, lipschitz)),
        ("hit_k", offset_of!(RayUniforms, hit_k)),
        ("relax", offset_of!(RayUniforms, relax)),
        ("offset", offset_of!(RayUniforms, offset)),
    ] {
        assert_eq!(offset(&members, name), at, "{name}");
    }
}

#[test]
fn the_palette_codes_agree_with_shade_wgsl() {
    use crate::palette::Palette;
    let wgsl = shader::file("shade").unwrap();
    for (name, palette) in [
        ("PALETTE_BLOG", Palette::Blog),
        ("PALETTE_TEMPLATE", Palette::SeedTemplate),
    ] {
        let line = format!("const {name}: u32 = {}u;", palette.code());
        assert!(wgsl.contains(&line), "shade.wgsl lacks `{line}`");
    }
}

#[test]
fn grass_uniforms_match_wgsl() {
    let m = parse("grass_probe", &crate::gpu::shader::source("grass_probe"));
    let (size, members) = layout(&m, "GrassUniforms");
    assert_eq!(
        size as usize,
        std::mem::size_of::<crate::gpu::grass::GrassUniforms>()
    );
    for (name, at) in [
        (
            "eye_clump",
            offset_of!(crate::gpu::grass::GrassUniforms, eye_clump),
        ),
        (
            "eye_rem",
            offset_of!(crate::gpu::grass::GrassUniforms, eye_rem),
        ),
        (
            "clump_cells",
            offset_of!(crate::gpu::grass::GrassUniforms, clump_cells),
        ),
        ("seed", offset_of!(crate::gpu::grass::GrassUniforms, seed)),
        (
            "height",
            offset_of!(crate::gpu::grass::GrassUniforms, height),
        ),
        ("cell", offset_of!(crate::gpu::grass::GrassUniforms, cell)),
    ] {
        assert_eq!(offset(&members, name), at, "GrassUniforms.{name}");
    }
}

mod props_tests {
    use super::{layout, offset, parse};
    use crate::gpu::props::PropsFrame;
    use crate::gpu::props_wgsl::{PropKind, PropOp};
    use crate::props::Props;
    use std::mem::{offset_of, size_of};

    #[test]
    fn the_props_structs_match_wgsl() {
        let m = parse(
            "props_scatter",
            &crate::gpu::shader::source("props_scatter"),
        );
        let (size, members) = layout(&m, "PropsFrame");
        assert_eq!(size as usize, size_of::<PropsFrame>());
        for (name, at) in [
            ("eye_in_cell", offset_of!(PropsFrame, eye_in_cell)),
            ("side", offset_of!(PropsFrame, side)),
            ("density", offset_of!(PropsFrame, density)),
            ("seed", offset_of!(PropsFrame, seed)),
            ("water", offset_of!(PropsFrame, water)),
            ("pixels", offset_of!(PropsFrame, pixels)),
            ("steps", offset_of!(PropsFrame, steps)),
            ("flags", offset_of!(PropsFrame, flags)),
        ] {
            assert_eq!(offset(&members, name), at, "PropsFrame.{name}");
        }
        let (size, members) = layout(&m, "PropKind");
        assert_eq!(size as usize, size_of::<PropKind>());
        for (name, at) in [
            ("lipschitz", offset_of!(PropKind, lipschitz)),
            ("lo", offset_of!(PropKind, lo)),
            ("scale", offset_of!(PropKind, scale)),
            ("sphere", offset_of!(PropKind, sphere)),
        ] {
            assert_eq!(offset(&members, name), at, "PropKind.{name}");
        }
        let (size, members) = layout(&m, "PropOp");
        assert_eq!(size as usize, size_of::<PropOp>());
        assert_eq!(offset(&members, "m0"), offset_of!(PropOp, rows));
    }

    #[test]
    fn the_compiled_tapes_validate() {
        let scene = crate::props::Scene::default();
        let mut kinds = scene.kinds.clone();
        kinds.push(crate::props::kinds::demo());
        let scene = crate::props::Scene { kinds, ..scene };
        let tapes = scene.compile(&Props::default()).unwrap();
        let source = crate::gpu::props_wgsl::march_source(&tapes, true);
        assert!(source.contains("fn kind_distance_tape(") && source.contains("fn kind_5("));
        parse("props_march (compiled)", &source);
    }
}
