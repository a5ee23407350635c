//! NIfTI files the loader must refuse cleanly, naming the file: bad magic and headers,
//! unsupported types, truncated or corrupt data, sizes a small file merely claims, and paths
//! that are not regular files.

use super::*;

#[test]
fn bad_magic_and_headers() {
    let mut nii = Nii::new([2, 2, 2], 2);
    nii.magic = Some(*b"abcd");
    let (err, text) = load_err(&nii.write("analyze.nii", &[0; 8]));
    assert!(matches!(err, DataError::Format { .. }), "{err}");
    assert!(text.contains("n+1") && text.contains("344"), "{text}");

    nii.magic = Some(*b"ni1\0");
    let (_, text) = load_err(&nii.write("pair.nii", &[0; 8]));
    assert!(text.contains(".hdr/.img"), "{text}");

    let path = test_path("text.nii");
    std::fs::write(&path, b"this is not a volume at all, just words").expect("write");
    let (_, text) = load_err(&path);
    assert!(text.contains("not a NIfTI file"), "{text}");

    let path = test_path("empty.nii");
    std::fs::write(&path, b"").expect("write");
    let (_, text) = load_err(&path);
    assert!(text.contains("not a NIfTI file"), "{text}");

    let bytes = Nii::new([2, 2, 2], 2).bytes(&[0; 8]);
    let path = test_path("stub.nii");
    std::fs::write(&path, &bytes[..200]).expect("write");
    let (err, text) = load_err(&path);
    assert!(matches!(err, DataError::Format { .. }), "{err}");
    assert!(text.contains("truncated") && text.contains("200"), "{text}");

    let mut nii = Nii::new([2, 2, 2], 2);
    nii.vox_offset = 100.0;
    let mut bytes = nii.bytes(&[]);
    bytes.extend([0; 360]);
    let path = test_path("offset.nii");
    std::fs::write(&path, bytes).expect("write");
    let (_, text) = load_err(&path);
    assert!(text.contains("vox_offset 100"), "{text}");

    let (err, _) = load_err(&test_path("absent.nii"));
    assert!(matches!(err, DataError::Io { .. }), "{err}");
}

#[test]
fn unsupported_datatypes() {
    for (code, name) in [
        (32, "complex64"),
        (128, "rgb24"),
        (1024, "int64"),
        (1, "binary"),
        (99, "not a NIfTI type"),
    ] {
        let path = Nii::new([2, 2, 2], code).write("odd.nii", &[0; 128]);
        let (err, text) = load_err(&path);
        assert!(matches!(err, DataError::UnknownType { .. }), "{err}");
        assert!(
            text.contains(name) && text.contains(&format!("datatype {code})")),
            "{text}"
        );
        assert!(text.contains("float32"), "{text}");
    }
}

#[test]
fn truncated_and_corrupt_data() {
    let nii = Nii::new([2, 3, 4], 4);
    let (err, text) = load_err(&nii.write("short.nii", &[0; 40]));
    assert!(
        matches!(
            err,
            DataError::SizeMismatch {
                expected_bytes: 48,
                found_bytes: 40,
                ..
            }
        ),
        "{err}"
    );
    assert!(
        text.contains("truncated") && text.contains("int16"),
        "{text}"
    );

    // Too little data inside a complete gzip stream.
    let (err, text) = load_err(&nii.write_gz("gshort.nii.gz", &[0; 30]));
    assert!(
        matches!(
            err,
            DataError::SizeMismatch {
                found_bytes: 30,
                ..
            }
        ),
        "{err}"
    );
    assert!(text.contains("truncated"), "{text}");

    // The stream ends inside the extensions, before vox_offset.
    let mut far = nii.clone();
    far.vox_offset = 4096.0;
    let bytes = far.bytes(&[0; 48]);
    let path = test_path("gext.nii.gz");
    std::fs::write(&path, gzip(&bytes[..1000])).expect("write");
    let (err, _) = load_err(&path);
    assert!(matches!(err, DataError::SizeMismatch { .. }), "{err}");

    // A gzip stream cut off part-way.
    let big = Nii::new([16, 16, 16], 2);
    let data: Vec<u8> = (0..4096u32).map(|i| (i * 7 % 251) as u8).collect();
    let packed = gzip(&big.bytes(&data));
    let path = test_path("gcut.nii.gz");
    std::fs::write(&path, &packed[..packed.len() / 2]).expect("write");
    let (err, text) = load_err(&path);
    assert!(matches!(err, DataError::SizeMismatch { .. }), "{err}");
    assert!(text.contains("truncated"), "{text}");

    // gzip magic followed by garbage.
    let path = test_path("gbad.nii.gz");
    let mut bytes = GZIP_MAGIC.to_vec();
    bytes.extend(b"this is not deflate data, not at all");
    std::fs::write(&path, bytes).expect("write");
    let (err, text) = load_err(&path);
    assert!(matches!(err, DataError::Format { .. }), "{err}");
    assert!(text.contains("corrupt gzip"), "{text}");

    // A valid gzip header with a corrupt deflate body.
    let mut packed = gzip(&big.bytes(&data));
    for b in &mut packed[20..60] {
        *b ^= 0x5a;
    }
    let path = test_path("gflip.nii.gz");
    std::fs::write(&path, packed).expect("write");
    let (err, _) = load_err(&path);
    assert!(
        matches!(
            err,
            DataError::Format { .. } | DataError::SizeMismatch { .. }
        ),
        "{err}"
    );
}

#[test]
fn huge_sizes_in_small_gzip_files_are_refused() {
    // 32767^3 float64 samples declared in 52 bytes.
    let (_, text) = load_err(&test_data("huge.nii.gz"));
    assert!(text.contains("64 GiB"), "{text}");
    // 58 GiB of float32, within the limit: the buffer grows with the 16 bytes there are.
    let (err, _) = load_err(&test_data("large.nii.gz"));
    assert!(
        matches!(
            err,
            DataError::SizeMismatch {
                found_bytes: 16,
                ..
            }
        ),
        "{err}"
    );
    // A 4-D coefficient volume: 1000^3 voxels of 1000 values.
    let path = test_data("huge_sh.nii.gz");
    let text = load_nifti_components(&path).expect_err("huge").to_string();
    assert!(
        text.contains("huge_sh.nii.gz") && text.contains("64 GiB"),
        "{text}"
    );
}

#[cfg(unix)]
#[test]
fn devices_and_pipes_are_refused() {
    let text = within(10, || {
        load_nifti(Path::new("/dev/zero"), NanPolicy::Reject).map(|v| v.name().to_string())
    })
    .expect_err("device")
    .to_string();
    assert!(text.contains("character device"), "{text}");
    let pipe = crate::test_files::test_fifo("pipe.nii.gz");
    let text = within(10, move || load_nifti_components(&pipe).map(|_| ()))
        .expect_err("pipe")
        .to_string();
    assert!(text.contains("named pipe"), "{text}");
}
