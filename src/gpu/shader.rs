//! WGSL sources and the include step that composes them.
//!
//! Each pass has its own file in `wgsl/`; what several passes share has a file of its own
//! (noise, shading, the level texel, the march). A file names the files it needs once, in a
//! first line `// import: noise, landscape`; [`source`] puts each needed file once before the
//! files that need it (WGSL declarations may come in any order, so this is only for reading).
//! A file that calls functions another file defines (the compute raster's `keep`, the march's
//! caster) says so in a line `// part of: ...`: it is composed only into those files' modules.
//! Every other file is a module of its own ([`modules`]), and the tests validate each one
//! composed, listed from `wgsl/` on disk. A stand-in (a file whose first line is
//! `// instead of: x`) replaces `x` in the modules whose own file names it in a line
//! `// with: ...` (the terrain's shadow in the air: the default sees none, the modules that
//! can tell take the shadow-height map or a march), and in [`source_for`]'s clouds.

macro_rules! wgsl_files {
    ($($name:ident),* $(,)?) => {
        [$((stringify!($name), include_str!(concat!("../../wgsl/", stringify!($name), ".wgsl")))),*]
    };
}

/// Every file of `wgsl/`, by name (without `.wgsl`), with its text.
pub const FILES: &[(&str, &str)] = &wgsl_files![
    air_shadow,
    bake,
    blit,
    blog,
    clouds,
    clouds_image,
    clouds_none,
    clouds_seen,
    composite,
    fullscreen,
    grass,
    grass_blade,
    grass_draw,
    grass_probe,
    grass_reference,
    grass_scatter,
    ground,
    horizon_probe,
    hybrid,
    landscape,
    landscape_bake,
    level_texel,
    march,
    mesh_history,
    noise,
    normals,
    props,
    props_grid,
    props_look,
    props_map,
    props_march,
    props_overlay,
    props_reference,
    props_scatter,
    raster,
    raster_blades,
    raster_depth,
    raster_ids,
    ray_depth,
    raymarch,
    rays,
    shade,
    sky,
    temporal,
    terrain_air,
    terrain_air_map,
    terrain_air_rays,
    test_box,
    vis_common,
    visibility,
    world,
    world_light,
    world_rays,
    world_rays_io,
];

/// The text of `wgsl/<name>.wgsl`, if relief has such a file.
pub fn file(name: &str) -> Option<&'static str> {
    FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, text)| *text)
}

/// What a file's `// <key>: a, b` header line lists (its first lines, before any code).
fn header<'a>(text: &'a str, key: &str) -> Vec<&'a str> {
    text.lines()
        .take_while(|l| l.starts_with("//"))
        .filter_map(|l| l.strip_prefix("// ")?.strip_prefix(key)?.strip_prefix(':'))
        .flat_map(|list| list.split(" (").next().unwrap_or("").split(','))
        .map(str::trim)
        .filter(|n| !n.is_empty())
        .collect()
}

/// The files `name` imports (its `// import:` line).
#[cfg(test)]
pub fn imports(name: &str) -> Vec<&'static str> {
    file(name).map_or_else(Vec::new, |text| header(text, "import"))
}

/// The files whose modules `name` is composed into, when it is only a part of them (its
/// `// part of:` line); empty for a module of its own.
#[cfg(test)]
pub fn part_of(name: &str) -> Vec<&'static str> {
    file(name).map_or_else(Vec::new, |text| header(text, "part of"))
}

/// The module `wgsl/<name>.wgsl` makes: every file it imports, directly or not, once each and
/// before the files that import it, then the file itself.
///
/// # Panics
///
/// When `name` or a file it imports is not in [`FILES`], or the imports go round in a circle:
/// relief's own files are fixed at build time, and the tests compose every one of them.
pub fn source(name: &str) -> String {
    fn visit(name: &str, path: &mut Vec<String>, done: &mut Vec<String>, out: &mut Vec<&str>) {
        if done.iter().any(|d| d == name) {
            return;
        }
        assert!(
            !path.iter().any(|p| p == name),
            "wgsl imports go round: {} -> {name}",
            path.join(" -> ")
        );
        let text = file(name).unwrap_or_else(|| panic!("no wgsl/{name}.wgsl"));
        path.push(name.to_owned());
        for import in header(text, "import") {
            visit(import, path, done, out);
        }
        path.pop();
        done.push(name.to_owned());
        out.push(text);
    }
    let mut out = Vec::new();
    visit(name, &mut Vec::new(), &mut Vec::new(), &mut out);
    let mut whole = out.join("\n");
    // The stand-ins the module's own file asks for (`// with:`), each for its first
    // `// instead of:` file.
    for stand_in in header(file(name).unwrap_or(""), "with") {
        let text = file(stand_in).unwrap_or_else(|| panic!("{name} takes no wgsl/{stand_in}.wgsl"));
        let replaced = header(text, "instead of");
        let old = replaced.first().and_then(|r| file(r));
        let old = old.filter(|old| whole.contains(old));
        let old = old
            .unwrap_or_else(|| panic!("{name} takes {stand_in}, but has none of what it replaces"));
        whole = whole.replacen(old, text, 1);
    }
    whole
}

/// The stand-ins a module's own file asks for (its `// with:` line).
#[cfg(test)]
pub fn with(name: &str) -> Vec<&'static str> {
    file(name).map_or_else(Vec::new, |text| header(text, "with"))
}

/// Which clouds a module is built with ([`source_for`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CloudCode {
    /// None: `clouds_none.wgsl` gives what the march gives at no coverage, without it.
    Without,
    /// The march, along every pixel's ray (`clouds.wgsl` and `clouds_seen.wgsl`).
    March,
    /// The march and the visibility method's image of it (`clouds_image.wgsl` for
    /// `clouds_seen.wgsl`).
    Image,
}

/// [`source`], with the clouds `code` asks for: the march is most of a shading pipeline's
/// build (3.4 s of the visibility method's 3.6 s on lavapipe), and the clouds are off by
/// default. A stand-in's first `// instead of:` file is replaced by it, the others dropped.
pub fn source_for(name: &str, code: CloudCode) -> String {
    let mut whole = source(name);
    let stand_in = match code {
        CloudCode::March => return whole,
        CloudCode::Without => "clouds_none",
        CloudCode::Image => "clouds_image",
    };
    let Some(text) = file(stand_in) else {
        return whole;
    };
    for (i, replaced) in header(text, "instead of").into_iter().enumerate() {
        if let Some(old) = file(replaced) {
            whole = whole.replacen(old, if i == 0 { text } else { "" }, 1);
        }
    }
    whole
}

/// The file that `name` stands in for (its `// instead of:` line: [`source_for`]); empty for
/// any other file.
#[cfg(test)]
pub fn instead_of(name: &str) -> Vec<&'static str> {
    file(name).map_or_else(Vec::new, |text| header(text, "instead of"))
}

/// Every shader module relief can build: each file that is not only a part of others, by
/// name, composed ([`source`]). What the tests validate.
#[cfg(test)]
pub fn modules() -> Vec<(&'static str, String)> {
    FILES
        .iter()
        .filter(|(name, _)| part_of(name).is_empty() && instead_of(name).is_empty())
        .map(|(name, _)| (*name, source(name)))
        .collect()
}

pub(crate) fn module(device: &wgpu::Device, label: &str, source: &str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    })
}
