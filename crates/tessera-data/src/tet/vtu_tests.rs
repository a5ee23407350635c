//! Tests of the VTK XML loader and writer, with hand-built files in every encoding.
use std::io::Write;

use flate2::write::ZlibEncoder;

use super::*;
use crate::test_files::test_path;
use crate::tet::procedural::box_mesh;
use crate::tet::tests::{data_file, load_error, two_tets, write_text};

fn b64(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let b = [c[0], *c.get(1).unwrap_or(&0), *c.get(2).unwrap_or(&0)];
        let v = u32::from(b[0]) << 16 | u32::from(b[1]) << 8 | u32::from(b[2]);
        for k in 0..4 {
            s.push(if k <= c.len() {
                A[(v >> (18 - 6 * k) & 63) as usize] as char
            } else {
                '='
            });
        }
    }
    s
}

/// The arrays of the test grid: (section, name, type, ncomp, little-endian bytes, ascii).
/// (section, name, type, ncomp, little-endian bytes, ascii text)
type Array = (
    &'static str,
    &'static str,
    &'static str,
    usize,
    Vec<u8>,
    String,
);

fn arrays() -> Vec<Array> {
    let pts = [0f64, 0., 0., 1., 0., 0., 0., 1., 0., 0., 0., 1., 1., 1., 1.];
    let conn = [0i32, 1, 2, 3, 4, 1, 3, 2, 0, 1, 2];
    let offs = [4i64, 8, 11];
    let types = [10u8, 10, 5];
    let heat = [1f32, 2., 3., 4., 5.];
    let join = |v: Vec<String>| v.join(" ");
    vec![
        (
            "PointData",
            "heat",
            "Float32",
            1,
            heat.iter().flat_map(|v| v.to_le_bytes()).collect(),
            join(heat.iter().map(|v| v.to_string()).collect()),
        ),
        (
            "Points",
            "Points",
            "Float64",
            3,
            pts.iter().flat_map(|v| v.to_le_bytes()).collect(),
            join(pts.iter().map(|v| v.to_string()).collect()),
        ),
        (
            "Cells",
            "connectivity",
            "Int32",
            1,
            conn.iter().flat_map(|v| v.to_le_bytes()).collect(),
            join(conn.iter().map(|v| v.to_string()).collect()),
        ),
        (
            "Cells",
            "offsets",
            "Int64",
            1,
            offs.iter().flat_map(|v| v.to_le_bytes()).collect(),
            join(offs.iter().map(|v| v.to_string()).collect()),
        ),
        (
            "Cells",
            "types",
            "UInt8",
            1,
            types.to_vec(),
            join(types.iter().map(|v| v.to_string()).collect()),
        ),
    ]
}

/// Builds the test grid in `mode`: ascii, binary, zlib (binary, UInt64 headers),
/// appended (raw), appended64 (base64).
fn grid(mode: &str) -> String {
    let mut appended = Vec::new();
    let mut body = String::new();
    let mut section = "";
    for (sec, name, ty, ncomp, bytes, ascii) in arrays() {
        if sec != section {
            if !section.is_empty() {
                body += &format!("</{section}>\n");
            }
            body += &format!("<{sec}>\n");
            section = sec;
        }
        let (format, content) = match mode {
            "ascii" => ("format=\"ascii\"".to_string(), ascii),
            "binary" => {
                let mut all = (bytes.len() as u32).to_le_bytes().to_vec();
                all.extend(&bytes);
                ("format=\"binary\"".into(), b64(&all))
            }
            "zlib" => {
                let mut enc = ZlibEncoder::new(Vec::new(), flate2::Compression::default());
                enc.write_all(&bytes).expect("zlib");
                let packed = enc.finish().expect("zlib");
                let header: Vec<u8> = [
                    1u64,
                    bytes.len() as u64,
                    bytes.len() as u64,
                    packed.len() as u64,
                ]
                .iter()
                .flat_map(|v| v.to_le_bytes())
                .collect();
                (
                    "format=\"binary\"".into(),
                    format!("{}{}", b64(&header), b64(&packed)),
                )
            }
            _ => {
                let mut all = (bytes.len() as u32).to_le_bytes().to_vec();
                all.extend(&bytes);
                let offset = appended.len();
                if mode == "appended64" {
                    appended.extend(b64(&all).into_bytes());
                } else {
                    appended.extend(all);
                }
                (
                    format!("format=\"appended\" offset=\"{offset}\""),
                    String::new(),
                )
            }
        };
        body += &format!("<DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{ncomp}\" {format}>\n{content}\n</DataArray>\n");
    }
    body += &format!("</{section}>\n");
    let (header, compressor) = if mode == "zlib" {
        ("UInt64", " compressor=\"vtkZLibDataCompressor\"")
    } else {
        ("UInt32", "")
    };
    let mut text = format!(
        "<?xml version=\"1.0\"?>\n<!-- test grid -->\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"{header}\"{compressor}>\n\
         <UnstructuredGrid>\n<Piece NumberOfPoints=\"5\" NumberOfCells=\"3\">\n{body}</Piece>\n</UnstructuredGrid>\n"
    );
    if mode.starts_with("appended") {
        let encoding = if mode == "appended64" {
            "base64"
        } else {
            "raw"
        };
        text += &format!("<AppendedData encoding=\"{encoding}\">\n_");
        // Raw data is patched in by `write_grid`; '#' stands in for it here.
        let filler = if mode == "appended64" {
            appended
        } else {
            vec![b'#'; appended.len()]
        };
        text += &String::from_utf8(filler).expect("ascii");
        return text + "\n</AppendedData>\n</VTKFile>\n";
    }
    text + "</VTKFile>\n"
}

fn write_grid(mode: &str) -> std::path::PathBuf {
    let path = test_path(&format!("{mode}.vtu"));
    if mode == "appended" {
        // Put the real raw bytes in place of the placeholder.
        let text = grid(mode);
        let tag = text.find("<AppendedData").expect("tag");
        let at = tag + text[tag..].find('_').expect("marker") + 1;
        let mut raw = Vec::new();
        for (_, _, _, _, bytes, _) in arrays() {
            raw.extend((bytes.len() as u32).to_le_bytes());
            raw.extend(bytes);
        }
        let mut out = text.as_bytes()[..at].to_vec();
        out.extend(&raw);
        out.extend(b"\n</AppendedData>\n</VTKFile>\n");
        std::fs::write(&path, out).expect("write");
    } else {
        std::fs::write(&path, grid(mode)).expect("write");
    }
    path
}

#[test]
fn every_encoding() {
    for mode in ["ascii", "binary", "zlib", "appended", "appended64"] {
        let path = write_grid(mode);
        let (mesh, report) = load_vtu(&path).unwrap_or_else(|e| panic!("{mode}: {e}"));
        assert_eq!(report.skipped_cells, 1, "{mode}");
        assert_eq!(mesh.tets, vec![[0, 1, 2, 3], [4, 1, 3, 2]], "{mode}");
        assert_eq!(mesh.vertices[4], [1.0, 1.0, 1.0], "{mode}");
        assert_eq!(mesh.scalar_name, "heat");
        assert_eq!(mesh.scalars, Some(vec![1.0, 2.0, 3.0, 4.0, 5.0]), "{mode}");
    }
}

#[test]
fn round_trip() {
    for mesh in [two_tets(), box_mesh(3)] {
        let path = test_path("rt.vtu");
        write_vtu_ascii(&mesh, &path).expect("write");
        let (back, report) = crate::tet::load_tet_mesh(&path).expect("load");
        assert_eq!(report, MeshReport::default());
        assert_eq!(back, mesh);
    }
}

#[test]
fn bad_files() {
    let good = grid("ascii");
    let cases = [
        (good[..good.len() / 2].to_string(), "never closed"),
        (
            good.replace("0 1 2 3 4 1 3 2 0 1 2", "0 1 2 3 4 1 3 2 0 1"),
            "holds 10 values, but the last offset (11) calls for 11",
        ),
        (
            good.replace("0 1 2 3 4 1 3 2", "0 1 2 3 9 1 3 2"),
            "out of range",
        ),
        (
            good.replace("NumberOfCells=\"3\"", "NumberOfCells=\"4\""),
            "holds 3 values, but NumberOfCells=\"4\" calls for 4",
        ),
        (good.replace("1 1 1", "1 nan 1"), "vertex 4"),
        (good.replace("10 10 5", "12 12 5"), "empty mesh"),
        (
            good.replace("UnstructuredGrid\" version", "PolyData\" version"),
            "UnstructuredGrid",
        ),
        (good.replace("LittleEndian", "MiddleEndian"), "byte_order"),
    ];
    for (text, what) in cases {
        let path = write_text("bad.vtu", &text);
        let message = load_error(load_vtu(&path), &path);
        assert!(message.contains(what), "{message}");
    }
    let path = write_text(
        "idx.vtu",
        &good.replace("0 1 2 3 4 1 3 2", "0 1 2 3 9 1 3 2"),
    );
    let message = load_error(load_vtu(&path), &path);
    assert!(
        message.contains("line 17") && message.contains("cell 1"),
        "{message}"
    );
}

#[test]
fn padding_only_base64_is_an_error() {
    let path = data_file("padding_only_base64.vtu");
    let message = load_error(load_vtu(&path), &path);
    assert!(
        message.contains("line 6") && message.contains("invalid base64"),
        "{message}"
    );
}

#[test]
fn block_sizes_are_checked_before_inflating() {
    let path = data_file("zlib_bomb.vtu");
    let message = load_error(load_vtu(&path), &path);
    assert!(
        message.contains("announces 4194304 bytes of data, the array needs 48"),
        "{message}"
    );
    assert!(message.contains("NumberOfPoints=\"4\""), "{message}");
    let path = data_file("zlib_beyond_inflation.vtu");
    let message = load_error(load_vtu(&path), &path);
    assert!(message.contains("more than zlib can"), "{message}");
}

#[test]
fn counts_beyond_the_file_fail_before_allocating() {
    let good = grid("binary");
    for (from, to) in [
        ("NumberOfPoints=\"5\"", "NumberOfPoints=\"1000000000000\""),
        (
            "NumberOfPoints=\"5\"",
            "NumberOfPoints=\"18446744073709551615\"",
        ),
        ("NumberOfCells=\"3\"", "NumberOfCells=\"4000000000000\""),
    ] {
        let path = write_text("huge.vtu", &good.replace(from, to));
        let message = load_error(load_vtu(&path), &path);
        assert!(
            message.contains("calls for") || message.contains("the array needs"),
            "{message}"
        );
    }
}

/// A grid of `n` pieces of one tet each, all arrays ascii.
fn pieces(n: usize) -> String {
    let mut text =
        String::from("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n<UnstructuredGrid>\n");
    for i in 0..n {
        let x = i as f32;
        text += &format!(
            "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n\
             <PointData Scalars=\"s\"><DataArray type=\"Float32\" Name=\"s\" format=\"ascii\">{i} 1 2 3</DataArray></PointData>\n\
             <CellData><DataArray type=\"Int32\" Name=\"r\" format=\"ascii\">{i}</DataArray></CellData>\n\
             <Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">{x} 0 0 {} 0 0 {x} 1 0 {x} 0 1</DataArray></Points>\n\
             <Cells><DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n\
             <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n\
             <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells>\n</Piece>\n",
            x + 1.0
        );
    }
    text + "</UnstructuredGrid>\n</VTKFile>\n"
}

#[test]
fn many_pieces_load_in_linear_time() {
    let path = write_text("pieces.vtu", &pieces(4000));
    let start = std::time::Instant::now();
    let (mesh, _) = load_vtu(&path).expect("load");
    let elapsed = start.elapsed();
    assert_eq!((mesh.vertex_count(), mesh.tet_count()), (16_000, 4000));
    assert_eq!(mesh.tets[3999], [15_996, 15_997, 15_998, 15_999]);
    assert_eq!(mesh.regions.as_ref().map(|r| r[3999]), Some(3999));
    assert_eq!(mesh.scalars.as_ref().map(|s| s[4 * 3999]), Some(3999.0));
    // Quadratic in the number of pieces, this took about 3 s.
    assert!(elapsed.as_secs_f64() < 1.0, "{elapsed:?}");
}

#[test]
fn count_messages_report_what_the_array_holds() {
    let path = data_file("points_count_mismatch.vtu");
    let message = load_error(load_vtu(&path), &path);
    assert!(
        message.contains(
            "line 6: the DataArray in <Points>: holds 24 values, but \
                          NumberOfPoints=\"0\" calls for 0 (0 x 3 components)"
        ),
        "{message}"
    );
}
