//! Tests of the `.vti` loader with small hand-made files in each encoding.
use super::*;
use crate::orientation::OrientationSource;
use crate::test_files::test_path;
use crate::volume::ScalarType;

fn data_file(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

#[test]
fn ascii_uint8_with_placement() {
    let image = read_vti(&data_file("ascii_u8.vti"), NanPolicy::Reject).expect("load");
    let v = &image.volume;
    assert_eq!(
        (v.name(), v.dims(), v.spacing()),
        ("ascii_u8", [3, 2, 2], [0.5, 1.0, 2.0])
    );
    assert_eq!(v.samples(), &Samples::U8((0..120).step_by(10).collect()));
    assert_eq!(image.origin, [1.0, 2.0, 3.0]);
    assert_eq!(
        image.direction,
        [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    );
    // The volume carries the placement: grid axis i is the direction matrix's column i.
    let placed = v.orientation();
    assert_eq!(placed.source(), OrientationSource::Vti);
    assert_eq!(placed.origin(), [1.0, 2.0, 3.0]);
    assert_eq!(
        placed.direction(),
        [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    );
}

#[test]
fn zlib_float64_picks_the_named_scalars() {
    let image = read_vti(&data_file("zlib_f64.vti"), NanPolicy::Reject).expect("load");
    let want: Vec<f32> = (0..8).map(|i| 0.5 * i as f32 - 1.0).collect();
    assert_eq!(image.volume.samples(), &Samples::F32(want));
    assert_eq!(image.origin, [0.0; 3]);
    assert_eq!(
        image.direction,
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    );
}

#[test]
fn appended_raw_big_endian_int16_becomes_f32() {
    let v = load_vti(&data_file("appended_raw_i16_be.vti"), NanPolicy::Reject).expect("load");
    assert_eq!((v.dims(), v.scalar_type()), ([2, 3, 2], ScalarType::F32));
    let want: Vec<f32> = (0..12).map(|i| -300.0 + 50.0 * i as f32).collect();
    assert_eq!(v.samples(), &Samples::F32(want));
}

#[test]
fn inline_base64_int8_with_an_offset_extent() {
    let v = load_vti(&data_file("binary_i8.vti"), NanPolicy::Reject).expect("load");
    assert_eq!((v.dims(), v.spacing()), ([2, 2, 2], [2.0; 3]));
    let want = vec![-128.0, -1.0, 0.0, 1.0, 127.0, 5.0, -5.0, 42.0];
    assert_eq!(v.samples(), &Samples::F32(want));
    // The first sample is at extent (1, -1, 5) × spacing 2 from the origin.
    assert_eq!(v.orientation().origin(), [2.0, -2.0, 10.0]);
}

#[test]
fn pieces_are_placed_by_extent() {
    let v = load_vti(&data_file("pieces_u16.vti"), NanPolicy::Reject).expect("load");
    assert_eq!(v.dims(), [4, 2, 2]);
    let want: Vec<u16> = (0..2)
        .flat_map(|z| (0..2).flat_map(move |y| (0..4).map(move |x| 1000 * z + 100 * y + x)))
        .collect();
    assert_eq!(v.samples(), &Samples::U16(want));
}

#[test]
fn through_the_volume_front_door() {
    let v =
        crate::load::load_volume(&data_file("ascii_u8.vti"), &Default::default()).expect("load");
    assert_eq!(v.dims(), [3, 2, 2]);
}

#[test]
fn bad_files() {
    let good = std::fs::read_to_string(data_file("ascii_u8.vti")).expect("read");
    let cases = [
        (
            good.replace("0 2 0 1 0 1\" Origin", "0 2 0 1 0 5\" Origin"),
            "line 3",
            "do not cover",
        ),
        (
            good.replace("Extent=\"0 2 0 1 0 1\">", "Extent=\"0 2 0 1 0 9\">"),
            "line 4",
            "outside WholeExtent",
        ),
        (
            good.replace("100 110", "100"),
            "line 6",
            "holds 11 values, but the piece Extent \"0 2 0 1 0 1\" calls for 12",
        ),
        (
            good.replace("100 110", "100 300"),
            "line 6",
            "does not fit UInt8",
        ),
        (
            good.replace("Spacing=\"0.5 1 2\"", "Spacing=\"0.5 1\""),
            "line 3",
            "Spacing needs 3",
        ),
        (
            good.replace("Spacing=\"0.5 1 2\"", "Spacing=\"0.5 0 2\""),
            "",
            "spacing",
        ),
        (
            good.replace("WholeExtent=\"0 2 0 1 0 1\"", "WholeExtent=\"0 2 0 1\""),
            "line 3",
            "six integers",
        ),
        (
            good.replace("type=\"ImageData\"", "type=\"UnstructuredGrid\""),
            "line 2",
            "read as a volume",
        ),
        (
            good.replace(
                "Name=\"density\"",
                "Name=\"density\" NumberOfComponents=\"3\"",
            ),
            "line 4",
            "no one-component",
        ),
        (
            good.replace(
                "WholeExtent=\"0 2 0 1 0 1\"",
                "WholeExtent=\"0 4294967299 0 1 0 1\"",
            ),
            "line 3",
            "too large",
        ),
    ];
    let mut wrong = Vec::new();
    for (text, place, what) in cases {
        let path = test_path("bad.vti");
        std::fs::write(&path, text).expect("write");
        let message = load_vti(&path, NanPolicy::Reject)
            .expect_err("should fail")
            .to_string();
        if !(message.contains("bad.vti") && message.contains(place) && message.contains(what)) {
            wrong.push(format!("want {place:?} {what:?}, got {message}"));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// A real file checked by hand: `TESSERA_VTI_FILE=/path/to/frog_tissues.vti`.
#[test]
fn real_file_from_the_environment() {
    let Some(path) = std::env::var_os("TESSERA_VTI_FILE") else {
        return;
    };
    let start = std::time::Instant::now();
    let image = read_vti(Path::new(&path), NanPolicy::Reject).expect("load");
    let v = &image.volume;
    let sum: f64 = (0..v.sample_count() as usize)
        .map(|i| {
            let n = v.dims()[0] as usize * v.dims()[1] as usize;
            let d = v.dims()[0] as usize;
            f64::from(v.texel((i % d) as u32, (i % n / d) as u32, (i / n) as u32))
        })
        .sum();
    eprintln!(
        "{}: {:?} {:?} spacing {:?} origin {:?} range {:?} sum {sum} in {:?}",
        v.name(),
        v.dims(),
        v.scalar_type(),
        v.spacing(),
        image.origin,
        v.value_range(),
        start.elapsed()
    );
    // pyvista's frog_tissues.vti (the wheel's examples folder), as its header and ranges say.
    if v.name() == "frog_tissues" {
        assert_eq!((v.dims(), v.spacing()), ([500, 470, 136], [1.0, 1.0, 1.5]));
        assert_eq!((v.value_range(), sum), ((0.0, 29.0), 12_244_762.0));
    }
}

#[test]
fn bytes_load_like_the_file() {
    let path = data_file("zlib_f64.vti");
    let bytes = std::fs::read(&path).expect("test file");
    let parsed = parse_bytes(&bytes, &path, NanPolicy::Reject).expect("parse");
    let loaded = read_vti(&path, NanPolicy::Reject).expect("load");
    assert_eq!(parsed.volume.dims(), loaded.volume.dims());
    assert_eq!(parsed.origin, loaded.origin);
    let err = parse_bytes(&bytes[..bytes.len() / 2], &path, NanPolicy::Reject).expect_err("cut");
    assert!(err.to_string().contains("zlib_f64.vti"), "{err}");
}

/// A `Direction` with a column of zeros cannot place the grid: the samples load at the default
/// placement, and the orientation says which placement was passed over.
#[test]
fn unusable_direction_is_recorded() {
    let good = std::fs::read_to_string(data_file("ascii_u8.vti")).expect("read");
    let bad = good.replace(
        "Direction=\"0 1 0 1 0 0 0 0 1\"",
        "Direction=\"0 1 0 0 0 0 0 0 1\"",
    );
    assert_ne!(bad, good);
    let parsed =
        parse_bytes(bad.as_bytes(), &data_file("flat.vti"), NanPolicy::Reject).expect("parse");
    let o = parsed.volume.orientation();
    assert_eq!(o.source(), crate::orientation::OrientationSource::Default);
    assert_eq!(
        o.unusable(),
        Some(crate::orientation::OrientationSource::Vti)
    );
}
