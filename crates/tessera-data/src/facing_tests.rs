use super::*;
use crate::camera::{GridFrame, OrbitCamera, Projection};
use crate::marching_cubes::marching_cubes;
use crate::procedural::{generate, ProceduralKind};
use crate::rasterize::{rasterize_clip_triangles, rasterize_clip_triangles_hiding};
use crate::volume::{IsoValue, ScalarType};

fn head(size: u32) -> Volume {
    generate(ProceduralKind::HeadPhantom, size, ScalarType::U8).unwrap()
}

/// The constant the module rests on. A closed surface's triangles, summed as tetrahedra with the
/// origin, give the volume it encloses (the cells at or above the isovalue, the boundary being
/// below), positive when every cross product points out of it, towards the samples below.
#[test]
fn marching_cubes_triangles_are_wound_towards_the_samples_below() {
    for (volume, fraction) in [(head(40), 0.3), (head(33), 0.6)] {
        let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
        assert!(boundary_range(&volume).1 < iso);
        let mesh = marching_cubes(&volume, iso);
        let enclosed: f64 = mesh
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| mesh.positions[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        let [nx, ny, nz] = volume.dims();
        let mut above = 0.0;
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    if volume.texel(x, y, z) >= iso {
                        above += 1.0;
                    }
                }
            }
        }
        let outward = if CROSS_POINTS_BELOW {
            enclosed
        } else {
            -enclosed
        };
        // About one cell per sample above the isovalue.
        assert!(
            outward > 0.5 * above && outward < 2.0 * above,
            "{enclosed} for {above} samples"
        );
    }
}

#[test]
fn the_eye_is_orthogonal_to_clip_x_y_and_w() {
    let volume = head(30);
    let frame = GridFrame::new(volume.dims(), volume.spacing());
    let camera = OrbitCamera::parse("30,20,1.8").unwrap();
    let m = Projection::new(&camera, &frame, 64, 48)
        .grid_to_clip
        .as_dmat4();
    let e = generalized_cross([m.row(0), m.row(1), m.row(3)]);
    for row in [m.row(0), m.row(1), m.row(3)] {
        assert!(row.dot(e).abs() < 1e-9 * row.length() * e.length());
    }
    let eye = e.truncate() / e.w;
    let expected = frame.world_to_grid_point(camera.eye()).as_dvec3();
    assert!((eye - expected).length() < 1e-3, "{eye} against {expected}");
}

/// Clip-space triangles of `volume`'s surface at `fraction` seen by `camera`.
fn clip_triangles(
    volume: &Volume,
    fraction: f32,
    camera: &OrbitCamera,
    size: (u32, u32),
) -> (Vec<[glam::Vec4; 3]>, glam::Mat4, f32) {
    let iso = volume.iso_to_texel(IsoValue::Normalized(fraction));
    let mesh = marching_cubes(volume, iso);
    let frame = GridFrame::new(volume.dims(), volume.spacing());
    let projection = Projection::new(camera, &frame, size.0, size.1);
    let tris = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| projection.to_clip(mesh.positions[i as usize])))
        .collect();
    (tris, projection.grid_to_clip, iso)
}

/// Seen from outside, the head's skin and bone draw the same frame with half their triangles
/// left out; leaving out the other half instead shows what was hidden.
#[test]
fn hiding_the_winding_keeps_the_frame_of_a_closed_surface() {
    let volume = head(48);
    let boundary = boundary_range(&volume);
    let size = (128, 96);
    for (camera, fraction) in [
        ("30,20,1.8", 0.3),
        ("200,-35,1.5", 0.3),
        ("120,60,2.2", 0.7),
    ] {
        let camera = OrbitCamera::parse(camera).unwrap();
        let (tris, grid_to_clip, iso) = clip_triangles(&volume, fraction, &camera, size);
        let side = boundary_side(boundary, iso).expect("a closed surface");
        let hidden = hidden_winding(grid_to_clip, volume.dims(), side)
            .unwrap_or_else(|| panic!("{camera:?}: nothing hidden"));
        let all = rasterize_clip_triangles(&tris, size.0, size.1);
        let kept = rasterize_clip_triangles_hiding(&tris, size.0, size.1, Some(hidden));
        let wrong = rasterize_clip_triangles_hiding(&tris, size.0, size.1, Some(hidden.opposite()));
        let covered = all.iter().filter(|p| p.is_some()).count();
        let differ = |other: &[Option<(f32, u32)>]| {
            all.iter()
                .zip(other)
                .filter(|(a, b)| a.map(|v| v.1) != b.map(|v| v.1))
                .count()
        };
        assert!(covered > 1000, "{covered}");
        eprintln!(
            "{camera:?}: {} of {covered} moved, {} with the other half",
            differ(&kept),
            differ(&wrong)
        );
        assert!(
            differ(&kept) * 1000 <= covered,
            "{camera:?}: {} of {covered} moved",
            differ(&kept)
        );
        assert!(
            differ(&wrong) * 2 > covered,
            "{camera:?}: the other half drew the same frame"
        );
    }
}

#[test]
fn nothing_is_hidden_where_the_surface_is_open_or_the_grid_reaches_the_eye() {
    let volume = head(40);
    let (_, grid_to_clip, iso) = clip_triangles(
        &volume,
        0.3,
        &OrbitCamera::parse("30,20,1.8").unwrap(),
        (64, 48),
    );
    let boundary = boundary_range(&volume);
    assert_eq!(boundary_side(boundary, iso), Some(BoundarySide::Below));
    assert!(hidden_winding(grid_to_clip, volume.dims(), BoundarySide::Below).is_some());
    // A boundary sample on either side of the isovalue: the surface may end there.
    assert_eq!(
        boundary_side((boundary.0.min(iso - 1.0), iso + 1.0), iso),
        None
    );
    assert_eq!(
        boundary_side((iso, iso + 5.0), iso),
        Some(BoundarySide::AtOrAbove)
    );
    // The eye inside the grid.
    let (_, inside, _) = clip_triangles(
        &volume,
        0.3,
        &OrbitCamera::parse("30,20,0.2").unwrap(),
        (64, 48),
    );
    assert_eq!(
        hidden_winding(inside, volume.dims(), BoundarySide::Below),
        None
    );
    // Rays that start above the isovalue see the other side first.
    assert_eq!(
        hidden_winding(grid_to_clip, volume.dims(), BoundarySide::AtOrAbove),
        hidden_winding(grid_to_clip, volume.dims(), BoundarySide::Below)
            .map(ScreenWinding::opposite)
    );
}

#[test]
fn the_boundary_range_covers_the_six_faces_only() {
    let volume = head(12);
    let (lo, hi) = boundary_range(&volume);
    let mut faces = Vec::new();
    let [nx, ny, nz] = volume.dims();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if x == 0 || y == 0 || z == 0 || x == nx - 1 || y == ny - 1 || z == nz - 1 {
                    faces.push(volume.texel(x, y, z));
                }
            }
        }
    }
    let expected = faces
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |r, &v| {
            (r.0.min(v), r.1.max(v))
        });
    assert_eq!((lo, hi), expected);
}
