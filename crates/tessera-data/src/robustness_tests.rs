//! Every loader on damaged copies of the test files: truncated at every byte and with bytes
//! replaced, each must return (an error or a value), never panic.

use std::path::Path;

use crate::test_files::test_path;

/// A small deterministic generator (no dependency needed for test noise).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
}

/// Bytes that matter to the parsers: digits, signs, separators, markers, base64 padding.
const INTERESTING: &[u8] = b"0123456789-+.eE \n\t<>/=\"_$#ABCQ9\x00\xff";

fn load(path: &Path) {
    let name = path.to_string_lossy();
    if name.ends_with(".vti") {
        let _ = crate::vti::load_vti(path, Default::default());
    } else if name.ends_with(".txt") {
        let _ = crate::transfer::TransferFunction::load(&name);
    } else {
        let _ = crate::tet::load_tet_mesh(path);
    }
}

#[test]
fn damaged_files_never_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut entries: Vec<_> = std::fs::read_dir(&dir)
        .expect("test data")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    let mut rng = Lcg(7);
    let mut failures = Vec::new();
    for source in entries {
        let good = std::fs::read(&source).expect("read");
        let ext = source.extension().and_then(|e| e.to_str()).unwrap_or("");
        let path = test_path(&format!("damaged.{ext}"));
        let step = good.len().div_ceil(100).max(1);
        let mut variants: Vec<Vec<u8>> = (0..good.len())
            .step_by(step)
            .map(|n| good[..n].to_vec())
            .collect();
        for _ in 0..200 {
            let mut bytes = good.clone();
            for _ in 0..1 + rng.next() % 3 {
                let at = rng.next() as usize % bytes.len();
                bytes[at] = INTERESTING[rng.next() as usize % INTERESTING.len()];
            }
            variants.push(bytes);
        }
        for bytes in variants {
            std::fs::write(&path, &bytes).expect("write");
            if std::panic::catch_unwind(|| load(&path)).is_err() {
                failures.push(format!(
                    "{}: {:?}",
                    source.display(),
                    String::from_utf8_lossy(&bytes)
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} panics, first: {}",
        failures.len(),
        failures[0]
    );
}
