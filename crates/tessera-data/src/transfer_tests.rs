use super::*;

fn numeric_mean(table: &IntegrandTable, a: f64, b: f64) -> DVec3 {
    let n = 200_000;
    let mut sum = DVec3::ZERO;
    for i in 0..n {
        sum += table.value(a + (b - a) * (i as f64 + 0.5) / n as f64);
    }
    sum / n as f64
}

#[test]
fn average_is_the_exact_mean_of_the_linear_table() {
    let tf = TransferFunction::preset("bands").unwrap();
    let table = IntegrandTable::new(&tf, ScalarMode::Emission, 2.0, 64);
    for (a, b) in [
        (0.1, 0.9),
        (0.29, 0.31),
        (0.5, 0.5001),
        (0.7, 0.2),
        (0.0, 1.0),
    ] {
        let exact = table.average(a, b);
        let numeric = numeric_mean(&table, a, b);
        assert!(
            (exact - numeric).abs().max_element() < 1e-6,
            "[{a}, {b}]: {exact} vs {numeric}"
        );
    }
    // Within one knot interval the mean of a linear function is its middle value.
    let mid = table.value(0.4015);
    assert!((table.average(0.401, 0.402) - mid).abs().max_element() < 1e-12);
    assert_eq!(table.average(0.25, 0.25), table.value(0.25));
}

#[test]
fn gpu_prefix_is_the_running_trapezoid_integral() {
    let tf = TransferFunction::preset("cool-warm").unwrap();
    let table = IntegrandTable::new(&tf, ScalarMode::Absorption, 3.0, 16);
    let words = table.gpu_words();
    assert_eq!(words.len(), 32);
    // Knot spacing is 1/15: the integral from 0 to knot i in knot units is 15 × the mean × i/15.
    for i in [1usize, 7, 15] {
        let expected = table.average(0.0, i as f64 / 15.0) * i as f64;
        let got = glam::Vec3::from_slice(&words[16 + i][..3]).as_dvec3();
        assert!((got - expected).abs().max_element() < 1e-5, "knot {i}");
    }
}

#[test]
fn modes_turn_colour_and_opacity_into_rates() {
    let tf = TransferFunction::parse("0 1 0 0 0.5\n1 1 0 0 0.5\n").unwrap();
    let absorption = IntegrandTable::new(&tf, ScalarMode::Absorption, 2.0, 4);
    let emission = IntegrandTable::new(&tf, ScalarMode::Emission, 2.0, 4);
    let maximum = IntegrandTable::new(&tf, ScalarMode::Maximum, 2.0, 4);
    // A red medium absorbs green and blue more than red.
    let a = absorption.values[0];
    assert!((a[0] - 0.2).abs() < 1e-6 && (a[1] - 1.0).abs() < 1e-6);
    assert_eq!(emission.values[3], [1.0, 0.0, 0.0]);
    assert_eq!(maximum.values[2], [1.0, 0.0, 0.0]);
}

#[test]
fn bad_transfer_functions_name_the_line() {
    let cases = [
        ("0 0 0 0\n", "line 1"),
        ("0 0 0 0 0\n0.5 1 1 1 2\n", "line 2"),
        ("# comment\n0.6 0 0 0 0\n0.5 1 1 1 1\n", "line 3"),
        ("0 zero 0 0 0\n", "line 1"),
        ("# nothing\n", "no knots"),
    ];
    for (text, expected) in cases {
        let err = TransferFunction::parse(text).unwrap_err();
        assert!(err.contains(expected), "{text:?}: {err}");
    }
    let err = TransferFunction::load("/nonexistent/tf.txt")
        .unwrap_err()
        .to_string();
    assert!(err.contains("unknown transfer function"), "{err}");
    let dir = std::env::temp_dir().join(format!("tessera-tf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("tf.txt");
    std::fs::write(&file, "0 0 0 0 0\n0.5 1 1\n").unwrap();
    let err = TransferFunction::load(file.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(err.contains("tf.txt") && err.contains("line 2"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn sample_is_linear_between_knots_and_steps_at_repeated_ones() {
    let tf = TransferFunction::parse("0 0 0 0 0\n0.5 1 1 1 1\n0.5 0 0 0 0\n1 0 0 0 1\n").unwrap();
    assert_eq!(tf.sample(0.25), [0.5; 4]);
    assert_eq!(tf.sample(0.75)[3], 0.5);
    assert_eq!(tf.sample(-1.0), [0.0; 4]);
    assert_eq!(tf.sample(2.0)[3], 1.0);
}

#[test]
fn bad_transfer_function_files_are_errors() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let cases = [
        ("transfer_unsorted.txt", "line 4: position 0.4 is below"),
        ("transfer_nan.txt", "line 2: NaN is not a number in [0, 1]"),
        (
            "transfer_huge_value.txt",
            "line 2: inf is not a number in [0, 1]",
        ),
        ("transfer_empty.txt", "no knots"),
    ];
    for (name, expected) in cases {
        let err = TransferFunction::load(data.join(name).to_str().unwrap())
            .unwrap_err()
            .to_string();
        assert!(err.contains(name) && err.contains(expected), "{err}");
    }
}

#[test]
fn huge_transfer_function_files_are_refused_unread() {
    let path = crate::test_files::test_path("big_tf.txt");
    let line = "0.5 0.5 0.5 0.5 0.5\n";
    std::fs::write(&path, line.repeat(MAX_FILE_BYTES as usize / line.len() + 1)).unwrap();
    let err = TransferFunction::load(path.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("big_tf.txt") && err.contains("larger than"),
        "{err}"
    );
    // A device that never ends is not read at all.
    if std::path::Path::new("/dev/zero").exists() {
        let err = TransferFunction::load("/dev/zero").unwrap_err().to_string();
        assert!(err.contains("not a regular file"), "{err}");
    }
    let path = crate::test_files::test_path("binary_tf.txt");
    std::fs::write(&path, [0u8, 159, 146, 150]).unwrap();
    let err = TransferFunction::load(path.to_str().unwrap())
        .unwrap_err()
        .to_string();
    assert!(err.contains("byte 1: not text"), "{err}");
}

#[test]
fn sampling_never_panics() {
    let tf = TransferFunction::preset("hot").unwrap();
    assert_eq!(tf.sample(f64::NAN), tf.sample(0.0));
    assert_eq!(tf.sample(f64::INFINITY), tf.sample(1.0));
    assert_eq!(TransferFunction { knots: vec![] }.sample(0.5), [0.0; 4]);
}

#[test]
fn text_reads_back_as_the_same_function() {
    for name in PRESETS {
        let tf = TransferFunction::preset(name).unwrap();
        assert_eq!(
            TransferFunction::parse(&tf.to_text()).unwrap(),
            tf,
            "{name}"
        );
    }
}
