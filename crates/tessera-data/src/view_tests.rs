use super::*;

fn camera(azimuth_deg: f32, elevation_deg: f32, distance: f32) -> OrbitCamera {
    OrbitCamera {
        azimuth_deg,
        elevation_deg,
        distance,
        ..OrbitCamera::default()
    }
}

fn raster_position(view: &View, clip: Vec4) -> Vec2 {
    let ndc = clip.truncate() / clip.w;
    let (w, h) = view.raster_size();
    Vec2::new(
        (ndc.x + 1.0) * 0.5 * w as f32,
        (ndc.y + 1.0) * 0.5 * h as f32,
    )
}

#[test]
fn pixel_rays_land_on_their_pixel_and_inside_the_depth_range() {
    let cam = camera(70.0, -25.0, 2.1);
    for supersample in [1, 3] {
        let view = View::new(&cam, (160, 90), supersample, DepthFit::UnitBox).unwrap();
        let (w, h) = view.raster_size();
        assert_eq!((w, h), (160 * supersample, 90 * supersample));
        for (x, y) in [(0, 0), (w / 2, h / 2), (w - 1, h - 1), (13, 70)] {
            let (origin, direction) = view.pixel_ray(x, y);
            assert!((direction.length() - 1.0).abs() < 1e-6);
            let p = origin + direction * cam.distance;
            let px = raster_position(&view, view.world_to_clip * p.extend(1.0));
            assert!((px.x - (x as f32 + 0.5)).abs() < 1e-3, "x {} for {x}", px.x);
            assert!((px.y - (y as f32 + 0.5)).abs() < 1e-3, "y {} for {y}", px.y);
            let (projected, depth) = view.project(p).unwrap();
            assert!((projected - px).length() < 1e-3);
            assert!((0.0..=1.0).contains(&depth), "depth {depth}");
        }
    }
}

#[test]
fn depth_range_maps_near_to_zero_and_far_to_one() {
    let cam = camera(10.0, 30.0, 1.8);
    let view = View::of_unit_box(&cam, (64, 64));
    for (distance, depth) in [(view.near, 0.0), (view.far, 1.0)] {
        let clip = view.world_to_clip * (view.eye + view.forward * distance).extend(1.0);
        assert!(
            (clip.z / clip.w - depth).abs() < 1e-5,
            "{distance}: {}",
            clip.z / clip.w
        );
    }
    assert_eq!((view.near, view.far), unit_box_depth_range(&cam));
    assert_eq!(view.far, 1.8 + UNIT_BOX_RADIUS);
}

#[test]
fn inside_the_unit_box_the_near_plane_stays_positive() {
    let view = View::of_unit_box(&camera(0.0, 0.0, 0.2), (8, 8));
    assert!(view.near > 0.0 && view.near < 0.01 * view.far);
}

#[test]
fn sphere_fit_encloses_every_sphere_with_a_margin() {
    let bounds = [
        (Vec3::new(0.3, 0.0, 0.0), 0.2),
        (Vec3::new(-0.4, 0.1, 0.2), 0.1),
    ];
    let cam = camera(40.0, 10.0, 3.0);
    let view = View::new(&cam, (32, 32), 1, DepthFit::Spheres(&bounds)).unwrap();
    for (centre, radius) in bounds {
        let d = view.forward.dot(centre - view.eye);
        assert!(view.near < d - radius && d + radius < view.far);
    }
    let nearest = bounds
        .iter()
        .map(|(c, r)| view.forward.dot(*c - view.eye) - r)
        .fold(f32::INFINITY, f32::min);
    assert!((view.near - nearest * 0.999).abs() < 1e-6);
}

/// The view matrix puts the eye at the origin looking down +z with the camera's axes as x and y;
/// a volume's grid points reach clip space through its frame exactly as their world points do.
#[test]
fn view_axes_and_grid_points_map_as_stated() {
    let cam = camera(33.0, 21.0, 1.7);
    let view = View::of_unit_box(&cam, (101, 57));
    let to_view = |p: Vec3| (view.world_to_view * p.extend(1.0)).truncate();
    assert!(to_view(view.eye).length() < 1e-6);
    for (axis, expected) in [
        (view.right, Vec3::X),
        (view.up, Vec3::Y),
        (view.forward, Vec3::Z),
    ] {
        let mapped = to_view(view.eye + axis) - to_view(view.eye);
        assert!((mapped - expected).length() < 1e-5, "{axis} -> {mapped}");
    }
    assert!((view.light.length() - 1.0).abs() < 1e-6);
    assert!(
        view.light.dot(view.forward) < 0.0,
        "the light is behind the eye"
    );
    let frame = GridFrame::new([33, 17, 9], [1.0, 2.0, 4.0]);
    for grid_point in [
        Vec3::ZERO,
        Vec3::new(32.0, 16.0, 8.0),
        Vec3::new(5.0, 11.0, 2.0),
    ] {
        let world = (grid_point - frame.centre()) * frame.grid_to_world;
        let by_grid = view.grid_to_clip(&frame) * grid_point.extend(1.0);
        let by_world = view.world_to_clip * world.extend(1.0);
        assert!((by_grid - by_world).length() < 1e-5, "{grid_point}");
    }
}

#[test]
fn grid_rays_follow_the_world_rays() {
    let cam = camera(-50.0, 35.0, 2.4);
    let frame = GridFrame::new([40, 30, 20], [1.0, 1.5, 2.0]);
    let view = View::of_unit_box(&cam, (48, 36));
    let grid = view.grid_camera(&frame);
    for (x, y) in [(0, 0), (24, 18), (47, 35)] {
        let (origin, direction) = view.pixel_ray(x, y);
        let world_point = origin + direction * 2.0;
        let grid_direction = grid.ray_direction(x, y, 48, 36);
        let to_point = (frame.world_to_grid_point(world_point) - grid.eye).normalize();
        assert!(grid_direction.dot(to_point) > 0.99999, "pixel ({x}, {y})");
    }
}

#[test]
fn stereo_eyes_share_the_depth_range_and_look_the_same_way() {
    let view = View::of_unit_box(&OrbitCamera::default(), (64, 48));
    let [left, right] = view.stereo_pair(0.06);
    assert!(((right.eye - left.eye).length() - 0.06).abs() < 1e-6);
    assert_eq!((left.near, left.far), (view.near, view.far));
    assert_eq!(left.forward, view.forward);
    assert_eq!(right.size, view.size);
}

#[test]
fn resizing_keeps_the_camera_and_depth_range() {
    let bounds = [(Vec3::ZERO, 0.5)];
    let view = View::new(
        &camera(0.0, 0.0, 2.0),
        (64, 48),
        2,
        DepthFit::Spheres(&bounds),
    )
    .unwrap();
    let resized = view.resized((200, 100)).unwrap();
    assert_eq!((resized.near, resized.far), (view.near, view.far));
    assert_eq!(resized.raster_size(), (400, 200));
    assert!((resized.tan_half_fov.x - 2.0 * resized.tan_half_fov.y).abs() < 1e-6);
    assert!(view.resized((0, 10)).is_err());
}

#[test]
fn bad_views_are_refused_with_the_reason() {
    let cam = OrbitCamera::default();
    let message = |r: Result<View>| r.unwrap_err().to_string();
    assert!(message(View::new(&cam, (0, 10), 1, DepthFit::UnitBox)).contains("empty"));
    assert!(message(View::new(&cam, (10, 10), 9, DepthFit::UnitBox)).contains("supersampling"));
    let wide = OrbitCamera {
        fov_y_deg: 180.0,
        ..cam
    };
    assert!(message(View::new(&wide, (10, 10), 1, DepthFit::UnitBox)).contains("camera"));
    let none: [(Vec3, f32); 0] = [];
    assert!(message(View::new(&cam, (10, 10), 1, DepthFit::Spheres(&none))).contains("bounds"));
    let infinite = [(Vec3::ZERO, f32::INFINITY)];
    assert!(message(View::new(&cam, (10, 10), 1, DepthFit::Spheres(&infinite))).contains("bounds"));
}
