//! [`World`]'s per-frame uniforms: the camera-relative matrix, the frustum's patches, the
//! render uniforms (sky, fog, water, the clock folded to its period) and their constants.

use super::*;

impl World {
    /// Selects the patches inside `view`'s frustum and writes the frame's uniforms.
    pub(super) fn write_uniforms(&mut self, queue: &wgpu::Queue, view: &WorldView) {
        let s0 = 2f64.powi(self.map.finest_log2);
        let reference = [(view.eye.x / s0).floor(), (view.eye.z / s0).floor()];
        self.reference = [reference[0] as i64, reference[1] as i64];
        let eye_frac = [
            view.eye.x - reference[0] * s0,
            view.eye.z - reference[1] * s0,
        ];
        let land = &self.params.land;
        let altitude = (view.eye.y - land.height_at(view.eye.x, view.eye.z)).max(0.0);
        let coarsest = self.map.levels.last().expect("a clipmap has levels");
        let far = (f64::from(self.map.cells()) * coarsest.spacing()) as f32;
        let near = (altitude as f32 * 0.1).clamp(0.05, 20.0);
        let matrix = view.relative_matrix(near, far);
        self.matrix = matrix;
        self.near_far = (near, far);
        let planes = frustum_planes(&matrix);
        let eye = view.eye;
        let bounds = self.tile.map_or(
            [
                f64::NEG_INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::INFINITY,
            ],
            |t| t.region,
        );
        let patches = self.map.patches([0.0, land.peak_height], |lo, hi| {
            if hi[0] < bounds[0] || hi[2] < bounds[1] || lo[0] > bounds[2] || lo[2] > bounds[3] {
                return false;
            }
            let lo = (DVec3::from(lo) - eye).as_vec3();
            let hi = (DVec3::from(hi) - eye).as_vec3();
            planes.iter().all(|p| {
                let v = Vec3::new(
                    if p.x >= 0.0 { hi.x } else { lo.x },
                    if p.y >= 0.0 { hi.y } else { lo.y },
                    if p.z >= 0.0 { hi.z } else { lo.z },
                );
                p.truncate().dot(v) + p.w >= 0.0
            })
        });
        // The tile's edge crosses patches: only their sub-patches inside it are drawn (or, in
        // the unlikely case that they overflow the buffer, the crossed patches whole).
        let (whole, subs) = match self.tile {
            Some(t) => Some(self.map.trim(&patches, t.region))
                .filter(|(w, s)| w.len() + s.len() <= instance_capacity(true))
                .unwrap_or((patches, Vec::new())),
            None => (patches, Vec::new()),
        };
        queue.write_buffer(&self.instances, 0, bytemuck::cast_slice(&whole));
        let at = std::mem::size_of_val(whole.as_slice()) as u64;
        queue.write_buffer(&self.instances, at, bytemuck::cast_slice(&subs));
        self.instance_counts = [whole.len() as u32, subs.len() as u32];
        self.raster_passes = crate::gpu::raster::pass_ends(whole.iter().map(|p| p.level));

        let first = self.map.first_drawn();
        let mut levels = [LevelUniforms::default(); MAX_LEVELS];
        let side = i64::from(self.map.side());
        let n = self.map.levels.len();
        for (l, level) in self.map.levels.iter().enumerate() {
            let shift = level.spacing_log2 - self.map.finest_log2;
            let coarse = (l + 1 < n).then(|| self.map.levels[l + 1]);
            let origin = [i64::from(level.origin[0]), i64::from(level.origin[1])];
            levels[l] = LevelUniforms {
                origin_rel: [
                    ((origin[0] << shift) - self.reference[0]) as i32,
                    ((origin[1] << shift) - self.reference[1]) as i32,
                ],
                // Inactive levels keep a stale origin: wrapping, never used.
                delta: coarse.map_or([0; 2], |c| {
                    [
                        level.origin[0].wrapping_sub(c.origin[0].wrapping_mul(2)),
                        level.origin[1].wrapping_sub(c.origin[1].wrapping_mul(2)),
                    ]
                }),
                origin_mod: [
                    origin[0].rem_euclid(side) as u32,
                    origin[1].rem_euclid(side) as u32,
                ],
                shift: shift as u32,
                layer: level.layer,
                coarse: if coarse.is_some() {
                    l as u32 + 1
                } else {
                    l as u32
                },
                has_coarse: u32::from(coarse.is_some_and(|c| c.active)),
                eye_local: [
                    (view.eye.x / level.spacing() - f64::from(level.origin[0])) as f32,
                    (view.eye.z / level.spacing() - f64::from(level.origin[1])) as f32,
                ],
                clip: {
                    let local = |v: f64, o: i32| {
                        (v / level.spacing() - f64::from(o)).clamp(-1e9, 1e9) as f32
                    };
                    [
                        local(bounds[0], level.origin[0]),
                        local(bounds[1], level.origin[1]),
                        local(bounds[2], level.origin[0]),
                        local(bounds[3], level.origin[1]),
                    ]
                },
                raise: self.level_raise(level.spacing_log2) as f32,
                light_from: if self.tile.is_some() {
                    l as u32
                } else {
                    self.light.queue.light_from(&self.map, l)
                },
                _pad: [0; 2],
            };
        }
        let world = WorldUniforms {
            eye: [
                eye_frac[0] as f32,
                view.eye.y as f32,
                eye_frac[1] as f32,
                s0 as f32,
            ],
            cells: self.map.cells(),
            patch_cells: self.map.patch,
            side: self.map.side(),
            morphing: u32::from(self.map.morphing),
            morph: self.map.morph.map(|m| m as f32),
            peak: land.peak_height as f32,
            // A first level drawn coarser than the first active (finer ones wait on a bake) is
            // not faded.
            fade: if self.map.levels.get(first).is_some_and(|l| l.active)
                && (first == 0 || !self.map.levels[first - 1].active)
            {
                self.map.fade as f32
            } else {
                0.0
            },
            first: first as u32,
            tile_eye: self.tile.map_or([0.0; 2], |t| {
                [(eye.x - t.region[0]) as f32, (eye.z - t.region[1]) as f32]
            }),
            tile_inv: self
                .tile
                .map_or(0.0, |t| (1.0 / (t.region[2] - t.region[0])) as f32),
            levels,
        };
        queue.write_buffer(&self.world_uniforms, 0, bytemuck::bytes_of(&world));

        let encode = !self.targets.color_format.is_srgb();
        let region = self.map.drawn_region(eye.x, eye.z);
        let uniforms = match self.tile {
            // The tile: the shading's own sun and sky, clear air, no water.
            Some(t) => tile_uniforms(&self.params, &self.shading, matrix, encode, &t),
            None => {
                let now = WorldParams {
                    clock: self.clock(),
                    sky: self.sky(),
                    ..self.params
                };
                let mut u = render_uniforms(&now, &self.shading, (matrix, region, eye), encode);
                if u.clouds[0] > 0.0 {
                    u.cloud_march[2] = self.cloud_offset(view.size);
                }
                // The ground under the grass, where the method draws its blades.
                if self.grass.is_some() && self.method.is_mesh() {
                    u.grass_distance = self.params.grass.distance;
                    u.grass_cover = self.params.grass.field_cover();
                }
                // The props' shade map, where the overlay draws the props (its bake follows).
                if self.props_overlaid() {
                    u.props_map_levels = crate::gpu::props_map::LEVELS as u32;
                    u.props_map = crate::gpu::props_map::placement(eye);
                }
                // The terrain's shadows in the air, where the frame draws shafts (the map's
                // bake follows).
                if crate::gpu::air_shadow::drawn(&u) {
                    u.air_shadow = crate::gpu::air_shadow::placement(eye);
                }
                u
            }
        };
        queue.write_buffer(&self.render_uniforms, 0, bytemuck::bytes_of(&uniforms));
        self.shafts.sun = (uniforms.air_shadow[3] > 0.0).then(|| {
            Vec3::new(
                uniforms.sun_dir[0],
                uniforms.sun_dir[1],
                uniforms.sun_dir[2],
            )
        });
        if let Some(history) = &self.mesh_history {
            history.write_uniforms(queue, &uniforms);
        }

        let active: Vec<_> = self.map.levels[first.min(n)..]
            .iter()
            .filter(|l| l.active)
            .collect();
        let cells = |n: usize, side: u32| n as u64 * u64::from(side).pow(2);
        self.stats = WorldStats {
            triangles: 2
                * (cells(whole.len(), self.map.patch) + cells(subs.len(), self.map.sub_cells())),
            patches: (whole.len() + subs.len()) as u32,
            texels_baked: self.stats.texels_baked,
            levels: active.len() as u32,
            levels_total: n as u32,
            patch_cells: self.map.patch,
            finest_spacing: active.first().map_or(0.0, |l| l.spacing()),
            error_bound_px: self.map.error_bound(view.pixels_per_radian()),
            texels_pending: self.map.pending_texels(),
            light_texels: self.stats.light_texels,
            light_pending: self.light_pending(),
            level_bytes: level_bytes(&self.map),
            // The resolve (after the shading) says.
            history_frames: 0,
            history_fresh: None,
            // Every pixel whose ray crosses the layer, every frame.
            clouds: (self.tile.is_none() && self.params.clouds.on())
                .then_some((1.0, self.params.clouds.steps.max(1))),
        };
        self.frame_prepared = true;
    }

    /// The camera-relative projection times view of the last [`World::prepare`] (positions
    /// relative to the eye): what turns its depth buffer back into positions.
    pub fn relative_matrix(&self) -> Mat4 {
        self.matrix
    }
}

/// How far the drawn square `region` ([`Clipmap::drawn_region`]) reaches from `eye` in every
/// direction: the terrain fades into the sky before this distance (where fog is on).
pub fn horizon(region: [f64; 4], eye: DVec3) -> f64 {
    (eye.x - region[0])
        .min(region[2] - eye.x)
        .min(eye.z - region[1])
        .min(region[3] - eye.z)
        .max(0.0)
}

/// Where terrain begins fading into the sky, as a fraction of [`horizon`].
pub(crate) const FADE_START: f64 = 0.7;

/// The shading uniforms of the endless world for a camera-relative `matrix` (the camera at the
/// origin), the square drawn (`region`, [`Clipmap::drawn_region`]) and the `eye`, shared by the
/// mesh and the ray casters: the sun and sky of `params.sky`, its fog and (with fog) the fade
/// into the sky before the [`horizon`], and the water.
pub fn render_uniforms(
    params: &WorldParams,
    shading: &Shading,
    (matrix, region, eye): (Mat4, [f64; 4], DVec3),
    encode_srgb: bool,
) -> RenderUniforms {
    // The sun where a running day has it at the frame's clock.
    let params = &WorldParams {
        sky: crate::world::day::sky_at(params.sky, params.clock),
        ..*params
    };
    let horizon = horizon(region, eye);
    let mut u = base_uniforms(params, shading, matrix, encode_srgb, 0);
    let sun = glam::Vec4::from(u.sun_color).truncate().to_array();
    let light = SkyLight::new(params.sky.sun_direction(), sun);
    u.set_sky(shading, &light);
    u.ambient_color = u.ambient_color.map(|c| c * light.day);
    u.ambient_color[3] = 1.0;
    // The world casts shadows (its callers pass the horizon) in its palette.
    u.shadows = u32::from(!params.no_shadows);
    u.palette = params.palette.code();
    if params.sky.fog > 0.0 {
        let e = params.sky.extinction();
        u.fog = [e[0], e[1], e[2], 0.0];
        u.fade_start = (FADE_START * horizon) as f32;
        u.fade_end = horizon as f32;
    }
    if !params.no_water {
        let peak = params.land.peak_height;
        let period = f64::from(RIPPLE_PERIOD);
        // The clock and the wind's drift reduced in f64 before they become f32: the waves
        // repeat every CLOCK_PERIOD seconds and every RIPPLE_PERIOD metres.
        let drift = params.wind.velocity() * params.clock;
        u.water_level = (f64::from(params.water_level) / peak) as f32;
        u.water_plane = (f64::from(params.water_level) - eye.y) as f32;
        u.clock = params.clock.rem_euclid(f64::from(CLOCK_PERIOD)) as f32;
        u.water_on = 1;
        u.ripple_origin = [
            (eye.x - drift.x).rem_euclid(period) as f32,
            (eye.z - drift.y).rem_euclid(period) as f32,
        ];
        u.sand_band = (SAND_BAND / peak) as f32;
    }
    if params.clouds.on() {
        cloud_uniforms(&mut u, params, eye, (&light, sun));
    }
    u
}

/// The clouds' uniforms (`wgsl/clouds.wgsl`): the layer, where the eye is in it (the wind's
/// drift reduced in f64), the sun the layer sees; and the overcast: the sky's colours, and so
/// the ambient light and the air's, go grey as the coverage grows.
fn cloud_uniforms(
    u: &mut RenderUniforms,
    params: &WorldParams,
    eye: DVec3,
    (light, above): (&SkyLight, [f32; 3]),
) {
    use crate::world::clouds::Clouds;
    let c = &params.clouds;
    u.clouds = [c.coverage, c.base, c.top, c.kind];
    u.cloud_origin = Clouds::origin(eye, params.wind.velocity() * params.clock);
    u.cloud_march = [
        eye.y as f32,
        c.steps.max(1) as f32,
        0.5,
        f32::from(u8::from(c.shafts)),
    ];
    let seen = SkyLight::new(c.sun_direction(light.sun_dir), above);
    u.cloud_sun = [seen.sun[0], seen.sun[1], seen.sun[2], 0.0];
    let grey = 0.6 * c.coverage * c.coverage;
    for colour in [&mut u.sky_zenith, &mut u.sky_horizon, &mut u.ambient_color] {
        let y = 0.2126 * colour[0] + 0.7152 * colour[1] + 0.0722 * colour[2];
        for v in colour.iter_mut().take(3) {
            *v += (y - *v) * grey;
        }
    }
}

/// The tile's uniforms: the [`Shading`]'s sun and sky (as the tile always had), the blog
/// palette's height occlusion, no shadows, fog or water.
pub(super) fn tile_uniforms(
    params: &WorldParams,
    shading: &Shading,
    matrix: Mat4,
    encode_srgb: bool,
    setup: &TileSetup,
) -> RenderUniforms {
    let mut u = base_uniforms(params, shading, matrix, encode_srgb, setup.tex_size);
    u.palette = crate::palette::Palette::Blog.code();
    u.shift = setup.shift;
    u
}

/// What every world's uniforms start from: the shading's sun and sky, clear air, the heights
/// in metres, camera-relative `matrix`, and the tile's textures' side (0: none).
pub(super) fn base_uniforms(
    params: &WorldParams,
    shading: &Shading,
    matrix: Mat4,
    encode_srgb: bool,
    tex_size: u32,
) -> RenderUniforms {
    let heights = TerrainParams {
        height_scale: params.land.peak_height as f32,
        snow_height: params.snow_height,
        ao_exponent: params.ao_exponent,
        ..TerrainParams::default()
    };
    let relative = View {
        view_proj: matrix,
        eye: Vec3::ZERO,
    };
    RenderUniforms {
        grid: 0,
        tex_size,
        ..RenderUniforms::new(&heights, shading, &relative, encode_srgb)
    }
}

/// Period in metres of the water's ripples (`RIPPLE_PERIOD` in `wgsl/shade.wgsl`).
pub const RIPPLE_PERIOD: f32 = 256.0;

/// Period in seconds of everything that moves on its own (`CLOCK_PERIOD` in
/// `wgsl/shade.wgsl`): the clock reaches the shaders reduced modulo it, and each wave repeats
/// within it (a whole number of cycles).
pub const CLOCK_PERIOD: f32 = 4096.0;

pub use crate::world::SAND_BAND;

/// The six planes (a x + b y + c z + d >= 0 inside) of a wgpu clip-space frustum (depth 0..1).
pub(super) fn frustum_planes(m: &Mat4) -> [Vec4; 6] {
    let r = |i: usize| m.row(i);
    [
        r(3) + r(0),
        r(3) - r(0),
        r(3) + r(1),
        r(3) - r(1),
        r(2),
        r(3) - r(2),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ripples_drift_downwind_with_the_clock() {
        // A west wind (from 270 degrees) blows towards +x, east.
        let params = WorldParams {
            wind: crate::world::Wind {
                speed: 4.0,
                from_azimuth: 270.0,
            },
            ..Default::default()
        };
        let v = params.wind.velocity();
        assert!((v.x - 4.0).abs() < 1e-9 && v.y.abs() < 1e-9, "{v}");
        let eye = DVec3::new(100.0, 1500.0, 30.0);
        let origin = |clock: f64| {
            let p = WorldParams { clock, ..params };
            let u = render_uniforms(
                &p,
                &Shading::default(),
                (Mat4::IDENTITY, [-1e4, -1e4, 1e4, 1e4], eye),
                false,
            );
            (u.ripple_origin[0], u.ripple_origin[1])
        };
        // The pattern's coordinate of a fixed point is its position less the drift: after 10 s
        // at 4 m/s the pattern has moved 40 m east, so the eye sees it 40 m further west.
        assert_eq!(origin(0.0), (100.0, 30.0));
        assert_eq!(origin(10.0), (60.0, 30.0));
        // Reduced in f64 modulo the ripples' period, whatever the clock.
        let late = origin(1e9);
        let want = (100.0 - 4e9f64).rem_euclid(f64::from(RIPPLE_PERIOD)) as f32;
        assert_eq!(late.0, want);
        assert!((0.0..RIPPLE_PERIOD).contains(&late.0));
    }
}
