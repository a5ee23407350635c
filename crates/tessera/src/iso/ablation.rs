//! Stages left out of an extraction, for performance work: timing an extraction with and
//! without a stage says what the stage costs where no profiler reads the GPU's counters. What
//! an ablated extraction writes is not a surface; only `tessera bench extraction --ablations`
//! runs them.

/// A stage left out (or made trivial).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Ablation {
    /// The whole extraction.
    #[default]
    None,
    /// Occupied-block filtering and compaction only, no extraction dispatch.
    FilteringOnly,
    /// The meshlets' region analysis without the extraction of its subblocks.
    AnalysisOnly,
    /// Every step, but each vertex placed at its edge's start with a fixed normal instead of
    /// the exact interpolation and the gradients at both ends.
    NoVertexArithmetic,
    /// `direct`'s extraction: each block's samples loaded, nothing classified.
    SamplesOnly,
}

impl Ablation {
    /// The ablations worth timing for the meshlet extraction and for PMB.
    pub const MESHLETS: [Ablation; 3] = [
        Ablation::FilteringOnly,
        Ablation::AnalysisOnly,
        Ablation::NoVertexArithmetic,
    ];
    pub const PMB: [Ablation; 2] = [Ablation::FilteringOnly, Ablation::NoVertexArithmetic];
    /// The ablations worth timing for `direct`'s extraction of a block list: the whole, then
    /// less and less of it. Its analysis is the cells' cases and triangle counts, their sum
    /// and the slots reserved, with no triangle written.
    pub const DIRECT: [Ablation; 4] = [
        Ablation::None,
        Ablation::NoVertexArithmetic,
        Ablation::AnalysisOnly,
        Ablation::SamplesOnly,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Ablation::None => "whole",
            Ablation::FilteringOnly => "filtering only",
            Ablation::AnalysisOnly => "analysis only",
            Ablation::NoVertexArithmetic => "no vertex arithmetic",
            Ablation::SamplesOnly => "samples only",
        }
    }

    /// The `EXTRACTION_ABLATION` define the extraction shaders read (`common/ablation.glsl`).
    pub(crate) fn define(self) -> (String, String) {
        let code = match self {
            Ablation::None | Ablation::FilteringOnly => 0,
            Ablation::AnalysisOnly => 1,
            Ablation::NoVertexArithmetic => 2,
            Ablation::SamplesOnly => 3,
        };
        ("EXTRACTION_ABLATION".into(), code.to_string())
    }
}
