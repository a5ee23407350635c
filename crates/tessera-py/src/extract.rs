//! `marching_cubes` in scikit-image's shapes: `(verts, faces, normals, values)`.

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use tessera::iso::surface::{extract_surface, SurfaceMethod};
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::mesh::TriangleMesh;
use tessera_data::{IsoValue, Volume as CpuVolume};

use tessera_gpu::{Gpu, GpuOptions};

use crate::data::Volume;
use crate::device::Device;
use crate::errors::{from_data, from_gpu, from_tessera, guarded, DataError};

type Surface<'py> = (
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray2<i64>>,
    Bound<'py, PyArray2<f32>>,
    Bound<'py, PyArray1<f32>>,
);

/// For each vertex (in grid units) the largest sample of the cell it lies in: scikit-image's
/// `values`, a measure of the data near the vertex for colouring.
fn cell_maxima(volume: &CpuVolume, mesh: &TriangleMesh) -> Vec<f32> {
    let [nx, ny, nz] = volume.dims();
    mesh.positions
        .iter()
        .map(|p| {
            let base = |v: f32, n: u32| (v.floor().max(0.0) as u32).min(n.saturating_sub(2));
            let (x, y, z) = (base(p.x, nx), base(p.y, ny), base(p.z, nz));
            let mut max = f32::NEG_INFINITY;
            for corner in 0..8u32 {
                let (dx, dy, dz) = (corner & 1, (corner >> 1) & 1, corner >> 2);
                max = max.max(volume.texel(x + dx, y + dy, z + dz));
            }
            max
        })
        .collect()
}

fn rows<T: Copy, const N: usize>(items: &[[T; N]]) -> Array2<T> {
    let flat: Vec<T> = items.iter().flatten().copied().collect();
    Array2::from_shape_vec((items.len(), N), flat).expect("N per row")
}

/// The `level` isosurface of `volume` (a `tessera.Volume`, or a 3-D array indexed
/// `[x, y, z]` with `spacing`) as scikit-image's `marching_cubes` returns it: vertices in
/// physical units (spacing × index, and a file's origin and axis directions), one per crossed
/// grid edge, triangles wound and normals pointing towards lower values (as VTK and
/// scikit-image's default), per-vertex normals, and per-vertex the largest sample of its
/// cell. Ambiguous faces are cut by the asymptotic decider (`ambiguity="vtk"` for VTK's
/// table).
///
/// `method="meshlets"` extracts on the GPU (paper C's meshlets, welded; `path="mesh"` for
/// the task/mesh pipeline, else compute), `method="pmb"` (or `"pmb:4x4x4"`, `"pmb:8x4x4"`,
/// `"pmb:8x8x4"`, `"pmb:8x8x8"` for the block size) by Parallel Marching Blocks, on
/// `device`, or on a device opened for this call when none is given; `method="cpu"` runs
/// marching cubes on the CPU. All give the same vertices and triangles; the GPU's come in the
/// order its blocks finished, which may change from run to run.
#[pyfunction]
#[pyo3(signature = (volume, level, spacing=None, method="meshlets", ambiguity="decider", device=None, path="auto"))]
#[allow(clippy::too_many_arguments)]
fn marching_cubes<'py>(
    py: Python<'py>,
    volume: &Bound<'py, PyAny>,
    level: f32,
    spacing: Option<(f32, f32, f32)>,
    method: &str,
    ambiguity: &str,
    device: Option<&Device>,
    path: &str,
) -> PyResult<Surface<'py>> {
    let method = SurfaceMethod::parse(method, path).map_err(from_tessera)?;
    if !level.is_finite() {
        return Err(DataError::new_err(format!("level {level} is not a number")));
    }
    let rule = AmbiguityRule::parse(ambiguity).map_err(from_data)?;
    let volume: CpuVolume = match volume.cast::<Volume>() {
        Ok(v) => {
            let v = v.get().volume().clone();
            match spacing {
                Some((x, y, z)) => v.with_spacing([x, y, z]).map_err(from_data)?,
                None => v,
            }
        }
        Err(_) => {
            let (x, y, z) = spacing.unwrap_or((1.0, 1.0, 1.0));
            let (dims, samples, _) = crate::arrays::volume_samples(volume)?;
            CpuVolume::new("array", dims, [x, y, z], samples).map_err(from_data)?
        }
    };
    let shared_gpu = device.map(|d| d.gpu.clone());
    let (mesh, values) = py.detach(|| {
        guarded("extracting the isosurface", || {
            let texel = volume.iso_to_texel(IsoValue::Raw(level));
            let own_gpu;
            let locked;
            let gpu = match (&shared_gpu, method.needs_gpu()) {
                (_, false) => None,
                (Some(shared), true) => {
                    locked = Device::lock(shared);
                    Some(&*locked)
                }
                (None, true) => {
                    own_gpu = Gpu::new(&GpuOptions::default()).map_err(from_gpu)?;
                    Some(&own_gpu)
                }
            };
            let surface =
                extract_surface(gpu, &volume, texel, rule, method).map_err(from_tessera)?;
            let values = cell_maxima(&volume, &surface.mesh);
            Ok((surface.mesh.transformed(&volume.grid_to_physical()), values))
        })
    })?;
    let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let normals: Vec<[f32; 3]> = mesh.normals.iter().map(|n| n.to_array()).collect();
    let faces: Vec<[i64; 3]> = mesh.triangles.iter().map(|t| t.map(i64::from)).collect();
    Ok((
        rows(&positions).into_pyarray(py),
        rows(&faces).into_pyarray(py),
        rows(&normals).into_pyarray(py),
        Array1::from_vec(values).into_pyarray(py),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(marching_cubes, m)?)?;
    Ok(())
}
