//! Camera maths on glam: an orbit camera and the per-frame view it produces.

use glam::{DVec3, Mat4, Vec3};

/// What the render pass needs to know about the camera for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Projection (wgpu clip space, depth 0..1) times view.
    pub view_proj: Mat4,
    /// Camera position in world space (for specular and the view vector).
    pub eye: Vec3,
}

/// A camera orbiting a target point: drag changes yaw and pitch, the wheel the distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitCamera {
    /// The point looked at.
    pub target: Vec3,
    /// Rotation about the vertical axis, radians.
    pub yaw: f32,
    /// Elevation above the horizontal plane, radians (clamped to just under +-90 degrees).
    pub pitch: f32,
    /// Distance from the target.
    pub distance: f32,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl Default for OrbitCamera {
    /// The default scene's framing: the whole tile, from above and to the south-west.
    fn default() -> Self {
        Self {
            target: Vec3::new(0.0, 0.12, 0.0),
            yaw: 0.7,
            pitch: 0.55,
            distance: 2.5,
            fov_y: 45f32.to_radians(),
        }
    }
}

impl OrbitCamera {
    /// Nearest the camera may come to its target.
    pub const MIN_DISTANCE: f32 = 0.2;
    /// Farthest the camera may go from its target.
    pub const MAX_DISTANCE: f32 = 20.0;
    const MAX_PITCH: f32 = 1.55;

    /// Camera position in world space.
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + self.distance * Vec3::new(cp * sy, sp, cp * cy)
    }

    /// The view for a viewport of the given aspect ratio (width / height).
    pub fn view(&self, aspect: f32) -> View {
        let eye = self.eye();
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let view = Mat4::look_at_rh(eye, self.target, Vec3::Y);
        let near = (self.distance * 0.01).max(0.001);
        // A viewport taller than wide keeps the horizontal field of a square one, so the tile
        // is not cut at its sides (a phone held upright); a wide one keeps the vertical field.
        let fov_y = if aspect < 1.0 {
            2.0 * ((self.fov_y * 0.5).tan() / aspect).atan()
        } else {
            self.fov_y
        };
        let proj = Mat4::perspective_rh(fov_y, aspect, near, self.distance + 10.0);
        View {
            view_proj: proj * view,
            eye,
        }
    }

    /// Rotates by a drag of (dx, dy) radians.
    pub fn rotate(&mut self, dx: f32, dy: f32) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        self.yaw = (self.yaw - dx).rem_euclid(std::f32::consts::TAU);
        self.pitch = (self.pitch + dy).clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
    }

    /// Zooms by `steps` wheel notches (positive moves closer).
    pub fn zoom(&mut self, steps: f32) {
        if steps.is_finite() {
            self.distance =
                (self.distance * 0.9f32.powf(steps)).clamp(Self::MIN_DISTANCE, Self::MAX_DISTANCE);
        }
    }

    /// Raises the camera (by pitching it up about its target) until the eye is at least
    /// `clearance` above `ground(x, z)` there, and above 0 everywhere (the tile's lowest
    /// possible height): no view from inside or underneath the terrain. Returns whether it
    /// moved.
    pub fn keep_above(&mut self, ground: impl Fn(f32, f32) -> f32, clearance: f32) -> bool {
        let r = clearance.max(0.0);
        // The ground under the eye and around it (the near plane has a size too).
        let floor = |eye: Vec3| {
            [(0.0, 0.0), (r, 0.0), (-r, 0.0), (0.0, r), (0.0, -r)]
                .iter()
                .map(|(dx, dz)| ground(eye.x + dx, eye.z + dz))
                .fold(0.0f32, f32::max)
        };
        let ok = |cam: &Self| {
            let eye = cam.eye();
            eye.y >= floor(eye) + clearance
        };
        if ok(self) {
            return false;
        }
        let start = self.pitch;
        // Pitch up in small steps: the ground under the eye changes as it moves.
        while !ok(self) && self.pitch < Self::MAX_PITCH {
            self.pitch = (self.pitch + 0.005).min(Self::MAX_PITCH);
        }
        // Straight above the target and still too low (the target is inside a mountain):
        // back away until the eye clears the peak.
        while !ok(self) && self.distance < Self::MAX_DISTANCE {
            self.distance = (self.distance * 1.05).min(Self::MAX_DISTANCE);
        }
        self.pitch != start || !ok(self)
    }
}

/// A free camera for the endless world: an eye in f64 metres, a heading and a pitch. Keys move
/// it along its heading at `speed` metres per second; a drag turns it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlyCamera {
    /// Eye position, world metres.
    pub eye: glam::DVec3,
    /// Heading about the vertical axis, radians (0 looks along +x).
    pub yaw: f64,
    /// Pitch, radians (positive looks up), within +-[`FlyCamera::MAX_PITCH`].
    pub pitch: f64,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Speed, metres per second.
    pub speed: f64,
}

impl FlyCamera {
    /// Largest |pitch|: just short of straight up or down.
    pub const MAX_PITCH: f64 = 1.5;
    /// Slowest and fastest speed, metres per second.
    pub const SPEEDS: (f64, f64) = (0.5, 20_000.0);

    /// A camera at `eye` looking towards `target`.
    pub fn looking_at(eye: glam::DVec3, target: glam::DVec3, fov_y: f32) -> Self {
        let d = (target - eye).normalize_or(glam::DVec3::X);
        Self {
            eye,
            yaw: d.z.atan2(d.x),
            pitch: d
                .y
                .clamp(-1.0, 1.0)
                .asin()
                .clamp(-Self::MAX_PITCH, Self::MAX_PITCH),
            fov_y,
            speed: 200.0,
        }
    }

    /// Unit direction looked along.
    pub fn forward(&self) -> glam::DVec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        glam::DVec3::new(cp * cy, sp, cp * sy)
    }

    /// The view for a target of `size` pixels.
    pub fn view(&self, size: (u32, u32)) -> crate::WorldView {
        crate::WorldView::look_at(self.eye, self.eye + self.forward(), self.fov_y, size)
    }

    /// Turns by a drag of (dx, dy) radians (right and down turn right and down).
    pub fn turn(&mut self, dx: f64, dy: f64) {
        if dx.is_finite() && dy.is_finite() {
            self.yaw = (self.yaw + dx).rem_euclid(std::f64::consts::TAU);
            self.pitch = (self.pitch - dy).clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
        }
    }

    /// Moves for `dt` seconds: `ahead` along the heading (level), `right` sideways, `up`
    /// vertically, each in -1..=1, times the speed (and `boost`).
    pub fn fly(&mut self, ahead: f64, right: f64, up: f64, boost: f64, dt: f64) {
        if !(ahead.is_finite() && right.is_finite() && up.is_finite() && dt.is_finite()) {
            return;
        }
        let (sy, cy) = self.yaw.sin_cos();
        let level = glam::DVec3::new(cy, 0.0, sy);
        let side = glam::DVec3::new(-sy, 0.0, cy);
        let step = self.speed * boost.max(0.0) * dt.clamp(0.0, 0.25);
        self.eye += (level * ahead + side * right + glam::DVec3::Y * up) * step;
    }

    /// Scales the speed by 1.25 per wheel notch, within [`FlyCamera::SPEEDS`].
    pub fn change_speed(&mut self, steps: f64) {
        if steps.is_finite() {
            self.speed = (self.speed * 1.25f64.powf(steps)).clamp(Self::SPEEDS.0, Self::SPEEDS.1);
        }
    }

    /// Lifts the eye to at least `clearance` above `ground` under it. Returns whether it moved.
    pub fn keep_above(&mut self, ground: impl Fn(f64, f64) -> f64, clearance: f64) -> bool {
        let floor = ground(self.eye.x, self.eye.z) + clearance;
        if self.eye.y < floor || !self.eye.y.is_finite() {
            self.eye.y = floor;
            return true;
        }
        false
    }
}

/// A fly-through of the endless world along a smooth path, as in the seed template: forward
/// along +x, weaving sideways, gliding a set height over the highest ground just around and
/// ahead, looking a little down along the path. A position on it is a time in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathCamera {
    /// Speed along x, metres per second.
    pub speed: f64,
    /// Height above the highest ground nearby, metres.
    pub height: f64,
    /// Amplitude of the sideways weave, metres.
    pub weave: f64,
    /// Vertical field of view, radians.
    pub fov_y: f32,
}

impl Default for PathCamera {
    fn default() -> Self {
        Self {
            speed: 120.0,
            height: 150.0,
            weave: 900.0,
            fov_y: 50f32.to_radians(),
        }
    }
}

impl PathCamera {
    /// Largest time accepted, seconds (a day: 10,000 km at the default speed).
    pub const MAX_TIME: f64 = 86_400.0;

    /// The ground track at time `t`: (x, z).
    fn track(&self, t: f64) -> (f64, f64) {
        let x = self.speed * t;
        (
            x,
            self.weave * (x / 2100.0).sin() + 0.4 * self.weave * (x / 770.0).cos(),
        )
    }

    /// The eye's height at time `t`: `height` over the highest ground along the path from 2 s
    /// behind to 4 s ahead (so the eye rises before a ridge), sampled every half second and
    /// interpolated between sample windows so it changes continuously with `t`, and never under
    /// `height` over the ground right below.
    fn altitude(&self, ground: &impl Fn(f64, f64) -> f64, t: f64) -> f64 {
        let window = |b: f64| {
            (-4..=8)
                .map(|k| {
                    let (x, z) = self.track(b + f64::from(k) * 0.5);
                    ground(x, z)
                })
                .fold(f64::MIN, f64::max)
        };
        let base = (t * 2.0).floor() / 2.0;
        let frac = (t - base) * 2.0;
        let (w0, w1) = (window(base), window(base + 0.5));
        let (x, z) = self.track(t);
        (w0 + (w1 - w0) * frac).max(ground(x, z)) + self.height
    }

    /// Eye and look-at point at time `t` (clamped to 0..=[`PathCamera::MAX_TIME`]).
    pub fn at(&self, ground: impl Fn(f64, f64) -> f64, t: f64) -> (glam::DVec3, glam::DVec3) {
        let t = if t.is_finite() {
            t.clamp(0.0, Self::MAX_TIME)
        } else {
            0.0
        };
        let (x, z) = self.track(t);
        let eye = glam::DVec3::new(x, self.altitude(&ground, t), z);
        let ahead = t + 3.0;
        let (ax, az) = self.track(ahead);
        let target = glam::DVec3::new(ax, self.altitude(&ground, ahead) - 0.6 * self.height, az);
        (eye, target)
    }

    /// The view at time `t` for a target of `size` pixels.
    pub fn view(
        &self,
        ground: impl Fn(f64, f64) -> f64,
        t: f64,
        size: (u32, u32),
    ) -> crate::WorldView {
        let (eye, target) = self.at(ground, t);
        crate::WorldView::look_at(eye, target, self.fov_y, size)
    }
}

/// A camera in the endless world: an eye in f64 metres, a direction and a lens.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldView {
    /// Eye position in world metres (f64: it may be far from the origin).
    pub eye: DVec3,
    /// Unit direction looked along.
    pub forward: Vec3,
    /// Vertical field of view, radians.
    pub fov_y: f32,
    /// Target size in pixels (the screen-error bound is in these pixels).
    pub size: (u32, u32),
    /// Applied after the projection (a crop to a tile of the image; identity otherwise).
    pub crop: Mat4,
    /// The host's own projection times view for camera-relative positions, used instead of
    /// the lens (`fov_y` still sets the screen-error bound); `None`: the lens's, with near and
    /// far planes that fit the world.
    pub projection: Option<Mat4>,
}

impl WorldView {
    /// A view from `eye` towards `target` with a vertical field of view of `fov_y` radians.
    pub fn look_at(eye: DVec3, target: DVec3, fov_y: f32, size: (u32, u32)) -> Self {
        let forward = (target - eye).normalize_or(DVec3::Z).as_vec3();
        Self {
            eye,
            forward,
            fov_y,
            size,
            crop: Mat4::IDENTITY,
            projection: None,
        }
    }

    /// `K` of the screen-error bound: pixels per radian at the image centre.
    pub fn pixels_per_radian(&self) -> f64 {
        f64::from(self.size.1.max(1)) / (2.0 * f64::from(self.fov_y * 0.5).tan())
    }

    /// Projection times view, with the camera at the origin (positions are camera-relative).
    pub fn relative_matrix(&self, near: f32, far: f32) -> Mat4 {
        if let Some(m) = self.projection {
            return self.crop * m;
        }
        let up = if self.forward.y.abs() > 0.999 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let aspect = self.size.0.max(1) as f32 / self.size.1.max(1) as f32;
        let proj = Mat4::perspective_rh(self.fov_y, aspect, near, far);
        self.crop * proj * Mat4::look_to_rh(Vec3::ZERO, self.forward, up)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_the_centre() {
        let cam = OrbitCamera::default();
        let v = cam.view(16.0 / 9.0);
        let c = v.view_proj.project_point3(cam.target);
        assert!(c.x.abs() < 1e-5 && c.y.abs() < 1e-5 && (0.0..1.0).contains(&c.z));
    }

    #[test]
    fn a_tall_viewport_keeps_the_tile_within_its_sides() {
        // The tile's corners, seen from the default orbit: wherever they land on a square
        // viewport, they land within the same horizontal extent on an upright one.
        let cam = OrbitCamera::default();
        let corners =
            [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)].map(|(x, z)| Vec3::new(x, 0.0, z));
        let widest = |aspect: f32| {
            let v = cam.view(aspect);
            corners
                .iter()
                .map(|&p| v.view_proj.project_point3(p).x.abs())
                .fold(0.0f32, f32::max)
        };
        for aspect in [0.5f32, 0.75, 0.9] {
            assert!(
                (widest(aspect) - widest(1.0)).abs() < 1e-4,
                "aspect {aspect}"
            );
        }
        // A wide viewport is as it was: the vertical field fixed.
        let wide = cam.view(16.0 / 9.0).view_proj;
        let proj = Mat4::perspective_rh(
            cam.fov_y,
            16.0 / 9.0,
            (cam.distance * 0.01).max(0.001),
            cam.distance + 10.0,
        );
        assert_eq!(
            wide,
            proj * Mat4::look_at_rh(cam.eye(), cam.target, Vec3::Y)
        );
    }

    #[test]
    fn the_camera_never_goes_under_the_ground() {
        // A bumpy tile over [-1, 1]^2 up to 0.6 high, nothing outside.
        let ground = |x: f32, z: f32| {
            if x.abs() <= 1.0 && z.abs() <= 1.0 {
                0.3 + 0.3 * (x * 7.0).sin() * (z * 5.0).cos()
            } else {
                0.0
            }
        };
        let clearance = 0.05;
        for yaw in [0.0f32, 0.7, 2.0, 4.0] {
            for pitch in [-1.5f32, -0.6, -0.1, 0.0, 0.1, 0.55, 1.2] {
                for steps in [-30.0f32, -5.0, 0.0, 5.0, 10.0, 40.0] {
                    let mut cam = OrbitCamera {
                        yaw,
                        pitch,
                        ..Default::default()
                    };
                    cam.zoom(steps);
                    let before = cam;
                    cam.keep_above(ground, clearance);
                    let eye = cam.eye();
                    assert!(
                        eye.y >= ground(eye.x, eye.z) + clearance - 1e-4 && eye.y > 0.0,
                        "yaw {yaw} pitch {pitch} zoom {steps}: eye {eye}"
                    );
                    assert!(cam.pitch >= before.pitch);
                }
            }
        }
        // A view from well above is left alone.
        let mut cam = OrbitCamera::default();
        assert!(!cam.keep_above(ground, clearance));
        assert_eq!(cam, OrbitCamera::default());
    }

    #[test]
    fn pitch_and_zoom_are_clamped() {
        let mut cam = OrbitCamera::default();
        cam.rotate(0.0, 10.0);
        assert!(cam.pitch < std::f32::consts::FRAC_PI_2);
        cam.zoom(1000.0);
        assert_eq!(cam.distance, OrbitCamera::MIN_DISTANCE);
        assert!(cam.view(0.0).view_proj.is_finite());
    }

    #[test]
    fn the_fly_camera_looks_where_asked_moves_along_its_heading_and_stays_above_ground() {
        let eye = glam::DVec3::new(1e6, 500.0, -3.0);
        let target = eye + glam::DVec3::new(3.0, -1.0, 4.0);
        let mut cam = FlyCamera::looking_at(eye, target, 0.8);
        let want = (target - eye).normalize();
        assert!(
            (cam.forward() - want).length() < 1e-12,
            "{:?}",
            cam.forward()
        );
        let before = cam.eye;
        cam.fly(1.0, 0.0, 0.0, 1.0, 0.1);
        let moved = cam.eye - before;
        assert!(
            (moved.length() - 20.0).abs() < 1e-9 && moved.y == 0.0,
            "{moved:?}"
        );
        cam.turn(0.3, 100.0);
        assert_eq!(cam.pitch, -FlyCamera::MAX_PITCH);
        cam.change_speed(1000.0);
        assert_eq!(cam.speed, FlyCamera::SPEEDS.1);
        cam.fly(f64::NAN, 0.0, 0.0, 1.0, 0.1);
        assert!(cam.eye.is_finite());
        assert!(cam.keep_above(|_, _| 900.0, 2.0));
        assert_eq!(cam.eye.y, 902.0);
        assert!(!cam.keep_above(|_, _| 0.0, 2.0));
        assert!(cam.view((640, 480)).relative_matrix(0.1, 1e5).is_finite());
    }

    #[test]
    fn the_path_glides_over_the_ground_smoothly_and_looks_ahead() {
        let ground = |x: f64, z: f64| 300.0 * (x / 500.0).sin() * (z / 700.0).cos() + 300.0;
        let path = PathCamera::default();
        let mut last: Option<(glam::DVec3, glam::DVec3)> = None;
        for i in 0..2000 {
            let t = f64::from(i) * 0.05;
            let (eye, target) = path.at(ground, t);
            assert!(
                eye.y >= ground(eye.x, eye.z) + path.height - 1e-9,
                "t {t}: {eye:?}"
            );
            assert!(target.x > eye.x, "looks ahead");
            if let Some((e0, _)) = last {
                // 0.05 s at 120 m/s: 6 m along; the height must not jump either.
                assert!(
                    (eye - e0).length() < 40.0,
                    "t {t}: jumped from {e0:?} to {eye:?}"
                );
            }
            last = Some((eye, target));
        }
        let (e, _) = path.at(ground, f64::NAN);
        assert!(e.is_finite());
    }
}
