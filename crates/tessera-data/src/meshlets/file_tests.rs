use std::path::Path;

use super::file::{read_meshlet_file, write_meshlet_file, MeshletFile, MeshletUnits};
use crate::error::DataError;
use crate::marching_cubes::{marching_cubes_with, AmbiguityRule};
use crate::meshlets::extract_meshlets;
use crate::procedural::{generate, ProceduralKind};
use crate::volume::ScalarType;

fn sphere_file() -> MeshletFile {
    let volume = generate(ProceduralKind::Sphere, 19, ScalarType::F32).unwrap();
    MeshletFile {
        mesh: extract_meshlets(&volume, 0.6123, AmbiguityRule::AsymptoticDecider).unwrap(),
        isovalue: 0.6123,
        units: MeshletUnits::Physical,
    }
}

fn bytes_of(file: &MeshletFile) -> Vec<u8> {
    let mut bytes = Vec::new();
    write_meshlet_file(file, &mut bytes).unwrap();
    bytes
}

#[test]
fn a_meshlet_file_reads_back_equal_and_has_the_documented_size() {
    let file = sphere_file();
    assert!(file.mesh.meshlets.len() > 4);
    let bytes = bytes_of(&file);
    let m = &file.mesh;
    assert_eq!(
        bytes.len(),
        32 + 44 * m.meshlets.len() + 24 * m.positions.len() + m.local_indices.len()
    );
    // The first record's counts sit at bytes 40..44, as the layout table says.
    let counts = u32::from_le_bytes(bytes[40..44].try_into().unwrap());
    assert_eq!(counts & 0xffff, m.meshlets[0].vertex_count());
    assert_eq!(counts >> 16, m.meshlets[0].triangle_count());
    let read = read_meshlet_file(Path::new("s.tsm"), &bytes).unwrap();
    assert_eq!(read, file);
}

#[test]
fn an_empty_surface_round_trips() {
    let mut file = sphere_file();
    file.mesh = Default::default();
    file.units = MeshletUnits::Grid;
    let read = read_meshlet_file(Path::new("e.tsm"), &bytes_of(&file)).unwrap();
    assert_eq!(read, file);
}

#[test]
fn damaged_meshlet_files_are_refused_with_the_file_and_the_reason() {
    let file = sphere_file();
    let good = bytes_of(&file);
    let path = Path::new("bad.tsm");
    let message = |bytes: &[u8]| read_meshlet_file(path, bytes).unwrap_err().to_string();

    let m = message(b"PLY and more bytes than a header holds....");
    assert!(m.contains("bad.tsm") && m.contains("magic"), "{m}");

    let m = message(&good[..good.len() - 1]);
    assert!(m.contains("bad.tsm") && m.contains("triangles"), "{m}");

    let mut record = good.clone();
    record[8] = 80;
    assert!(message(&record).contains("records of 80 bytes"));

    // A local index past its meshlet's vertices.
    let mut index = good.clone();
    let last = index.len() - 1;
    index[last] = 255;
    let err = read_meshlet_file(path, &index).unwrap_err();
    assert!(matches!(err, DataError::Format { .. }), "{err}");
    assert!(err.to_string().contains("local index 255"), "{err}");
}

#[test]
fn welding_gives_the_marching_cubes_vertices_and_triangles() {
    let volume = generate(ProceduralKind::MarschnerLobb, 25, ScalarType::F32).unwrap();
    let rule = AmbiguityRule::AsymptoticDecider;
    let meshlets = extract_meshlets(&volume, 0.5013, rule).unwrap();
    let reference = marching_cubes_with(&volume, 0.5013, rule);
    let welded = meshlets.welded();
    assert!(
        meshlets.vertex_count() > welded.vertex_count(),
        "nothing to weld"
    );
    assert_eq!(welded.vertex_count(), reference.vertex_count());
    assert_eq!(
        welded.canonical_triangle_multiset(1e-5),
        reference.canonical_triangle_multiset(1e-5)
    );
    let bits = |v: glam::Vec3| v.to_array().map(f32::to_bits);
    let mut ours: Vec<_> = welded.positions.iter().map(|&p| bits(p)).collect();
    let mut theirs: Vec<_> = reference.positions.iter().map(|&p| bits(p)).collect();
    ours.sort_unstable();
    theirs.sort_unstable();
    assert_eq!(ours, theirs);
}
