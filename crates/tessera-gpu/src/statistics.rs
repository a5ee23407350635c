//! What the driver says of a compiled pipeline (`VK_KHR_pipeline_executable_properties`):
//! registers, shared memory, instruction counts and the like, per executable. Captured only
//! when [`crate::GpuOptions::pipeline_statistics`] asks for it, since drivers may compile
//! differently or more slowly while capturing; for performance work, never for results.

use crate::context::Gpu;
use ash::vk;

/// The statistics of one executable (a stage, or a part of one) of one pipeline.
#[derive(Debug, Clone, PartialEq)]
pub struct PipelineStatistics {
    /// The pipeline's name as it was created.
    pub pipeline: String,
    /// The driver's name for the executable (e.g. "compute shader").
    pub executable: String,
    /// Name and value of each statistic, in the driver's order and words.
    pub values: Vec<(String, String)>,
}

fn text(chars: &[std::ffi::c_char]) -> String {
    let bytes: Vec<u8> = chars
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

fn value_text(statistic: &vk::PipelineExecutableStatisticKHR) -> String {
    // SAFETY: the union member read is the one `format` names, as the specification defines.
    unsafe {
        match statistic.format {
            vk::PipelineExecutableStatisticFormatKHR::BOOL32 => {
                (statistic.value.b32 != 0).to_string()
            }
            vk::PipelineExecutableStatisticFormatKHR::INT64 => statistic.value.i64.to_string(),
            vk::PipelineExecutableStatisticFormatKHR::UINT64 => statistic.value.u64.to_string(),
            vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => statistic.value.f64.to_string(),
            _ => "?".into(),
        }
    }
}

impl Gpu {
    /// Whether pipelines are created with their statistics captured.
    pub fn captures_pipeline_statistics(&self) -> bool {
        self.pipeline_executables.is_some()
    }

    /// Whether the options asked for the statistics (captured or not: the device may lack the
    /// extension).
    pub fn statistics_requested(&self) -> bool {
        self.shared.statistics_requested
    }

    /// Reads and keeps the statistics of `pipeline` (just created as `name` with capture on);
    /// nothing when capture is off. A driver that fails the query leaves a note in the list
    /// rather than failing the pipeline.
    pub(crate) fn capture_statistics(&self, name: &str, pipeline: vk::Pipeline) {
        let Some(loader) = &self.pipeline_executables else {
            return;
        };
        let info = vk::PipelineInfoKHR::default().pipeline(pipeline);
        // SAFETY: `pipeline` is a live pipeline of this device created with
        // CAPTURE_STATISTICS, and the feature was enabled with the extension.
        let executables = match unsafe { loader.get_pipeline_executable_properties(&info) } {
            Ok(e) => e,
            Err(e) => {
                self.keep_statistics(
                    name,
                    "(query failed)",
                    vec![("error".into(), e.to_string())],
                );
                return;
            }
        };
        for (index, executable) in executables.iter().enumerate() {
            let exe = vk::PipelineExecutableInfoKHR::default()
                .pipeline(pipeline)
                .executable_index(index as u32);
            // SAFETY: as above; `index` is below the count the driver reported.
            let values = match unsafe { loader.get_pipeline_executable_statistics(&exe) } {
                Ok(stats) => stats
                    .iter()
                    .map(|s| (text(&s.name), value_text(s)))
                    .collect(),
                Err(e) => vec![("error".into(), e.to_string())],
            };
            self.keep_statistics(name, &text(&executable.name), values);
        }
    }

    fn keep_statistics(&self, pipeline: &str, executable: &str, values: Vec<(String, String)>) {
        if let Ok(mut kept) = self.shared.pipeline_statistics.lock() {
            kept.push(PipelineStatistics {
                pipeline: pipeline.into(),
                executable: executable.into(),
                values,
            });
        }
    }

    /// The statistics as lines to print: one per executable, or, when they were asked for on
    /// a device that does not report them, a line saying so; none when not asked for.
    pub fn pipeline_statistics_report(&self) -> Vec<String> {
        if !self.captures_pipeline_statistics() {
            return match self.statistics_requested() {
                true => vec![format!(
                    "pipeline statistics: {} does not report them \
                     (no VK_KHR_pipeline_executable_properties)",
                    self.caps().device_name
                )],
                false => Vec::new(),
            };
        }
        self.pipeline_statistics()
            .iter()
            .map(|s| {
                let values: Vec<String> =
                    s.values.iter().map(|(k, v)| format!("{k}={v}")).collect();
                format!(
                    "pipeline {} / {}: {}",
                    s.pipeline,
                    s.executable,
                    values.join(", ")
                )
            })
            .collect()
    }

    /// The statistics captured so far, in creation order (empty when capture is off).
    pub fn pipeline_statistics(&self) -> Vec<PipelineStatistics> {
        self.shared
            .pipeline_statistics
            .lock()
            .map(|kept| kept.clone())
            .unwrap_or_default()
    }
}
