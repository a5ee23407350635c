//! `Renderer`: one technique on one device, reused across data, looks, views and image
//! sizes. A new isovalue or transfer function changes push constants only; new data uploads
//! once; a new size makes a new target once.

use std::sync::{Arc, Mutex};

use numpy::ndarray::Array3;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tessera::path::PathChoice;
use tessera::renderer::{
    self, Accumulation, AmbientOcclusion, AmbiguityRule, Culling, Frame, FrameStats, FrameTimes,
    HiddenSide, LayoutKind, Light, RendererOptions, Technique,
};
use tessera_data::pmb::PmbBlockSize;
use tessera_data::scene::parse::parse_colour;
use tessera_data::scene::{Appearance, Dataset, IntegrandChoice};
use tessera_data::tet::shell::DEFAULT_AO_RADIUS;
use tessera_data::transfer::TransferFunction;
use tessera_data::{IsoValue, OrbitCamera, RgbaImage, ViewUp};
use tessera_gpu::Gpu;

use crate::data::dataset_of;
use crate::device::Device;
use crate::errors::{from_data, from_tessera, guarded, DataError};

/// What one call changes of the look; `None` keeps what the last call set.
#[derive(Default)]
struct LookChange {
    iso: Option<IsoValue>,
    transfer: Option<TransferFunction>,
    integrand: Option<IntegrandChoice>,
    density: Option<f32>,
    background: Option<[f32; 3]>,
}

struct State {
    gpu: Arc<Mutex<Gpu>>,
    /// As asked for; `None` picks the default for each data set's kind.
    asked: Option<String>,
    options: RendererOptions,
    renderer: Option<Box<dyn renderer::Renderer>>,
    data: Option<Arc<Dataset>>,
    look: Appearance,
    /// Whether the isovalue was given (else a volume's Otsu threshold is used).
    iso_given: bool,
    frame: Option<Frame>,
    last: Option<(FrameTimes, FrameStats)>,
    /// What the last float image held (`Accumulation::quantity_name`).
    quantity: Option<&'static str>,
}

/// A technique on a device: `Renderer(device, "direct", path="auto")`, then `set_data(data)`
/// and `render(...)` as often as wanted. `technique=None` draws each kind of data with its
/// default (raymarch, interval, param-points). Options as the CLI's flags: `culling`
/// (direct, meshlets, pmb: True, False, "on", "off" or "auto", the default), `supersample`, `msaa`, `pre_split` (parametric), `ambiguity` (direct's
/// marching cubes), `layout` (shell: tet32, tet20 or tet16), `pmb_block` (pmb: "4x4x4",
/// "8x4x4", "8x8x4" or "8x8x8"), `hidden_side` (direct, meshlets, offline, pmb: "skip", the
/// default, leaves out the side of a closed surface no pixel shows; "draw" draws it, for
/// measuring), and shell traversal's effects:
/// `shadows` (with `light=(x, y, z)` or `light_dir=(x, y, z)`; default a sun above +y),
/// `ao` (rays per tet, with `ao_radius`) and `gradient`.
#[pyclass(module = "tessera", frozen)]
pub struct Renderer {
    state: Mutex<State>,
}

fn invalid(message: String) -> PyErr {
    DataError::new_err(message)
}

impl State {
    fn apply_look(&mut self, gpu: &Gpu, change: LookChange) -> PyResult<()> {
        let mut look = self.look.clone();
        if let Some(iso) = change.iso {
            look.iso = iso;
            self.iso_given = true;
        }
        if let Some(t) = change.transfer {
            look.transfer = t;
        }
        if let Some(i) = change.integrand {
            look.integrand = i;
        }
        if let Some(d) = change.density {
            look.density = d;
        }
        if change.background.is_some() {
            look.background = change.background;
        }
        if let (Some(Dataset::Volume(volume)), false) = (self.data.as_deref(), self.iso_given) {
            if let Some(t) = tessera_data::histogram::otsu_isovalue(volume) {
                look.iso = IsoValue::Raw(t);
            }
        }
        if look != self.look {
            if let Some(r) = self.renderer.as_mut() {
                r.set_appearance(gpu, &look).map_err(from_tessera)?;
            }
            self.look = look;
        }
        Ok(())
    }

    fn set_data(&mut self, gpu: &Gpu, data: Arc<Dataset>) -> PyResult<()> {
        let technique = Technique::for_data(self.asked.as_deref(), data.kind(), data.name())
            .map_err(from_tessera)?;
        if self.renderer.as_ref().map(|r| r.technique()) != Some(technique) {
            self.renderer = None;
            self.renderer =
                Some(renderer::create(gpu, technique, &self.options).map_err(from_tessera)?);
        }
        self.data = Some(data.clone());
        // The isovalue of a volume that was given none follows the new volume.
        self.apply_look(gpu, LookChange::default())?;
        let r = self.renderer.as_mut().expect("made above");
        r.set_appearance(gpu, &self.look).map_err(from_tessera)?;
        r.set_data(gpu, &data).map_err(from_tessera)
    }

    /// The float quantity the frame just rendered accumulated, for `dtype="float32"`.
    fn accumulated(&self, gpu: &Gpu) -> PyResult<Accumulation> {
        let r = self.renderer.as_ref().expect("a frame was rendered");
        r.accumulated(gpu).map_err(from_tessera)?.ok_or_else(|| {
            invalid(format!(
                "dtype='float32': {} draws colours only; interval shading (optical depth, \
                 emission or maximum) and shell traversal (radiance) give a float image",
                r.technique().name()
            ))
        })
    }

    fn render(&mut self, gpu: &Gpu, camera: &OrbitCamera, size: (u32, u32)) -> PyResult<RgbaImage> {
        let r = self
            .renderer
            .as_mut()
            .ok_or_else(|| invalid("render() before set_data(): nothing to draw".to_string()))?;
        let view = r.view(camera, size).map_err(from_tessera)?;
        let same_size = self
            .frame
            .as_ref()
            .is_some_and(|f| (f.target.width, f.target.height) == size);
        if !same_size {
            self.frame = None;
            self.frame = Some(Frame::new(gpu, size).map_err(from_tessera)?);
        }
        let frame = self.frame.as_mut().expect("made above");
        let times = frame.render(gpu, r.as_mut(), &view).map_err(from_tessera)?;
        let image = frame.target.read(gpu).map_err(from_tessera)?;
        self.last = Some((times, r.stats()));
        Ok(image)
    }
}

enum Rendered {
    Colour(RgbaImage),
    Accumulated(Accumulation),
}

/// An image as an (H, W, 4) uint8 array, rows top to bottom.
fn image_array(image: RgbaImage) -> Array3<u8> {
    let (w, h) = (image.width as usize, image.height as usize);
    let bytes: Vec<u8> = image.pixels.iter().flat_map(|p| p.to_le_bytes()).collect();
    Array3::from_shape_vec((h, w, 4), bytes).expect("4 bytes per pixel")
}

/// An accumulation as an (H, W, 3) float32 array, rows top to bottom.
fn float_array(accumulation: Accumulation) -> Array3<f32> {
    let (w, h) = (accumulation.width as usize, accumulation.height as usize);
    let floats: Vec<f32> = accumulation.values.into_iter().flatten().collect();
    Array3::from_shape_vec((h, w, 3), floats).expect("3 floats per pixel")
}

/// Images come out as uint8 colours or as the float quantity behind them.
#[derive(Clone, Copy, PartialEq)]
enum ImageType {
    Colour,
    Accumulated,
}

fn image_type(dtype: &Bound<'_, PyAny>) -> PyResult<ImageType> {
    let numpy = PyModule::import(dtype.py(), "numpy")?;
    let name: String = numpy
        .call_method1("dtype", (dtype,))
        .and_then(|d| d.getattr("name")?.extract())
        .map_err(|e| invalid(format!("dtype: {e}")))?;
    match name.as_str() {
        "uint8" => Ok(ImageType::Colour),
        "float32" => Ok(ImageType::Accumulated),
        other => Err(invalid(format!(
            "dtype {other}: images are uint8 (colour) or float32 (the accumulated quantity)"
        ))),
    }
}

fn camera_of(camera: Option<Vec<f32>>, up: Option<ViewUp>) -> PyResult<OrbitCamera> {
    let mut orbit = OrbitCamera::default();
    if let Some(c) = camera {
        match c[..] {
            [az, el] => (orbit.azimuth_deg, orbit.elevation_deg) = (az, el),
            [az, el, dist] => {
                (orbit.azimuth_deg, orbit.elevation_deg, orbit.distance) = (az, el, dist)
            }
            _ => {
                return Err(invalid(format!(
                    "camera {c:?}: expected (azimuth, elevation) or (azimuth, elevation, \
                     distance), in degrees and units of the data's longest side"
                )))
            }
        }
        if !c.iter().all(|v| v.is_finite()) || orbit.distance <= 0.0 {
            return Err(invalid(format!(
                "camera {c:?}: finite angles and a positive distance"
            )));
        }
    }
    if let Some(up) = up {
        orbit.up = up;
    }
    Ok(orbit)
}

/// `culling=`: a bool, or "on", "off" or "auto".
#[derive(FromPyObject)]
enum CullingArg {
    Flag(bool),
    Name(String),
}

impl CullingArg {
    fn choice(&self) -> PyResult<Culling> {
        match self {
            CullingArg::Flag(true) => Ok(Culling::On),
            CullingArg::Flag(false) => Ok(Culling::Off),
            CullingArg::Name(text) => Culling::parse(text).map_err(from_tessera),
        }
    }
}

#[pymethods]
impl Renderer {
    #[new]
    #[pyo3(signature = (device, technique=None, path="auto", culling=CullingArg::Name("auto".into()), supersample=1, msaa=1, pre_split=None, ambiguity="decider", layout="tet20", shadows=false, light=None, light_dir=None, ao=None, ao_radius=None, gradient=false, pmb_block="8x8x4", hidden_side="skip"))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        device: &Bound<'_, Device>,
        technique: Option<String>,
        path: &str,
        culling: CullingArg,
        supersample: u32,
        msaa: u32,
        pre_split: Option<u32>,
        ambiguity: &str,
        layout: &str,
        shadows: bool,
        light: Option<[f64; 3]>,
        light_dir: Option<[f64; 3]>,
        ao: Option<u32>,
        ao_radius: Option<f32>,
        gradient: bool,
        pmb_block: &str,
        hidden_side: &str,
    ) -> PyResult<Self> {
        if let Some(name) = &technique {
            Technique::parse(name).map_err(from_tessera)?;
        }
        if !shadows && (light.is_some() || light_dir.is_some()) {
            return Err(invalid("light and light_dir take shadows=True".into()));
        }
        let up = ViewUp::default().vector().as_dvec3();
        let shadows = shadows
            .then(|| Light::chosen(light, light_dir, up))
            .transpose()
            .map_err(from_data)?;
        let ao = ao
            .map(|n| AmbientOcclusion::new(n, ao_radius.unwrap_or(DEFAULT_AO_RADIUS)))
            .transpose()
            .map_err(from_data)?;
        let options = RendererOptions {
            path: PathChoice::parse(path).map_err(from_tessera)?,
            culling: culling.choice()?,
            supersample,
            msaa,
            pre_split,
            ambiguity: AmbiguityRule::parse(ambiguity).map_err(from_data)?,
            layout: LayoutKind::parse(layout).map_err(from_data)?,
            shadows,
            ao,
            gradient,
            pmb_block: PmbBlockSize::parse(pmb_block).map_err(from_data)?,
            hidden_side: HiddenSide::parse(hidden_side).map_err(from_tessera)?,
            ..RendererOptions::default()
        };
        Ok(Renderer {
            state: Mutex::new(State {
                gpu: device.get().gpu.clone(),
                asked: technique,
                options,
                renderer: None,
                data: None,
                look: Appearance::default(),
                iso_given: false,
                frame: None,
                last: None,
                quantity: None,
            }),
        })
    }

    /// Uploads `data` (a `Volume`, `TetMesh`, `GlyphField` or `Scene`) and builds what the
    /// technique needs of it.
    fn set_data(&self, py: Python<'_>, data: &Bound<'_, PyAny>) -> PyResult<()> {
        let data = dataset_of(data)?;
        py.detach(|| {
            guarded("setting the data", || {
                let mut state = self.lock();
                let gpu = state.gpu.clone();
                let gpu = Device::lock(&gpu);
                state.set_data(&gpu, data)
            })
        })
    }

    /// Renders one image and returns it as an (H, W, 4) uint8 array; with `dtype="float32"`
    /// the float quantity the colours were made from, as an (H, W, 3) float32 array, where
    /// the technique has one: interval shading's optical depth per channel (absorption
    /// integrands; the colour is `background * exp(-depth)`), emitted light (emission; the
    /// colour is `background + light`) or `[largest scalar mapped to [0, 1], coverage, 0]`
    /// (mip); shell traversal's radiance (the light reaching the eye, over the background,
    /// before it is clamped and quantized); other techniques raise `DataError`; `r.quantity`
    /// names what the last float image holds. `camera` is
    /// (azimuth, elevation[, distance]) in degrees around the data (longest side 1); `iso` a
    /// value in the data's units or `iso_fraction` a fraction of its range (default: Otsu's
    /// threshold); `tf` a transfer function preset or file; `integrate` how tet meshes are
    /// integrated (auto, tet-absorption, absorption, emission, mip); `up` the axis that appears
    /// up (default: towards the head where a medical file says). Settings persist to the next
    /// call.
    #[pyo3(signature = (camera=None, size=(512, 512), iso=None, iso_fraction=None, tf=None, integrate=None, density=None, background=None, up=None, dtype=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        camera: Option<Vec<f32>>,
        size: (u32, u32),
        iso: Option<f32>,
        iso_fraction: Option<f32>,
        tf: Option<String>,
        integrate: Option<String>,
        density: Option<f32>,
        background: Option<String>,
        up: Option<String>,
        dtype: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let image_type = dtype.map_or(Ok(ImageType::Colour), image_type)?;
        let iso = match (iso, iso_fraction) {
            (Some(_), Some(_)) => {
                return Err(invalid("give iso or iso_fraction, not both".to_string()))
            }
            (Some(v), None) => Some(IsoValue::Raw(v)),
            (None, Some(f)) => Some(IsoValue::Normalized(f)),
            (None, None) => None,
        };
        let change = LookChange {
            iso,
            transfer: tf
                .map(|t| TransferFunction::load(&t))
                .transpose()
                .map_err(from_data)?,
            integrand: integrate
                .map(|i| IntegrandChoice::parse(&i))
                .transpose()
                .map_err(from_data)?,
            density,
            background: background
                .map(|b| parse_colour(&b))
                .transpose()
                .map_err(invalid)?,
        };
        let up = up.map(|u| ViewUp::parse(&u)).transpose().map_err(invalid)?;
        let camera_arg = camera;
        let image = py.detach(|| {
            guarded("rendering", || {
                let mut state = self.lock();
                let up = up.or_else(|| state.data.as_ref().and_then(|d| d.view_up()));
                let camera = camera_of(camera_arg, up)?;
                let gpu = state.gpu.clone();
                let gpu = Device::lock(&gpu);
                state.apply_look(&gpu, change)?;
                let image = state.render(&gpu, &camera, size)?;
                match image_type {
                    ImageType::Colour => Ok(Rendered::Colour(image)),
                    ImageType::Accumulated => state.accumulated(&gpu).map(|a| {
                        state.quantity = Some(a.quantity_name());
                        Rendered::Accumulated(a)
                    }),
                }
            })
        })?;
        Ok(match image {
            Rendered::Colour(image) => image_array(image).into_pyarray(py).into_any(),
            Rendered::Accumulated(a) => float_array(a).into_pyarray(py).into_any(),
        })
    }

    /// The technique drawing the current data (`None` before `set_data` when none was named).
    #[getter]
    fn technique(&self) -> Option<String> {
        let state = self.lock();
        state
            .renderer
            .as_ref()
            .map(|r| r.technique().name().to_string())
            .or_else(|| state.asked.clone())
    }

    /// What the last `dtype="float32"` image holds: `optical-depth`, `emission`, `maximum`
    /// or `radiance` (`None` before one was rendered).
    #[getter]
    fn quantity(&self) -> Option<&'static str> {
        self.lock().quantity
    }

    /// The path taken: `graphics` or `compute` (`None` before `set_data`).
    #[getter]
    fn path(&self) -> Option<&'static str> {
        self.lock().renderer.as_ref().map(|r| r.path().name())
    }

    /// The last frame: its GPU milliseconds (`gpu_ms`, the whole frame, gaps between passes
    /// included) and each stage's (`stages_ms`), the technique's counters, and the uploads and
    /// pipeline builds so far.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let state = self.lock();
        let dict = PyDict::new(py);
        if let Some(r) = &state.renderer {
            dict.set_item("technique", r.technique().name())?;
            dict.set_item("path", r.path().name())?;
            let counters = r.counters();
            dict.set_item("data_uploads", counters.data_uploads)?;
            dict.set_item("data_bytes", counters.data_bytes)?;
            dict.set_item("pipeline_builds", counters.pipeline_builds)?;
        }
        if let Some((times, stats)) = &state.last {
            dict.set_item("gpu_ms", times.total_ms())?;
            let stages = PyDict::new(py);
            for (name, ms) in &times.scopes {
                stages.set_item(name, ms)?;
            }
            dict.set_item("stages_ms", stages)?;
            dict.set_item("triangles", stats.triangles)?;
            dict.set_item("patches", stats.patches)?;
            dict.set_item("tets_clipped", stats.tets_clipped)?;
            dict.set_item("blocks_drawn", stats.blocks_drawn)?;
            for (name, value) in &stats.details {
                dict.set_item(*name, value)?;
            }
        }
        Ok(dict)
    }

    fn __repr__(&self) -> String {
        format!("tessera.Renderer({:?})", self.technique())
    }
}

impl Renderer {
    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Renderer>()?;
    Ok(())
}
