//! Tests of `input`.

use super::*;
use crate::test_files::test_path;

#[test]
fn regular_files_open_and_others_are_named() {
    let path = test_path("plain.raw");
    std::fs::write(&path, [1u8, 2]).expect("write");
    assert_eq!(regular_file(&path).expect("regular").len(), 2);
    assert!(open_regular(&path).is_ok());

    let dir = test_path("folder.nrrd");
    std::fs::create_dir_all(&dir).expect("mkdir");
    let text = open_regular(&dir).expect_err("a directory").to_string();
    assert!(
        text.contains("folder.nrrd") && text.contains("is a directory"),
        "{text}"
    );

    let missing = test_path("missing.nii");
    let err = open_regular(&missing).expect_err("missing");
    assert!(matches!(err, DataError::Io { .. }), "{err}");
}

#[cfg(unix)]
#[test]
fn devices_and_pipes_are_refused_without_reading() {
    let text = open_regular(Path::new("/dev/zero"))
        .expect_err("a device")
        .to_string();
    assert!(
        text.contains("/dev/zero") && text.contains("character device"),
        "{text}"
    );
    // Opening a FIFO for reading blocks until a writer comes: the check must come first.
    let fifo = crate::test_files::test_fifo("pipe.nii");
    let text = crate::test_files::within(10, move || open_regular(&fifo).map(|_| ()))
        .expect_err("a pipe")
        .to_string();
    assert!(
        text.contains("pipe.nii") && text.contains("named pipe"),
        "{text}"
    );
}

#[test]
fn sample_bytes_are_checked() {
    let path = Path::new("h.nrrd");
    assert_eq!(sample_bytes(path, 10, SourceType::F64).expect("small"), 80);
    assert_eq!(
        sample_bytes(path, MAX_SAMPLE_BYTES / 2, SourceType::U16).expect("at the limit"),
        MAX_SAMPLE_BYTES
    );
    let text = sample_bytes(path, MAX_SAMPLE_BYTES / 2 + 1, SourceType::U16)
        .expect_err("over the limit")
        .to_string();
    assert!(text.contains("h.nrrd") && text.contains("64 GiB"), "{text}");
    // count * size overflows u64.
    assert!(sample_bytes(path, u64::MAX / 2, SourceType::F32).is_err());
}
