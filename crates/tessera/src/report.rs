//! One-line descriptions of a rendered frame, as `tessera render` prints them and the viewer
//! shows them.

use crate::renderer::{FrameStats, FrameTimes, RendererOptions, Technique};
use tessera_data::scene::{Appearance, Dataset};

/// What the image shows besides technique and path, as the report line gives it.
pub fn describe(
    dataset: &Dataset,
    look: &Appearance,
    technique: Technique,
    options: &RendererOptions,
) -> String {
    match dataset {
        // Shell traversal always composites emission and absorption of the vertex scalars.
        Dataset::Tets(tets) if technique == Technique::Shell => format!(
            ", emission-absorption in {}{}, {} tets",
            options.layout.name(),
            describe_effects(options),
            tets.mesh.tets.len()
        ),
        Dataset::Volume(volume) => {
            let iso = look
                .iso_texel(volume)
                .map(|iso| format!(", iso {iso}"))
                .unwrap_or_default();
            if technique == Technique::Pmb {
                format!("{iso}, {} blocks", options.pmb_block.name())
            } else {
                iso
            }
        }
        Dataset::Tets(tets) => {
            let what = look
                .resolve_integrand(tets)
                .map(|i| i.describe(&tets.mesh))
                .unwrap_or_default();
            format!(", {what}, {} tets", tets.mesh.tets.len())
        }
        Dataset::Param(param) => format!(", {} objects", param.scene.objects.len()),
    }
}

/// The GPU time of each of a frame's passes and the secondary rays shell traversal cast.
pub fn effect_passes(times: &FrameTimes, stats: &FrameStats) -> String {
    let passes: Vec<String> = times
        .scopes
        .iter()
        .map(|(name, ms)| format!("{name} {ms:.3} ms"))
        .collect();
    let count = |name: &str| stats.details.get(name).copied().unwrap_or(0);
    format!(
        "passes: {}; secondary rays: {} shadow, {} AO ({} tet steps)",
        passes.join(", "),
        count("shadow_rays"),
        count("ao_rays"),
        count("secondary_steps")
    )
}

/// Shell traversal's effects as the report line names them.
fn describe_effects(options: &RendererOptions) -> String {
    let mut on = Vec::new();
    if options.shadows.is_some() {
        on.push("shadows".to_string());
    }
    if let Some(ao) = options.ao {
        on.push(format!("AO {}x{}", ao.samples, ao.radius));
    }
    if options.gradient {
        on.push("gradient shading".to_string());
    }
    if on.is_empty() {
        String::new()
    } else {
        format!(" with {}", on.join(", "))
    }
}
