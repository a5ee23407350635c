//! `tessera render --technique shell` with its secondary-ray effects: the flags change the
//! image and report each pass's time and the secondary rays; shell-only flags given to another
//! technique, and interval shading's flags given to shell, are warned about; contradictory or
//! out-of-range effect flags are refused.

mod common;

use common::*;

#[test]
fn effect_flags_shade_the_image_and_report_their_passes() {
    let dir = scratch("shell-effects");
    let run = |name: &str, flags: &[&str]| {
        let out = dir.join(format!("{name}.png"));
        let mut args = vec![
            "--validation",
            "render",
            "tets:box:3",
            "--technique",
            "shell",
            "--layout",
            "tet16",
            "--size",
            "40x30",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(flags);
        (tessera(&args), out)
    };
    let render = |name: &str, flags: &[&str]| {
        let (o, out) = run(name, flags);
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        assert!(!stderr(&o).contains("warning"), "{name}: {}", stderr(&o));
        (
            String::from_utf8_lossy(&o.stdout).into_owned(),
            png_pixels(&out),
        )
    };
    let (plain_out, plain) = render("plain", &[]);
    assert!(!plain_out.contains("passes:"), "{plain_out}");
    let cases: [(&str, &[&str], &str, &str); 5] = [
        ("sun", &["--shadows"], "with shadows", "shell ground"),
        (
            "point",
            &["--shadows", "--light", "0.6,0.8,-0.2"],
            "with shadows",
            "shell shadows",
        ),
        (
            "sun-dir",
            &["--shadows", "--light-dir", "-1,2,0.5"],
            "with shadows",
            "shell shadows",
        ),
        (
            "ao",
            &["--ao", "4", "--ao-radius", "0.2"],
            "with AO 4x0.2",
            "shell ambient occlusion",
        ),
        (
            "gradient",
            &["--gradient"],
            "with gradient shading",
            "shell gradients",
        ),
    ];
    for (name, flags, described, pass) in cases {
        let (stdout, image) = render(name, flags);
        assert!(stdout.contains(described), "{name}: {stdout}");
        assert!(stdout.contains(pass), "{name}: {stdout}");
        assert!(stdout.contains("secondary rays:"), "{name}: {stdout}");
        assert_ne!(image, plain, "{name}: the effect changed nothing");
    }
    let (stdout, _) = render("all", &["--shadows", "--ao", "2", "--gradient"]);
    assert!(
        stdout.contains("with shadows, AO 2x0.1, gradient shading"),
        "{stdout}"
    );
    // The ray-tracing pipeline (the graphics path) draws the compute path's image.
    let (o, out) = run("ray-tracing", &["--path", "graphics"]);
    if stderr(&o).contains("needs features") {
        tessera_test::skip("ray-tracing pipeline", &stderr(&o));
    } else {
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(png_pixels(&out), plain, "the ray-tracing pipeline's image");
    }
}

#[test]
fn misplaced_effect_and_interval_flags_are_warned_about() {
    let dir = scratch("shell-misplaced");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let warned = |args: &[&str], warning: &str| {
        let mut all = vec!["render", "tets:box:2", "--size", "16x16", "-o", out];
        all.extend(args);
        let o = tessera(&all);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains(warning), "{args:?}: {err}");
    };
    warned(
        &["--technique", "interval", "--shadows"],
        "warning: interval ignores --shadows",
    );
    warned(&["--ao", "4"], "warning: interval ignores --ao");
    warned(
        &["--technique", "interval", "--gradient"],
        "warning: interval ignores --gradient",
    );
    warned(
        &["--technique", "shell", "--integrate", "emission"],
        "warning: shell ignores --integrate",
    );
    warned(
        &["--technique", "shell", "--absorption", "1,2,3"],
        "warning: shell ignores --absorption",
    );
    let o = tessera(&[
        "render",
        "procedural:sphere:16",
        "--size",
        "16x16",
        "--shadows",
        "-o",
        out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: raymarch ignores --shadows"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn contradictory_or_out_of_range_effect_flags_are_refused() {
    let dir = scratch("shell-refused");
    let out = dir.join("x.png");
    let out = out.to_str().unwrap();
    let refused = |flags: &[&str], needles: &[&str]| {
        let mut all = vec![
            "render",
            "tets:box:2",
            "--technique",
            "shell",
            "--size",
            "16x16",
            "-o",
            out,
        ];
        all.extend(flags);
        let o = tessera(&all);
        let err = stderr(&o);
        // Usage errors (clap's) exit with 2, refused values with 1.
        assert!(
            matches!(o.status.code(), Some(1 | 2)),
            "{flags:?}: expected failure, got {:?}: {err}",
            o.status
        );
        assert!(!err.contains("panicked"), "{flags:?}: {err}");
        for n in needles {
            assert!(err.contains(n), "{flags:?}: '{n}' missing from: {err}");
        }
    };
    refused(&["--light", "1,2,3"], &["--shadows"]);
    refused(&["--light-dir", "0,1,0"], &["--shadows"]);
    refused(
        &["--shadows", "--light", "1,2,3", "--light-dir", "0,1,0"],
        &["--light-dir"],
    );
    refused(&["--shadows", "--light-dir", "0,0,0"], &["0,0,0"]);
    refused(&["--ao", "0"], &["1 to 64"]);
    refused(&["--ao", "65"], &["1 to 64"]);
    refused(&["--ao", "4", "--ao-radius", "-1"], &["radius"]);
    refused(&["--ao-radius", "0.2"], &["--ao"]);
}
