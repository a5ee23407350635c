//! Which technique, with which settings, on which path: the names the CLI, benchmarks and
//! Python use, the kind of data each draws, the options each reads (so front ends can warn
//! about the others) and the path `auto` picks on a device.

use crate::error::{Error, Result};
use crate::iso::direct::compute::DirectRaster;
use crate::iso::HiddenSide;
use crate::path::{Path, PathChoice};
use crate::tet::interval::IntervalTuning;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::pmb::PmbBlockSize;
use tessera_data::scene::DataKind;
use tessera_data::tet::shell::{AmbientOcclusion, LayoutKind, Light, ShellEffects};
use tessera_gpu::Capabilities;

/// The techniques, by the names the CLI and benchmarks use.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Technique {
    /// Min-max octree ray marching of an isosurface (paper D's reference).
    Raymarch,
    /// Marching cubes straight to a rasterizer (paper D): task/mesh shaders or compute.
    Direct,
    /// Persistent meshlets extracted on the GPU when the isovalue changes, then drawn
    /// (paper C): task/mesh shaders or compute.
    Meshlets,
    /// meshoptimizer meshlets of the CPU marching-cubes mesh, drawn like `meshlets` (paper
    /// C's offline reference).
    Offline,
    /// Parallel Marching Blocks extracted on the GPU when the isovalue changes, then drawn
    /// (paper C's real-time reference): indexed indirect draws or compute.
    Pmb,
    /// Interval shading of tet meshes (paper A): mesh shaders or compute.
    Interval,
    /// Ray-traced shell traversal of tet meshes (paper B): compute.
    Shell,
    /// Parametric objects: patch LOD, then points (paper E).
    ParamPoints,
    /// Parametric objects: patch LOD, then hardware tessellation (paper E).
    ParamTess,
    /// SH glyphs ray-traced per pixel (Peters et al. 2023, paper E's reference).
    ShRaytrace,
}

impl Technique {
    pub const ALL: [Technique; 10] = [
        Technique::Raymarch,
        Technique::Direct,
        Technique::Meshlets,
        Technique::Offline,
        Technique::Pmb,
        Technique::Interval,
        Technique::Shell,
        Technique::ParamPoints,
        Technique::ParamTess,
        Technique::ShRaytrace,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Technique::Raymarch => "raymarch",
            Technique::Direct => "direct",
            Technique::Meshlets => "meshlets",
            Technique::Offline => "offline",
            Technique::Pmb => "pmb",
            Technique::Interval => "interval",
            Technique::Shell => "shell",
            Technique::ParamPoints => "param-points",
            Technique::ParamTess => "param-tess",
            Technique::ShRaytrace => "sh-raytrace",
        }
    }

    pub fn parse(name: &str) -> Result<Technique> {
        Technique::ALL
            .into_iter()
            .find(|t| t.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Technique::ALL.iter().map(|t| t.name()).collect();
                Error::Invalid(format!("unknown technique '{name}' ({})", names.join(", ")))
            })
    }

    /// The kind of data the technique draws.
    pub fn draws(self) -> DataKind {
        match self {
            Technique::Raymarch
            | Technique::Direct
            | Technique::Meshlets
            | Technique::Offline
            | Technique::Pmb => DataKind::Volume,
            Technique::Interval | Technique::Shell => DataKind::Tets,
            Technique::ParamPoints | Technique::ParamTess | Technique::ShRaytrace => {
                DataKind::Param
            }
        }
    }

    /// What draws `kind` when no technique is named.
    pub fn default_for(kind: DataKind) -> Technique {
        match kind {
            DataKind::Volume => Technique::Raymarch,
            DataKind::Tets => Technique::Interval,
            DataKind::Param => Technique::ParamPoints,
        }
    }

    /// `name` (or the default) for data of `kind`, refused with the techniques that do draw
    /// it when it does not.
    pub fn for_data(name: Option<&str>, kind: DataKind, what: &str) -> Result<Technique> {
        let Some(name) = name else {
            return Ok(Technique::default_for(kind));
        };
        let technique = Technique::parse(name)?;
        if technique.draws() == kind {
            return Ok(technique);
        }
        let fitting: Vec<&str> = Technique::ALL
            .iter()
            .filter(|t| t.draws() == kind)
            .map(|t| t.name())
            .collect();
        Err(Error::Invalid(format!(
            "{what}: technique '{name}' draws {}, not {}; use {}",
            technique.draws().describe(),
            kind.describe(),
            fitting.join(" or ")
        )))
    }
}

/// Occlusion culling of `direct`; frustum culling (and, on the compute path, occlusion
/// culling) of the stored surfaces (`meshlets`, `offline`, `pmb`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Culling {
    Off,
    On,
    /// `direct` on the compute path culls only while a frame's counts say it pays
    /// ([`crate::iso::direct::cull_choice`]); elsewhere as `On` (on the mesh path culling
    /// paid on every volume measured).
    #[default]
    Auto,
}

impl Culling {
    pub fn parse(text: &str) -> Result<Culling> {
        match text {
            "off" => Ok(Culling::Off),
            "on" => Ok(Culling::On),
            "auto" => Ok(Culling::Auto),
            _ => Err(Error::Invalid(format!(
                "culling '{text}': choose on, off or auto"
            ))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Culling::Off => "off",
            Culling::On => "on",
            Culling::Auto => "auto",
        }
    }

    /// Whether culling may run at all (its state is needed).
    pub fn enabled(self) -> bool {
        self != Culling::Off
    }
}

/// Settings that shape a renderer's pipelines and buffers (not the data's look).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RendererOptions {
    /// For techniques with a graphics and a compute path (direct, interval).
    pub path: PathChoice,
    /// Culling of the isosurface techniques (occlusion culling carried from frame to frame).
    pub culling: Culling,
    /// Raster samples per pixel along each axis, averaged (parametric techniques).
    pub supersample: u32,
    /// Samples per pixel of `param-tess`'s multisampling.
    pub msaa: u32,
    /// Each parametric object starts as `pre_split`² patches before the LOD stage; `None`: the
    /// technique's own choice (param-tess starts SH glyphs as 2 × 2 patches, since a patch
    /// gets at most 64 segments per edge and a small glyph's lobes need more; else 1).
    pub pre_split: Option<u32>,
    /// Interval shading's speed settings.
    pub interval: IntervalTuning,
    /// How `direct`'s marching cubes cuts ambiguous faces (a shader define).
    pub ambiguity: AmbiguityRule,
    /// The compact tet layout shell traversal marches through.
    pub layout: LayoutKind,
    /// Shell traversal's volumetric shadows, and the ground plane they fall on, from this
    /// light (world space; [`Light::above`] is the usual sun).
    pub shadows: Option<Light>,
    /// Shell traversal's ambient occlusion.
    pub ao: Option<AmbientOcclusion>,
    /// Shell traversal's gradient shading.
    pub gradient: bool,
    /// The block size of `pmb`'s extraction.
    pub pmb_block: PmbBlockSize,
    /// Whether the isosurface draws leave out the side of a closed surface no pixel shows
    /// (the image is the same; drawing it measures what leaving it out saves).
    pub hidden_side: HiddenSide,
    /// Where `direct`'s compute path draws its triangles (the frames are the same; for
    /// measuring which is faster).
    pub direct_raster: DirectRaster,
}

impl RendererOptions {
    /// Shell traversal's effects as these options set them.
    pub fn shell_effects(&self) -> ShellEffects {
        ShellEffects {
            shadows: self.shadows,
            ambient_occlusion: self.ao,
            gradient: self.gradient,
        }
    }
}

impl Default for RendererOptions {
    fn default() -> Self {
        RendererOptions {
            path: PathChoice::Auto,
            culling: Culling::Auto,
            supersample: 1,
            msaa: 1,
            pre_split: None,
            interval: IntervalTuning::default(),
            ambiguity: AmbiguityRule::default(),
            layout: LayoutKind::Tet20,
            shadows: None,
            ao: None,
            gradient: false,
            pmb_block: PmbBlockSize::default(),
            hidden_side: HiddenSide::default(),
            direct_raster: DirectRaster::default(),
        }
    }
}

/// The settings of [`RendererOptions`] by name (as the CLI's flags spell them, `_` for `-`;
/// `hidden_side` and `direct_raster`, for measuring, have none).
pub const OPTION_NAMES: [&str; 14] = [
    "path",
    "culling",
    "supersample",
    "msaa",
    "pre_split",
    "interval",
    "ambiguity",
    "layout",
    "shadows",
    "ao",
    "gradient",
    "pmb_block",
    "hidden_side",
    "direct_raster",
];

impl Technique {
    /// The [`RendererOptions`] settings this technique reads ([`OPTION_NAMES`]); it ignores
    /// the others.
    pub fn reads_options(self) -> &'static [&'static str] {
        match self {
            Technique::Raymarch => &[],
            Technique::Direct => &[
                "path",
                "culling",
                "ambiguity",
                "hidden_side",
                "direct_raster",
            ],
            Technique::Meshlets | Technique::Offline => {
                &["path", "culling", "ambiguity", "hidden_side"]
            }
            Technique::Pmb => &["path", "culling", "ambiguity", "pmb_block", "hidden_side"],
            Technique::Interval => &["path", "interval"],
            Technique::Shell => &["path", "layout", "shadows", "ao", "gradient"],
            Technique::ParamPoints => &["supersample", "pre_split"],
            Technique::ParamTess => &["supersample", "msaa", "pre_split"],
            Technique::ShRaytrace => &["supersample"],
        }
    }
}

impl RendererOptions {
    /// The settings that differ from the defaults but that `technique` does not read, so a
    /// front end can say they have no effect ([`OPTION_NAMES`]).
    pub fn ignored_by(&self, technique: Technique) -> Vec<&'static str> {
        let d = RendererOptions::default();
        let changed = [
            self.path != d.path,
            self.culling != d.culling,
            self.supersample != d.supersample,
            self.msaa != d.msaa,
            self.pre_split != d.pre_split,
            self.interval != d.interval,
            self.ambiguity != d.ambiguity,
            self.layout != d.layout,
            self.shadows != d.shadows,
            self.ao != d.ao,
            self.gradient != d.gradient,
            self.pmb_block != d.pmb_block,
            self.hidden_side != d.hidden_side,
            self.direct_raster != d.direct_raster,
        ];
        OPTION_NAMES
            .into_iter()
            .zip(changed)
            .filter(|&(name, changed)| changed && !technique.reads_options().contains(&name))
            .map(|(name, _)| name)
            .collect()
    }
}

/// The path `technique` takes on a device with `caps` when asked for `choice`: the one
/// [`create`] picks (the renderers call this), so that `tessera info` reports what `auto`
/// really does. Techniques with a single path take it whatever the choice (see
/// [`RendererOptions::ignored_by`]).
pub fn path_for(caps: &Capabilities, technique: Technique, choice: PathChoice) -> Result<Path> {
    let measured = crate::path::remembered(caps);
    match technique {
        Technique::Raymarch | Technique::ParamPoints | Technique::ShRaytrace => Ok(Path::Compute),
        // The graphics path is the ray-tracing pipeline. `auto` takes the compute path: the
        // BVH walk needs nothing special, and on devices without ray-tracing hardware the
        // pipeline's traversal is software too (docs/BENCHMARKS.md compares them).
        Technique::Shell => {
            crate::path::choose_for(caps, &crate::tet::shell::path_support(caps), choice, None)
        }
        Technique::ParamTess => Ok(Path::Graphics),
        // The meshlet draw needs what direct's two paths need: task and mesh shaders, or the
        // compute rasterizer's 64-bit atomics.
        Technique::Direct | Technique::Meshlets | Technique::Offline => {
            crate::path::choose(caps, choice, measured.as_ref())
        }
        Technique::Pmb => crate::path::choose_for(
            caps,
            &crate::iso::pmb_draw::path_support(caps),
            choice,
            measured.as_ref(),
        ),
        Technique::Interval => crate::path::choose_for(
            caps,
            &crate::tet::interval::path_support(caps),
            choice,
            measured.as_ref(),
        ),
    }
}

#[cfg(test)]
mod option_tests {
    use super::*;

    #[test]
    fn options_a_technique_ignores_are_named() {
        let defaults = RendererOptions::default();
        for t in Technique::ALL {
            assert!(defaults.ignored_by(t).is_empty(), "{t:?}");
            for name in t.reads_options() {
                assert!(OPTION_NAMES.contains(name), "{name}");
            }
        }
        let graphics = RendererOptions {
            path: PathChoice::Graphics,
            ..defaults
        };
        assert_eq!(graphics.ignored_by(Technique::Raymarch), ["path"]);
        assert!(graphics.ignored_by(Technique::Direct).is_empty());
        let no_culling = RendererOptions {
            culling: Culling::Off,
            ..defaults
        };
        assert_eq!(no_culling.ignored_by(Technique::Interval), ["culling"]);
        assert!(no_culling.ignored_by(Technique::Direct).is_empty());
        let msaa = RendererOptions {
            msaa: 4,
            supersample: 2,
            ..defaults
        };
        assert_eq!(msaa.ignored_by(Technique::ParamPoints), ["msaa"]);
        assert_eq!(
            msaa.ignored_by(Technique::Raymarch),
            ["supersample", "msaa"]
        );
        assert!(msaa.ignored_by(Technique::ParamTess).is_empty());
        let effects = RendererOptions {
            shadows: Some(Light::Directional(glam::DVec3::Y)),
            ao: Some(AmbientOcclusion::new(4, 0.1).unwrap()),
            gradient: true,
            ..defaults
        };
        assert!(effects.ignored_by(Technique::Shell).is_empty());
        assert_eq!(
            effects.ignored_by(Technique::Interval),
            ["shadows", "ao", "gradient"]
        );
    }

    #[test]
    fn path_for_follows_each_techniques_support() {
        // Mesh shaders and float atomics but no 64-bit atomics: direct and interval differ.
        let caps = Capabilities {
            device_name: "test".into(),
            mesh_shader: true,
            task_shader: true,
            buffer_float32_atomic_add: true,
            ..Capabilities::default()
        };
        let auto = PathChoice::Auto;
        assert_eq!(
            path_for(&caps, Technique::Raymarch, auto).unwrap(),
            Path::Compute
        );
        assert_eq!(
            path_for(&caps, Technique::Raymarch, PathChoice::Graphics).unwrap(),
            Path::Compute
        );
        assert_eq!(
            path_for(&caps, Technique::Direct, auto).unwrap(),
            Path::Graphics
        );
        assert!(path_for(&caps, Technique::Direct, PathChoice::Compute).is_err());
        assert_eq!(
            path_for(&caps, Technique::Interval, PathChoice::Compute).unwrap(),
            Path::Compute
        );
        assert_eq!(
            path_for(&caps, Technique::ParamTess, auto).unwrap(),
            Path::Graphics
        );
        // PMB's graphics path draws with indirect counts, not mesh shaders.
        assert!(path_for(&caps, Technique::Pmb, PathChoice::Graphics).is_err());
        let counts = Capabilities {
            draw_indirect_count: true,
            ..Capabilities::default()
        };
        assert_eq!(
            path_for(&counts, Technique::Pmb, auto).unwrap(),
            Path::Graphics
        );
        assert!(path_for(&counts, Technique::Meshlets, auto).is_err());
        // Shell traversal's graphics path is the ray-tracing pipeline; `auto` stays on compute.
        assert!(path_for(&caps, Technique::Shell, PathChoice::Graphics).is_err());
        let rays = Capabilities {
            ray_tracing_pipeline: true,
            acceleration_structure: true,
            ..Capabilities::default()
        };
        assert_eq!(
            path_for(&rays, Technique::Shell, PathChoice::Graphics).unwrap(),
            Path::Graphics
        );
        assert_eq!(
            path_for(&rays, Technique::Shell, auto).unwrap(),
            Path::Compute
        );
    }
}
