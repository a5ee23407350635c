//! The `tessera` binary on volume files: spacing and placement from headers, isovalues
//! (negative, out of range, the Otsu default), the view-up axis, and `extract`'s PLY output
//! (physical units, outward faces, the rule for ambiguous faces).

mod common;

use common::*;

#[test]
fn extract_writes_ply() {
    let dir = scratch("extract");
    let out = dir.join("s.ply");
    let o = tessera(&[
        "extract",
        "procedural:sphere:24",
        "--iso-fraction",
        "0.6",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let bytes = std::fs::read(&out).unwrap();
    let header = String::from_utf8_lossy(&bytes[..400.min(bytes.len())]).into_owned();
    assert!(header.starts_with("ply"), "{header}");
    let faces: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element face "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    assert!(faces > 100, "{faces} faces");
    // The sphere is high inside; its surface must face out, toward lower values, as VTK's
    // does: outward normals and a positive enclosed volume (divergence theorem).
    let vertices: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    let body = header.find("end_header\n").unwrap() + "end_header\n".len();
    let float = |at: usize| f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let vertex = |i: usize| -> [[f32; 3]; 2] {
        let at = body + 24 * i;
        [
            [0, 1, 2].map(|k| float(at + 4 * k)),
            [3, 4, 5].map(|k| float(at + 4 * k)),
        ]
    };
    let centre = (0..vertices).fold([0.0f32; 3], |c, i| {
        let p = vertex(i)[0];
        [0, 1, 2].map(|k| c[k] + p[k] / vertices as f32)
    });
    let outward = (0..vertices)
        .filter(|&i| {
            let [p, n] = vertex(i);
            (0..3).map(|k| (p[k] - centre[k]) * n[k]).sum::<f32>() > 0.0
        })
        .count();
    assert_eq!(outward, vertices, "normals point out of the sphere");
    let faces_at = body + 24 * vertices;
    let volume: f64 = (0..faces)
        .map(|f| {
            let at = faces_at + 13 * f;
            assert_eq!(bytes[at], 3);
            let [a, b, c] = [0, 1, 2].map(|k| {
                let i =
                    u32::from_le_bytes(bytes[at + 1 + 4 * k..at + 5 + 4 * k].try_into().unwrap());
                vertex(i as usize)[0].map(f64::from)
            });
            let cross = [
                b[1] * c[2] - b[2] * c[1],
                b[2] * c[0] - b[0] * c[2],
                b[0] * c[1] - b[1] * c[0],
            ];
            (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
        })
        .sum();
    assert!(volume > 0.0, "enclosed volume {volume}");
}

/// Writes a 16³ uint8 NRRD: 200 inside a ball of radius 4 around `centre` (grid units), 10
/// elsewhere, with extra header `fields`.
fn ball_nrrd(path: &std::path::Path, centre: [f32; 3], fields: &str) {
    let mut bytes =
        format!("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n{fields}\n")
            .into_bytes();
    for z in 0..16 {
        for y in 0..16 {
            for x in 0..16 {
                let d = [x, y, z]
                    .iter()
                    .zip(centre)
                    .map(|(&i, c)| (i as f32 - c).powi(2))
                    .sum::<f32>()
                    .sqrt();
                bytes.push(if d < 4.0 { 200 } else { 10 });
            }
        }
    }
    std::fs::write(path, bytes).unwrap();
}

/// Bounds (min, max) of the vertices of a binary PLY the CLI wrote.
fn ply_bounds(path: &std::path::Path) -> ([f32; 3], [f32; 3]) {
    let bytes = std::fs::read(path).unwrap();
    let end = b"end_header\n";
    let body = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = String::from_utf8_lossy(&bytes[..body]).into_owned();
    let vertices: usize = header
        .lines()
        .find_map(|l| l.strip_prefix("element vertex "))
        .and_then(|n| n.trim().parse().ok())
        .unwrap();
    assert!(vertices > 0, "{header}");
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for v in 0..vertices {
        for a in 0..3 {
            let at = body + v * 24 + a * 4;
            let x = f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
            lo[a] = lo[a].min(x);
            hi[a] = hi[a].max(x);
        }
    }
    (lo, hi)
}

/// The area `extract` printed.
fn printed_area(o: &std::process::Output) -> f32 {
    let text = String::from_utf8_lossy(&o.stdout);
    text.split("area ")
        .nth(1)
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no area in {text}"))
}

#[test]
fn extract_takes_spacing_from_the_header_and_the_flag_overrides_it() {
    let dir = scratch("spacing");
    let data = dir.join("aniso.nrrd");
    ball_nrrd(&data, [7.5, 7.5, 7.5], "spacings: 1 2 0.5\n");
    let run_on = |data: &std::path::Path, name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "extract",
            data.to_str().unwrap(),
            "--iso",
            "100",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = tessera(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        (o, ply_bounds(&out))
    };
    let run = |name: &str, extra: &[&str]| run_on(&data, name, extra);
    let (header, (hlo, hhi)) = run("header.ply", &[]);
    let (unit, (ulo, uhi)) = run("unit.ply", &["--spacing", "1,1,1"]);
    let (double, (dlo, dhi)) = run("double.ply", &["--spacing", "2,2,2"]);
    assert!(!stderr(&header).contains("note:"), "{}", stderr(&header));
    for o in [&unit, &double] {
        let err = stderr(o);
        assert!(
            err.contains("note: --spacing") && err.contains("replaces the spacing 1,2,0.5"),
            "{err}"
        );
    }
    let spacing = [1.0, 2.0, 0.5];
    for a in 0..3 {
        let (h, u, d) = (hhi[a] - hlo[a], uhi[a] - ulo[a], dhi[a] - dlo[a]);
        assert!(u > 5.0, "axis {a}: unit extent {u}");
        assert!((h - u * spacing[a]).abs() < 1e-3, "axis {a}: {h} vs {u}");
        assert!((d - 2.0 * u).abs() < 1e-3, "axis {a}: {d} vs {u}");
    }
    // Placed by space directions and an origin: vertices at origin + spacing × index.
    let placed = dir.join("placed.nrrd");
    ball_nrrd(
        &placed,
        [7.5, 7.5, 7.5],
        "space dimension: 3\nspace directions: (1,0,0) (0,2,0) (0,0,0.5)\nspace origin: (100,0,-20)\n",
    );
    let (_, (plo, phi)) = run_on(&placed, "placed.ply", &[]);
    let origin = [100.0, 0.0, -20.0];
    for a in 0..3 {
        let expect_lo = origin[a] + (ulo[a] - 0.0) * spacing[a];
        assert!(
            (plo[a] - expect_lo).abs() < 1e-3,
            "axis {a}: {plo:?} vs unit {ulo:?}"
        );
        assert!(
            (phi[a] - plo[a] - (hhi[a] - hlo[a])).abs() < 1e-3,
            "axis {a}"
        );
    }
    // `render` keeps the header's spacing too, and says when the flag replaces it.
    let png = dir.join("aniso.png");
    let png = png.to_str().unwrap();
    let data_arg = data.to_str().unwrap();
    let o = tessera(&["render", data_arg, "--size", "16x16", "-o", png]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("spacing 1,2,0.5)"), "{}", stderr(&o));
    let o = tessera(&[
        "render",
        data_arg,
        "--spacing",
        "1,1,1",
        "--size",
        "16x16",
        "-o",
        png,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("note: --spacing 1,1,1 replaces the spacing 1,2,0.5"),
        "{}",
        stderr(&o)
    );
    let (ha, ua, da) = (
        printed_area(&header),
        printed_area(&unit),
        printed_area(&double),
    );
    assert!((da / ua - 4.0).abs() < 0.01, "areas {da} {ua}");
    // Stretched by 2 along y and squashed by 2 along z: neither unit nor double.
    assert!(
        (ha / ua - 1.0).abs() > 0.05 && ha < da,
        "areas {ha} {ua} {da}"
    );
}

#[test]
fn negative_values_parse_and_isovalues_outside_the_data_warn() {
    let dir = scratch("negative");
    let out = dir.join("s.ply");
    for flags in [
        &["--iso", "-300"][..],
        &["--iso-fraction", "-0.5"],
        &["--iso-fraction", "1.5", "--nan-fill", "-1"],
    ] {
        let mut args = vec![
            "extract",
            "procedural:sphere:16",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(flags);
        let o = tessera(&args);
        assert!(o.status.success(), "{flags:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(
            err.contains("warning: isovalue") && err.contains("outside the values"),
            "{flags:?}: {err}"
        );
        assert!(err.contains("(0..238)"), "{err}");
    }
    let o = tessera(&[
        "extract",
        "procedural:sphere:16",
        "--iso",
        "100",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}

#[test]
fn default_isovalue_is_otsus_threshold() {
    let dir = scratch("otsu");
    let data = dir.join("ball.nrrd");
    ball_nrrd(&data, [7.5, 7.5, 7.5], "");
    let out = dir.join("ball.ply");
    let o = tessera(&[
        "extract",
        data.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    // Two values, 10 and 200: the threshold lies between them.
    let iso: f32 = err
        .split("isovalue ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{err}"));
    assert!(err.contains("(Otsu threshold of the histogram)"), "{err}");
    assert!(iso > 10.0 && iso < 200.0, "{iso}");
}

/// Mean row of the pixels that differ from the top-left one, as a fraction of the height.
fn drawn_centre_row(path: &std::path::Path) -> f32 {
    let (w, _) = png_size(path);
    let pixels = png_pixels(path);
    let background = pixels[0];
    let rows: Vec<f32> = pixels
        .iter()
        .enumerate()
        .filter(|(_, p)| **p != background)
        .map(|(i, _)| (i / w as usize) as f32)
        .collect();
    assert!(rows.len() > 20, "{} pixels drawn", rows.len());
    rows.iter().sum::<f32>() / rows.len() as f32 / (pixels.len() / w as usize) as f32
}

#[test]
fn view_up_turns_the_named_axis_up() {
    let dir = scratch("up");
    // A ball near the top (high z) of the grid.
    let plain = dir.join("top.nrrd");
    ball_nrrd(&plain, [7.5, 7.5, 11.0], "");
    let lps = dir.join("top-lps.nrrd");
    ball_nrrd(
        &lps,
        [7.5, 7.5, 11.0],
        "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (0,0,0)\n",
    );
    let render = |data: &std::path::Path, up: Option<&str>| {
        let out = dir.join(format!(
            "{}-{}.png",
            data.file_stem().unwrap().to_string_lossy(),
            up.unwrap_or("default")
        ));
        let mut args = vec![
            "render",
            data.to_str().unwrap(),
            "--iso",
            "100",
            "--camera",
            "0,0,1.8",
            "--size",
            "64x64",
            "-o",
            out.to_str().unwrap(),
        ];
        if let Some(up) = up {
            args.extend(["--up", up]);
        }
        let o = tessera(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        (drawn_centre_row(&out), stderr(&o))
    };
    let (up_z, _) = render(&plain, Some("z"));
    let (down_z, _) = render(&plain, Some("-z"));
    let (default, _) = render(&plain, None);
    assert!(up_z < 0.4, "--up z: ball at {up_z} of the height");
    assert!(down_z > 0.6, "--up -z: ball at {down_z} of the height");
    assert!((default - 0.5).abs() < 0.1, "default: ball at {default}");
    // A medical file's orientation puts the head (superior, +z) up without the flag.
    let (medical, err) = render(&lps, None);
    assert!(medical < 0.4, "LPS file: ball at {medical}");
    assert!(err.contains("view up z"), "{err}");
    let o = tessera(&["render", "procedural:sphere:16", "--up", "w"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

/// `--ambiguity` picks how a face with diagonal above-iso corners is cut: on one cell with 1
/// at corners (0,0,0) and (1,1,0), VTK 9.7.2's vtkMarchingCubes gives area 1.1085 at iso 0.2
/// (the corners kept apart), the asymptotic decider joins them (saddle value 0.5 ≥ 0.2):
/// 1.6628. Bad names are refused.
#[test]
fn extract_cuts_ambiguous_faces_by_the_rule_asked_for() {
    let dir = scratch("ambiguity");
    let data = dir.join("diagonal_2x2x2_float32.raw");
    let mut values = [0f32; 8];
    values[0] = 1.0;
    values[3] = 1.0;
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(&data, bytes).unwrap();
    let area = |rule: &str| -> f64 {
        let out = dir.join(format!("{rule}.ply"));
        let o = tessera(&[
            "extract",
            data.to_str().unwrap(),
            "--iso",
            "0.2",
            "--ambiguity",
            rule,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        f64::from(printed_area(&o))
    };
    let (vtk, decider) = (area("vtk"), area("decider"));
    assert!((vtk - 1.1085).abs() < 0.06, "vtk rule: area {vtk}");
    assert!((decider - 1.6628).abs() < 0.06, "decider: area {decider}");
    let o = tessera(&["extract", data.to_str().unwrap(), "--ambiguity", "maybe"]);
    let err = stderr(&o);
    assert!(!o.status.success(), "{err}");
    assert!(
        ["maybe", "decider", "vtk"].iter().all(|w| err.contains(w)),
        "{err}"
    );
}
