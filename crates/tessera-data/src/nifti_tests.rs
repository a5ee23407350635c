//! Tests of `nifti`.
use std::io::Write;
use std::path::PathBuf;

use flate2::write::GzEncoder;

use super::*;
use crate::orientation::{AnatomicalSpace, OrientationSource};
use crate::test_files::{test_data, test_path, within};
use crate::volume::ScalarType;

/// A header to write: NIfTI-1 or -2, either byte order. `vox_offset` 0 means "right after
/// the header and extension flag"; the writer pads up to it.
#[derive(Clone)]
struct Nii {
    version: u8,
    big: bool,
    dim: [i64; 8],
    datatype: i16,
    pixdim: [f64; 8],
    vox_offset: f64,
    slope: f64,
    inter: f64,
    magic: Option<[u8; 4]>,
    qform_code: i16,
    sform_code: i16,
    quatern: [f64; 3],
    qoffset: [f64; 3],
    srow: [[f64; 4]; 3],
}

impl Nii {
    fn new(dims: [i64; 3], datatype: i16) -> Nii {
        Nii {
            version: 1,
            big: false,
            dim: [3, dims[0], dims[1], dims[2], 1, 1, 1, 1],
            datatype,
            pixdim: [1.0; 8],
            vox_offset: 0.0,
            slope: 0.0,
            inter: 0.0,
            magic: None,
            qform_code: 0,
            sform_code: 0,
            quatern: [0.0; 3],
            qoffset: [0.0; 3],
            srow: [[0.0; 4]; 3],
        }
    }

    fn bytes(&self, data: &[u8]) -> Vec<u8> {
        let (len, magic_at) = match self.version {
            1 => (NIFTI1_HEADER, 344),
            _ => (NIFTI2_HEADER, 4),
        };
        let mut h = vec![0u8; len];
        let big = self.big;
        let mut put = |at: usize, le: &[u8]| {
            let mut b = le.to_vec();
            if big {
                b.reverse();
            }
            h[at..at + b.len()].copy_from_slice(&b);
        };
        put(0, &(len as i32).to_le_bytes());
        let offset = if self.vox_offset == 0.0 {
            len as f64 + 4.0
        } else {
            self.vox_offset
        };
        if self.version == 1 {
            for (i, d) in self.dim.iter().enumerate() {
                put(40 + 2 * i, &(*d as i16).to_le_bytes());
            }
            put(70, &self.datatype.to_le_bytes());
            for (i, p) in self.pixdim.iter().enumerate() {
                put(76 + 4 * i, &(*p as f32).to_le_bytes());
            }
            put(108, &(offset as f32).to_le_bytes());
            put(112, &(self.slope as f32).to_le_bytes());
            put(116, &(self.inter as f32).to_le_bytes());
            put(252, &self.qform_code.to_le_bytes());
            put(254, &self.sform_code.to_le_bytes());
            for (i, v) in self.quatern.iter().chain(&self.qoffset).enumerate() {
                put(256 + 4 * i, &(*v as f32).to_le_bytes());
            }
            for (i, v) in self.srow.iter().flatten().enumerate() {
                put(280 + 4 * i, &(*v as f32).to_le_bytes());
            }
        } else {
            put(12, &self.datatype.to_le_bytes());
            for (i, d) in self.dim.iter().enumerate() {
                put(16 + 8 * i, &d.to_le_bytes());
            }
            for (i, p) in self.pixdim.iter().enumerate() {
                put(104 + 8 * i, &p.to_le_bytes());
            }
            put(168, &(offset as i64).to_le_bytes());
            put(176, &self.slope.to_le_bytes());
            put(184, &self.inter.to_le_bytes());
            put(344, &i32::from(self.qform_code).to_le_bytes());
            put(348, &i32::from(self.sform_code).to_le_bytes());
            for (i, v) in self.quatern.iter().chain(&self.qoffset).enumerate() {
                put(352 + 8 * i, &v.to_le_bytes());
            }
            for (i, v) in self.srow.iter().flatten().enumerate() {
                put(400 + 8 * i, &v.to_le_bytes());
            }
        }
        let magic = self.magic.unwrap_or(match self.version {
            1 => *b"n+1\0",
            _ => *b"n+2\0",
        });
        h[magic_at..magic_at + 4].copy_from_slice(&magic);
        if self.version == 2 {
            h[8..12].copy_from_slice(b"\r\n\x1a\n");
        }
        h.resize((offset as usize).max(len), 0);
        h.extend_from_slice(data);
        h
    }

    fn write(&self, name: &str, data: &[u8]) -> PathBuf {
        let path = test_path(name);
        std::fs::write(&path, self.bytes(data)).expect("write test file");
        path
    }

    fn write_gz(&self, name: &str, data: &[u8]) -> PathBuf {
        let path = test_path(name);
        std::fs::write(&path, gzip(&self.bytes(data))).expect("write test file");
        path
    }
}

fn gzip(data: &[u8]) -> Vec<u8> {
    let mut enc = GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(data).expect("compress");
    enc.finish().expect("compress")
}

fn load(path: &Path) -> Volume {
    load_nifti(path, NanPolicy::Reject).expect("load")
}

fn load_err(path: &Path) -> (DataError, String) {
    let err = load_nifti(path, NanPolicy::Reject).expect_err("should fail");
    let text = err.to_string();
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("?");
    assert!(text.contains(name), "{text}");
    (err, text)
}

fn ramp(n: u8) -> Vec<u8> {
    (0..n).map(|i| i * 3).collect()
}

#[test]
fn little_endian_uint8() {
    let mut nii = Nii::new([3, 2, 4], 2);
    nii.pixdim = [-1.0, 0.5, 2.0, 3.25, 0.0, 0.0, 0.0, 0.0];
    let data = ramp(24);
    let v = load(&nii.write("brain.nii", &data));
    assert_eq!(v.name(), "brain");
    assert_eq!(v.dims(), [3, 2, 4]);
    assert_eq!(v.spacing(), [0.5, 2.0, 3.25]);
    assert_eq!(v.scalar_type(), ScalarType::U8);
    assert_eq!(v.bytes(), &data[..]);
    assert_eq!(v.texel(2, 1, 3), 69.0);
    assert_eq!(v.value_range(), (0.0, 69.0));
}

#[test]
fn big_endian_int16_and_lenient_spacing() {
    let values: Vec<i16> = (0..8).map(|i| i * 1000 - 3500).collect();
    let mut nii = Nii::new([2, 2, 2], 4);
    nii.big = true;
    nii.pixdim = [1.0, 0.0, -2.0, f64::NAN, 0.0, 0.0, 0.0, 0.0];
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    let v = load(&nii.write("Be16.NII", &data));
    assert_eq!(v.name(), "Be16");
    assert_eq!(v.spacing(), [1.0, 1.0, 1.0]);
    let want: Vec<f32> = values.iter().map(|&x| f32::from(x)).collect();
    assert_eq!(v.samples(), &Samples::F32(want));

    // Big-endian uint16 stays native.
    let values: Vec<u16> = (0..8).map(|i| 0x0102 * (i + 1)).collect();
    let mut nii = Nii::new([2, 2, 2], 512);
    nii.big = true;
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    let v = load(&nii.write("be_u16.nii", &data));
    assert_eq!(v.samples(), &Samples::U16(values));
}

#[test]
fn converted_types() {
    let cases: [(i16, Vec<u8>, Vec<f32>); 5] = [
        (
            256,
            vec![0x80, 0xFF, 0, 1, 2, 3, 4, 127],
            vec![-128., -1., 0., 1., 2., 3., 4., 127.],
        ),
        (
            8,
            (0..8i32).flat_map(|i| (-i * 100).to_le_bytes()).collect(),
            (0..8).map(|i| (-i * 100) as f32).collect(),
        ),
        (
            768,
            (0..8u32).flat_map(|i| (i * 70000).to_le_bytes()).collect(),
            (0..8).map(|i| (i * 70000) as f32).collect(),
        ),
        (
            16,
            (0..8)
                .flat_map(|i| (i as f32 * 0.25).to_le_bytes())
                .collect(),
            (0..8).map(|i| i as f32 * 0.25).collect(),
        ),
        (
            64,
            (0..8)
                .flat_map(|i| (i as f64 * -1.5).to_le_bytes())
                .collect(),
            (0..8).map(|i| i as f32 * -1.5).collect(),
        ),
    ];
    for (code, data, want) in cases {
        let v = load(&Nii::new([2, 2, 2], code).write("t.nii", &data));
        assert_eq!(v.samples(), &Samples::F32(want), "datatype {code}");
    }
}

#[test]
fn scl_slope_and_inter() {
    // float32 data, big-endian, scaled by 2 and shifted by -1.
    let mut nii = Nii::new([2, 2, 2], 16);
    nii.big = true;
    nii.slope = 2.0;
    nii.inter = -1.0;
    let data: Vec<u8> = (0..8)
        .flat_map(|i| (i as f32 + 0.5).to_be_bytes())
        .collect();
    let v = load(&nii.write("scaled.nii", &data));
    let want: Vec<f32> = (0..8).map(|i| (i as f32 + 0.5) * 2.0 - 1.0).collect();
    assert_eq!(v.samples(), &Samples::F32(want));

    // Scaled uint8 becomes f32.
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.slope = 0.5;
    nii.inter = 10.0;
    let v = load(&nii.write("scaled8.nii", &[0, 1, 2, 3, 4, 5, 6, 200]));
    assert_eq!(v.scalar_type(), ScalarType::F32);
    assert_eq!(v.value_range(), (10.0, 110.0));
    assert_eq!(v.texel(1, 0, 0), 10.5);

    // Identity and zero slopes keep the native type (slope 0 means "no scaling").
    for (slope, inter) in [(1.0, 0.0), (0.0, 0.0), (0.0, 5.0), (f64::NAN, 3.0)] {
        let mut nii = Nii::new([2, 2, 2], 2);
        nii.slope = slope;
        nii.inter = inter;
        let v = load(&nii.write("plain.nii", &[7; 8]));
        assert_eq!(v.samples(), &Samples::U8(vec![7; 8]), "{slope} {inter}");
    }

    // A slope of 1 with an offset still scales.
    let mut nii = Nii::new([2, 2, 2], 512);
    nii.slope = 1.0;
    nii.inter = -1024.0;
    let data: Vec<u8> = [0u16, 1024, 2048, 0, 0, 0, 0, 0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let v = load(&nii.write("ct.nii", &data));
    assert_eq!(v.scalar_type(), ScalarType::F32);
    assert_eq!(v.texel(0, 1, 0), 1024.0);
    assert_eq!(v.value_range(), (-1024.0, 1024.0));
}

#[test]
fn gzip_files() {
    let values: Vec<u16> = (0..12).map(|i| i * 5000).collect();
    let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
    let mut nii = Nii::new([2, 3, 2], 512);
    nii.pixdim[2] = 0.75;
    let v = load(&nii.write_gz("head.nii.gz", &data));
    assert_eq!(v.name(), "head");
    assert_eq!(v.dims(), [2, 3, 2]);
    assert_eq!(v.spacing(), [1.0, 0.75, 1.0]);
    assert_eq!(v.samples(), &Samples::U16(values.clone()));

    // Compression is found by its magic bytes whatever the name, and an extension block
    // before the data (vox_offset 400) is skipped.
    let mut nii = nii.clone();
    nii.big = true;
    nii.vox_offset = 400.0;
    let be: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    let v = load(&nii.write_gz("Packed.NII", &be));
    assert_eq!(v.name(), "Packed");
    assert_eq!(v.samples(), &Samples::U16(values.clone()));
    // ...and an uncompressed file named .nii.gz loads as well.
    let v = load(&nii.write("plain.nii.gz", &be));
    assert_eq!(v.name(), "plain");
    assert_eq!(v.samples(), &Samples::U16(values.clone()));

    // Several gzip members (as from concatenated or parallel compressors).
    let bytes = Nii::new([2, 3, 2], 512).bytes(&data);
    let mut members = gzip(&bytes[..300]);
    members.extend(gzip(&bytes[300..]));
    let path = test_path("multi.nii.gz");
    std::fs::write(&path, members).expect("write");
    assert_eq!(load(&path).samples(), &Samples::U16(values));
}

#[test]
fn nifti2() {
    let values: Vec<i32> = (0..8).map(|i| i * -7).collect();
    for big in [false, true] {
        let mut nii = Nii::new([2, 2, 2], 8);
        nii.version = 2;
        nii.big = big;
        nii.pixdim = [1.0, 0.5, 0.25, 4.0, 2.0, 0.0, 0.0, 0.0];
        let data: Vec<u8> = values
            .iter()
            .flat_map(|v| {
                if big {
                    v.to_be_bytes()
                } else {
                    v.to_le_bytes()
                }
            })
            .collect();
        let v = load(&nii.write("two.nii", &data));
        assert_eq!(v.dims(), [2, 2, 2]);
        assert_eq!(v.spacing(), [0.5, 0.25, 4.0]);
        let want: Vec<f32> = values.iter().map(|&x| x as f32).collect();
        assert_eq!(v.samples(), &Samples::F32(want), "big {big}");
    }

    let mut nii = Nii::new([2, 2, 2], 2);
    nii.version = 2;
    nii.dim[0] = 4;
    nii.dim[4] = 1;
    nii.slope = 3.0;
    let v = load(&nii.write_gz("two.nii.gz", &[1; 8]));
    assert_eq!(v.samples(), &Samples::F32(vec![3.0; 8]));

    nii.magic = Some(*b"ni2\0");
    let (_, text) = load_err(&nii.write("pair2.nii", &[1; 8]));
    assert!(text.contains(".hdr/.img"), "{text}");

    let mut nii = Nii::new([2, 2, 2], 2);
    nii.version = 2;
    nii.dim[1] = 1 << 33;
    let (_, text) = load_err(&nii.write("huge2.nii", &[]));
    assert!(text.contains("too large"), "{text}");
}

#[test]
fn four_and_five_dimensions() {
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.dim[0] = 4;
    let v = load(&nii.write("single_frame.nii", &[9; 8]));
    assert_eq!(v.dims(), [2, 2, 2]);
    nii.dim[0] = 5;
    assert_eq!(load(&nii.write("single5.nii", &[9; 8])).dims(), [2, 2, 2]);

    let mut nii = Nii::new([2, 2, 2], 2);
    nii.dim[0] = 4;
    nii.dim[4] = 3;
    let (err, text) = load_err(&nii.write("fmri.nii", &[0; 24]));
    assert!(matches!(err, DataError::Format { .. }), "{err}");
    assert!(
        text.contains("has 3 volumes (dim[4]=3)") && text.contains("only 3-D scalar"),
        "{text}"
    );

    let mut nii = Nii::new([2, 2, 2], 16);
    nii.dim[0] = 5;
    nii.dim[5] = 3;
    let (_, text) = load_err(&nii.write("vectors.nii", &[0; 96]));
    assert!(text.contains("3 components per voxel (dim[5]=3)"), "{text}");

    // A 4th dimension beyond dim[0] is ignored, as the standard says.
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.dim[4] = 7;
    assert_eq!(load(&nii.write("ignored.nii", &[1; 8])).dims(), [2, 2, 2]);

    let mut nii = Nii::new([2, 2, 2], 2);
    nii.dim[0] = 2;
    let (_, text) = load_err(&nii.write("slice.nii", &[0; 8]));
    assert!(text.contains("dim[0]=2"), "{text}");

    let nii = Nii::new([2, 1, 2], 2);
    let (err, text) = load_err(&nii.write("thin.nii", &[0; 4]));
    assert!(matches!(err, DataError::InvalidDims { .. }), "{err}");
    assert!(text.contains("2x1x2"), "{text}");
}

#[test]
fn nan_policy_applies() {
    let mut vals = [2.0f64; 8];
    vals[5] = f64::NAN; // voxel (1, 0, 1)
    let data: Vec<u8> = vals.iter().flat_map(|v| v.to_le_bytes()).collect();
    let path = Nii::new([2, 2, 2], 64).write("nan.nii", &data);
    let (err, text) = load_err(&path);
    assert!(
        matches!(err, DataError::NonFinite { count: 1, .. }),
        "{err}"
    );
    assert!(text.contains("(1, 0, 1)"), "{text}");
    let v = load_nifti(&path, NanPolicy::Replace(-5.0)).expect("replaced");
    assert_eq!(v.texel(1, 0, 1), -5.0);
    assert_eq!(v.value_range(), (-5.0, 2.0));
}

#[test]
fn names() {
    assert_eq!(volume_name(Path::new("/a/b.nii.gz")), "b");
    assert_eq!(volume_name(Path::new("B.NII.GZ")), "B");
    assert_eq!(volume_name(Path::new("c.nii")), "c");
    assert_eq!(volume_name(Path::new("d.gz")), "d");
    assert_eq!(volume_name(Path::new("x.y.nii")), "x.y");
    assert_eq!(volume_name(Path::new(".nii")), "volume");
}

/// The Colin 27 ("ch2") template shipped by Debian's mricron-data package.
#[test]
fn real_ch2_template() {
    let path = Path::new("/usr/share/mricron/templates/ch2.nii.gz");
    if !path.exists() {
        // Written past the test harness's capture so that the skip is visible.
        let _ = writeln!(
            std::io::stderr().lock(),
            "skipped: {} not found (install mricron-data)",
            path.display()
        );
        return;
    }
    let v = load(path);
    assert_eq!(v.name(), "ch2");
    assert_eq!(v.dims(), [181, 217, 181]);
    assert_eq!(v.spacing(), [1.0, 1.0, 1.0]);
    assert_eq!(v.scalar_type(), ScalarType::U8);
    let (lo, hi) = v.value_range();
    assert!(hi - lo >= 100.0, "value range {lo}..{hi}");
    // A head in a dark background: the corner is background, a good part is tissue.
    assert_eq!(v.texel(0, 0, 0), lo);
    let Samples::U8(s) = v.samples() else {
        panic!("uint8 expected");
    };
    let bright = s
        .iter()
        .filter(|&&x| f32::from(x) > lo + 0.25 * (hi - lo))
        .count();
    assert!(
        bright > s.len() / 20 && bright < s.len() * 3 / 4,
        "{bright}"
    );
}

#[path = "nifti_components_tests.rs"]
mod components;

#[path = "nifti_orientation_tests.rs"]
mod orientation;

#[path = "nifti_bad_input_tests.rs"]
mod bad_input;

#[test]
fn bytes_in_memory_load_like_files() {
    let mut nii = Nii::new([3, 2, 4], 2);
    nii.sform_code = 1;
    nii.srow = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0, 0.0],
    ];
    let data = ramp(24);
    let from_file = load(&nii.write("mem.nii", &data));
    for bytes in [nii.bytes(&data), gzip(&nii.bytes(&data))] {
        let v = parse_bytes(&bytes, Path::new("mem.nii"), NanPolicy::Reject).expect("bytes");
        assert_eq!(v.samples(), from_file.samples());
        assert_eq!(v.orientation(), from_file.orientation());
        assert_eq!(v.name(), "mem");
    }
    let cut = &nii.bytes(&data)[..360];
    let err = parse_bytes(cut, Path::new("cut.nii"), NanPolicy::Reject).expect_err("short");
    assert!(
        matches!(err, DataError::SizeMismatch { found_bytes: 8, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("cut.nii"), "{err}");

    let mut sh = Nii::new([1, 1, 1], 16);
    sh.dim[0] = 4;
    sh.dim[4] = 6;
    let values: Vec<u8> = (0..6).flat_map(|i| (i as f32).to_le_bytes()).collect();
    let v = parse_components_bytes(&gzip(&sh.bytes(&values)), Path::new("sh.nii.gz"))
        .expect("components");
    assert_eq!(v.voxel(0, 0, 0), vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
}
