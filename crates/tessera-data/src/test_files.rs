//! Files for tests: fresh temp paths, the input files of `tests/data`, named pipes, and a
//! time limit for loaders that might hang.

use std::path::{Path, PathBuf};

/// A unique path in the system temp directory for test files.
pub fn test_path(name: &str) -> PathBuf {
    use std::sync::atomic::{AtomicU32, Ordering};
    static NEXT: AtomicU32 = AtomicU32::new(0);
    let dir = std::env::temp_dir().join(format!(
        "tessera-data-{}-{}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// A file of `tests/data`, the crate's small hostile and unusual input files.
pub fn test_data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Runs `load` on a thread and fails the test if it takes longer than `seconds` (a loader
/// that hangs would otherwise hang the test run instead of failing it).
pub fn within<T: Send + 'static>(seconds: u64, load: impl FnOnce() -> T + Send + 'static) -> T {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(load());
    });
    receive
        .recv_timeout(std::time::Duration::from_secs(seconds))
        .unwrap_or_else(|_| panic!("still loading after {seconds} s"))
}

/// A named pipe (FIFO) in a fresh temp directory; nothing ever writes to it.
#[cfg(unix)]
pub fn test_fifo(name: &str) -> PathBuf {
    let path = test_path(name);
    let status = std::process::Command::new("mkfifo")
        .arg(&path)
        .status()
        .expect("run mkfifo");
    assert!(status.success(), "mkfifo {}", path.display());
    path
}
