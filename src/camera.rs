//! Camera maths on glam: an orbit camera and the per-frame view it produces.

use glam::{Mat4, Vec3};

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
        let proj = Mat4::perspective_rh(self.fov_y, aspect, near, self.distance + 10.0);
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
}
