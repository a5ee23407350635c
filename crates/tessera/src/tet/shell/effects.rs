//! The secondary-ray effects of shell traversal on the GPU (`lighting.comp.glsl`,
//! `effects.glsl`), as `tessera_data::tet::shell::effects` models them: per frame, a pass per
//! effect fills per-tet lighting (gradients, then AO, then the shadow rays), a pixel pass
//! lights the ground plane through the volume, and the pixel pass shades each stretch with its
//! tet's lighting. Each pass has its own timer scope; the effects are compiled in, so with none
//! the pixel pass is the plain one.
//!
//! The per-tet passes read each tet's vertex ids from a buffer of their own: the compact
//! layouts yield a tet's vertices only to a ray entering it through a known face.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::shell::{
    ao_pattern, GroundPlane, Light, SecondaryStats, ShellEffects, ShellMesh, TetLighting,
    AO_FALLBACK_NORMAL, GRADIENT_RAMP, GRADIENT_THRESHOLD, GROUND_ALBEDO, GROUND_HALF_EXTENT,
    VOLUME_AMBIENT,
};
use tessera_data::View;
use tessera_gpu::{vk, Buffer, Gpu, MemoryLocation};

use crate::config::{float, vec3};
use crate::error::Result;

/// Bindings the effects add after the pixels and their radiance (`effects.glsl`).
pub(crate) const EFFECT_BINDINGS: usize = 6;

/// The effects' passes, as `lighting.comp.glsl`'s LIGHTING_PASS names them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum LightingPass {
    Gradients,
    Occlusion,
    Shadows,
    Ground,
}

impl LightingPass {
    pub(crate) const ALL: [LightingPass; 4] = [
        LightingPass::Gradients,
        LightingPass::Occlusion,
        LightingPass::Shadows,
        LightingPass::Ground,
    ];

    const fn define(self) -> &'static str {
        match self {
            LightingPass::Gradients => "PASS_GRADIENTS",
            LightingPass::Occlusion => "PASS_OCCLUSION",
            LightingPass::Shadows => "PASS_SHADOWS",
            LightingPass::Ground => "PASS_GROUND",
        }
    }

    /// The timer scope (and frame-time name) of the pass.
    pub(crate) fn scope(self) -> &'static str {
        match self {
            LightingPass::Gradients => "shell gradients",
            LightingPass::Occlusion => "shell ambient occlusion",
            LightingPass::Shadows => "shell shadows",
            LightingPass::Ground => "shell ground",
        }
    }

    /// Whether `effects` need this pass.
    pub(crate) fn needed(self, effects: &ShellEffects) -> bool {
        match self {
            LightingPass::Gradients => effects.needs_gradients(),
            LightingPass::Occlusion => effects.ambient_occlusion.is_some(),
            LightingPass::Shadows | LightingPass::Ground => effects.shadows.is_some(),
        }
    }

    /// Per tet, or per pixel.
    pub(crate) fn per_pixel(self) -> bool {
        self == LightingPass::Ground
    }
}

/// The defines of every pass that shades with `effects` (none without effects: the pixel pass
/// is then exactly the plain one).
pub(crate) fn effect_defines(effects: &ShellEffects) -> Vec<(String, String)> {
    if !effects.any() {
        return vec![("SHELL_EFFECTS".into(), "0".into())];
    }
    let samples = effects.ambient_occlusion.map_or(0, |ao| ao.samples);
    let mut defines: Vec<(String, String)> = vec![
        ("SHELL_EFFECTS".into(), "1".into()),
        (
            "SHELL_SHADOWS".into(),
            u32::from(effects.shadows.is_some()).to_string(),
        ),
        (
            "SHELL_GRADIENT".into(),
            u32::from(effects.gradient).to_string(),
        ),
        ("SHELL_AO_SAMPLES".into(), samples.to_string()),
        ("VOLUME_AMBIENT".into(), float(VOLUME_AMBIENT)),
        ("GRADIENT_THRESHOLD".into(), float(GRADIENT_THRESHOLD)),
        ("GRADIENT_RAMP".into(), float(GRADIENT_RAMP)),
        ("GROUND_ALBEDO".into(), vec3(GROUND_ALBEDO)),
        ("GROUND_HALF_EXTENT".into(), float(GROUND_HALF_EXTENT)),
        ("AO_FALLBACK_NORMAL".into(), vec3(AO_FALLBACK_NORMAL)),
    ];
    if samples > 0 {
        let pattern: Vec<String> = ao_pattern(samples).into_iter().map(vec3).collect();
        defines.push((
            "AO_PATTERN".into(),
            format!("vec3[{samples}]({})", pattern.join(", ")),
        ));
    }
    defines.extend(
        LightingPass::ALL
            .iter()
            .enumerate()
            .map(|(i, p)| (p.define().to_string(), i.to_string())),
    );
    defines
}

/// The defines of lighting pass `pass`.
pub(crate) fn pass_defines(effects: &ShellEffects, pass: LightingPass) -> Vec<(String, String)> {
    let mut defines = effect_defines(effects);
    defines.push(("LIGHTING_PASS".into(), pass.define().into()));
    defines
}

/// The effects' per-frame settings (`EffectParams` in `effects.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct EffectParams {
    /// A point light's position (w = 1) or the direction towards the light (w = 0).
    pub light: [f32; 4],
    /// The ground plane's unit up axis and, in w, its height along it.
    pub ground: [f32; 4],
    pub ao_radius: f32,
    /// The absorption table's largest value.
    pub max_absorption: f32,
    pub pad: [f32; 2],
}

impl EffectParams {
    /// The settings of a frame of `view` onto a mesh whose world-space bounds are `bounds`,
    /// drawn through `optics` (the same light and ground as the CPU reference's).
    pub fn new(
        effects: &ShellEffects,
        view: &View,
        bounds: (DVec3, DVec3),
        optics: &EmissionAbsorption,
    ) -> EffectParams {
        let light = match effects.light(view.light.as_dvec3()) {
            Light::Point(p) => p.as_vec3().extend(1.0),
            Light::Directional(d) => d.as_vec3().extend(0.0),
        };
        let ground = GroundPlane::below(bounds, view.camera.up.vector().as_dvec3());
        EffectParams {
            light: light.to_array(),
            ground: ground.up.as_vec3().extend(ground.height as f32).to_array(),
            ao_radius: effects.ambient_occlusion.map_or(0.0, |ao| ao.radius),
            max_absorption: optics.max_absorption() as f32,
            pad: [0.0; 2],
        }
    }
}

/// The buffers of the effects for one mesh and image size. Those of effects that are off hold
/// one element, so every pass binds the same set.
pub struct EffectBuffers {
    pub(crate) params: Buffer,
    tet_vertices: Buffer,
    gradients: Buffer,
    light: Buffer,
    occlusion: Buffer,
    ground: Buffer,
    effects: ShellEffects,
    tet_count: usize,
    pixels: u64,
}

/// Bytes of one element of a per-tet or per-pixel buffer (a `vec4` or `uvec4`).
const ELEMENT: u64 = 16;

impl EffectBuffers {
    /// Buffers for `shell` (its tets' vertex ids are uploaded) and images of `pixels` pixels.
    pub fn new(
        gpu: &Gpu,
        shell: &ShellMesh,
        effects: &ShellEffects,
        pixels: u64,
    ) -> Result<EffectBuffers> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let params = gpu.upload_buffer(
            "shell effect params",
            bytemuck::bytes_of(&EffectParams::default()),
            storage | vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let tet_vertices = gpu.upload_buffer(
            "shell tet vertices",
            bytemuck::cast_slice(&shell.mesh.tets),
            storage,
        )?;
        let tets = shell.mesh.tets.len() as u64;
        let per_tet = |name: &str, on: bool| -> Result<Buffer> {
            let n = if on { tets } else { 1 };
            Ok(gpu.create_buffer(
                name,
                n * ELEMENT,
                storage | vk::BufferUsageFlags::TRANSFER_SRC,
                MemoryLocation::GpuOnly,
            )?)
        };
        Ok(EffectBuffers {
            params,
            tet_vertices,
            gradients: per_tet("shell tet gradients", effects.needs_gradients())?,
            light: per_tet("shell tet light", effects.shadows.is_some())?,
            occlusion: per_tet("shell tet occlusion", effects.ambient_occlusion.is_some())?,
            ground: Self::ground_buffer(gpu, effects, pixels)?,
            effects: *effects,
            tet_count: shell.mesh.tets.len(),
            pixels,
        })
    }

    fn ground_buffer(gpu: &Gpu, effects: &ShellEffects, pixels: u64) -> Result<Buffer> {
        let n = if effects.shadows.is_some() {
            pixels.max(1)
        } else {
            1
        };
        Ok(gpu.create_buffer(
            "shell ground hits",
            n * ELEMENT,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?)
    }

    /// Grows or shrinks the per-pixel buffer to images of `pixels` pixels.
    pub fn resize(&mut self, gpu: &Gpu, pixels: u64) -> Result<()> {
        if pixels != self.pixels {
            self.ground = Self::ground_buffer(gpu, &self.effects, pixels)?;
            self.pixels = pixels;
        }
        Ok(())
    }

    pub fn pixels(&self) -> u64 {
        self.pixels
    }

    pub fn effects(&self) -> &ShellEffects {
        &self.effects
    }

    /// Bindings 8 to 13.
    pub(crate) fn bindings(&self) -> [tessera_gpu::Binding<'_>; EFFECT_BINDINGS] {
        use tessera_gpu::Binding;
        [
            Binding::Buffer(&self.params),
            Binding::Buffer(&self.tet_vertices),
            Binding::Buffer(&self.gradients),
            Binding::Buffer(&self.light),
            Binding::Buffer(&self.occlusion),
            Binding::Buffer(&self.ground),
        ]
    }

    /// The per-tet lighting of the last frame, as the CPU reference's [`TetLighting`] holds it.
    pub fn read_lighting(&self, gpu: &Gpu) -> Result<TetLighting> {
        let read = |buffer: &Buffer, on: bool| -> Result<Vec<DVec3>> {
            if !on {
                return Ok(Vec::new());
            }
            let words: Vec<[f32; 4]> = gpu.read_buffer_as(buffer)?;
            Ok(words
                .iter()
                .take(self.tet_count)
                .map(|w| glam::Vec3::new(w[0], w[1], w[2]).as_dvec3())
                .collect())
        };
        let e = &self.effects;
        Ok(TetLighting {
            gradients: read(&self.gradients, e.needs_gradients())?,
            light: read(&self.light, e.shadows.is_some())?,
            occlusion: read(&self.occlusion, e.ambient_occlusion.is_some())?,
        })
    }
}

/// The secondary-ray counters, `word` reading the stats buffer by `STAT_…` name.
pub(crate) fn secondary_stats(word: impl Fn(&str) -> u64) -> SecondaryStats {
    SecondaryStats {
        shadow_rays: word("STAT_SHADOW_RAYS"),
        ao_rays: word("STAT_AO_RAYS"),
        steps: word("STAT_SECONDARY_STEPS_LOW") | word("STAT_SECONDARY_STEPS_HIGH") << 32,
        guard_hits: word("STAT_SECONDARY_GUARD_HITS"),
    }
}
