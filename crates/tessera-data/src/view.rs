//! The one view every technique renders from: an orbit camera over an image of a given size,
//! turned once into world-to-clip matrices, the eye's axes, the light and the pixel rays.
//!
//! The pixel model is shared by ray casters and rasterizers: the centre of raster pixel (x, y)
//! sees along `forward + sx·right + sy·up` with `sx = (2(x+½)/W − 1)·tan(fov_x/2)` and
//! `sy = (1 − 2(y+½)/H)·tan(fov_y/2)`. Clip space is Vulkan's: y points down, depth in [0, 1].
//! Techniques that work in a volume's sample grid take the view there with
//! [`View::grid_camera`] and [`View::grid_to_clip`]; none builds a matrix of its own.

use crate::camera::{GridCamera, GridFrame, OrbitCamera};
use crate::error::{DataError, Result};
use glam::{Mat4, Vec2, Vec3, Vec4};

/// Smallest near plane, as a fraction of the far plane (keeps f32 depth usable).
const MIN_NEAR_FRACTION: f32 = 1e-4;
/// World space's unit box (a volume's, or a mesh's placed by `tet::optical::MeshFrame`) lies
/// within a sphere of this radius around the origin (√3/2, rounded up).
pub const UNIT_BOX_RADIUS: f32 = 0.87;
/// Most raster samples per pixel along each axis.
pub const MAX_SUPERSAMPLE: u32 = 8;

/// What the depth range (near and far planes) is fitted to.
#[derive(Debug, Clone, Copy)]
pub enum DepthFit<'a> {
    /// World space's unit box, where volumes and tet meshes are placed: a sphere of radius
    /// [`UNIT_BOX_RADIUS`] around the origin, independent of the view direction, so the CPU
    /// references that clip at the near plane agree with every technique.
    UnitBox,
    /// Bounding spheres (centre, radius) of the objects of a parametric scene, along the view
    /// direction, with a margin of 0.1 %.
    Spheres(&'a [(Vec3, f32)]),
}

/// Near and far planes of [`DepthFit::UnitBox`]: the near plane stays a small positive distance
/// from the eye when the camera is inside the box's sphere. CPU references that clip at the near
/// plane use this too.
pub fn unit_box_depth_range(camera: &OrbitCamera) -> (f32, f32) {
    let far = camera.distance + UNIT_BOX_RADIUS;
    let near = (camera.distance - UNIT_BOX_RADIUS).max(far * MIN_NEAR_FRACTION);
    (near, far)
}

impl DepthFit<'_> {
    /// View-space depths of the near and far planes for `camera`.
    fn near_far(&self, camera: &OrbitCamera) -> Result<(f32, f32)> {
        match self {
            DepthFit::UnitBox => Ok(unit_box_depth_range(camera)),
            DepthFit::Spheres(bounds) => {
                let forward = camera.basis().0;
                let eye = camera.eye();
                let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
                for &(centre, radius) in bounds.iter() {
                    let d = forward.dot(centre - eye);
                    lo = lo.min(d - radius);
                    hi = hi.max(d + radius);
                }
                if !hi.is_finite() || !lo.is_finite() {
                    return Err(DataError::Invalid(
                        "the scene has no finite bounds to fit the depth range to".into(),
                    ));
                }
                // Everything behind the eye: any range will do, nothing is drawn.
                let far = (hi * 1.001).max(1e-3);
                let near = (lo * 0.999).max(far * MIN_NEAR_FRACTION);
                Ok((near, far))
            }
        }
    }
}

/// A camera over an image, with everything techniques derive from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub camera: OrbitCamera,
    /// Image size in pixels.
    pub size: (u32, u32),
    /// Raster samples per image pixel along each axis (1 = no supersampling).
    pub supersample: u32,
    pub eye: Vec3,
    /// Unit axes of the camera in world space; the eye shift of a stereo eye does not turn them.
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    /// `tan` of half the field of view across (x) and down (y).
    pub tan_half_fov: Vec2,
    /// Unit direction towards the light: above, right and behind the eye.
    pub light: Vec3,
    pub near: f32,
    pub far: f32,
    pub world_to_view: Mat4,
    pub view_to_clip: Mat4,
    pub world_to_clip: Mat4,
}

impl View {
    /// The view of `camera` onto an image of `size` pixels, `supersample`² raster samples per
    /// pixel, with the depth range fitted to `fit`.
    pub fn new(
        camera: &OrbitCamera,
        size: (u32, u32),
        supersample: u32,
        fit: DepthFit,
    ) -> Result<View> {
        if size.0 == 0 || size.1 == 0 {
            return Err(DataError::Invalid(format!(
                "image size {}x{} is empty",
                size.0, size.1
            )));
        }
        if supersample == 0 || supersample > MAX_SUPERSAMPLE {
            return Err(DataError::Invalid(format!(
                "supersampling must be 1 to {MAX_SUPERSAMPLE} samples per axis, got {supersample}"
            )));
        }
        let eye = camera.eye();
        if !(eye.is_finite() && camera.fov_y_deg > 0.0 && camera.fov_y_deg < 180.0) {
            return Err(DataError::Invalid(format!("unusable camera {camera:?}")));
        }
        let (near, far) = fit.near_far(camera)?;
        Ok(View::with_depth_range(camera, size, supersample, near, far))
    }

    /// A view of the unit box without supersampling: what volume and mesh techniques and their
    /// CPU references use. Unchecked: an empty side counts as one pixel.
    pub fn of_unit_box(camera: &OrbitCamera, size: (u32, u32)) -> View {
        let size = (size.0.max(1), size.1.max(1));
        let (near, far) = unit_box_depth_range(camera);
        View::with_depth_range(camera, size, 1, near, far)
    }

    fn with_depth_range(
        camera: &OrbitCamera,
        size: (u32, u32),
        supersample: u32,
        near: f32,
        far: f32,
    ) -> View {
        let (forward, right, up) = camera.basis();
        let eye = camera.eye();
        let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
        let tan_x = tan_y * size.0 as f32 / size.1 as f32;
        // World to view: rows are the camera axes, translated by the eye.
        let world_to_view = Mat4::from_cols(
            Vec4::new(right.x, up.x, forward.x, 0.0),
            Vec4::new(right.y, up.y, forward.y, 0.0),
            Vec4::new(right.z, up.z, forward.z, 0.0),
            Vec4::new(-right.dot(eye), -up.dot(eye), -forward.dot(eye), 1.0),
        );
        // View (x right, y up, z forward) to clip: x / tan_x, -y / tan_y, depth 0 at near and
        // 1 at far, w = z.
        let a = far / (far - near);
        let view_to_clip = Mat4::from_cols(
            Vec4::new(1.0 / tan_x, 0.0, 0.0, 0.0),
            Vec4::new(0.0, -1.0 / tan_y, 0.0, 0.0),
            Vec4::new(0.0, 0.0, a, 1.0),
            Vec4::new(0.0, 0.0, -a * near, 0.0),
        );
        View {
            camera: *camera,
            size,
            supersample,
            eye,
            forward,
            right,
            up,
            tan_half_fov: Vec2::new(tan_x, tan_y),
            light: (-forward + 0.6 * up + 0.4 * right).normalize(),
            near,
            far,
            world_to_view,
            view_to_clip,
            world_to_clip: view_to_clip * world_to_view,
        }
    }

    /// The two eyes of a stereo pair `separation` world units apart, with this view's depth
    /// range (both eyes then share one depth buffer's meaning).
    pub fn stereo_pair(&self, separation: f32) -> [View; 2] {
        self.camera.stereo_pair(separation).map(|eye| {
            View::with_depth_range(&eye, self.size, self.supersample, self.near, self.far)
        })
    }

    /// The same camera over another image size (e.g. a window that was resized).
    /// The depth range does not depend on the image size, so it is kept.
    pub fn resized(&self, size: (u32, u32)) -> Result<View> {
        if size.0 == 0 || size.1 == 0 {
            return Err(DataError::Invalid(format!(
                "image size {}x{} is empty",
                size.0, size.1
            )));
        }
        let (near, far) = (self.near, self.far);
        Ok(View::with_depth_range(
            &self.camera,
            size,
            self.supersample,
            near,
            far,
        ))
    }

    /// The raster the passes draw into: `supersample` times the image size.
    pub fn raster_size(&self) -> (u32, u32) {
        (
            self.size.0 * self.supersample,
            self.size.1 * self.supersample,
        )
    }

    pub fn viewport(&self) -> Vec2 {
        let (w, h) = self.raster_size();
        Vec2::new(w as f32, h as f32)
    }

    /// Screen offsets `(sx, sy)` of raster pixel (x, y)'s centre; y grows downwards.
    pub fn screen(&self, x: u32, y: u32) -> Vec2 {
        let (w, h) = self.raster_size();
        let sx = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * self.tan_half_fov.x;
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * self.tan_half_fov.y;
        Vec2::new(sx, sy)
    }

    /// The world-space ray through raster pixel (x, y)'s centre: origin and unit direction.
    pub fn pixel_ray(&self, x: u32, y: u32) -> (Vec3, Vec3) {
        let s = self.screen(x, y);
        let direction = (self.forward + s.x * self.right + s.y * self.up).normalize();
        (self.eye, direction)
    }

    /// Raster position and NDC depth of world point `p`, `None` when not in front of the eye.
    /// The operation order is that of `param_project` in the parametric shaders' `view.glsl`.
    pub fn project(&self, p: Vec3) -> Option<(Vec2, f32)> {
        let m = self.world_to_clip;
        let clip = ((m.x_axis * p.x + m.y_axis * p.y) + m.z_axis * p.z) + m.w_axis;
        let viewport = self.viewport();
        let pixel = Vec2::new(
            (clip.x / clip.w * 0.5 + 0.5) * viewport.x,
            (clip.y / clip.w * 0.5 + 0.5) * viewport.y,
        );
        (clip.w > 0.0 && !pixel.is_nan()).then_some((pixel, clip.z / clip.w))
    }

    /// The camera in a volume's sample grid, for ray casters.
    pub fn grid_camera(&self, frame: &GridFrame) -> GridCamera {
        GridCamera {
            eye: frame.world_to_grid_point(self.eye),
            forward: frame.world_to_grid_vector(self.forward),
            right: frame.world_to_grid_vector(self.right),
            up: frame.world_to_grid_vector(self.up),
            tan_half_fov_x: self.tan_half_fov.x,
            tan_half_fov_y: self.tan_half_fov.y,
            light_world: self.light,
        }
    }

    /// Grid point (w = 1) of a volume placed by `frame` to clip space.
    pub fn grid_to_clip(&self, frame: &GridFrame) -> Mat4 {
        self.world_to_clip * frame.grid_to_world_matrix()
    }
}

#[cfg(test)]
#[path = "view_tests.rs"]
mod tests;
