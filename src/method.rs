//! How a frame is drawn, as a value: one list of methods serves `relief render --method`, the
//! benchmark's sweep, its CSV and chart, and the tests. Each method knows its name, its words
//! for people, and which GPU path draws it.

/// A way of drawing the terrain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Method {
    /// relief's pipeline: baked textures, a displaced grid mesh, forward shading, 4x MSAA.
    #[default]
    Mesh,
    /// The same mesh rasterised into depth and surface attributes per MSAA sample, every
    /// sample shaded in compute and composited into the host's pass
    /// ([`crate::gpu::visibility`]).
    Visibility,
    /// The mesh, each level raised by a bound on how far the continuous surface rises above
    /// it, rasterised as [`Method::Visibility`] does; from where each sample's ray meets it, a
    /// short conservative march in compute finds the continuous surface, which is shaded
    /// ([`crate::gpu::visibility`]; the endless world only so far).
    Hybrid,
    /// The seed template's heightfield ray march, in a compute shader.
    Raymarch,
    /// The same march in a full-screen fragment shader, as the seed does it.
    RaymarchFragment,
    /// relief's own march: the seed's, in compute, with octaves finer than the pixel's
    /// footprint faded out of its shading (the endless world only so far).
    RaymarchBandlimited,
    /// The seed blog's per-frame pipeline, written again as a peer: an 8-bit bake of its own
    /// sine-hash noise and normals every frame, a 1024²-vertex grid, no anti-aliasing
    /// ([`crate::gpu::blog`]; the tile only).
    Blog,
    /// relief's conservative ray cast of the continuous surface (every octave, Lipschitz
    /// steps, bisection), supersampled 3x3: the ground truth.
    Reference,
}

impl Method {
    /// Every method, in the order of docs, charts and tables.
    pub const ALL: [Method; 8] = [
        Method::Mesh,
        Method::Visibility,
        Method::Hybrid,
        Method::Raymarch,
        Method::RaymarchFragment,
        Method::RaymarchBandlimited,
        Method::Blog,
        Method::Reference,
    ];

    /// The names `--method` takes, in [`Method::ALL`]'s order.
    pub const NAMES: &'static [&'static str] = &[
        "mesh",
        "visibility",
        "hybrid",
        "raymarch",
        "raymarch-fragment",
        "raymarch-bandlimited",
        "blog",
        "reference",
    ];

    /// The names of the methods the tile draws ([`Method::in_tile`]), in the same order.
    pub const TILE_NAMES: &'static [&'static str] = &[
        "mesh",
        "visibility",
        "raymarch",
        "raymarch-fragment",
        "blog",
        "reference",
    ];

    /// The names of the methods the endless world draws ([`Method::in_world`]), in the same
    /// order.
    pub const WORLD_NAMES: &'static [&'static str] = &[
        "mesh",
        "visibility",
        "hybrid",
        "raymarch",
        "raymarch-fragment",
        "raymarch-bandlimited",
        "reference",
    ];

    /// Its name on the command line, in the CSV and on the chart.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The method called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name.trim())
    }

    /// One line for people.
    pub fn doc(self) -> &'static str {
        match self {
            Method::Mesh => "the displaced grid mesh, forward shaded (relief's pipeline)",
            Method::Visibility => "the same mesh rasterised to depth and attributes, four samples a pixel shaded in compute",
            Method::Hybrid => "the mesh raised to bound the surface from above, rasterised, each sample's ray refined to the continuous surface in compute (endless world)",
            Method::Raymarch => "the seed template's heightfield ray march, in compute",
            Method::RaymarchFragment => "the same march in a fragment shader, as the seed does it",
            Method::RaymarchBandlimited => "the march in compute, octaves finer than a pixel faded from its shading (endless world)",
            Method::Blog => "the seed blog's pipeline: its own noise baked to 8 bits with its normals every frame, a 1024² grid, no anti-aliasing (tile)",
            Method::Reference => "the conservative ray cast of the continuous surface, 3x3 supersampled: the ground truth",
        }
    }

    /// Where a ray-cast method runs (`None` for the mesh).
    pub fn ray_path(self) -> Option<RayPath> {
        match self {
            Method::Mesh | Method::Visibility | Method::Hybrid | Method::Blog => None,
            Method::Raymarch | Method::RaymarchBandlimited | Method::Reference => {
                Some(RayPath::Compute)
            }
            Method::RaymarchFragment => Some(RayPath::Fragment),
        }
    }

    /// Whether relief's mesh (its clipmap levels, [`crate::World`]) draws it: the forward
    /// mesh, the visibility method and the hybrid, which share the levels and the raster.
    pub fn is_mesh(self) -> bool {
        matches!(self, Method::Mesh | Method::Visibility | Method::Hybrid)
    }

    /// Whether the tile world draws it (band-limiting and the hybrid's refinement against the
    /// continuous surface are the endless world's only so far).
    pub fn in_tile(self) -> bool {
        !matches!(self, Method::RaymarchBandlimited | Method::Hybrid)
    }

    /// Whether the endless world draws it (the blog's pipeline draws its own tile).
    pub fn in_world(self) -> bool {
        self != Method::Blog
    }

    /// Whether it draws a terrain of its own rather than the scene's (the blog's pipeline bakes
    /// the blog's noise): its picture is not the scene's and is scored against its own surface.
    pub fn own_terrain(self) -> bool {
        self == Method::Blog
    }

    /// The scene keys this method does not read, which a front end refuses with it: the ray
    /// casters draw the continuous surface (no texture size, grid or normal map); the blog has
    /// its own noise, texture and grid and reads only the height scale and the snow line.
    pub fn unread_keys(self) -> &'static [&'static str] {
        match self {
            Method::Mesh | Method::Visibility | Method::Hybrid => &[],
            Method::Blog => &[
                "seed",
                "size",
                "grid",
                "octaves",
                "frequency",
                "gain",
                "ao_exponent",
                "offset",
                "normals",
            ],
            _ => &["size", "grid", "normals"],
        }
    }

    /// Supersampling per axis of the image this method draws.
    pub fn supersample(self) -> u32 {
        match self {
            Method::Reference => 3,
            _ => 1,
        }
    }

    /// The ray caster's settings for a scene of `octaves` (seed march knobs at their default).
    pub fn ray_method(self, octaves: u32) -> Option<RayMethod> {
        match self {
            Method::Mesh | Method::Visibility | Method::Hybrid | Method::Blog => None,
            Method::Reference => Some(RayMethod::Reference),
            Method::Raymarch | Method::RaymarchFragment | Method::RaymarchBandlimited => {
                Some(RayMethod::SeedMarch(SeedMarch {
                    normal_octaves: octaves,
                    band_limit: self == Method::RaymarchBandlimited,
                    ..SeedMarch::default()
                }))
            }
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Which ray caster, with its knobs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RayMethod {
    /// Conservative stepping from the Lipschitz bound, bisection, all octaves, analytic normals.
    Reference,
    /// The seed's heightfield marcher.
    SeedMarch(SeedMarch),
}

/// Knobs of the seed's heightfield ray marcher.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeedMarch {
    /// c in `t += c * h`.
    pub step_factor: f32,
    /// k in "hit when |h| < k t".
    pub hit_k: f32,
    /// Octaves summed while stepping (at most the scene's).
    pub march_octaves: u32,
    /// Octaves summed for the normal (at most the scene's).
    pub normal_octaves: u32,
    /// Fade octaves finer than the pixel's footprint out of the shading (relief's own march;
    /// the endless world only so far). The seed does not.
    pub band_limit: bool,
    /// The seed's relaxation variant: each step is multiplied by `max(relax * t, 1)`, so steps
    /// grow with distance (per unit of distance; 0, the seed's plain march, leaves them be).
    pub relax: f32,
}

impl Default for SeedMarch {
    /// The seed's own choices: a step factor of 0.4, a hit threshold of 0.0015 t, and fewer
    /// octaves while stepping than for the normal.
    fn default() -> Self {
        Self {
            step_factor: 0.4,
            hit_k: 0.0015,
            march_octaves: 5,
            normal_octaves: 8,
            band_limit: false,
            relax: 0.0,
        }
    }
}

/// Where a ray caster runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayPath {
    /// A compute shader writing storage textures.
    Compute,
    /// A full-screen triangle whose fragment shader casts the ray.
    Fragment,
}

/// Where the visibility method rasterises its mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Raster {
    /// The GPU's rasteriser: a render pass writing depth (and the world's attributes).
    #[default]
    Hardware,
    /// A compute pass: one sample a pixel only.
    Compute,
}

impl Raster {
    /// Every raster, in the order of docs and tables.
    pub const ALL: [Raster; 2] = [Raster::Hardware, Raster::Compute];

    /// Its name on the command line and in the benchmark's CSV.
    pub fn name(self) -> &'static str {
        match self {
            Raster::Hardware => "hardware",
            Raster::Compute => "compute",
        }
    }

    /// The raster called `name`.
    pub fn from_name(name: &str) -> crate::Result<Self> {
        Self::ALL
            .into_iter()
            .find(|r| r.name() == name.trim())
            .ok_or_else(|| crate::Error::invalid("raster", name, "hardware or compute"))
    }

    /// Why this raster cannot draw at `samples` a pixel, or `None` where it can.
    pub fn refusal(self, samples: u32) -> Option<&'static str> {
        match self {
            Raster::Compute if samples != 1 => Some(
                "hardware at 4 samples a pixel; the compute raster draws one sample a pixel \
                 (--samples 1)",
            ),
            _ => None,
        }
    }
}

impl std::fmt::Display for Raster {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// How frames are drawn, whole: the method and, for the methods shaded in compute
/// (`visibility`, `hybrid`), the samples a pixel they rasterise and shade and where they
/// rasterise. Set in one call ([`crate::World::set_method`], [`crate::Terrain::set_method`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct MethodConfig {
    /// The method.
    pub method: Method,
    /// Samples a pixel that `visibility` and `hybrid` rasterise and shade: 4 (edges
    /// anti-aliased) or 1 (a quarter of the raster work); 1 or 4 for every method. The mesh
    /// draws at the host target's samples and keeps this for when the method changes.
    pub samples: u32,
    /// Where `visibility` and `hybrid` rasterise: [`Raster::Compute`] at one sample a pixel
    /// only.
    pub raster: Raster,
}

impl MethodConfig {
    /// The forward-shaded mesh: what a renderer draws until told otherwise.
    pub const MESH: Self = Self::new(Method::Mesh);

    /// The marching method: the visibility method at one sample a pixel rasterised in compute,
    /// the one that marches the props between its raster and its shading, so their shadows and
    /// their occlusion of the sky fall on the terrain and the grass (the others draw them
    /// through the overlay, without). What `auto` draws when props are on.
    pub const MARCHING: Self = Self::new(Method::Visibility)
        .with_samples(1)
        .with_raster(Raster::Compute);

    /// Whether it marches the props and each pixel's props' shadow on the ground
    /// ([`MethodConfig::MARCHING`] at any samples the compute raster takes; the other
    /// mesh-based methods draw them through the overlay and its shade map).
    pub fn marches_props(&self) -> bool {
        self.method == Method::Visibility && self.raster == Raster::Compute
    }

    /// `method` at 4 samples a pixel, rasterised by the GPU's rasteriser.
    pub const fn new(method: Method) -> Self {
        Self {
            method,
            samples: 4,
            raster: Raster::Hardware,
        }
    }

    /// The same at `samples` a pixel.
    pub const fn with_samples(self, samples: u32) -> Self {
        Self { samples, ..self }
    }

    /// The same rasterised by `raster`.
    pub const fn with_raster(self, raster: Raster) -> Self {
        Self { raster, ..self }
    }

    /// Refuses samples other than 1 or 4, and the compute raster at 4 samples for the methods
    /// that rasterise.
    pub fn validate(&self) -> crate::Result<()> {
        if !matches!(self.samples, 1 | 4) {
            return Err(crate::Error::invalid("samples", self.samples, "1 or 4"));
        }
        if matches!(self.method, Method::Visibility | Method::Hybrid) {
            if let Some(why) = self.raster.refusal(self.samples) {
                return Err(crate::Error::invalid("raster", self.raster, why));
            }
        }
        Ok(())
    }
}

impl Default for MethodConfig {
    fn default() -> Self {
        Self::MESH
    }
}

impl From<Method> for MethodConfig {
    fn from(method: Method) -> Self {
        Self::new(method)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Method::ALL {
            assert_eq!(Method::from_name(m.name()), Some(m));
            assert!(!m.doc().is_empty());
        }
        assert_eq!(Method::NAMES.len(), Method::ALL.len());
        let tile: Vec<&str> = Method::ALL
            .iter()
            .filter(|m| m.in_tile())
            .map(|m| m.name())
            .collect();
        assert_eq!(tile, Method::TILE_NAMES);
        let world: Vec<&str> = Method::ALL
            .iter()
            .filter(|m| m.in_world())
            .map(|m| m.name())
            .collect();
        assert_eq!(world, Method::WORLD_NAMES);
        assert_eq!(Method::from_name("raymarch-compute"), None);
    }
}
