//! stub
use super::{MeshReport, TetMesh};
use crate::error::{DataError, Result};
use std::path::Path;
pub fn load_vtu(path: &Path) -> Result<(TetMesh, MeshReport)> {
    Err(DataError::format(path, "todo"))
}
pub fn write_vtu_ascii(_mesh: &TetMesh, _path: &Path) -> Result<()> {
    Ok(())
}
