//! `tessera bench growth`: every technique measured along both ladders (image pixels and data
//! size), each record carrying the sizes the plots put on their axes and what the renderer
//! counted; `bench interval --variants` times only the variants asked for (at each `--sizes`
//! size), its records saying when they were made and whether their warm-up settled, and the
//! ways of the per-tet pass's subgroup drawing only when asked for; `bench isosurface
//! --variants hidden-side` times each surface draw again with the hidden side drawn, and
//! `--ablations` `direct`'s compute frame with each of the rasterizer's ways.

mod common;
use common::*;
use serde_json::Value;
use std::collections::{BTreeMap, BTreeSet};
use std::time::{SystemTime, UNIX_EPOCH};

#[test]
fn growth_measures_every_technique_along_both_ladders() {
    let records = bench_records(
        "bench_growth",
        &["growth", "--quick", "--frames", "2", "--warmup", "1"],
    );
    // Per (unit, technique, ladder): the (data size, pixels) points measured.
    let mut points: BTreeMap<(String, String, String), BTreeSet<(u64, u64)>> = BTreeMap::new();
    for r in &records {
        assert_eq!(r["scenario"], "growth");
        let counts = r["counts"].as_object().unwrap();
        let unit = ["voxels", "tets", "glyphs"]
            .into_iter()
            .find(|u| counts.contains_key(*u))
            .unwrap_or_else(|| panic!("no data size in {r}"));
        let (w, h) = (r["width"].as_u64().unwrap(), r["height"].as_u64().unwrap());
        assert_eq!(counts["pixels"].as_f64().unwrap() as u64, w * h, "{r}");
        // What the renderer counted in its frame comes along: interval shading's scheme, the
        // triangles an isosurface technique drew.
        let counted = match r["technique"].as_str().unwrap() {
            "interval" => Some("tiled_tets"),
            "direct" | "meshlets" | "pmb" => Some("triangles_last_frame"),
            _ => None,
        };
        if let Some(name) = counted {
            assert!(counts.contains_key(name), "no {name} in {r}");
        }
        let stages = r["stages"].as_array().unwrap();
        assert!(
            stages
                .iter()
                .all(|s| s["median_ms"].as_f64().unwrap() > 0.0),
            "{r}"
        );
        let key = (
            unit.to_string(),
            r["technique"].as_str().unwrap().to_string(),
            r["variant"].as_str().unwrap().to_string(),
        );
        points
            .entry(key)
            .or_default()
            .insert((counts[unit].as_f64().unwrap() as u64, w * h));
    }
    // The quick ladders: two datasets per family, two image sizes (128x72, 256x144); the
    // pixel ladder on the middle (second) dataset, the data ladder at the middle size.
    let families = [
        (
            "voxels",
            &["raymarch", "direct", "meshlets", "pmb", "offline"][..],
            [24u64.pow(3), 40u64.pow(3)],
        ),
        (
            "tets",
            &["interval", "shell"][..],
            [6 * 2u64.pow(3), 6 * 3u64.pow(3)],
        ),
        (
            "glyphs",
            &["param-points", "param-tess", "sh-raytrace"][..],
            [4, 9],
        ),
    ];
    let (small, large) = (128 * 72, 256 * 144);
    for (unit, techniques, [first, second]) in families {
        for technique in techniques {
            let at = |ladder: &str| {
                points
                    .get(&(unit.to_string(), technique.to_string(), ladder.to_string()))
                    .cloned()
                    .unwrap_or_default()
            };
            assert_eq!(
                at("pixels"),
                BTreeSet::from([(second, small), (second, large)]),
                "{technique}: pixel ladder"
            );
            assert_eq!(
                at("data"),
                BTreeSet::from([(first, large), (second, large)]),
                "{technique}: data ladder"
            );
        }
    }
}

#[test]
fn interval_times_only_the_variants_asked_for() {
    let records = bench_records(
        "bench_variants",
        &quick_interval(&["--variants", "scalar", "--sizes", "64x48,80x40"]),
    );
    // Every variant and view at each size asked for, in that order.
    let sizes: Vec<(u64, u64)> = records
        .iter()
        .map(|r| (r["width"].as_u64().unwrap(), r["height"].as_u64().unwrap()))
        .collect();
    let half = sizes.len() / 2;
    assert!(half > 0 && sizes.len() == 2 * half, "{sizes:?}");
    assert!(sizes[..half].iter().all(|&s| s == (64, 48)), "{sizes:?}");
    assert!(sizes[half..].iter().all(|&s| s == (80, 40)), "{sizes:?}");
    let variants: BTreeSet<&str> = records
        .iter()
        .map(|r| r["variant"].as_str().unwrap())
        .collect();
    // The scalar field's three compute variants, and nothing of tet absorption.
    assert_eq!(variants.len(), 3, "{variants:?}");
    assert!(
        variants.iter().all(|v| v.starts_with("scalar absorption")),
        "{variants:?}"
    );
    // Each record says when it was made, that its warm-up (none) did not settle, and that no
    // dispatch kept the GPU busy between its frames (a quick run's).
    let now = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .unwrap()
        .as_secs_f64();
    for r in &records {
        let made = r["unix_time_s"].as_f64().unwrap();
        assert!((now - 600.0..=now).contains(&made), "{made} against {now}");
        let stages = r["stages"].as_array().unwrap();
        assert!(stages.iter().all(|s| s["settled"] == false), "{stages:?}");
        assert_eq!(r["keep_busy_ms"].as_f64(), Some(0.0), "{r}");
    }
}

#[test]
fn interval_compares_the_ways_of_subgroup_drawing_when_asked() {
    let records = bench_records(
        "bench_subgroup_ways",
        &quick_interval(&[
            "--variants",
            "tet absorption, tiles above 16384 px, subgroup",
        ]),
    );
    let variants: BTreeSet<&str> = records
        .iter()
        .map(|r| r["variant"].as_str().unwrap())
        .collect();
    // The default limit, none, a higher limit, and three set-up costs of the chosen limit;
    // each in every view.
    assert_eq!(variants.len(), 6, "{variants:?}");
    assert_eq!(records.len(), 6 * 3, "{variants:?}");
    for way in [
        "above 64 px",
        "off",
        "above 256 px",
        "chosen (set-up 32 px)",
    ] {
        assert!(
            variants
                .iter()
                .any(|v| v.ends_with(&format!("subgroup drawing {way}"))),
            "{way}: {variants:?}"
        );
    }
}

#[test]
fn variants_that_match_nothing_are_refused() {
    let quick = [
        "--quick",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--data",
        "tets:box:2",
    ];
    let mut args = vec!["bench", "interval", "--variants", "no such variant"];
    args.extend(quick);
    assert_fails_with(&tessera(&args), &["no interval variant", "no such variant"]);
    let o = tessera(&["bench", "raymarch", "--quick", "--variants", "binned"]);
    assert_fails_with(&o, &["--variants", "raymarch"]);
    let o = tessera(&["bench", "isosurface", "--quick", "--variants", "binned"]);
    assert_fails_with(&o, &["variants are 'hidden-side' and", "binned"]);
}

#[test]
fn techniques_that_no_scenario_times_are_refused() {
    let o = tessera(&["bench", "raymarch", "--quick", "--techniques", "direct"]);
    assert_fails_with(&o, &["--techniques", "raymarch reads none"]);
    let o = tessera(&[
        "bench",
        "isosurface",
        "--quick",
        "--techniques",
        "direct,direct+nothing",
    ]);
    assert_fails_with(
        &o,
        &["no isosurface technique 'direct+nothing'", "direct+hzb"],
    );
}

#[test]
fn isosurface_times_each_draw_again_with_the_hidden_side_drawn_when_asked() {
    let records = bench_records(
        "bench_hidden_side",
        &[
            "isosurface",
            "--quick",
            "--data",
            "procedural:head:40:uint8",
            "--paths",
            "compute",
            "--sizes",
            "64x48",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--min-warmup-ms",
            "0",
            "--variants",
            "hidden-side",
        ],
    );
    let name = |r: &Value| format!("{} {} {}", r["technique"], r["path"], r["variant"]);
    let one_side = |r: &Value| r["counts"]["one_side_drawn"].as_f64();
    // Ray marching alone, then each surface draw (compute path only) followed by its twin.
    assert_eq!(records[0]["technique"], "raymarch");
    let draws = &records[1..];
    assert!(
        draws.len() >= 2 * 4 && draws.len().is_multiple_of(2),
        "{}",
        draws.len()
    );
    for pair in draws.chunks(2) {
        let (first, twin) = (&pair[0], &pair[1]);
        assert_eq!(first["path"], "compute", "{}", name(first));
        assert_eq!(first["technique"], twin["technique"], "{}", name(twin));
        let variant = first["variant"].as_str().unwrap_or(""); // absent when empty
        let expected = match variant {
            "" => "hidden side drawn".to_string(),
            v => format!("{v}, hidden side drawn"),
        };
        assert_eq!(twin["variant"].as_str(), Some(expected.as_str()));
        // The head's surface is closed: one side drawn, then both.
        assert_eq!(one_side(first), Some(1.0), "{}", name(first));
        assert_eq!(one_side(twin), Some(0.0), "{}", name(twin));
    }
    let techniques: BTreeSet<&str> = draws
        .iter()
        .map(|r| r["technique"].as_str().unwrap())
        .collect();
    for t in [
        "direct",
        "direct+hzb",
        "direct+auto",
        "meshlets",
        "offline",
        "pmb",
    ] {
        assert!(techniques.contains(t), "{t}: {techniques:?}");
    }
}

#[test]
fn the_printed_tables_head_lines_up_with_its_rows() {
    let o = tessera(&["bench", "raymarch", "--quick", "--frames", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    let head = out.lines().find(|l| l.starts_with("scenario")).unwrap();
    let row = out.lines().find(|l| l.starts_with("raymarch")).unwrap();
    let (head, row) = (head.as_bytes(), row.as_bytes());
    // Left-aligned columns start where their heads do; the times end where theirs do.
    for name in ["technique", "path", "dataset", "stage"] {
        let at = find(head, name);
        assert!(row[at - 1] == b' ' && row[at] != b' ', "{name} at {at}");
    }
    for name in ["median ms", "min ms", "max ms"] {
        let end = find(head, name) + name.len();
        assert!(
            row[end - 1] != b' ' && row[end] == b' ',
            "{name} ends at {end}"
        );
    }
}

fn find(text: &[u8], word: &str) -> usize {
    text.windows(word.len())
        .position(|w| w == word.as_bytes())
        .unwrap_or_else(|| panic!("no {word}"))
}

#[test]
fn a_keep_busy_target_that_is_not_a_duration_is_refused() {
    for value in [
        "--keep-busy-ms=-1",
        "--keep-busy-ms=nan",
        "--keep-busy-ms=inf",
    ] {
        let o = tessera(&["bench", "raymarch", "--quick", "--frames", "1", value]);
        assert_fails_with(&o, &["--keep-busy-ms", "0 or more"]);
    }
}

/// The JSON records of `tessera --validation bench ARGS --json FILE` (FILE in a scratch folder
/// named `scratch_name`), after checking that it succeeded.
/// `bench interval` on a small box, compute path, one frame per cell and no warm-up, then
/// `more`.
fn quick_interval<'a>(more: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "interval",
        "--quick",
        "--data",
        "tets:box:3",
        "--paths",
        "compute",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--min-warmup-ms",
        "0",
    ];
    args.extend_from_slice(more);
    args
}

fn bench_records(scratch_name: &str, args: &[&str]) -> Vec<Value> {
    let json = scratch(scratch_name).join("records.jsonl");
    let mut all = vec!["--validation", "bench"];
    all.extend_from_slice(args);
    all.extend(["--json", json.to_str().unwrap()]);
    let o = tessera(&all);
    assert!(o.status.success(), "bench failed: {}", stderr(&o));
    std::fs::read_to_string(&json)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn isosurface_ablations_time_the_rasterizers_ways_and_the_first_extraction() {
    let records = bench_records(
        "bench_raster_ablations",
        &[
            "isosurface",
            "--quick",
            "--data",
            "procedural:head:32:uint8",
            "--paths",
            "compute",
            "--sizes",
            "64x48",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--min-warmup-ms",
            "0",
            "--ablations",
        ],
    );
    let ways: Vec<(String, String)> = records
        .iter()
        .filter(|r| {
            r["variant"]
                .as_str()
                .is_some_and(|v| v.starts_with("raster "))
        })
        .map(|r| {
            let technique = r["technique"].as_str().unwrap().to_string();
            (technique, r["variant"].as_str().unwrap().to_string())
        })
        .collect();
    // Each way unculled, in the raster pass and in the extraction; the exact ones culled too.
    for place in ["", ", in extraction"] {
        for way in [
            "exact",
            "read before atomic",
            "subgroup walk above 16 px",
            "subgroup walk above 64 px",
            "no atomics",
            "set-up only",
            "no drawing",
        ] {
            let variant = format!("raster {way}{place}");
            let culled = !way.starts_with("no") && !way.starts_with("set");
            for (technique, timed) in [("direct", true), ("direct+hzb", culled)] {
                let found = ways.contains(&(technique.to_string(), variant.clone()));
                assert_eq!(found, timed, "{technique} {variant}: {ways:?}");
            }
        }
    }
    assert_eq!(ways.len(), 22, "{ways:?}");
    // Then pass A's extraction alone, each way, over the settled view's blocks.
    let extractions: Vec<&str> = records
        .iter()
        .filter_map(|r| r["variant"].as_str())
        .filter(|v| v.starts_with("pass A extraction"))
        .collect();
    assert_eq!(
        extractions,
        [
            "pass A extraction, whole",
            "pass A extraction, no vertex arithmetic",
            "pass A extraction, analysis only",
            "pass A extraction, samples only",
            "pass A extraction, whole, corners spread"
        ]
    );
    // A frame timed pass by pass also carries its whole time, first pass start to last end,
    // which holds every pass and whatever runs between them.
    let culled_frames = records.iter().filter(|r| {
        r["technique"] == "direct+hzb"
            && r["variant"]
                .as_str()
                .is_some_and(|v| v.starts_with("raster "))
    });
    for r in culled_frames {
        let median = |name: &str| {
            let stages = r["stages"].as_array().unwrap();
            let stage = stages.iter().find(|s| s["stage"] == name);
            stage.map(|s| s["median_ms"].as_f64().unwrap())
        };
        let (Some(sum), Some(span)) = (median("frame"), median("frame-span")) else {
            panic!("no frame or frame-span in {r}");
        };
        assert!(span >= sum, "{r}");
    }
}
