//! What every shell pass binds besides the mesh: the transfer function's absorption and
//! emission tables, and the traversal counters (`stats.glsl`) with their read-back.

use super::{effects, GpuShellMesh, COMMON_BINDINGS};
use crate::error::{Error, Result};
use tessera_data::tet::emission_absorption::EmissionAbsorption;
use tessera_data::tet::shell::{SecondaryStats, TraversalStats};
use tessera_gpu::{vk, Binding, Buffer, Gpu};

/// The counters of `stats.glsl`, in buffer order (each a `STAT_…` define; 64-bit counts take
/// two, low word first).
pub(crate) const STATS: [&str; 13] = [
    "STAT_RAYS",
    "STAT_SEGMENTS",
    "STAT_STEPS_LOW",
    "STAT_STEPS_HIGH",
    "STAT_DEAD_ENDS",
    "STAT_STEP_LIMITS",
    "STAT_BACKWARD_STEPS",
    "STAT_UNMATCHED_EXITS",
    "STAT_SHADOW_RAYS",
    "STAT_AO_RAYS",
    "STAT_SECONDARY_STEPS_LOW",
    "STAT_SECONDARY_STEPS_HIGH",
    "STAT_SECONDARY_GUARD_HITS",
];

/// The absorption and emission tables back to back, as `integrate.glsl` reads them.
fn table_words(optics: &EmissionAbsorption) -> Result<Vec<[f32; 4]>> {
    if optics.absorption.values.len() != optics.emission.values.len()
        || optics.absorption.values.len() < 2
    {
        return Err(Error::Invalid(format!(
            "shell traversal: tables of {} and {} knots (need one count, at least 2)",
            optics.absorption.values.len(),
            optics.emission.values.len()
        )));
    }
    let mut words = optics.absorption.gpu_words();
    words.extend(optics.emission.gpu_words());
    Ok(words)
}

/// What every pass binds besides the mesh: the tables and the counters.
pub(crate) struct ShellTables {
    table: Buffer,
    pub(crate) stats: Buffer,
    pub(crate) knots: usize,
}

impl ShellTables {
    pub(crate) fn new(gpu: &Gpu, optics: &EmissionAbsorption) -> Result<ShellTables> {
        let words = table_words(optics)?;
        let table = gpu.upload_buffer(
            "shell tables",
            bytemuck::cast_slice(&words),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        let stats = gpu.upload_buffer(
            "shell stats",
            bytemuck::cast_slice(&[0u32; STATS.len()]),
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
        )?;
        Ok(ShellTables {
            table,
            stats,
            knots: optics.absorption.values.len(),
        })
    }

    /// Writes `optics`' tables (of the knot count the pipelines were built for).
    pub(crate) fn write(&self, gpu: &Gpu, optics: &EmissionAbsorption) -> Result<()> {
        if optics.absorption.values.len() != self.knots {
            return Err(Error::Invalid(format!(
                "shell traversal: tables of {} knots for pipelines built for {}",
                optics.absorption.values.len(),
                self.knots
            )));
        }
        Ok(gpu.write_buffer(&self.table, bytemuck::cast_slice(&table_words(optics)?))?)
    }

    pub(crate) fn bindings<'a>(&'a self, mesh: &'a GpuShellMesh) -> [Binding<'a>; COMMON_BINDINGS] {
        [
            Binding::Buffer(&mesh.vertices),
            Binding::Buffer(&mesh.tets),
            Binding::Buffer(&mesh.faces),
            Binding::Buffer(&mesh.bvh),
            Binding::Buffer(&self.table),
            Binding::Buffer(&self.stats),
        ]
    }

    /// The pixel rays' counts and the secondary rays'.
    pub(crate) fn read_all_stats(&self, gpu: &Gpu) -> Result<(TraversalStats, SecondaryStats)> {
        let w = gpu.read_buffer_as::<u32>(&self.stats)?;
        let word = |name: &str| {
            let i = STATS.iter().position(|s| *s == name).unwrap_or(0);
            u64::from(w.get(i).copied().unwrap_or(0))
        };
        let traversal = TraversalStats {
            rays: word("STAT_RAYS"),
            segments: word("STAT_SEGMENTS"),
            steps: word("STAT_STEPS_LOW") | word("STAT_STEPS_HIGH") << 32,
            dead_ends: word("STAT_DEAD_ENDS"),
            step_limits: word("STAT_STEP_LIMITS"),
            backward_steps: word("STAT_BACKWARD_STEPS"),
            unmatched_exits: word("STAT_UNMATCHED_EXITS"),
        };
        Ok((traversal, effects::secondary_stats(word)))
    }

    pub(crate) fn read_stats(&self, gpu: &Gpu) -> Result<TraversalStats> {
        Ok(self.read_all_stats(gpu)?.0)
    }
}
