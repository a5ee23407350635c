//! Parametric scenes: objects (a function of `tessera_data::param` placed by a transform) and
//! their upload into the buffers every pass of the technique reads (`param/scene.glsl`).
//!
//! GPU layout, bindings 0–2 of every pass:
//! * `ParamObject param_objects[]` ([`GpuObject`], 112 bytes): object-to-world rows, colour,
//!   domain, the SH radius map, the function's kind, the offset of its parameters, SH order and
//!   flags (direction colouring, positive lobes, a closed seam along v, SH basis).
//! * `float param_values[]`: the objects' parameters (SH coefficients as f32, the seashell's and
//!   the yarn tube's constants), at least one.
//! * `vec2 sh_recurrence[]`: the SH recurrence factors, built once per device
//!   ([`sh_recurrence_table`]).
//!
//! Adding a function: its GLSL in `functions.glsl` (plus a case in `param_position`), one arm in
//! [`encode_function`] and a bound in `ParamObject::object_radius`.

use crate::error::{Error, Result};
use bytemuck::{Pod, Zeroable};
use glam::{Mat3, Vec3};
use tessera_data::param::{
    functions, KnitCurve, ParamFunction, RadiusNormalization, SeashellParams, ShBasis, YarnTube,
};
use tessera_data::{DepthFit, OrbitCamera, View};
use tessera_gpu::{vk, Buffer, Gpu};

pub use tessera_data::param::scene::{ParamObject, ParamScene, MAX_OBJECTS};

/// Largest SH order the GPU evaluates (size of the recurrence table; the CPU goes further).
pub const GPU_MAX_SH_ORDER: u32 = 32;

/// The function families the shaders evaluate (`PARAM_KIND_*`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum GpuKind {
    Sphere = 0,
    Heart = 1,
    ShGlyph = 2,
    /// The user's GLSL function (`param/user.rs`).
    User = 3,
    Seashell = 4,
    /// A tube around a knit yarn or fibre curve.
    Yarn = 5,
}

/// `PARAM_FLAG_DIRECTION_COLOUR`: colour by direction from the object's centre.
pub const FLAG_DIRECTION_COLOUR: u32 = 1;
/// `PARAM_FLAG_POSITIVE_LOBES`: an SH glyph drawn as `max(r, 0)`, which the ray tracer must
/// know (its squared implicit form holds negative lobes too; the radius map clamps them away
/// for the other techniques).
pub const FLAG_POSITIVE_LOBES: u32 = 2;
/// `PARAM_FLAG_PERIODIC_V`: the surface at `v` and at `v` plus the domain's `v` span is the
/// same (a closed seam), so patches may reach across it.
pub const FLAG_PERIODIC_V: u32 = 4;
/// Bits 4–5 of the flags hold the SH basis (`SH_*` codes).
pub const BASIS_SHIFT: u32 = 4;

/// `ParamObject` of `param/scene.glsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuObject {
    pub model: [[f32; 4]; 3],
    pub colour: [f32; 4],
    pub domain: [f32; 4],
    pub radius_map: [f32; 4],
    pub kind: u32,
    pub params: u32,
    pub order: u32,
    pub flags: u32,
}

fn basis_code(basis: ShBasis) -> u32 {
    match basis {
        ShBasis::Descoteaux07 { legacy: true } => 0,
        ShBasis::Descoteaux07 { legacy: false } => 1,
        ShBasis::Tournier07 { legacy: true } => 2,
        ShBasis::Tournier07 { legacy: false } => 3,
    }
}

/// The kind, SH order, flags and radius map of `function`, its parameters appended to
/// `values`. The one place that knows how each family is handed to the shaders.
pub fn encode_function(
    function: &ParamFunction,
    values: &mut Vec<f32>,
) -> Result<(GpuKind, u32, u32, [f32; 4])> {
    let identity = [1.0, 0.0, f32::MIN, f32::MAX];
    match function {
        ParamFunction::Sphere => Ok((GpuKind::Sphere, 0, FLAG_PERIODIC_V, identity)),
        ParamFunction::Heart => Ok((GpuKind::Heart, 0, FLAG_PERIODIC_V, identity)),
        ParamFunction::User(_) => Ok((GpuKind::User, 0, 0, identity)),
        ParamFunction::ShGlyph(g) => {
            if g.order() > GPU_MAX_SH_ORDER {
                return Err(Error::Invalid(format!(
                    "SH glyph of order {} exceeds the GPU's maximum order {GPU_MAX_SH_ORDER}",
                    g.order()
                )));
            }
            values.extend(g.coefficients().iter().map(|&c| c as f32));
            let positive = g.normalization() == RadiusNormalization::PositiveLobes;
            let flags = FLAG_DIRECTION_COLOUR
                | FLAG_PERIODIC_V
                | if positive { FLAG_POSITIVE_LOBES } else { 0 }
                | (basis_code(g.basis()) << BASIS_SHIFT);
            Ok((GpuKind::ShGlyph, g.order(), flags, radius_map(g)))
        }
        ParamFunction::Seashell(p) => {
            p.validate()
                .map_err(|e| Error::Invalid(format!("cannot draw this seashell: {e}")))?;
            values.extend(seashell_values(p));
            Ok((GpuKind::Seashell, 0, 0, identity))
        }
        ParamFunction::Yarn(t) => {
            values.extend(yarn_values(t)?);
            Ok((GpuKind::Yarn, 0, 0, identity))
        }
    }
}

/// The seashell's parameters as `param_seashell` reads them. Everything that does not depend
/// on `(u, v)` is computed here with the CPU's own f32 expressions
/// (`SeashellParams::position`), so these values are the CPU's bit for bit.
fn seashell_values(p: &SeashellParams) -> Vec<f32> {
    let beta = p.beta_deg.to_radians();
    let tilt = Mat3::from_rotation_z(-p.omega_deg.to_radians())
        * Mat3::from_rotation_y(-p.mu_deg.to_radians())
        * Mat3::from_rotation_x(-p.phi_deg.to_radians());
    let nodule = |count: f32, offset_deg: f32, width: f32, spikiness: f32| {
        [
            offset_deg.to_radians(),
            std::f32::consts::TAU / count,
            -(width / count).powf(spikiness),
        ]
    };
    let mut out = vec![
        p.alpha_deg.to_radians().tan().recip(),
        p.spiral_start,
        beta.sin(),
        -beta.cos(),
        p.scale,
        p.ellipse_a,
        p.ellipse_b,
    ];
    out.extend(tilt.to_cols_array());
    out.extend(nodule(
        p.nodules_around,
        p.nodule_offset_around_deg,
        p.nodule_width_around,
        p.nodule_spikiness_around,
    ));
    out.extend(nodule(
        p.nodules_along,
        p.nodule_offset_along_deg,
        p.nodule_width_along,
        p.nodule_spikiness_along,
    ));
    out.push((p.nodule_height_around / 20.0) * (p.nodule_height_along / 20.0));
    out
}

/// The tube's parameters as `param_yarn` reads them, rounded from the CPU's f64.
fn yarn_values(t: &YarnTube) -> Result<[f32; 8]> {
    let k = t.knit();
    // Only the phase modulo 2π matters; reduced in f64 it keeps its precision in f32.
    let (fibre, phase) = match t.curve() {
        KnitCurve::Yarn => (0.0, 0.0),
        KnitCurve::Fiber { phase } => (1.0, phase.rem_euclid(std::f64::consts::TAU)),
    };
    let values = [
        k.roundness,
        k.height,
        k.depth,
        k.yarn_radius,
        k.twist,
        fibre,
        phase,
        t.tube_radius(),
    ]
    .map(|x| x as f32);
    if values.iter().any(|x| !x.is_finite()) {
        return Err(Error::Invalid(format!(
            "yarn tube parameters {values:?} do not fit in f32"
        )));
    }
    Ok(values)
}

/// `radius' = clamp(r · x + y, z, w)`, the glyph's normalisation from its CPU-estimated range.
fn radius_map(g: &tessera_data::param::ShGlyph) -> [f32; 4] {
    let (lo, hi) = g.raw_range();
    match g.normalization() {
        RadiusNormalization::Raw => [1.0, 0.0, f32::MIN, f32::MAX],
        RadiusNormalization::MinMax => {
            let span = hi - lo;
            if span <= 1e-12 * hi.abs().max(lo.abs()) {
                [0.0, 1.0, 0.0, 1.0]
            } else {
                [(1.0 / span) as f32, (-lo / span) as f32, 0.0, 1.0]
            }
        }
        RadiusNormalization::PositiveLobes if hi <= 0.0 => [0.0, 0.0, 0.0, 1.0],
        RadiusNormalization::PositiveLobes => [(1.0 / hi) as f32, 0.0, 0.0, 1.0],
        RadiusNormalization::MaxAbs => {
            let m = hi.abs().max(lo.abs());
            if m == 0.0 {
                [0.0, 0.0, -1.0, 1.0]
            } else {
                [(1.0 / m) as f32, 0.0, -1.0, 1.0]
            }
        }
    }
}

/// The SH recurrence factors (`param/sh.glsl`), in f64 rounded once to f32.
pub fn sh_recurrence_table() -> Vec<[f32; 2]> {
    let width = (GPU_MAX_SH_ORDER + 1) as usize;
    let mut table = vec![[0.0f32; 2]; width * width];
    for a in 0..width {
        let af = a as f64;
        let mut kaa = 1.0 / (4.0 * std::f64::consts::PI).sqrt();
        for j in 1..=a {
            let j = j as f64;
            kaa *= -((2.0 * j + 1.0) / (2.0 * j)).sqrt();
        }
        table[a * width + a] = [kaa as f32, 0.0];
        if a + 1 < width {
            table[a * width + a + 1] = [(2.0 * af + 3.0).sqrt() as f32, 0.0];
        }
        for l in a + 2..width {
            let lf = l as f64;
            let alm = ((4.0 * lf * lf - 1.0) / (lf * lf - af * af)).sqrt();
            let lm1 = lf - 1.0;
            let blm = ((lm1 * lm1 - af * af) / (4.0 * lm1 * lm1 - 1.0)).sqrt();
            table[a * width + l] = [alm as f32, blm as f32];
        }
    }
    table
}

/// The defines that describe the scene layout to the shaders.
pub fn scene_defines() -> Vec<(String, String)> {
    let u = |v: u32| format!("{v}u");
    vec![
        ("PARAM_KIND_SPHERE".into(), u(GpuKind::Sphere as u32)),
        ("PARAM_KIND_HEART".into(), u(GpuKind::Heart as u32)),
        ("PARAM_KIND_SH_GLYPH".into(), u(GpuKind::ShGlyph as u32)),
        ("PARAM_KIND_USER".into(), u(GpuKind::User as u32)),
        ("PARAM_KIND_SEASHELL".into(), u(GpuKind::Seashell as u32)),
        ("PARAM_KIND_YARN".into(), u(GpuKind::Yarn as u32)),
        (
            "PARAM_FLAG_DIRECTION_COLOUR".into(),
            u(FLAG_DIRECTION_COLOUR),
        ),
        ("PARAM_FLAG_POSITIVE_LOBES".into(), u(FLAG_POSITIVE_LOBES)),
        ("PARAM_FLAG_PERIODIC_V".into(), u(FLAG_PERIODIC_V)),
        ("PARAM_BASIS_SHIFT".into(), u(BASIS_SHIFT)),
        ("SH_DESCOTEAUX_LEGACY".into(), u(0)),
        ("SH_DESCOTEAUX".into(), u(1)),
        ("SH_TOURNIER_LEGACY".into(), u(2)),
        ("SH_TOURNIER".into(), u(3)),
        ("SH_TABLE_WIDTH".into(), u(GPU_MAX_SH_ORDER + 1)),
        (
            "PARAM_NORMAL_STEP".into(),
            format!("{:?}", functions::STEP_FRACTION),
        ),
        (
            "PARAM_NORMAL_NUDGE".into(),
            format!("{:?}", functions::NUDGE_FRACTION),
        ),
        (
            "PARAM_NORMAL_NUDGE_STEP".into(),
            format!("{:?}", functions::NUDGE_STEP_FRACTION),
        ),
        (
            "PARAM_NORMAL_COLLAPSE".into(),
            format!("{:?}", functions::COLLAPSE_RATIO),
        ),
    ]
}

/// A scene on the GPU.
pub struct GpuParamScene {
    pub objects: Buffer,
    pub values: Buffer,
    pub object_count: u32,
    /// Payload bits per parameter (`param/payload.glsl`): what the object index leaves of 32.
    pub uv_bits: u32,
    /// World-space bounding spheres, for the view's depth range.
    pub bounds: Vec<(Vec3, f32)>,
}

impl GpuParamScene {
    /// The view of `camera` onto the scene at `size` with `supersample` × `supersample`
    /// samples per pixel, its depth range fitted to the objects' bounds.
    pub fn view(&self, camera: &OrbitCamera, size: (u32, u32), supersample: u32) -> Result<View> {
        Ok(View::new(
            camera,
            size,
            supersample,
            DepthFit::Spheres(&self.bounds),
        )?)
    }

    /// Bytes on the GPU.
    pub fn bytes(&self) -> u64 {
        self.objects.size + self.values.size
    }

    pub fn upload(gpu: &Gpu, scene: &ParamScene) -> Result<GpuParamScene> {
        let n = scene.objects.len();
        if n == 0 || n > MAX_OBJECTS {
            return Err(Error::Invalid(format!(
                "a parametric scene needs 1 to {MAX_OBJECTS} objects, got {n}"
            )));
        }
        let mut values = Vec::new();
        let mut records = Vec::with_capacity(n);
        for (i, o) in scene.objects.iter().enumerate() {
            let m = o.object_to_world;
            if !m.is_finite() || m.row(3) != glam::Vec4::W || m.determinant() == 0.0 {
                return Err(Error::Invalid(format!(
                    "object {i}: the transform must be finite, affine and invertible, got {m}"
                )));
            }
            if !o.colour.iter().all(|c| c.is_finite()) {
                return Err(Error::Invalid(format!(
                    "object {i}: colour {:?} is not finite",
                    o.colour
                )));
            }
            let params = values.len() as u32;
            let (kind, order, flags, radius_map) = encode_function(&o.function, &mut values)
                .map_err(|e| Error::Invalid(format!("object {i}: {e}")))?;
            let d = o.function.domain();
            let [r0, r1, r2] = [m.row(0), m.row(1), m.row(2)].map(|r| r.to_array());
            records.push(GpuObject {
                model: [r0, r1, r2],
                colour: [o.colour[0], o.colour[1], o.colour[2], 1.0],
                domain: [d.u[0], d.u[1], d.v[0], d.v[1]],
                radius_map,
                kind: kind as u32,
                params,
                order,
                flags,
            });
        }
        if values.is_empty() {
            values.push(0.0);
        }
        let bounds = scene.bounding_spheres();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let objects = gpu.upload_buffer("param objects", bytemuck::cast_slice(&records), usage)?;
        let values = gpu.upload_buffer("param values", bytemuck::cast_slice(&values), usage)?;
        let object_bits = usize::BITS - (n - 1).leading_zeros();
        Ok(GpuParamScene {
            objects,
            values,
            object_count: n as u32,
            uv_bits: ((32 - object_bits) / 2).min(16),
            bounds,
        })
    }
}
