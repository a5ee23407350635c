//! Orbit camera and the mapping between a volume's sample grid and world space.
//!
//! World space puts the volume's centre at the origin with its longest physical side of length
//! 1, so one camera distance fits volumes of any size. Ray casters work in grid space (sample
//! (x,y,z) at position (x,y,z)); [`GridCamera`] carries the camera into it.

use crate::view::View;
use glam::Vec3;

/// Which world axis points up on screen. Grid axes are world axes (scaled), so for a volume
/// this names a grid axis and its direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ViewUp {
    PlusX,
    MinusX,
    /// The usual default: +y up.
    #[default]
    PlusY,
    MinusY,
    PlusZ,
    MinusZ,
}

impl ViewUp {
    pub const ALL: [ViewUp; 6] = [
        ViewUp::PlusX,
        ViewUp::MinusX,
        ViewUp::PlusY,
        ViewUp::MinusY,
        ViewUp::PlusZ,
        ViewUp::MinusZ,
    ];

    /// `x`, `-x`, `y`, `-y`, `z`, `-z` (also `+x` etc., any case).
    pub fn parse(text: &str) -> Result<ViewUp, String> {
        let t = text.trim().to_ascii_lowercase();
        let t = t.strip_prefix('+').unwrap_or(&t);
        ViewUp::ALL
            .into_iter()
            .find(|u| u.name() == t)
            .ok_or_else(|| format!("view up '{text}': choose x, y, z, -x, -y or -z"))
    }

    pub fn name(self) -> &'static str {
        match self {
            ViewUp::PlusX => "x",
            ViewUp::MinusX => "-x",
            ViewUp::PlusY => "y",
            ViewUp::MinusY => "-y",
            ViewUp::PlusZ => "z",
            ViewUp::MinusZ => "-z",
        }
    }

    /// Grid axis `axis` (0 = x) pointing up when `sign` > 0, down otherwise (the form of
    /// [`crate::Volume::up_axis`]); `None` for an axis past 2.
    pub fn from_axis(axis: usize, sign: i8) -> Option<ViewUp> {
        let up = [
            [ViewUp::PlusX, ViewUp::MinusX],
            [ViewUp::PlusY, ViewUp::MinusY],
            [ViewUp::PlusZ, ViewUp::MinusZ],
        ]
        .get(axis)?;
        Some(if sign > 0 { up[0] } else { up[1] })
    }

    /// The view up towards the patient's head, from a grid's `up_axis` (as
    /// [`crate::Orientation::up_axis`] gives it); `None` where the file names no anatomical
    /// space.
    pub fn towards_head(up_axis: Option<(usize, i8)>) -> Option<ViewUp> {
        up_axis.and_then(|(axis, sign)| ViewUp::from_axis(axis, sign))
    }

    /// A right-handed orthonormal frame (x', y', z') with y' up: the orbit is laid out in it
    /// as it is in (x, y, z) for +y, so azimuth turns about the up axis and azimuth 0 looks
    /// along -z'.
    pub fn frame(self) -> (Vec3, Vec3, Vec3) {
        match self {
            ViewUp::PlusY => (Vec3::X, Vec3::Y, Vec3::Z),
            ViewUp::MinusY => (-Vec3::X, -Vec3::Y, Vec3::Z),
            ViewUp::PlusZ => (Vec3::X, Vec3::Z, -Vec3::Y),
            ViewUp::MinusZ => (Vec3::X, -Vec3::Z, Vec3::Y),
            ViewUp::PlusX => (-Vec3::Y, Vec3::X, Vec3::Z),
            ViewUp::MinusX => (Vec3::Y, -Vec3::X, Vec3::Z),
        }
    }

    /// The world vector that appears up on screen.
    pub fn vector(self) -> Vec3 {
        self.frame().1
    }
}

/// A camera on a sphere around the origin, looking at it with [`OrbitCamera::up`] up (+Y by
/// default): azimuth turns about the up axis, elevation lifts towards it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitCamera {
    pub azimuth_deg: f32,
    pub elevation_deg: f32,
    /// Distance from the origin in world units (the volume's longest side is 1).
    pub distance: f32,
    pub fov_y_deg: f32,
    /// Sideways shift of the eye along the camera's right axis, in world units, keeping the
    /// view direction: the two eyes of a stereo pair are ±half the eye separation.
    pub eye_shift: f32,
    /// Upward shift of the eye along the camera's up axis, in world units, keeping the view
    /// direction: with `eye_shift`, how a viewer pans.
    pub eye_rise: f32,
    /// The world axis that appears up on screen.
    pub up: ViewUp,
}

impl Default for OrbitCamera {
    fn default() -> Self {
        OrbitCamera {
            azimuth_deg: 30.0,
            elevation_deg: 20.0,
            distance: 1.8,
            fov_y_deg: 40.0,
            eye_shift: 0.0,
            eye_rise: 0.0,
            up: ViewUp::PlusY,
        }
    }
}

impl OrbitCamera {
    /// Parses `AZ,EL,DIST` (degrees, degrees, world units).
    pub fn parse(text: &str) -> Result<OrbitCamera, String> {
        let parts: Vec<&str> = text.split(',').map(str::trim).collect();
        if parts.len() != 3 {
            return Err(format!("camera '{text}': expected AZ,EL,DIST"));
        }
        let num = |s: &str| {
            s.parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("camera '{text}': '{s}' is not a number"))
        };
        let camera = OrbitCamera {
            azimuth_deg: num(parts[0])?,
            elevation_deg: num(parts[1])?,
            distance: num(parts[2])?,
            ..OrbitCamera::default()
        };
        if camera.distance <= 0.0 {
            return Err(format!("camera '{text}': distance must be positive"));
        }
        Ok(camera)
    }

    /// The orbit position, before any eye shift or rise.
    fn orbit_position(&self) -> Vec3 {
        // Straight up or down has no defined "right"; stay just short of the pole.
        let el = self.elevation_deg.clamp(-89.9, 89.9).to_radians();
        let az = self.azimuth_deg.to_radians();
        let (x, y, z) = self.up.frame();
        self.distance * (el.cos() * az.sin() * x + el.sin() * y + el.cos() * az.cos() * z)
    }

    pub fn eye(&self) -> Vec3 {
        let (_, right, up) = self.basis();
        self.orbit_position() + right * self.eye_shift + up * self.eye_rise
    }

    /// Orthonormal (forward, right, up) in world space; the eye shift and rise do not turn it.
    pub fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (-self.orbit_position()).normalize();
        let right = forward.cross(self.up.vector()).normalize();
        let up = right.cross(forward);
        (forward, right, up)
    }

    /// The left and right eyes of a stereo pair `separation` world units apart.
    pub fn stereo_pair(&self, separation: f32) -> [OrbitCamera; 2] {
        [-0.5, 0.5].map(|side| OrbitCamera {
            eye_shift: self.eye_shift + side * separation,
            ..*self
        })
    }
}

/// How sample-grid coordinates map to world space for a volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridFrame {
    pub dims: [u32; 3],
    /// World units per grid unit along each axis.
    pub grid_to_world: Vec3,
}

impl GridFrame {
    pub fn new(dims: [u32; 3], spacing: [f32; 3]) -> GridFrame {
        let extent = Vec3::new(
            (dims[0].max(2) - 1) as f32 * spacing[0],
            (dims[1].max(2) - 1) as f32 * spacing[1],
            (dims[2].max(2) - 1) as f32 * spacing[2],
        );
        let scale = 1.0 / extent.max_element();
        GridFrame {
            dims,
            grid_to_world: Vec3::from(spacing) * scale,
        }
    }

    pub fn centre(&self) -> Vec3 {
        Vec3::new(
            (self.dims[0] - 1) as f32,
            (self.dims[1] - 1) as f32,
            (self.dims[2] - 1) as f32,
        ) * 0.5
    }

    pub fn world_to_grid_point(&self, p: Vec3) -> Vec3 {
        p / self.grid_to_world + self.centre()
    }

    pub fn world_to_grid_vector(&self, v: Vec3) -> Vec3 {
        v / self.grid_to_world
    }

    /// Grid point (w = 1) to world space, column-major.
    pub fn grid_to_world_matrix(&self) -> glam::Mat4 {
        glam::Mat4::from_scale_rotation_translation(
            self.grid_to_world,
            glam::Quat::IDENTITY,
            -self.centre() * self.grid_to_world,
        )
    }
}

/// The camera expressed in grid space, as both the CPU and GPU ray casters consume it. A pixel's
/// ray direction is `normalize(forward + sx * right + sy * up)` with `sx, sy` from
/// [`GridCamera::screen`]; the vectors are not unit length in grid space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridCamera {
    pub eye: Vec3,
    pub forward: Vec3,
    pub right: Vec3,
    pub up: Vec3,
    pub tan_half_fov_x: f32,
    pub tan_half_fov_y: f32,
    /// Light direction (towards the light) in world space: above and to the right of the eye.
    pub light_world: Vec3,
}

impl GridCamera {
    pub fn new(camera: &OrbitCamera, frame: &GridFrame, width: u32, height: u32) -> GridCamera {
        View::of_unit_box(camera, (width, height)).grid_camera(frame)
    }

    /// Screen offsets of pixel (x, y)'s centre; y grows downwards in the image.
    pub fn screen(&self, x: u32, y: u32, width: u32, height: u32) -> (f32, f32) {
        let sx = (2.0 * (x as f32 + 0.5) / width as f32 - 1.0) * self.tan_half_fov_x;
        let sy = (1.0 - 2.0 * (y as f32 + 0.5) / height as f32) * self.tan_half_fov_y;
        (sx, sy)
    }

    pub fn ray_direction(&self, x: u32, y: u32, width: u32, height: u32) -> Vec3 {
        let (sx, sy) = self.screen(x, y, width, height);
        (self.forward + sx * self.right + sy * self.up).normalize()
    }
}

/// Perspective projection of grid points for rasterizing techniques, matching the ray casters'
/// pixel model: the centre of pixel (x, y) sees along `forward + sx * right + sy * up` with
/// `sx = (2(x+0.5)/W - 1) tan(fov_x/2)` and `sy = (1 - 2(y+0.5)/H) tan(fov_y/2)`.
/// Clip space is Vulkan's: y points down, depth in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Grid point (homogeneous, w = 1) to clip space, column-major.
    pub grid_to_clip: glam::Mat4,
    /// World point to clip space (for re-projecting world-space geometry to another view).
    pub world_to_clip: glam::Mat4,
    /// Eye position in world space, for view vectors in shading.
    pub eye_world: Vec3,
    pub near: f32,
    pub far: f32,
}

impl Projection {
    /// View-space depths of the near and far clip planes for `camera` (see
    /// [`crate::view::unit_box_depth_range`]).
    pub fn near_far(camera: &OrbitCamera) -> (f32, f32) {
        crate::view::unit_box_depth_range(camera)
    }

    pub fn new(camera: &OrbitCamera, frame: &GridFrame, width: u32, height: u32) -> Projection {
        Projection::of_view(&View::of_unit_box(camera, (width, height)), frame)
    }

    pub fn of_view(view: &View, frame: &GridFrame) -> Projection {
        Projection {
            grid_to_clip: view.grid_to_clip(frame),
            world_to_clip: view.world_to_clip,
            eye_world: view.eye,
            near: view.near,
            far: view.far,
        }
    }

    pub fn to_clip(&self, grid_point: Vec3) -> glam::Vec4 {
        self.grid_to_clip * grid_point.extend(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_at_volume_centre() {
        let cam = OrbitCamera::default();
        let frame = GridFrame::new([33, 17, 9], [1.0, 2.0, 4.0]);
        let gc = GridCamera::new(&cam, &frame, 101, 101);
        let d = gc.ray_direction(50, 50, 101, 101);
        let to_centre = (frame.centre() - gc.eye).normalize();
        assert!(d.dot(to_centre) > 0.99999, "{d} vs {to_centre}");
    }

    #[test]
    fn projection_puts_ray_points_on_their_pixel() {
        let cam = OrbitCamera {
            azimuth_deg: 70.0,
            elevation_deg: -25.0,
            distance: 2.1,
            eye_shift: 0.0,
            eye_rise: 0.0,
            up: ViewUp::PlusY,
            fov_y_deg: 35.0,
        };
        let frame = GridFrame::new([40, 30, 20], [1.0, 1.5, 2.0]);
        let (w, h) = (160, 90);
        let gc = GridCamera::new(&cam, &frame, w, h);
        let proj = Projection::new(&cam, &frame, w, h);
        for (x, y) in [(0, 0), (80, 45), (159, 89), (13, 70)] {
            // A point as far along the ray as the volume's centre is from the eye.
            let p = gc.eye + gc.ray_direction(x, y, w, h) * (frame.centre() - gc.eye).length();
            let c = proj.to_clip(p);
            let ndc = c.truncate() / c.w;
            let px = (ndc.x + 1.0) * 0.5 * w as f32;
            let py = (ndc.y + 1.0) * 0.5 * h as f32;
            assert!((px - (x as f32 + 0.5)).abs() < 1e-3, "x {px} for {x}");
            assert!((py - (y as f32 + 0.5)).abs() < 1e-3, "y {py} for {y}");
            assert!((0.0..=1.0).contains(&ndc.z), "depth {}", ndc.z);
        }
    }

    #[test]
    fn stereo_eyes_are_apart_along_right_and_look_the_same_way() {
        let cam = OrbitCamera::default();
        let [l, r] = cam.stereo_pair(0.06);
        assert!(((r.eye() - l.eye()).length() - 0.06).abs() < 1e-6);
        assert!((r.eye() - l.eye()).normalize().dot(cam.basis().1) > 0.99999);
        assert_eq!(l.basis(), cam.basis());
        assert!(((l.eye() + r.eye()) * 0.5 - cam.eye()).length() < 1e-6);
    }

    #[test]
    fn view_up_puts_its_axis_up_on_screen() {
        assert_eq!(ViewUp::parse("-Z"), Ok(ViewUp::MinusZ));
        assert_eq!(ViewUp::parse("+x"), Ok(ViewUp::PlusX));
        assert!(ViewUp::parse("up").is_err());
        assert_eq!(ViewUp::from_axis(2, -1), Some(ViewUp::MinusZ));
        assert_eq!(ViewUp::from_axis(3, 1), None);
        // +y up is the orbit as it always was: azimuth 0, elevation 0 looks along -z.
        let cam = OrbitCamera {
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            ..OrbitCamera::default()
        };
        assert!((cam.eye() - Vec3::new(0.0, 0.0, 1.8)).length() < 1e-6);
        for up in ViewUp::ALL {
            let (x, y, z) = up.frame();
            assert!((x.cross(y) - z).length() < 1e-6, "{up:?} not right-handed");
            assert_eq!(ViewUp::parse(up.name()), Ok(up));
            for (az, el) in [(30.0, 20.0), (-120.0, -40.0), (200.0, 5.0)] {
                let cam = OrbitCamera {
                    azimuth_deg: az,
                    elevation_deg: el,
                    up,
                    ..OrbitCamera::default()
                };
                let view = View::of_unit_box(&cam, (100, 100));
                assert!(view.up.dot(up.vector()) > 0.5, "{up:?} {az} {el}");
                // The top of the box along the up axis is above the centre in the image
                // (image y grows downwards), and the elevation is towards the up axis.
                let (top, _) = view.project(up.vector() * 0.5).unwrap();
                let (centre, _) = view.project(Vec3::ZERO).unwrap();
                assert!(
                    top.y < centre.y - 10.0,
                    "{up:?} {az} {el}: {top} vs {centre}"
                );
                let lift = cam.eye().normalize().dot(up.vector());
                assert!((lift - el.to_radians().sin()).abs() < 1e-5, "{up:?}");
            }
        }
    }

    #[test]
    fn volume_up_axis_gives_the_view_up_towards_the_head() {
        use crate::orientation::{AnatomicalSpace, Orientation, OrientationSource};
        use crate::{Samples, Volume};
        let v = Volume::new("v", [2, 2, 2], [1.0; 3], Samples::U8(vec![0; 8])).unwrap();
        assert_eq!(ViewUp::towards_head(v.up_axis()), None);
        // Grid z runs from head to feet in an LPS file.
        let flipped = Orientation::new(
            [0.0; 3],
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
            Some(AnatomicalSpace::Lps),
            OrientationSource::Nrrd,
        )
        .unwrap();
        assert_eq!(
            ViewUp::towards_head(v.with_orientation(flipped).up_axis()),
            Some(ViewUp::MinusZ)
        );
    }

    #[test]
    fn world_box_longest_side_is_one() {
        let frame = GridFrame::new([65, 33, 17], [1.0, 1.0, 1.0]);
        let size = Vec3::new(64.0, 32.0, 16.0) * frame.grid_to_world;
        assert!((size.max_element() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn parse_rejects_bad_text() {
        assert!(OrbitCamera::parse("10,20").is_err());
        assert!(OrbitCamera::parse("10,x,2").is_err());
        assert!(OrbitCamera::parse("10,20,-1").is_err());
        assert_eq!(OrbitCamera::parse("10, 20, 2.5").unwrap().distance, 2.5);
    }
}
