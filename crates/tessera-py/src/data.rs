//! The data a renderer draws, one class per kind. Each holds a loaded
//! `tessera_data::scene::Dataset`; renderers share it without copying.

use std::sync::Arc;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tessera_data::nifti::ComponentVolume;
use tessera_data::param::ShBasis;
use tessera_data::raw::RawOptions;
use tessera_data::scene::parse::{parse_basis, parse_endian, parse_glyph_radius};
use tessera_data::scene::{glyph_field_scene, Dataset, LoadOptions, ParamData, TetData};
use tessera_data::tet::TetMesh as CpuTetMesh;
use tessera_data::{NanPolicy, Orientation, Volume as CpuVolume};

use crate::arrays;
use crate::errors::{from_data, guarded, DataError};

fn invalid(message: String) -> PyErr {
    DataError::new_err(message)
}

/// A scalar volume: `Volume(array, spacing=(1, 1, 1))` from a 3-D array indexed `[x, y, z]`
/// (uint8 and uint16 kept as they are, other numbers as float32). Non-finite samples are
/// refused unless `nan_fill` gives a value to put in their place.
#[pyclass(module = "tessera", frozen)]
pub struct Volume {
    pub(crate) data: Arc<Dataset>,
}

/// A tetrahedral mesh: `TetMesh(points, tets, point_data=None, cell_data=None)` with
/// `points` of shape (N, 3), `tets` of shape (M, 4) (vertex indices), and either
/// `point_data`, one value per point, or `cell_data`, one value per tet (an array, or a dict
/// whose first entry is used; `scalars` names the entry to take). The renderers interpolate
/// values per point, so `cell_data` becomes point values as VTK's CellDataToPointData makes
/// them: each point gets the plain (unweighted) mean of the values of the tets that use it,
/// matching VTK and ParaView, and counting degenerate tets that a volume weight would drop;
/// a point no tet uses gets NaN (never drawn, left out of the scalar range). Non-finite
/// values are kept in both (a NaN tet makes its points NaN). Giving both is an error: which
/// one to draw would be a guess.
#[pyclass(module = "tessera", frozen)]
pub struct TetMesh {
    pub(crate) data: Arc<Dataset>,
}

/// A field of SH glyphs from a DIPY-style coefficient array of shape (X, Y, Z, K):
/// `GlyphField(coeffs, basis="descoteaux07", legacy=True, spacing=(1, 1, 1))`; one glyph per
/// voxel whose coefficients are not all zero, `z_slice` to keep one slice. `affine=img.affine`
/// (nibabel's voxel-to-world matrix, RAS+) places the field and gives its spacing, so it is
/// drawn as `tessera.load("sh:file.nii.gz")` draws the same fit.
#[pyclass(module = "tessera", frozen)]
pub struct GlyphField {
    pub(crate) data: Arc<Dataset>,
}

/// Parametric objects: `Scene("param:sh-glyphs:8x8:order8")`, `Scene("param:heart")`, a user
/// GLSL file defining `vec3 f(float u, float v)`, ... (every `param:` spec the CLI takes).
#[pyclass(module = "tessera", frozen)]
pub struct Scene {
    pub(crate) data: Arc<Dataset>,
}

fn spacing_of(spacing: (f32, f32, f32)) -> [f32; 3] {
    [spacing.0, spacing.1, spacing.2]
}

#[pymethods]
impl Volume {
    #[new]
    #[pyo3(signature = (array, spacing=(1.0, 1.0, 1.0), name="array", nan_fill=None))]
    fn new(
        array: &Bound<'_, PyAny>,
        spacing: (f32, f32, f32),
        name: &str,
        nan_fill: Option<f32>,
    ) -> PyResult<Self> {
        let (dims, samples, _converted) = arrays::volume_samples(array)?;
        let policy = nan_fill.map_or(NanPolicy::Reject, NanPolicy::Replace);
        let volume = guarded("reading the volume", || {
            CpuVolume::with_nan_policy(name, dims, spacing_of(spacing), samples, policy).map_err(
                // The data layer's advice names the CLI's flag; here it is an argument.
                |e| invalid(e.to_string().replace("--nan-fill VALUE", "nan_fill=VALUE")),
            )
        })?;
        Ok(Volume {
            data: Arc::new(Dataset::Volume(volume)),
        })
    }

    /// Samples along x, y and z.
    #[getter]
    fn shape(&self) -> (u32, u32, u32) {
        let [x, y, z] = self.volume().dims();
        (x, y, z)
    }

    #[getter]
    fn spacing(&self) -> (f32, f32, f32) {
        let [x, y, z] = self.volume().spacing();
        (x, y, z)
    }

    /// The sample type kept: `uint8`, `uint16` or `float32`.
    #[getter]
    fn dtype(&self) -> &'static str {
        self.volume().scalar_type().name()
    }

    /// The smallest and largest sample.
    #[getter]
    fn value_range(&self) -> (f32, f32) {
        self.volume().value_range()
    }

    #[getter]
    fn name(&self) -> String {
        self.volume().name().to_string()
    }

    /// The samples as a numpy array indexed `[x, y, z]` in the kept `dtype` (a copy; x runs
    /// fastest in memory, so the array is Fortran-ordered), e.g. to hand a loaded file to
    /// scikit-image or DIPY.
    fn to_numpy<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        use numpy::ndarray::Array3;
        use numpy::IntoPyArray;
        use tessera_data::Samples;
        let [x, y, z] = self.volume().dims().map(|d| d as usize);
        fn grid<'py, T: numpy::Element + Copy>(
            py: Python<'py>,
            samples: &[T],
            (x, y, z): (usize, usize, usize),
        ) -> PyResult<Bound<'py, PyAny>> {
            let zyx = Array3::from_shape_vec((z, y, x), samples.to_vec())
                .map_err(|e| DataError::new_err(format!("volume samples: {e}")))?;
            Ok(zyx.reversed_axes().into_pyarray(py).into_any())
        }
        match self.volume().samples() {
            Samples::U8(v) => grid(py, v, (x, y, z)),
            Samples::U16(v) => grid(py, v, (x, y, z)),
            Samples::F32(v) => grid(py, v, (x, y, z)),
        }
    }

    fn __repr__(&self) -> String {
        let (x, y, z) = self.shape();
        format!(
            "tessera.Volume({x}x{y}x{z} {}, {:?})",
            self.dtype(),
            self.name()
        )
    }
}

impl Volume {
    pub(crate) fn volume(&self) -> &CpuVolume {
        match &*self.data {
            Dataset::Volume(v) => v,
            _ => unreachable!("a Volume holds a volume"),
        }
    }
}

/// The values of `data` (the argument `what`, one value per item): an array, or a dict's
/// entry `scalars` (else its first), with the name they go by.
fn named_values(
    data: &Bound<'_, PyAny>,
    what: &str,
    scalars: Option<&str>,
    count: usize,
) -> PyResult<(String, Vec<f32>)> {
    let Ok(dict) = data.cast::<PyDict>() else {
        let values = arrays::per_item(data, what, count)?;
        return Ok(("scalars".to_string(), values));
    };
    let (name, values) = match scalars {
        Some(name) => {
            let values = dict.get_item(name)?.ok_or_else(|| {
                let keys: Vec<String> = dict.keys().iter().map(|k| k.to_string()).collect();
                invalid(format!(
                    "{what} has no entry '{name}' (it has: {})",
                    keys.join(", ")
                ))
            })?;
            (name.to_string(), values)
        }
        None => {
            let (key, values) = dict
                .iter()
                .next()
                .ok_or_else(|| invalid(format!("{what} is an empty dict")))?;
            (key.str()?.to_string(), values)
        }
    };
    let values = arrays::per_item(&values, &format!("{what}['{name}']"), count)?;
    Ok((name, values))
}

#[pymethods]
impl TetMesh {
    #[new]
    #[pyo3(signature = (points, tets, point_data=None, cell_data=None, scalars=None, name="mesh"))]
    fn new(
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        tets: &Bound<'_, PyAny>,
        point_data: Option<&Bound<'_, PyAny>>,
        cell_data: Option<&Bound<'_, PyAny>>,
        scalars: Option<&str>,
        name: &str,
    ) -> PyResult<Self> {
        let vertices = arrays::points(points, "points")?;
        let tets = arrays::tets(tets, "tets", vertices.len())?;
        let mut mesh = CpuTetMesh::new(vertices, tets);
        match (point_data, cell_data) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "give point_data or cell_data, not both".to_string(),
                ))
            }
            (Some(point_data), None) => {
                let (scalar_name, values) =
                    named_values(point_data, "point_data", scalars, mesh.vertex_count())?;
                mesh.scalars = Some(values);
                mesh.scalar_name = scalar_name;
            }
            (None, Some(cell_data)) => {
                let (scalar_name, values) =
                    named_values(cell_data, "cell_data", scalars, mesh.tet_count())?;
                let averaged = py.detach(|| {
                    guarded("averaging cell_data onto the points", || {
                        mesh.point_values_from_cells(&values)
                            .map_err(|e| invalid(format!("cell_data: {e}")))
                    })
                })?;
                mesh.scalars = Some(averaged);
                mesh.scalar_name = scalar_name;
            }
            (None, None) => {
                if let Some(name) = scalars {
                    return Err(invalid(format!(
                        "scalars='{name}' without point_data or cell_data to take it from"
                    )));
                }
            }
        }
        let report = guarded("checking the mesh", || {
            mesh.validate(name).map_err(from_data)
        })?;
        Ok(TetMesh {
            data: Arc::new(Dataset::Tets(TetData {
                name: name.to_string(),
                mesh,
                asteroids: false,
                report: Some(report),
            })),
        })
    }

    #[getter]
    fn n_points(&self) -> usize {
        self.mesh().vertex_count()
    }

    #[getter]
    fn n_tets(&self) -> usize {
        self.mesh().tet_count()
    }

    /// The name of the per-point scalars, `None` without any.
    #[getter]
    fn scalars(&self) -> Option<String> {
        let mesh = self.mesh();
        mesh.scalars.as_ref().map(|_| mesh.scalar_name.clone())
    }

    fn __repr__(&self) -> String {
        format!(
            "tessera.TetMesh({} points, {} tets)",
            self.n_points(),
            self.n_tets()
        )
    }
}

impl TetMesh {
    fn mesh(&self) -> &CpuTetMesh {
        match &*self.data {
            Dataset::Tets(t) => &t.mesh,
            _ => unreachable!("a TetMesh holds a tet mesh"),
        }
    }
}

#[pymethods]
impl GlyphField {
    #[new]
    #[pyo3(signature = (coeffs, basis="descoteaux07", legacy=true, spacing=None, z_slice=None, glyph_radius="minmax", name="coefficients", affine=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        coeffs: &Bound<'_, PyAny>,
        basis: &str,
        legacy: bool,
        spacing: Option<(f32, f32, f32)>,
        z_slice: Option<u32>,
        glyph_radius: &str,
        name: &str,
        affine: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let basis = match parse_basis(basis).map_err(invalid)? {
            ShBasis::Descoteaux07 { .. } => ShBasis::Descoteaux07 { legacy },
            ShBasis::Tournier07 { .. } => ShBasis::Tournier07 { legacy },
        };
        let radius = parse_glyph_radius(glyph_radius).map_err(invalid)?;
        let (dims, components, values) = arrays::coefficients(coeffs)?;
        let (orientation, spacing) = match (affine, spacing) {
            (Some(_), Some(_)) => {
                return Err(DataError::new_err(
                    "give spacing or affine, not both (the affine holds the spacing)",
                ))
            }
            (Some(affine), None) => {
                let rows = arrays::affine_rows(affine, "affine")?;
                Orientation::from_affine(rows).ok_or_else(|| {
                    DataError::new_err("affine: a value is not finite or a grid axis has no length")
                })?
            }
            (None, spacing) => (
                Orientation::default(),
                spacing_of(spacing.unwrap_or((1.0, 1.0, 1.0))),
            ),
        };
        let volume = ComponentVolume {
            dims,
            spacing,
            orientation,
            components,
            values,
        };
        let scene = py.detach(|| {
            guarded("building the glyphs", || {
                glyph_field_scene(&volume, basis, z_slice, name).map_err(from_data)
            })
        })?;
        Ok(GlyphField {
            data: Arc::new(Dataset::Param(ParamData {
                name: name.to_string(),
                scene: scene.with_glyph_radius(radius),
                user: None,
            })),
        })
    }

    /// Glyphs drawn (voxels whose coefficients are not all zero).
    #[getter]
    fn n_glyphs(&self) -> usize {
        match &*self.data {
            Dataset::Param(p) => p.scene.objects.len(),
            _ => unreachable!("a GlyphField holds a parametric scene"),
        }
    }

    fn __repr__(&self) -> String {
        format!("tessera.GlyphField({} glyphs)", self.n_glyphs())
    }
}

#[pymethods]
impl Scene {
    #[new]
    #[pyo3(signature = (spec, basis=None, glyph_radius="minmax"))]
    fn new(py: Python<'_>, spec: &str, basis: Option<&str>, glyph_radius: &str) -> PyResult<Self> {
        let options = LoadOptions {
            basis: basis.map(parse_basis).transpose().map_err(invalid)?,
            glyph_radius: parse_glyph_radius(glyph_radius).map_err(invalid)?,
            ..LoadOptions::default()
        };
        let data = py.detach(|| {
            guarded("loading the scene", || {
                ParamData::load(spec, &options).map_err(from_data)
            })
        })?;
        Ok(Scene {
            data: Arc::new(Dataset::Param(data)),
        })
    }

    #[getter]
    fn n_objects(&self) -> usize {
        match &*self.data {
            Dataset::Param(p) => p.scene.objects.len(),
            _ => unreachable!("a Scene holds a parametric scene"),
        }
    }

    fn __repr__(&self) -> String {
        format!("tessera.Scene({} objects)", self.n_objects())
    }
}

/// Loads any file or spec the CLI reads (NRRD, NIfTI, VTK, VTU, TetGen, Gmsh, raw with
/// `dims`/`dtype`, `procedural:`, `tets:`, `param:`, `sh:`, GLSL): a `Volume`, `TetMesh` or
/// `Scene`. `spacing` replaces the file's spacing.
#[pyfunction]
#[pyo3(signature = (spec, spacing=None, dims=None, dtype=None, endian="little", header_bytes=0, nan_fill=None, basis=None, glyph_radius="minmax"))]
#[allow(clippy::too_many_arguments)]
fn load(
    py: Python<'_>,
    spec: std::path::PathBuf,
    spacing: Option<(f32, f32, f32)>,
    dims: Option<(u32, u32, u32)>,
    dtype: Option<String>,
    endian: &str,
    header_bytes: u64,
    nan_fill: Option<f32>,
    basis: Option<&str>,
    glyph_radius: &str,
) -> PyResult<Py<PyAny>> {
    let spec = spec.to_string_lossy().into_owned();
    let options = LoadOptions {
        raw: RawOptions {
            dims: dims.map(|(x, y, z)| [x, y, z]),
            dtype,
            endian: parse_endian(endian).map_err(invalid)?,
            header_bytes,
            spacing: spacing.map(spacing_of),
            nan_policy: nan_fill.map_or(NanPolicy::Reject, NanPolicy::Replace),
        },
        basis: basis.map(parse_basis).transpose().map_err(invalid)?,
        glyph_radius: parse_glyph_radius(glyph_radius).map_err(invalid)?,
        ..LoadOptions::default()
    };
    let dataset = py.detach(|| {
        guarded("loading", || {
            Dataset::load(&spec, &options).map_err(from_data)
        })
    })?;
    wrap(py, Arc::new(dataset))
}

/// The Python object of the class that holds `dataset`'s kind.
fn wrap(py: Python<'_>, data: Arc<Dataset>) -> PyResult<Py<PyAny>> {
    Ok(match &*data {
        Dataset::Volume(_) => Py::new(py, Volume { data })?.into_any(),
        Dataset::Tets(_) => Py::new(py, TetMesh { data })?.into_any(),
        Dataset::Param(_) => Py::new(py, Scene { data })?.into_any(),
    })
}

/// The dataset inside any of the data classes.
pub fn dataset_of(value: &Bound<'_, PyAny>) -> PyResult<Arc<Dataset>> {
    if let Ok(v) = value.cast::<Volume>() {
        return Ok(v.get().data.clone());
    }
    if let Ok(t) = value.cast::<TetMesh>() {
        return Ok(t.get().data.clone());
    }
    if let Ok(g) = value.cast::<GlyphField>() {
        return Ok(g.get().data.clone());
    }
    if let Ok(s) = value.cast::<Scene>() {
        return Ok(s.get().data.clone());
    }
    Err(invalid(format!(
        "expected a tessera Volume, TetMesh, GlyphField or Scene, got {}",
        value.get_type().name()?
    )))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Volume>()?;
    m.add_class::<TetMesh>()?;
    m.add_class::<GlyphField>()?;
    m.add_class::<Scene>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    Ok(())
}
