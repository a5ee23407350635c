//! Parametric scenes: objects (a function of `tessera_data::param` placed by a transform) and
//! their upload into the buffers every pass of the technique reads (`param/scene.glsl`).
//!
//! GPU layout, bindings 0–2 of every pass:
//! * `ParamObject param_objects[]` ([`GpuObject`], 112 bytes): object-to-world rows, colour,
//!   domain, the SH radius map, the function's kind, the offset of its parameters, SH order and
//!   flags (direction colouring, SH basis).
//! * `float param_values[]`: the objects' parameters (SH coefficients as f32), at least one.
//! * `vec2 sh_recurrence[]`: the SH recurrence factors, built once per device
//!   ([`sh_recurrence_table`]).
//!
//! Adding a function: its GLSL in `functions.glsl` (plus a case in `param_position`) and one
//! arm in [`encode_function`].

use crate::error::{Error, Result};
use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use tessera_data::param::reference::ReferenceObject;
use tessera_data::param::sh::sh_degrees_and_orders;
use tessera_data::param::{ParamFunction, RadiusNormalization, ShBasis};
use tessera_gpu::{vk, Buffer, Gpu};

/// Largest SH order the GPU evaluates (size of the recurrence table; the CPU goes further).
pub const GPU_MAX_SH_ORDER: u32 = 32;
/// Most objects one scene holds: the payload keeps at least 4 bits per parameter.
pub const MAX_OBJECTS: usize = 1 << 24;

/// The function families the shaders evaluate (`PARAM_KIND_*`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u32)]
pub enum GpuKind {
    Sphere = 0,
    Heart = 1,
    ShGlyph = 2,
    /// The user's GLSL function (`param/user.rs`).
    User = 3,
}

/// `PARAM_FLAG_DIRECTION_COLOUR`: colour by direction from the object's centre.
pub const FLAG_DIRECTION_COLOUR: u32 = 1;
/// Bits 4–5 of the flags hold the SH basis (`SH_*` codes).
pub const BASIS_SHIFT: u32 = 4;

/// One object: `object_to_world · f(u, v)`, coloured by `colour` (SH glyphs are coloured by
/// direction instead).
#[derive(Debug, Clone, PartialEq)]
pub struct ParamObject {
    pub function: ParamFunction,
    pub object_to_world: Mat4,
    pub colour: [f32; 3],
}

impl ParamObject {
    /// `function` at the origin, light grey.
    pub fn new(function: ParamFunction) -> ParamObject {
        ParamObject {
            function,
            object_to_world: Mat4::IDENTITY,
            colour: [0.85, 0.85, 0.85],
        }
    }

    pub fn with_transform(self, object_to_world: Mat4) -> ParamObject {
        ParamObject {
            object_to_world,
            ..self
        }
    }

    pub fn with_colour(self, colour: [f32; 3]) -> ParamObject {
        ParamObject { colour, ..self }
    }

    /// The object as `tessera_data::param::reference` takes it.
    pub fn reference(&self) -> ReferenceObject<'_> {
        ReferenceObject {
            function: &self.function,
            object_to_world: self.object_to_world,
            colour: Vec3::from(self.colour),
        }
    }

    /// A sphere around the origin of object space that holds the whole surface.
    fn object_radius(&self) -> f32 {
        match &self.function {
            // |f| <= 1 for both: the heart only shrinks the unit sphere's coordinates.
            ParamFunction::Sphere | ParamFunction::Heart => 1.0,
            ParamFunction::ShGlyph(g) => match g.normalization() {
                RadiusNormalization::MinMax | RadiusNormalization::MaxAbs => 1.0,
                // |Y_l^m| <= sqrt(2 (2l + 1) / 4π) for every real basis here, so this bounds |r|.
                RadiusNormalization::Raw => sh_degrees_and_orders(g.order())
                    .map(|lm| {
                        lm.iter()
                            .zip(g.coefficients())
                            .map(|((l, _), c)| {
                                c.abs()
                                    * (2.0 * (2.0 * f64::from(*l) + 1.0)
                                        / (4.0 * std::f64::consts::PI))
                                        .sqrt()
                            })
                            .sum::<f64>() as f32
                    })
                    .unwrap_or(f32::INFINITY),
            },
            // Not drawn on the GPU yet (encode_function refuses them).
            _ => f32::INFINITY,
        }
    }

    /// World-space bounding sphere (centre, radius).
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let m = self.object_to_world;
        // The Frobenius norm of the linear part bounds how far it stretches any vector.
        let stretch = (m.x_axis.truncate().length_squared()
            + m.y_axis.truncate().length_squared()
            + m.z_axis.truncate().length_squared())
        .sqrt();
        (m.w_axis.truncate(), self.object_radius() * stretch)
    }
}

/// The objects of one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ParamScene {
    pub objects: Vec<ParamObject>,
}

impl ParamScene {
    pub fn new(objects: Vec<ParamObject>) -> ParamScene {
        ParamScene { objects }
    }

    pub fn bounding_spheres(&self) -> Vec<(Vec3, f32)> {
        self.objects
            .iter()
            .map(ParamObject::bounding_sphere)
            .collect()
    }

    pub fn reference_objects(&self) -> Vec<ReferenceObject<'_>> {
        self.objects.iter().map(ParamObject::reference).collect()
    }
}

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
        ParamFunction::Sphere => Ok((GpuKind::Sphere, 0, 0, identity)),
        ParamFunction::Heart => Ok((GpuKind::Heart, 0, 0, identity)),
        ParamFunction::User(_) => Ok((GpuKind::User, 0, 0, identity)),
        ParamFunction::ShGlyph(g) => {
            if g.order() > GPU_MAX_SH_ORDER {
                return Err(Error::Invalid(format!(
                    "SH glyph of order {} exceeds the GPU's maximum order {GPU_MAX_SH_ORDER}",
                    g.order()
                )));
            }
            values.extend(g.coefficients().iter().map(|&c| c as f32));
            let flags = FLAG_DIRECTION_COLOUR | (basis_code(g.basis()) << BASIS_SHIFT);
            Ok((GpuKind::ShGlyph, g.order(), flags, radius_map(g)))
        }
        other => Err(Error::Invalid(format!(
            "{} is not drawn on the GPU yet",
            match other {
                ParamFunction::Seashell(_) => "a seashell",
                _ => "a yarn tube",
            }
        ))),
    }
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
        (
            "PARAM_FLAG_DIRECTION_COLOUR".into(),
            u(FLAG_DIRECTION_COLOUR),
        ),
        ("PARAM_BASIS_SHIFT".into(), u(BASIS_SHIFT)),
        ("SH_DESCOTEAUX_LEGACY".into(), u(0)),
        ("SH_DESCOTEAUX".into(), u(1)),
        ("SH_TOURNIER_LEGACY".into(), u(2)),
        ("SH_TOURNIER".into(), u(3)),
        ("SH_TABLE_WIDTH".into(), u(GPU_MAX_SH_ORDER + 1)),
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
        let values = match gpu.upload_buffer("param values", bytemuck::cast_slice(&values), usage) {
            Ok(v) => v,
            Err(e) => {
                gpu.destroy_buffer(objects);
                return Err(e.into());
            }
        };
        let object_bits = usize::BITS - (n - 1).leading_zeros();
        Ok(GpuParamScene {
            objects,
            values,
            object_count: n as u32,
            uv_bits: ((32 - object_bits) / 2).min(16),
            bounds,
        })
    }

    pub fn destroy(self, gpu: &Gpu) {
        gpu.destroy_buffer(self.objects);
        gpu.destroy_buffer(self.values);
    }
}
