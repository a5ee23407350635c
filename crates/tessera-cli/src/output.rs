//! Output files (PNG images, PLY meshes): written through a buffer that is flushed and
//! checked, so a full disk or a failing device is an error naming the file, never a truncated
//! file reported as written.

use anyhow::{Context, Result};
use std::io::{BufWriter, Write};
use std::path::Path;
use tessera_data::RgbaImage;

/// Creates `path` (and its folder), hands `write` a buffered writer, then flushes it and the
/// file; any failure names the file.
pub fn write_file(
    path: &Path,
    write: impl FnOnce(&mut BufWriter<std::fs::File>) -> Result<()>,
) -> Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut out = BufWriter::new(file);
    write(&mut out)
        .and_then(|()| Ok(out.flush()?))
        .with_context(|| format!("writing {}", path.display()))
}

pub fn write_png(path: &Path, image: &RgbaImage) -> Result<()> {
    write_file(path, |out| Ok(image.write_png(out)?))
}
