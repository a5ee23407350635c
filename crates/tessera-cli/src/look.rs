//! Flags that become the library's `Appearance`, `LoadOptions` and `RendererOptions`.

use crate::data::{IsoArgs, VolumeArgs};
use anyhow::Result;
use clap::Args;
use tessera::path::PathChoice;
use tessera::renderer::{AmbientOcclusion, Light, PmbBlockSize, RendererOptions, Technique};
use tessera_data::scene::parse::{
    parse_basis, parse_colour, parse_glyph_radius, parse_integrand, parse_param_range, parse_range,
    parse_triple,
};
use tessera_data::scene::{Appearance, IntegrandChoice, LoadOptions};
use tessera_data::tet::shell::{LayoutKind, DEFAULT_AO_RADIUS};
use tessera_data::transfer::TransferFunction;
use tessera_data::ViewUp;

/// How tet meshes are shown (interval shading, shell traversal).
#[derive(Args)]
pub struct TetArgs {
    /// What rays accumulate through a tet mesh: tet-absorption (per-tet colours, or white),
    /// absorption / emission / mip (the vertex scalars through --tf), or auto (absorption when
    /// the mesh has vertex scalars and no per-tet colours).
    #[arg(long, default_value = "auto", value_parser = parse_integrand)]
    integrate: IntegrandChoice,
    /// Transfer function for scalar integration: cool-warm, grey, hot, bands, or a file of
    /// 'at r g b a' lines.
    #[arg(long, default_value = "cool-warm")]
    tf: String,
    /// Absorption or emission per unit length at full opacity (the mesh's longest side is 1).
    #[arg(long, default_value_t = 4.0)]
    density: f32,
    /// One absorption colour R,G,B (per unit length) for every tet, in place of the mesh's
    /// per-tet colours (tet-absorption).
    #[arg(long, value_parser = parse_colour)]
    absorption: Option<[f32; 3]>,
    /// Scalar range LO,HI mapped onto the transfer function (default: the mesh's own).
    #[arg(long, value_parser = parse_range, allow_hyphen_values = true)]
    range: Option<(f32, f32)>,
    /// Compact tet layout shell traversal marches through: tet32, tet20 or tet16.
    #[arg(long, default_value = "tet20", value_parser = |s: &str| LayoutKind::parse(s))]
    layout: LayoutKind,
}

impl TetArgs {
    pub fn layout(&self) -> LayoutKind {
        self.layout
    }

    /// The interval-shading flags given away from their defaults (shell traversal always
    /// composites emission and absorption of the vertex scalars, so it reads neither).
    fn interval_flags(&self) -> Vec<&'static str> {
        let mut given = Vec::new();
        if self.integrate != IntegrandChoice::Auto {
            given.push("integrate");
        }
        if self.absorption.is_some() {
            given.push("absorption");
        }
        given
    }
}

/// Shell traversal's secondary-ray effects.
#[derive(Args)]
pub struct ShellArgs {
    /// Shell traversal: volumetric shadows, and a ground plane below the mesh that they fall
    /// on (default light: a sun above, along the view's up axis, tilted aside).
    #[arg(long)]
    shadows: bool,
    /// Point light X,Y,Z for --shadows, in world space (the mesh is centred at the origin, its
    /// longest side 1).
    #[arg(long, value_parser = parse_triple::<f64>, allow_hyphen_values = true,
          requires = "shadows", conflicts_with = "light_dir")]
    light: Option<[f64; 3]>,
    /// Directional light for --shadows: the direction X,Y,Z towards the light.
    #[arg(long, value_parser = parse_triple::<f64>, allow_hyphen_values = true,
          requires = "shadows")]
    light_dir: Option<[f64; 3]>,
    /// Shell traversal: ambient occlusion with N hemisphere rays per tet (1 to 64).
    #[arg(long, value_name = "N")]
    ao: Option<u32>,
    /// Length of the ambient occlusion rays (world units).
    #[arg(long, value_name = "R", requires = "ao", allow_hyphen_values = true)]
    ao_radius: Option<f32>,
    /// Shell traversal: diffuse and specular shading with each tet's scalar gradient as the
    /// normal, in dense regions.
    #[arg(long)]
    gradient: bool,
}

impl ShellArgs {
    /// `options` with the effects set; `up` is the view's up axis (the default sun's).
    pub fn apply(&self, options: RendererOptions, up: ViewUp) -> Result<RendererOptions> {
        let shadows = self
            .shadows
            .then(|| Light::chosen(self.light, self.light_dir, up.vector().as_dvec3()))
            .transpose()?;
        let ao = self
            .ao
            .map(|n| AmbientOcclusion::new(n, self.ao_radius.unwrap_or(DEFAULT_AO_RADIUS)))
            .transpose()?;
        Ok(RendererOptions {
            shadows,
            ao,
            gradient: self.gradient,
            ..options
        })
    }
}

/// Options of the parametric-object techniques.
#[derive(Args)]
pub struct ParamArgs {
    /// Render at K×K samples per pixel and average (supersampling).
    #[arg(long, default_value_t = 1)]
    supersample: u32,
    /// Start each object as K×K patches (a power of two up to 16) before the LOD stage
    /// (default 1; param-tess starts SH glyphs as 2×2, since a patch gets at most 64 segments
    /// per edge)
    #[arg(long)]
    pre_split: Option<u32>,
    /// Multisampling of param-tess: 1, 2, 4 or 8 samples per pixel.
    #[arg(long, default_value_t = 1)]
    msaa: u32,
    /// Parameter range FROM,TO of u for a user function file (numbers, or multiples of pi/tau:
    /// 0,2pi); overrides the file's '// u: FROM TO' line.
    #[arg(long, value_parser = parse_param_range, allow_hyphen_values = true)]
    u_range: Option<[f32; 2]>,
    /// Parameter range of v for a user function file, like --u-range.
    #[arg(long, value_parser = parse_param_range, allow_hyphen_values = true)]
    v_range: Option<[f32; 2]>,
    /// SH basis of glyphs: descoteaux07 or tournier07, each also -legacy (DIPY's `legacy=True`).
    /// Default: descoteaux07-legacy for coefficient files (DIPY's default), descoteaux07 else.
    #[arg(long, value_parser = parse_basis)]
    basis: Option<tessera_data::param::ShBasis>,
    /// How a glyph's SH values become its radius: minmax ((r - min) / (max - min) per glyph, as
    /// DIPY draws ODFs: never inverted, but directions where the ODF dips below zero are lifted)
    /// abs (|r| / max|r|: shapes kept, a negative lobe drawn as large as a positive one) or
    /// clamp (max(r, 0) / max r: negative lobes dropped)
    #[arg(long, default_value = "minmax", value_parser = parse_glyph_radius)]
    glyph_radius: tessera_data::param::RadiusNormalization,
}

/// The pipeline and culling flags every technique may take.
#[derive(Args)]
pub struct PathArgs {
    /// Pipeline for techniques that have two: graphics (task/mesh shaders), compute, or auto
    /// (from capabilities and `tessera bench pipeline-throughput` if it ran on this device).
    #[arg(long, default_value = "auto", value_parser = PathChoice::parse)]
    path: PathChoice,
    /// Occlusion culling of direct, frustum culling of meshlets and PMB blocks: on, off or auto
    /// (direct's compute path culls only in frames where it pays; elsewhere on).
    #[arg(long, default_value = "auto", value_parser = tessera::renderer::Culling::parse)]
    culling: tessera::renderer::Culling,
    /// Block size of pmb's extraction: 4x4x4, 8x4x4, 8x8x4 or 8x8x8.
    #[arg(long, default_value = "8x8x4", value_parser = parse_pmb_block)]
    pmb_block: PmbBlockSize,
}

fn parse_pmb_block(text: &str) -> std::result::Result<PmbBlockSize, String> {
    PmbBlockSize::parse(text).map_err(|e| e.to_string())
}

/// The look the flags give; a volume's isovalue, when none is given, is settled once the
/// volume is loaded ([`IsoArgs::resolve`]).
pub fn appearance(iso: &IsoArgs, tets: &TetArgs) -> Result<Appearance> {
    Ok(Appearance {
        iso: iso.value().unwrap_or(Appearance::default().iso),
        integrand: tets.integrate,
        transfer: TransferFunction::load(&tets.tf)?,
        density: tets.density,
        range: tets.range,
        absorption: tets.absorption,
        background: None,
    })
}

pub fn load_options(volume: &VolumeArgs, param: &ParamArgs) -> LoadOptions {
    LoadOptions {
        raw: volume.raw_options(),
        basis: param.basis,
        glyph_radius: param.glyph_radius,
        u_range: param.u_range,
        v_range: param.v_range,
    }
}

/// Warns about the options `technique` does not read that were set away from their defaults,
/// and about interval shading's look flags given to shell traversal.
pub fn warn_ignored(options: &RendererOptions, tets: &TetArgs, technique: Technique) {
    for name in options.ignored_by(technique) {
        eprintln!(
            "warning: {} ignores --{}",
            technique.name(),
            name.replace('_', "-")
        );
    }
    if technique == Technique::Shell {
        for name in tets.interval_flags() {
            eprintln!(
                "warning: shell ignores --{name} (interval shading's; shell traversal always \
                 composites emission and absorption of the vertex scalars through --tf)"
            );
        }
    }
}

pub fn renderer_options(paths: &PathArgs, param: &ParamArgs, iso: &IsoArgs) -> RendererOptions {
    RendererOptions {
        ambiguity: iso.ambiguity,
        path: paths.path,
        culling: paths.culling,
        supersample: param.supersample,
        msaa: param.msaa,
        pre_split: param.pre_split,
        pmb_block: paths.pmb_block,
        ..RendererOptions::default()
    }
}
