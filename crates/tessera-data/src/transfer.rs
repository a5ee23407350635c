//! Transfer functions: colour and opacity as piecewise-linear functions of a scalar normalized to
//! [0, 1], and the tables the integrating renderers read. A table holds one RGB value per
//! uniformly spaced knot, already in the units the renderer accumulates (absorption per unit
//! length, emission per unit length, or a colour), and is linear between knots; integrals over
//! it are therefore exact sums of trapezoids, which is what the CPU references compute.

use crate::error::{DataError, Result};
use glam::DVec3;
use std::io::Read;
use std::path::Path;

/// The largest transfer function file read (some 30,000 knots).
pub const MAX_FILE_BYTES: u64 = 1 << 20;

/// One control point: the normalized scalar it sits at and its colour and opacity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Knot {
    pub at: f32,
    pub rgba: [f32; 4],
}

/// Colour and opacity, linear between knots and constant beyond the first and last.
#[derive(Clone, Debug, PartialEq)]
pub struct TransferFunction {
    pub knots: Vec<Knot>,
}

/// Names of the built-in transfer functions.
pub const PRESETS: &[&str] = &["cool-warm", "grey", "hot", "bands"];

impl TransferFunction {
    /// A built-in transfer function (see [`PRESETS`]).
    pub fn preset(name: &str) -> Result<TransferFunction> {
        let k = |at: f32, rgba: [f32; 4]| Knot { at, rgba };
        let knots = match name {
            "grey" => vec![k(0.0, [1.0, 1.0, 1.0, 0.0]), k(1.0, [0.0, 0.0, 0.0, 1.0])],
            "cool-warm" => vec![
                k(0.0, [0.23, 0.30, 0.75, 0.15]),
                k(0.5, [0.87, 0.87, 0.87, 0.05]),
                k(1.0, [0.71, 0.02, 0.15, 1.0]),
            ],
            "hot" => vec![
                k(0.0, [0.0, 0.0, 0.0, 0.0]),
                k(0.4, [0.9, 0.1, 0.0, 0.3]),
                k(0.8, [1.0, 0.9, 0.1, 0.8]),
                k(1.0, [1.0, 1.0, 1.0, 1.0]),
            ],
            // Narrow opaque bands: a test of how exactly an integrator resolves sharp features.
            "bands" => vec![
                k(0.0, [0.2, 0.4, 1.0, 0.0]),
                k(0.28, [0.2, 0.4, 1.0, 0.0]),
                k(0.3, [0.2, 0.4, 1.0, 1.0]),
                k(0.32, [0.2, 0.4, 1.0, 0.0]),
                k(0.68, [1.0, 0.5, 0.1, 0.0]),
                k(0.7, [1.0, 0.5, 0.1, 1.0]),
                k(0.72, [1.0, 0.5, 0.1, 0.0]),
                k(1.0, [1.0, 0.5, 0.1, 0.0]),
            ],
            _ => {
                return Err(DataError::Invalid(format!(
                    "unknown transfer function '{name}' (built in: {}; or a file of 'at r g b a' lines)",
                    PRESETS.join(", ")
                )))
            }
        };
        Ok(TransferFunction { knots })
    }

    /// A preset by name, or a text file of `at r g b a` lines (all in [0, 1], `at` rising;
    /// `#` starts a comment).
    pub fn load(spec: &str) -> Result<TransferFunction> {
        if PRESETS.contains(&spec) {
            return TransferFunction::preset(spec);
        }
        let path = Path::new(spec);
        if !path.exists() {
            return TransferFunction::preset(spec);
        }
        let fail = |message: String| DataError::Format {
            path: path.to_owned(),
            message,
        };
        crate::input::regular_file(path)?;
        let file = std::fs::File::open(path).map_err(|e| DataError::io(path, e))?;
        // Read through a limit: the path may name a file far larger than any transfer
        // function.
        let mut bytes = Vec::new();
        file.take(MAX_FILE_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| DataError::io(path, e))?;
        if bytes.len() as u64 > MAX_FILE_BYTES {
            return Err(fail(format!(
                "larger than {MAX_FILE_BYTES} bytes: read as a transfer function file of \
                 'at r g b a' lines, which is never that long"
            )));
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            fail(format!(
                "byte {}: not text; read as a transfer function file of 'at r g b a' lines",
                e.utf8_error().valid_up_to()
            ))
        })?;
        TransferFunction::parse(&text).map_err(fail)
    }

    /// Parses `at r g b a` lines; the error names the line.
    pub fn parse(text: &str) -> std::result::Result<TransferFunction, String> {
        let mut knots: Vec<Knot> = Vec::new();
        for (number, line) in text.lines().enumerate() {
            let line = line.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let here = |what: String| format!("line {}: {what}", number + 1);
            let values: Vec<f32> = line
                .split_whitespace()
                .map(|w| w.parse::<f32>())
                .collect::<std::result::Result<_, _>>()
                .map_err(|_| here(format!("'{line}' is not five numbers")))?;
            let [at, r, g, b, a] = values[..] else {
                return Err(here(format!(
                    "expected 'at r g b a', found {} numbers",
                    values.len()
                )));
            };
            if let Some(bad) = values.iter().find(|v| !(0.0..=1.0).contains(*v)) {
                return Err(here(format!(
                    "{bad} is not a number in [0, 1] (every number must be)"
                )));
            }
            if knots.last().is_some_and(|k| k.at > at) {
                return Err(here(format!("position {at} is below the previous knot's")));
            }
            knots.push(Knot {
                at,
                rgba: [r, g, b, a],
            });
        }
        if knots.is_empty() {
            return Err("no knots".into());
        }
        Ok(TransferFunction { knots })
    }

    /// The knots as `at r g b a` lines, the text [`TransferFunction::parse`] reads back.
    pub fn to_text(&self) -> String {
        let mut text = String::from("# at r g b a (normalized scalar, colour, opacity)\n");
        for k in &self.knots {
            let [r, g, b, a] = k.rgba;
            text.push_str(&format!("{} {r} {g} {b} {a}\n", k.at));
        }
        text
    }

    /// Colour and opacity at normalized scalar `x` (NaN counts as below the first knot);
    /// transparent black without knots.
    pub fn sample(&self, x: f64) -> [f64; 4] {
        let (Some(first), Some(last)) = (self.knots.first(), self.knots.last()) else {
            return [0.0; 4];
        };
        let widen = |k: &Knot| k.rgba.map(f64::from);
        if x.is_nan() || x <= f64::from(first.at) {
            return widen(first);
        }
        if x >= f64::from(last.at) {
            return widen(last);
        }
        // The first knot at or beyond x; equal positions make steps.
        let i = self.knots.partition_point(|k| f64::from(k.at) < x);
        let (a, b) = (&self.knots[i - 1], &self.knots[i]);
        let t = (x - f64::from(a.at)) / f64::from(b.at - a.at);
        std::array::from_fn(|c| f64::from(a.rgba[c]) + t * f64::from(b.rgba[c] - a.rgba[c]))
    }
}

/// What an integrating renderer accumulates along a ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScalarMode {
    /// Optical depth: light through the medium keeps exp(-depth) (Beer–Lambert).
    Absorption,
    /// Light emitted along the ray and added up (no absorption).
    Emission,
    /// The largest scalar on the ray, shown through the transfer function's colour.
    Maximum,
}

impl ScalarMode {
    pub fn parse(text: &str) -> Result<ScalarMode> {
        match text {
            "absorption" => Ok(ScalarMode::Absorption),
            "emission" => Ok(ScalarMode::Emission),
            "mip" | "maximum" => Ok(ScalarMode::Maximum),
            _ => Err(DataError::Invalid(format!(
                "integration '{text}': choose absorption, emission or mip"
            ))),
        }
    }
}

/// A transfer function sampled at uniformly spaced knots over [0, 1], in the renderer's units.
#[derive(Clone, Debug, PartialEq)]
pub struct IntegrandTable {
    pub values: Vec<[f32; 3]>,
}

/// Knots of the tables the renderers use.
pub const TABLE_KNOTS: usize = 256;

impl IntegrandTable {
    /// The table for `mode`: per unit length, absorption `scale · α · (1 − 0.8 c)` per channel (a
    /// medium of colour c lets that colour through; white still dims) or emission `scale · α · c`;
    /// for the maximum, the colour c itself.
    pub fn new(tf: &TransferFunction, mode: ScalarMode, scale: f32, knots: usize) -> Self {
        let knots = knots.max(2);
        let values = (0..knots)
            .map(|i| {
                let [r, g, b, a] = tf.sample(i as f64 / (knots - 1) as f64);
                let s = f64::from(scale);
                let v = match mode {
                    ScalarMode::Absorption => [r, g, b].map(|c| s * a * (1.0 - 0.8 * c)),
                    ScalarMode::Emission => [r, g, b].map(|c| s * a * c),
                    ScalarMode::Maximum => [r, g, b],
                };
                v.map(|c| c as f32)
            })
            .collect();
        IntegrandTable { values }
    }

    fn knot(&self, i: usize) -> DVec3 {
        glam::Vec3::from(self.values[i]).as_dvec3()
    }

    /// The table at `x` (clamped to [0, 1]), linear between knots.
    pub fn value(&self, x: f64) -> DVec3 {
        let last = (self.values.len() - 1) as f64;
        let u = x.clamp(0.0, 1.0) * last;
        let i = (u.floor() as usize).min(self.values.len() - 2);
        let t = u - i as f64;
        self.knot(i) * (1.0 - t) + self.knot(i + 1) * t
    }

    /// The mean of the table over `[a, b]` (either order): the integral by trapezoids between
    /// the knots the interval crosses, divided by its length; the value itself when `a == b`.
    pub fn average(&self, a: f64, b: f64) -> DVec3 {
        let (lo, hi) = (a.min(b).clamp(0.0, 1.0), a.max(b).clamp(0.0, 1.0));
        if hi <= lo {
            return self.value(lo);
        }
        let last = (self.values.len() - 1) as f64;
        let mut sum = DVec3::ZERO;
        let mut x = lo;
        while x < hi {
            let next_knot = ((x * last).floor() + 1.0) / last;
            let end = next_knot.min(hi);
            sum += (self.value(x) + self.value(end)) * (0.5 * (end - x));
            x = end;
        }
        sum / (hi - lo)
    }

    /// The table as the GPU reads it: the values, then their running integral by trapezoids
    /// in units of the knot spacing (entry i = integral from knot 0 to knot i).
    pub fn gpu_words(&self) -> Vec<[f32; 4]> {
        let mut out: Vec<[f32; 4]> = self
            .values
            .iter()
            .map(|v| [v[0], v[1], v[2], 0.0])
            .collect();
        let mut running = DVec3::ZERO;
        out.push([0.0; 4]);
        for i in 1..self.values.len() {
            running += (self.knot(i - 1) + self.knot(i)) * 0.5;
            let r = running.as_vec3();
            out.push([r.x, r.y, r.z, 0.0]);
        }
        out
    }
}

#[cfg(test)]
#[path = "transfer_tests.rs"]
mod tests;
