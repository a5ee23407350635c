#![no_main]

mod common;

use std::path::PathBuf;
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use tessera_data::raw::{load_raw, parse_scivis_name, scalar_from_name, Endian, RawOptions};
use tessera_data::NanPolicy;

/// A directory of this process for the raw files.
fn dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("tessera-fuzz-raw-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        dir
    })
}

// The input is an Open SciVis file name (name_256x256x256_uint8.raw), a newline, one byte
// of options (endian, NaN policy, header size) and the file's contents. The name is parsed;
// then the file is written under that name and loaded as a raw volume.
fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == b'\n').unwrap_or(data.len());
    let Ok(name) = std::str::from_utf8(&data[..split]) else {
        return;
    };
    let rest = data.get(split + 1..).unwrap_or(&[]);
    let _ = scalar_from_name(common::path(name), name);
    if let Some((_, dtype)) = parse_scivis_name(name) {
        let _ = scalar_from_name(common::path(name), &dtype);
    }
    let usable = !name.is_empty()
        && name.len() < 100
        && !name.contains(['/', '\\', '\0'])
        && name != "."
        && name != "..";
    if !usable {
        return;
    }
    let (flags, contents) = rest.split_first().map_or((0, rest), |(&f, c)| (f, c));
    let path = dir().join(name);
    std::fs::write(&path, contents).expect("write raw file");
    let opts = RawOptions {
        endian: if flags & 1 == 0 {
            Endian::Little
        } else {
            Endian::Big
        },
        nan_policy: if flags & 2 == 0 {
            NanPolicy::Reject
        } else {
            NanPolicy::Replace(0.0)
        },
        header_bytes: u64::from(flags >> 2),
        ..RawOptions::default()
    };
    let result = load_raw(&path, &opts);
    std::fs::remove_file(&path).expect("remove raw file");
    if let Err(e) = result {
        let text = e.to_string();
        assert!(text.contains(name), "error does not name {name}: {text}");
    }
});
