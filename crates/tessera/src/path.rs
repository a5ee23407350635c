//! Which pipeline a technique runs on: the paper's graphics path (task/mesh/fragment stages) or
//! the compute path (compute extraction + the shared compute rasterizer). `auto` decides from
//! the device's capabilities and, where `tessera bench pipeline-throughput` has run on this
//! device, from its measured graphics/compute ratio.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use tessera_gpu::Capabilities;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Path {
    Graphics,
    Compute,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathChoice {
    Graphics,
    Compute,
    Auto,
}

impl PathChoice {
    pub fn parse(text: &str) -> Result<PathChoice> {
        match text {
            "graphics" => Ok(PathChoice::Graphics),
            "compute" => Ok(PathChoice::Compute),
            "auto" => Ok(PathChoice::Auto),
            _ => Err(Error::Invalid(format!(
                "path '{text}': choose graphics, compute or auto"
            ))),
        }
    }
}

impl Path {
    /// "graphics" or "compute" (a path measured or forced, so not "auto").
    pub fn parse(text: &str) -> Result<Path> {
        match text {
            "graphics" => Ok(Path::Graphics),
            "compute" => Ok(Path::Compute),
            _ => Err(Error::Invalid(format!(
                "path '{text}': choose graphics or compute"
            ))),
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Path::Graphics => "graphics",
            Path::Compute => "compute",
        }
    }
}

/// Graphics-over-compute time ratios measured on one device and driver.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ThroughputRecord {
    pub device: String,
    pub driver: String,
    /// Mesh-shader triangles versus the compute splat of the same pixels.
    pub mesh_over_compute: f64,
    /// Fragment-shader versus compute-shader time for the same per-pixel work.
    pub fragment_over_compute: f64,
}

fn cache_file() -> Option<PathBuf> {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))?;
    Some(base.join("tessera").join("throughput.json"))
}

/// Remembers a measurement for later `auto` choices; failing to write only loses the hint.
pub fn remember(record: &ThroughputRecord) {
    if let (Some(file), Ok(text)) = (cache_file(), serde_json::to_string_pretty(record)) {
        if let Some(dir) = file.parent() {
            let _ = std::fs::create_dir_all(dir);
        }
        let _ = std::fs::write(file, text);
    }
}

/// The remembered measurement, if it was taken on this device and driver.
pub fn remembered(caps: &Capabilities) -> Option<ThroughputRecord> {
    let text = std::fs::read_to_string(cache_file()?).ok()?;
    let record: ThroughputRecord = serde_json::from_str(&text).ok()?;
    let driver = format!("{} {}", caps.driver_name, caps.driver_info);
    (record.device == caps.device_name && record.driver == driver).then_some(record)
}

/// Resolves `choice` for a technique with both paths. The compute path needs 64-bit buffer
/// atomics; the graphics path task and mesh shaders. `auto` takes the measured faster one, and
/// without a measurement the compute path, since graphics stages are the scarce resource on the
/// data-centre GPUs this targets (DESIGN §3) and never faster on CPU drivers.
pub fn choose(
    caps: &Capabilities,
    choice: PathChoice,
    measured: Option<&ThroughputRecord>,
) -> Result<Path> {
    let support = Support {
        graphics: caps.mesh_shader && caps.task_shader,
        graphics_needs: "task/mesh shaders",
        compute: caps.buffer_int64_atomics,
        compute_needs: "64-bit buffer atomics",
    };
    choose_for(caps, &support, choice, measured)
}

/// Which paths a technique can run on a device, and what each needs (for messages).
pub struct Support {
    pub graphics: bool,
    pub graphics_needs: &'static str,
    pub compute: bool,
    pub compute_needs: &'static str,
}

/// [`choose`] for a technique whose paths need other features.
pub fn choose_for(
    caps: &Capabilities,
    support: &Support,
    choice: PathChoice,
    measured: Option<&ThroughputRecord>,
) -> Result<Path> {
    let unsupported = |what: &str| {
        Error::Invalid(format!(
            "the {what} path needs features {} lacks",
            caps.device_name
        ))
    };
    let graphics_what = format!("graphics ({})", support.graphics_needs);
    let compute_what = format!("compute ({})", support.compute_needs);
    match choice {
        PathChoice::Graphics if support.graphics => Ok(Path::Graphics),
        PathChoice::Graphics => Err(unsupported(&graphics_what)),
        PathChoice::Compute if support.compute => Ok(Path::Compute),
        PathChoice::Compute => Err(unsupported(&compute_what)),
        PathChoice::Auto => match (support.graphics, support.compute) {
            (true, true) => Ok(match measured {
                Some(m) if m.mesh_over_compute < 1.0 => Path::Graphics,
                _ => Path::Compute,
            }),
            (true, false) => Ok(Path::Graphics),
            (false, true) => Ok(Path::Compute),
            (false, false) => Err(unsupported("graphics or compute")),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn caps(mesh: bool, atomics: bool) -> Capabilities {
        Capabilities {
            device_name: "test".into(),
            mesh_shader: mesh,
            task_shader: mesh,
            buffer_int64_atomics: atomics,
            ..Capabilities::default()
        }
    }

    fn measured(ratio: f64) -> ThroughputRecord {
        ThroughputRecord {
            device: "test".into(),
            driver: " ".into(),
            mesh_over_compute: ratio,
            fragment_over_compute: ratio,
        }
    }

    #[test]
    fn auto_follows_measurement_and_capabilities() {
        let both = caps(true, true);
        assert_eq!(
            choose(&both, PathChoice::Auto, None).unwrap(),
            Path::Compute
        );
        assert_eq!(
            choose(&both, PathChoice::Auto, Some(&measured(0.5))).unwrap(),
            Path::Graphics
        );
        assert_eq!(
            choose(&both, PathChoice::Auto, Some(&measured(30.0))).unwrap(),
            Path::Compute
        );
        assert_eq!(
            choose(&caps(true, false), PathChoice::Auto, None).unwrap(),
            Path::Graphics
        );
        assert_eq!(
            choose(&caps(false, true), PathChoice::Auto, None).unwrap(),
            Path::Compute
        );
        assert!(choose(&caps(false, false), PathChoice::Auto, None).is_err());
        assert!(choose(&caps(false, true), PathChoice::Graphics, None).is_err());
        assert!(choose(&caps(true, false), PathChoice::Compute, None).is_err());
        assert!(PathChoice::parse("gpu").is_err());
        assert_eq!(Path::parse("compute").unwrap(), Path::Compute);
        assert_eq!(Path::parse("graphics").unwrap(), Path::Graphics);
        assert!(Path::parse("auto").is_err());
    }
}
