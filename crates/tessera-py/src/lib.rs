//! Python bindings: the native module `tessera._tessera`, which the pure-Python package
//! `tessera` (python/tessera) re-exports. Arrays come in as numpy arrays indexed `[x, y, z]`
//! (nibabel's and scikit-image's order), images and meshes go out as numpy arrays.
//!
//! | file | job |
//! |---|---|
//! | `errors` | the exception types, Rust errors and panics turned into them |
//! | `arrays` | numpy arrays checked and copied into Tessera's layouts |
//! | `device` | `Device`, `devices()`, capabilities |
//! | `data` | `Volume`, `TetMesh`, `GlyphField`, `Scene`, `load()` |
//! | `render` | `Renderer`: one technique, reused across looks, views and sizes |
//! | `extract` | `marching_cubes` in scikit-image's shapes |
//! | `bench` | the benchmark scenarios, records as JSON lines |

mod arrays;
mod bench;
mod data;
mod device;
mod errors;
mod extract;
mod render;

use pyo3::prelude::*;

#[pymodule]
fn _tessera(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    device::register(m)?;
    data::register(m)?;
    render::register(m)?;
    extract::register(m)?;
    bench::register(m)?;
    Ok(())
}
