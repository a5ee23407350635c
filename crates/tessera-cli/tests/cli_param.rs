//! The `tessera` binary on parametric objects: named scenes, glyph fields, user GLSL functions
//! and real diffusion MRI coefficients, on every parametric technique.

mod common;

use common::*;
use std::path::PathBuf;

#[test]
fn renders_parametric_scenes() {
    let dir = scratch("param");
    let out = dir.join("param.png");
    for spec in [
        "param:heart",
        "param:sh-glyph:order8",
        "procedural:sh-glyphs:3x2:order4",
    ] {
        let o = tessera(&[
            "--validation",
            "render",
            spec,
            "--size",
            "48x40",
            "--supersample",
            "2",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{spec}: {}", stderr(&o));
        assert_eq!(png_size(&out), (48, 40));
        assert!(String::from_utf8_lossy(&o.stdout).contains("param-points"));
    }
    let o = tessera(&[
        "--validation",
        "render",
        "param:heart",
        "--technique",
        "param-tess",
        "--msaa",
        "4",
        "--pre-split",
        "2",
        "--size",
        "48x40",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "param-tess: {}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("param-tess"));
    let o = tessera(&[
        "--validation",
        "render",
        "param:sh-glyphs:2x2:order6",
        "--technique",
        "sh-raytrace",
        "--size",
        "48x40",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "sh-raytrace: {}", stderr(&o));
    let o = tessera(&["render", "param:heart", "--technique", "sh-raytrace"]);
    assert_fails_with(&o, &["SH glyphs"]);
    let o = tessera(&["render", "param:heart", "--msaa", "4"]);
    assert_fails_with(&o, &["msaa", "param-tess"]);
    let o = tessera(&["render", "param:sh-glyph:order7"]);
    assert_fails_with(&o, &["param:sh-glyph:order7"]);
    let o = tessera(&["render", "param:torus"]);
    assert_fails_with(&o, &["torus", "param:heart"]);
    let o = tessera(&["render", "param:heart", "--technique", "raymarch"]);
    assert_fails_with(&o, &["param:heart", "param-points"]);
}

#[test]
fn renders_user_functions_and_names_their_errors() {
    let dir = scratch("user-function");
    let file = dir.join("torus.glsl");
    std::fs::write(
        &file,
        "// u: 0 2pi\n// v: 0 tau\nvec3 f(float u, float v) {\n    float r = 0.3;\n    \
         return vec3((1.0 + r * cos(v)) * cos(u), (1.0 + r * cos(v)) * sin(u), r * sin(v));\n}\n",
    )
    .unwrap();
    let out = dir.join("torus.png");
    let o = tessera(&[
        "--validation",
        "render",
        file.to_str().unwrap(),
        "--size",
        "48x40",
        "--camera",
        "20,40,4",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Something was drawn: not every pixel is the background.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&out).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut bytes = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut bytes).unwrap();
    let pixels: Vec<&[u8]> = bytes.chunks(4).collect();
    assert!(pixels.iter().filter(|&&p| p != pixels[0]).count() > 100);
    // A syntax error names the file and its line; a missing or wrong f, and a missing range,
    // are refused before compiling.
    let bad = dir.join("bad.glsl");
    let cases = [
        (
            "// u: 0 1\n// v: 0 1\nvec3 f(float u, float v) {\n    return vec3(u, v, );\n}\n",
            "bad.glsl:4",
        ),
        (
            "// u: 0 1\n// v: 0 1\nvec3 g(float u, float v) { return vec3(u); }\n",
            "no function",
        ),
        (
            "// u: 0 1\n// v: 0 1\nvec3 f(float u) { return vec3(u); }\n",
            "line 3",
        ),
        (
            "// u: 0 1\nvec3 f(float u, float v) { return vec3(u); }\n",
            "--v-range",
        ),
    ];
    for (text, expected) in cases {
        std::fs::write(&bad, text).unwrap();
        let o = tessera(&[
            "render",
            bad.to_str().unwrap(),
            "--size",
            "16x16",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert_fails_with(&o, &["bad.glsl", expected]);
    }
}

/// Real diffusion MRI glyphs (DIPY's small_64D fitted by scripts/fetch-dwi.sh): ray tracing and
/// the point variant draw the same silhouettes and colours. Skipped where the file is missing.
#[test]
fn renders_diffusion_glyphs_from_a_coefficient_volume() {
    let file = tessera_test::data_file("dwi/small_64D_csa8.nii.gz");
    if !file.exists() {
        let reason = format!("{} not found (scripts/fetch-dwi.sh)", file.display());
        tessera_test::skip("", &reason);
        return;
    }
    let dir = scratch("dwi");
    let spec = format!("sh:{}:z5", file.display());
    let mut images = Vec::new();
    for technique in ["sh-raytrace", "param-points"] {
        let out = dir.join(format!("{technique}.png"));
        let o = tessera(&[
            "--validation",
            "render",
            &spec,
            "--technique",
            technique,
            "--camera",
            "0,0,0.5",
            "--size",
            "256x256",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{technique}: {}", stderr(&o));
        assert!(String::from_utf8_lossy(&o.stdout).contains("100 objects"));
        images.push(png_pixels(&out));
    }
    // The background is the most common colour.
    let mut counts = std::collections::HashMap::new();
    for p in &images[0] {
        *counts.entry(*p).or_insert(0) += 1;
    }
    let background = *counts.iter().max_by_key(|(_, n)| **n).unwrap().0;
    let covered = |img: &Vec<[u8; 4]>| img.iter().map(|p| *p != background).collect::<Vec<_>>();
    let (a, b) = (covered(&images[0]), covered(&images[1]));
    let both = a.iter().zip(&b).filter(|(x, y)| **x && **y).count();
    let either = a.iter().zip(&b).filter(|(x, y)| **x || **y).count();
    let iou = both as f64 / either as f64;
    assert!(both > 1000, "{both} pixels covered by both");
    assert!(iou >= 0.97, "silhouette IoU {iou} ({both} pixels in both)");
    let close = images[0]
        .iter()
        .zip(&images[1])
        .zip(a.iter().zip(&b))
        .filter(|(_, (x, y))| **x && **y)
        .filter(|((p, q), _)| (0..3).all(|c| p[c].abs_diff(q[c]) <= 8))
        .count();
    assert!(
        close as f64 >= 0.9 * both as f64,
        "{close} of {both} pixels within 8/255"
    );
    // A file of a count that is no SH order is refused by name.
    let o = tessera(&[
        "render",
        &format!("sh:{}", dir.join("missing.nii").display()),
    ]);
    assert_fails_with(&o, &["missing.nii"]);
}

/// User functions the GPU cannot survive stop cleanly: an endless loop at the time limit (in
/// seconds, not for ever), naming the file, the technique and the pass; a huge local array
/// before any GPU work. A bad `--gpu-timeout` is refused.
#[test]
fn user_functions_that_never_end_or_need_too_much_memory_stop_cleanly() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let out = scratch("user-limits").join("out.png");
    let run = |file: &str, extra: &[&str]| {
        let path = data.join(file);
        let mut args = vec!["render", path.to_str().unwrap(), "--size", "16x16", "-o"];
        args.push(out.to_str().unwrap());
        args.extend_from_slice(extra);
        let started = std::time::Instant::now();
        (tessera(&args), started.elapsed())
    };
    let (o, took) = run("endless_loop.glsl", &["--gpu-timeout", "3"]);
    assert_fails_with(
        &o,
        &[
            "endless_loop.glsl",
            "param-points",
            "did not finish within 3 s",
        ],
    );
    assert!(took.as_secs() < 120, "took {took:?}");
    let (o, _) = run("huge_local_array.glsl", &["--technique", "param-tess"]);
    assert_fails_with(
        &o,
        &["huge_local_array.glsl", "4000012 bytes of local variables"],
    );
    let (o, _) = run("huge_local_array.glsl", &["--gpu-timeout", "-1"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--gpu-timeout"), "{}", stderr(&o));
    assert!(!out.exists());
}

/// `--glyph-radius` picks how SH values become radii: the three mappings draw different
/// glyphs, by ray tracing and by points alike, and an unknown name is refused.
#[test]
fn glyph_radius_mappings_change_the_glyphs() {
    let dir = scratch("glyph-radius");
    for technique in ["sh-raytrace", "param-points"] {
        let images: Vec<Vec<[u8; 4]>> = ["minmax", "abs", "clamp"]
            .into_iter()
            .map(|mapping| {
                let out = dir.join(format!("{technique}-{mapping}.png"));
                let o = tessera(&[
                    "render",
                    "param:sh-glyphs:3x2:order6",
                    "--technique",
                    technique,
                    "--glyph-radius",
                    mapping,
                    "--size",
                    "64x48",
                    "-o",
                    out.to_str().unwrap(),
                ]);
                assert!(o.status.success(), "{mapping}: {}", stderr(&o));
                png_pixels(&out)
            })
            .collect();
        assert_ne!(images[0], images[1], "{technique}: minmax = abs");
        assert_ne!(images[1], images[2], "{technique}: abs = clamp");
        assert_ne!(images[0], images[2], "{technique}: minmax = clamp");
    }
    let o = tessera(&["render", "param:heart", "--glyph-radius", "log"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("minmax, abs or clamp"),
        "{}",
        stderr(&o)
    );
}
