#![allow(dead_code)] // each target uses what it needs

// Shared by the targets: a path that names the input in error messages, and a check that
// every error the loaders return names it.

use std::path::Path;

pub fn path(name: &str) -> &Path {
    Path::new(name)
}

/// Loaders must name the file in their errors.
pub fn names_file<T>(result: &tessera_data::error::Result<T>, file: &str) {
    if let Err(e) = result {
        let text = e.to_string();
        assert!(text.contains(file), "error does not name {file}: {text}");
    }
}
