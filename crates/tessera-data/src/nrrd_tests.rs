//! Tests of `nrrd`.
use std::io::Write;
use std::path::PathBuf;

use flate2::write::GzEncoder;

use super::*;
use crate::orientation::{AnatomicalSpace, OrientationSource};
use crate::test_files::{test_data, test_path, within};
use crate::volume::{Samples, ScalarType};

fn write(name: &str, header: &str, data: &[u8]) -> PathBuf {
    let path = test_path(name);
    let mut bytes = header.as_bytes().to_vec();
    bytes.extend_from_slice(data);
    std::fs::write(&path, bytes).expect("write test file");
    path
}

fn gzip(data: &[u8]) -> Vec<u8> {
    let mut enc = GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(data).expect("compress");
    enc.finish().expect("compress")
}

fn ramp() -> Vec<u8> {
    (0..24).collect()
}

fn load_err(path: &Path) -> String {
    let err = load_nrrd(path, NanPolicy::Reject).expect_err("should fail");
    let text = err.to_string();
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("?");
    assert!(text.contains(name), "{text}");
    text
}

const U8_HEAD: &str = "NRRD0004\n# a comment\ntype: unsigned char\ndimension: 3\n\
                       sizes: 2 3 4\nspacings: 0.5 1 2\nmodality:=CT\n";

#[test]
fn attached_raw() {
    let path = write("a.nrrd", &format!("{U8_HEAD}encoding: raw\n\n"), &ramp());
    let v = load_nrrd(&path, NanPolicy::Reject).expect("load");
    assert_eq!(v.dims(), [2, 3, 4]);
    assert_eq!(v.spacing(), [0.5, 1.0, 2.0]);
    assert_eq!(v.name(), "a");
    assert_eq!(v.bytes(), &ramp()[..]);
}

#[test]
fn attached_gzip_and_byte_skip() {
    let mut data = vec![9u8; 3];
    data.extend(ramp());
    let head = format!("{U8_HEAD}encoding: gzip\nbyte skip: 3\n\n");
    let path = write("g.nrrd", &head, &gzip(&data));
    let v = load_nrrd(&path, NanPolicy::Reject).expect("load");
    assert_eq!(v.bytes(), &ramp()[..]);

    let head = format!("{U8_HEAD}encoding: raw\nbyte skip: -1\n\n");
    let mut data = b"padding".to_vec();
    data.extend(ramp());
    let v = load_nrrd(&write("end.nrrd", &head, &data), NanPolicy::Reject).expect("load");
    assert_eq!(v.bytes(), &ramp()[..]);
}

#[test]
fn detached_header() {
    let path = write(
        "d.nhdr",
        "NRRD0005\ntype: uint16\ndimension: 4\nsizes: 1 2 2 2\nendian: big\n\
         encoding: raw\nspace directions: none (0,3,4) (1,0,0) (0,0,2)\n\
         data file: ./d.raw\nline skip: 1\nbyte skip: 2\n",
        b"",
    );
    let values: Vec<u16> = (0..8).map(|i| 300 * i + 1).collect();
    let mut data = b"text line\nXX".to_vec();
    data.extend(values.iter().flat_map(|v| v.to_be_bytes()));
    let dir = path.parent().expect("dir");
    std::fs::write(dir.join("d.raw"), data).expect("write data");
    let v = load_nrrd(&path, NanPolicy::Reject).expect("load");
    assert_eq!(v.dims(), [2, 2, 2]);
    assert_eq!(v.spacing(), [5.0, 1.0, 2.0]);
    assert_eq!(v.samples(), &Samples::U16(values));
}

#[test]
fn big_endian_float_and_short() {
    let head = "NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nendian: big\nencoding: raw\n\n";
    let data: Vec<u8> = (0..8)
        .flat_map(|i| (i as f32 * 1.5).to_be_bytes())
        .collect();
    let v = load_nrrd(&write("f.nrrd", head, &data), NanPolicy::Reject).expect("load");
    assert_eq!(v.scalar_type(), ScalarType::F32);
    assert_eq!(v.texel(1, 1, 1), 10.5);

    let head = "NRRD0004\ntype: short\ndimension: 3\nsizes: 2 2 2\nendian: big\nencoding: gz\n\n";
    let data: Vec<u8> = (0..8).flat_map(|i| (i as i16 - 4).to_be_bytes()).collect();
    let v = load_nrrd(&write("s.nrrd", head, &gzip(&data)), NanPolicy::Reject).expect("load");
    assert_eq!(v.value_range(), (-4.0, 3.0));
}

#[test]
fn header_errors_name_file_and_line() {
    let text = load_err(&write("magic.nrrd", "NRRD0009\n", &[]));
    assert!(
        text.contains("line 1") && text.contains("NRRD0009"),
        "{text}"
    );
    let text = load_err(&write("png.nrrd", "\u{89}PNG\r\n", &[0; 64]));
    assert!(text.contains("not a NRRD file"), "{text}");

    let head = "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 4 4\nencoding: raw\n\n";
    let text = load_err(&write("flat.nrrd", head, &[0; 16]));
    assert!(
        text.contains("line 3") && text.contains("dimension 2"),
        "{text}"
    );

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: bzip2\n\n";
    let text = load_err(&write("bz.nrrd", head, &[0; 8]));
    assert!(
        text.contains("line 5") && text.contains("'bzip2'"),
        "{text}"
    );

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2\nencoding: raw\n\n";
    let text = load_err(&write("sizes.nrrd", head, &[0; 8]));
    assert!(text.contains("line 4"), "{text}");

    let head = "NRRD0004\ntype: block\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n";
    let text = load_err(&write("block.nrrd", head, &[0; 8]));
    assert!(
        text.contains("'block'") && text.contains("uint16"),
        "{text}"
    );

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\
                data file: LIST\na.raw\n";
    let text = load_err(&write("list.nhdr", head, &[]));
    assert!(text.contains("line 6") && text.contains("LIST"), "{text}");

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\n\n";
    let text = load_err(&write("noenc.nrrd", head, &[0; 8]));
    assert!(text.contains("'encoding'"), "{text}");

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 1 2\nencoding: raw\n\n";
    let text = load_err(&write("thin.nrrd", head, &[0; 4]));
    assert!(text.contains("2x1x2"), "{text}");
}

#[test]
fn truncated_data() {
    let head = format!("{U8_HEAD}encoding: raw\n\n");
    let path = write("short.nrrd", &head, &ramp()[..20]);
    let text = load_err(&path);
    assert!(
        text.contains("truncated") && text.contains("24") && text.contains("20"),
        "{text}"
    );

    // Too little data inside a complete gzip stream.
    let path = write(
        "gshort.nrrd",
        &format!("{U8_HEAD}encoding: gzip\n\n"),
        &gzip(&[1; 10]),
    );
    let err = load_nrrd(&path, NanPolicy::Reject).expect_err("short");
    assert!(
        matches!(
            err,
            DataError::SizeMismatch {
                found_bytes: 10,
                ..
            }
        ),
        "{err}"
    );
    assert!(load_err(&path).contains("truncated"));

    // A gzip stream cut off part-way.
    let big: Vec<u8> = (0..4096u32).map(|i| (i * 7 % 251) as u8).collect();
    let packed = gzip(&big);
    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 16 16 16\nencoding: gzip\n\n";
    let path = write("gcut.nrrd", head, &packed[..packed.len() / 2]);
    assert!(load_err(&path).contains("truncated"));

    let path = write("gbad.nrrd", head, b"this is not gzip at all");
    assert!(load_err(&path).contains("corrupt gzip"));

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\
                data file: missing.raw\n";
    let text = load_err(&write("nodata.nhdr", head, &[]));
    assert!(text.contains("missing.raw"), "{text}");
}

#[test]
fn nan_policy_applies() {
    let head =
        "NRRD0004\ntype: double\ndimension: 3\nsizes: 2 2 2\nendian: little\nencoding: raw\n\n";
    let mut vals = [2.0f64; 8];
    vals[3] = f64::NAN; // voxel (1, 1, 0)
    let data: Vec<u8> = vals.iter().flat_map(|v| v.to_le_bytes()).collect();
    let path = write("nan.nrrd", head, &data);
    let text = load_err(&path);
    assert!(text.contains("(1, 1, 0)"), "{text}");
    let v = load_nrrd(&path, NanPolicy::Replace(-5.0)).expect("replaced");
    assert_eq!(v.texel(1, 1, 0), -5.0);
}

#[test]
fn sizes_past_the_limit_are_refused_before_allocating() {
    // 10^15 samples declared in a 101-byte file.
    let text = load_err(&test_data("huge_gzip.nrrd"));
    assert!(text.contains("64 GiB"), "{text}");
    // 64 * 10^9 samples, within the limit: the buffer grows with the 16 bytes there are.
    let err = load_nrrd(&test_data("large_gzip.nrrd"), NanPolicy::Reject).expect_err("short");
    assert!(
        matches!(
            err,
            DataError::SizeMismatch {
                expected_bytes: 64_000_000_000,
                found_bytes: 16,
                ..
            }
        ),
        "{err}"
    );
    assert!(err.to_string().contains("large_gzip.nrrd"), "{err}");
}

#[test]
fn line_skip_stops_at_the_end_of_the_file() {
    let path = test_data("line_skip.nrrd");
    let text = within(10, move || load_err(&path));
    assert!(
        text.contains("line skip 9223372036854775807") && text.contains("ends after 1 line(s)"),
        "{text}"
    );
}

#[test]
fn data_files_must_be_regular_files() {
    let path = test_data("dev_zero.nhdr");
    let text = within(10, move || load_err(&path));
    assert!(
        text.contains("data file")
            && text.contains("/dev/zero")
            && text.contains("not a regular file"),
        "{text}"
    );
}

#[cfg(unix)]
#[test]
fn named_pipes_are_refused() {
    let pipe = crate::test_files::test_fifo("pipe.nrrd");
    let text = within(10, move || load_err(&pipe));
    assert!(text.contains("named pipe"), "{text}");

    let data = crate::test_files::test_fifo("pipe.raw");
    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\
                data file: pipe.raw\n";
    let header = data.with_file_name("pipe.nhdr");
    std::fs::write(&header, head).expect("write header");
    let text = within(10, move || load_err(&header));
    assert!(
        text.contains("pipe.raw") && text.contains("named pipe"),
        "{text}"
    );
}

#[test]
fn orientation_from_space_fields() {
    // LPS, axial slices stored from the head down, rows along -y, with 0.5/2/3 spacing.
    let head = "NRRD0005\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nencoding: raw\n\
                space: left-posterior-superior\n\
                space directions: (0.5,0,0) (0,-2,0) (0,0,-3)\n\
                space origin: (-10.5, 20, 30.25)\n\n";
    let v = load_nrrd(&write("lps.nrrd", head, &ramp()), NanPolicy::Reject).expect("load");
    assert_eq!(v.spacing(), [0.5, 2.0, 3.0]);
    let o = v.orientation();
    assert_eq!(o.source(), OrientationSource::Nrrd);
    assert_eq!(o.space(), Some(AnatomicalSpace::Lps));
    assert_eq!(o.origin(), [-10.5, 20.0, 30.25]);
    assert_eq!(
        o.direction(),
        [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
    );
    assert_eq!(v.up_axis(), Some((2, -1)));

    // A rotated grid in a space that is not anatomical: directions but no up.
    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nencoding: raw\n\
                space: scanner-xyz\nspace directions: (0,0,1) (1,0,0) (0,1,0)\n\n";
    let v = load_nrrd(&write("scanner.nrrd", head, &ramp()), NanPolicy::Reject).expect("load");
    assert_eq!(v.orientation().origin(), [0.0; 3]);
    assert_eq!(v.orientation().direction()[0], [0.0, 0.0, 1.0]);
    assert_eq!(v.up_axis(), None);

    // Without space directions only the spacing is known.
    let path = write(
        "plain.nrrd",
        &format!("{U8_HEAD}encoding: raw\n\n"),
        &ramp(),
    );
    let v = load_nrrd(&path, NanPolicy::Reject).expect("load");
    assert_eq!(v.orientation().source(), OrientationSource::Default);

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nencoding: raw\n\
                space directions: (1,0,0) (0,1,0) (0,0,1)\nspace origin: (1,2)\n\n";
    let text = load_err(&write("origin.nrrd", head, &ramp()));
    assert!(
        text.contains("line 7") && text.contains("space origin has 2 components"),
        "{text}"
    );
    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nencoding: raw\n\
                space origin: none\n\n";
    let text = load_err(&write("origin_none.nrrd", head, &ramp()));
    assert!(text.contains("bad space origin"), "{text}");
}

#[test]
fn bytes_in_memory_load_like_files() {
    let head = format!("{U8_HEAD}encoding: gzip\n\n");
    let mut bytes = head.as_bytes().to_vec();
    bytes.extend(gzip(&ramp()));
    let path = write("mem.nrrd", "", &bytes);
    let from_file = load_nrrd(&path, NanPolicy::Reject).expect("file");
    let from_bytes = parse_bytes(&bytes, Path::new("mem.nrrd"), NanPolicy::Reject).expect("bytes");
    assert_eq!(from_bytes.samples(), from_file.samples());
    assert_eq!(from_bytes.name(), "mem");

    let head = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\
                data file: other.raw\n";
    let err =
        parse_bytes(head.as_bytes(), Path::new("d.nhdr"), NanPolicy::Reject).expect_err("detached");
    assert!(err.to_string().contains("detached data file"), "{err}");
    let err =
        parse_bytes(b"NRRD0004\n", Path::new("e.nrrd"), NanPolicy::Reject).expect_err("empty");
    assert!(err.to_string().contains("e.nrrd"), "{err}");
}
