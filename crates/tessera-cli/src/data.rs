//! The DATA argument and the options that say how to read it: loaded through
//! `tessera_data::scene` with a progress spinner, volumes checked against the device before
//! their bytes are read.

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use std::time::Duration;
use tessera_data::mc_ambiguity::AmbiguityRule;
use tessera_data::raw::{Endian, RawOptions};
use tessera_data::scene::parse::{parse_dims, parse_spacing};
use tessera_data::scene::{expected_volume_bytes, load_volume_spec, Dataset, LoadOptions};
use tessera_data::{IsoValue, NanPolicy, Volume};
use tessera_gpu::Gpu;

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
    /// Physical spacing X,Y,Z between samples (default: from the file's header, 1,1,1 for raw
    /// files); given for a file with a header, it replaces the header's spacing.
    #[arg(long, value_parser = parse_spacing)]
    pub spacing: Option<[f32; 3]>,
    /// Replace NaN/Inf samples with this value (by default such files are refused).
    #[arg(long)]
    pub nan_fill: Option<f32>,
}

#[derive(Args, Clone, Debug)]
pub struct IsoArgs {
    /// Isovalue in the data's own units (default: Otsu's threshold of the value histogram).
    #[arg(long, conflicts_with = "iso_fraction")]
    pub iso: Option<f32>,
    /// Isovalue as a fraction of the data's value range (0 = min, 1 = max).
    #[arg(long)]
    pub iso_fraction: Option<f32>,
    /// How marching cubes (extract, direct) cuts a face whose above-iso corners are
    /// diagonal: decider (the asymptotic decider, topologically consistent) or vtk (VTK's
    /// fixed convention: always separated, as vtkMarchingCubes does).
    #[arg(long, default_value = "decider", value_parser = parse_ambiguity)]
    pub ambiguity: AmbiguityRule,
}

fn parse_ambiguity(text: &str) -> std::result::Result<AmbiguityRule, String> {
    AmbiguityRule::parse(text).map_err(|e| e.to_string())
}

impl IsoArgs {
    /// The isovalue the flags give, if any.
    pub fn value(&self) -> Option<IsoValue> {
        match (self.iso, self.iso_fraction) {
            (Some(v), _) => Some(IsoValue::Raw(v)),
            (None, Some(f)) => Some(IsoValue::Normalized(f)),
            (None, None) => None,
        }
    }

    /// The isovalue for `volume`: the one given, else Otsu's threshold of its histogram
    /// (said on the terminal), else the middle of its range; with a warning when no surface
    /// can be found at it.
    pub fn resolve(&self, volume: &Volume) -> IsoValue {
        let iso =
            self.value()
                .unwrap_or_else(|| match tessera_data::histogram::otsu_isovalue(volume) {
                    Some(t) => {
                        eprintln!("isovalue {t} (Otsu threshold of the histogram)");
                        IsoValue::Raw(t)
                    }
                    None => IsoValue::Normalized(0.5),
                });
        if let Some(warning) = volume.isovalue_warning(volume.iso_to_texel(iso)) {
            eprintln!("warning: {warning}");
        }
        iso
    }
}

impl VolumeArgs {
    pub fn raw_options(&self) -> RawOptions {
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

/// Refuses a volume the device cannot hold before its bytes are read, where the size is known
/// from the spec.
pub fn check_fits(gpu: &Gpu, spec: &str, args: &VolumeArgs) -> Result<()> {
    if let Some(bytes) = expected_volume_bytes(spec, &args.raw_options()) {
        use anyhow::Context;
        gpu.check_fits(spec, bytes)
            .with_context(|| format!("{spec} does not fit on {}", gpu.caps().device_name))?;
    }
    Ok(())
}

/// Loads DATA of any kind, saying what was loaded.
pub fn load_dataset(spec: &str, options: &LoadOptions) -> Result<Dataset> {
    let bar = spinner(format!("loading {spec}"));
    let result = Dataset::load(spec, options);
    bar.finish_and_clear();
    let data = result?;
    match &data {
        Dataset::Volume(volume) => report_volume(volume),
        Dataset::Tets(tets) => {
            if let Some(line) = tets.repairs() {
                eprintln!("{line}");
            }
        }
        Dataset::Param(_) => {}
    }
    Ok(data)
}

/// Loads a volume: a file path, or `procedural:NAME:SIZE[:TYPE]`.
pub fn load(spec: &str, args: &VolumeArgs) -> Result<Volume> {
    let bar = spinner(format!("loading {spec}"));
    let result = load_volume_spec(spec, &args.raw_options());
    bar.finish_and_clear();
    let volume = result?;
    report_volume(&volume);
    Ok(volume)
}

fn report_volume(volume: &Volume) {
    let (lo, hi) = volume.value_range();
    let [x, y, z] = volume.dims();
    let [sx, sy, sz] = volume.spacing();
    eprintln!(
        "loaded {} {x}x{y}x{z} {} (values {lo}..{hi}, spacing {sx},{sy},{sz})",
        volume.name(),
        volume.scalar_type().name()
    );
    if let Some(declared) = volume.orientation().unusable() {
        eprintln!(
            "warning: {}: the header's {} cannot be used (an axis of no length or a value that \
             is not finite); placed by {} instead",
            volume.name(),
            declared.name(),
            volume.orientation().source().name()
        );
    }
    if let Some([ax, ay, az]) = volume.replaced_spacing() {
        eprintln!(
            "note: --spacing {sx},{sy},{sz} replaces the spacing {ax},{ay},{az} of {}",
            volume.name()
        );
    }
}
