//! The DATA argument: a volume file or `procedural:NAME:SIZE[:TYPE]`, loaded with a progress
//! spinner and checked against the device before the bytes are read.

use anyhow::{bail, Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::path::Path;
use std::time::Duration;
use tessera_data::raw::{parse_scivis_name, scalar_from_name, Endian, RawOptions, SourceType};
use tessera_data::scene::parse::{parse_dims, parse_spacing};
use tessera_data::{procedural, IsoValue, NanPolicy, Volume};

pub use tessera_data::scene::parse::parse_size;

#[derive(Args, Clone, Debug)]
pub struct VolumeArgs {
    /// Sample counts X,Y,Z for raw files (default: from an Open SciVis style name).
    #[arg(long, value_parser = parse_dims)]
    pub dims: Option<[u32; 3]>,
    /// Sample type for raw files: uint8, uint16, int16, float32, float64, …
    #[arg(long)]
    pub dtype: Option<String>,
    /// Byte order of raw files.
    #[arg(long, default_value = "little", value_parser = ["little", "big"])]
    pub endian: String,
    /// Bytes to skip at the start of a raw file.
    #[arg(long, default_value_t = 0)]
    pub header_bytes: u64,
    /// Physical spacing X,Y,Z between samples.
    #[arg(long, value_parser = parse_spacing, default_value = "1,1,1")]
    pub spacing: [f32; 3],
    /// Replace NaN/Inf samples with this value (by default such files are refused).
    #[arg(long)]
    pub nan_fill: Option<f32>,
}

#[derive(Args, Clone, Debug)]
pub struct IsoArgs {
    /// Isovalue in the data's own units.
    #[arg(long, conflicts_with = "iso_fraction")]
    pub iso: Option<f32>,
    /// Isovalue as a fraction of the data's value range (0 = min, 1 = max).
    #[arg(long, default_value_t = 0.5)]
    pub iso_fraction: f32,
}

impl IsoArgs {
    pub fn resolve(&self, volume: &Volume) -> Result<f32> {
        let iso = match self.iso {
            Some(v) => IsoValue::Raw(v),
            None => IsoValue::Normalized(self.iso_fraction),
        };
        let value = volume.iso_to_texel(iso);
        if !value.is_finite() {
            bail!("isovalue {value} is not a finite number");
        }
        Ok(value)
    }
}

impl VolumeArgs {
    fn raw_options(&self) -> RawOptions {
        RawOptions {
            dims: self.dims,
            dtype: self.dtype.clone(),
            endian: if self.endian == "big" {
                Endian::Big
            } else {
                Endian::Little
            },
            header_bytes: self.header_bytes,
            spacing: self.spacing,
            nan_policy: self.nan_fill.map_or(NanPolicy::Reject, NanPolicy::Replace),
        }
    }

    /// Bytes the volume will take once loaded, when that is known before reading it.
    pub fn expected_bytes(&self, spec: &str) -> Option<u64> {
        if let Some(rest) = spec.strip_prefix("procedural:") {
            let (_, size, scalar) = procedural::parse_spec(rest).ok()?;
            return Some((size as u64).pow(3) * scalar.size_bytes() as u64);
        }
        let path = Path::new(spec);
        let name = path.file_name()?.to_str()?;
        let from_name = parse_scivis_name(name);
        let dims = self.dims.or(from_name.as_ref().map(|n| n.0))?;
        let dtype = self.dtype.clone().or(from_name.map(|n| n.1))?;
        let ty = scalar_from_name(path, &dtype).ok()?;
        // 8- and 16-bit unsigned data stay as they are; other types become 32-bit floats.
        let size = match ty {
            SourceType::U8 => 1,
            SourceType::U16 => 2,
            _ => 4,
        };
        Some(dims.iter().map(|&d| d as u64).product::<u64>() * size)
    }
}

pub fn spinner(message: String) -> ProgressBar {
    let bar = ProgressBar::new_spinner();
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    bar.set_message(message);
    bar.enable_steady_tick(Duration::from_millis(120));
    bar
}

/// Loads DATA: a file path, or `procedural:NAME:SIZE[:TYPE]`.
pub fn load(spec: &str, args: &VolumeArgs) -> Result<Volume> {
    let bar = spinner(format!("loading {spec}"));
    let result = if let Some(rest) = spec.strip_prefix("procedural:") {
        procedural::parse_spec(rest)
            .and_then(|(kind, size, scalar)| procedural::generate(kind, size, scalar))
            .with_context(|| format!("procedural data '{spec}'"))
    } else {
        let path = Path::new(spec);
        tessera_data::load::load_volume(path, &args.raw_options()).map_err(anyhow::Error::from)
    };
    bar.finish_and_clear();
    let volume = result?;
    let (lo, hi) = volume.value_range();
    eprintln!(
        "loaded {} {}x{}x{} {} (values {lo}..{hi})",
        volume.name(),
        volume.dims()[0],
        volume.dims()[1],
        volume.dims()[2],
        volume.scalar_type().name()
    );
    Ok(volume)
}
