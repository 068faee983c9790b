//! The palettes: how terrain is coloured and lit.
//!
//! - [`Palette::SeedTemplate`] (the endless world's default), after the ShaderToy-style
//!   template relief grew from: rock, grass, snow and sand chosen by height, slope and noise
//!   with soft, noise-perturbed edges; the sun (Blinn-Phong, shadowed), a hemisphere of sky
//!   light (dimmer from below), a weak back light from the side away from the sun, a Fresnel
//!   rim of sky light at grazing angles, valley occlusion, and a tone curve ([`tone_map`]).
//! - [`Palette::Blog`]: the seed blog's look, kept as a preset: two colours mixed by the colour
//!   noise, a snow line, Blinn-Phong with height occlusion `h^k`, no tone curve. The tile
//!   always draws with it.
//!
//! The materials live in `shade` in `wgsl/shade.wgsl`, one code path for every method.

/// How terrain is coloured and lit (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Palette {
    /// Rock, grass, snow and sand, with the template's lighting and a tone curve.
    #[default]
    SeedTemplate,
    /// The seed blog's two colours, snow line and height occlusion.
    Blog,
}

impl Palette {
    /// Every palette, in the order the help lists them.
    pub const ALL: [Palette; 2] = [Palette::SeedTemplate, Palette::Blog];
    /// Their names, in the same order.
    pub const NAMES: &'static [&'static str] = &["seed-template", "blog"];

    /// The name on the command line, in scene files and in the page's URL.
    pub fn name(self) -> &'static str {
        match self {
            Palette::SeedTemplate => "seed-template",
            Palette::Blog => "blog",
        }
    }

    /// The palette called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// What `RenderUniforms::palette` carries (`PALETTE_BLOG` and `PALETTE_TEMPLATE` in
    /// `wgsl/shade.wgsl`).
    pub fn code(self) -> u32 {
        match self {
            Palette::Blog => 0,
            Palette::SeedTemplate => 1,
        }
    }
}

/// Where the tone curve leaves the identity.
pub(crate) const SHOULDER: f32 = 0.8;

/// The seed template's tone curve, per linear channel: the identity up to `SHOULDER`, then a
/// shoulder that rolls off smoothly (continuous in value and slope) towards 1, so bright snow
/// and the sun's halo keep their gradations instead of clipping. The twin of `tone_map` in
/// `wgsl/shade.wgsl`.
pub fn tone_map(x: f32) -> f32 {
    if x <= SHOULDER {
        x
    } else {
        let k = 1.0 - SHOULDER;
        SHOULDER + k * (1.0 - (-(x - SHOULDER) / k).exp())
    }
}

/// CIE L*a*b* (D65) of a linear sRGB colour: what colour differences are measured in.
pub fn cie_lab(c: [f64; 3]) -> [f64; 3] {
    let [r, g, b] = c;
    let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
    let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
    let f = |t: f64| {
        if t > 216.0 / 24389.0 {
            t.cbrt()
        } else {
            (24389.0 / 27.0 * t + 16.0) / 116.0
        }
    };
    let (fx, fy, fz) = (f(x), f(y), f(z));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// The CIE76 difference (ΔE) of two linear sRGB colours: about 2.3 is just noticeable.
pub fn delta_e(a: [f64; 3], b: [f64; 3]) -> f64 {
    let (p, q) = (cie_lab(a), cie_lab(b));
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_the_curve_is_smooth_and_bounded() {
        for p in Palette::ALL {
            assert_eq!(Palette::from_name(p.name()), Some(p));
        }
        assert_eq!(Palette::from_name("rainbow"), None);
        assert_eq!(tone_map(0.5), 0.5);
        let e = 1e-3;
        let slope = (tone_map(SHOULDER + e) - tone_map(SHOULDER)) / e;
        assert!((slope - 1.0).abs() < 0.01, "{slope}");
        assert!(tone_map(100.0) <= 1.0 && tone_map(2.0) > tone_map(1.0));
    }
}
