//! Option texts that describe data, as plain parsers a front end can hand to its argument
//! parser (clap's `value_parser` takes any `fn(&str) -> Result<T, String>`). Negative numbers
//! parse; letting them past the argument parser (clap's `allow_hyphen_values`) is the front
//! end's part.

use std::str::FromStr;

use super::appearance::IntegrandChoice;
use crate::param::user::parse_end;
use crate::param::{RadiusNormalization, ShBasis};
use crate::raw::Endian;

/// Largest image side [`parse_size`] accepts.
pub const MAX_IMAGE_SIDE: u32 = 16384;

/// Three values separated by `,` or `x`: `256,256,128`, `256x256x128`.
pub fn parse_triple<T: FromStr>(text: &str) -> Result<[T; 3], String> {
    let parts: Vec<&str> = text.split([',', 'x']).map(str::trim).collect();
    if parts.len() != 3 {
        return Err(format!("'{text}': expected three values like 256,256,128"));
    }
    let mut out = Vec::with_capacity(3);
    for p in parts {
        out.push(
            p.parse::<T>()
                .map_err(|_| format!("'{p}' is not a valid number"))?,
        );
    }
    out.try_into().map_err(|_| "three values".to_string())
}

/// Sample counts X,Y,Z of a raw file.
pub fn parse_dims(text: &str) -> Result<[u32; 3], String> {
    parse_triple(text)
}

/// Physical spacing X,Y,Z between samples, each positive.
pub fn parse_spacing(text: &str) -> Result<[f32; 3], String> {
    let s: [f32; 3] = parse_triple(text)?;
    if s.iter().any(|v| !v.is_finite() || *v <= 0.0) {
        return Err(format!("spacing '{text}' must be positive"));
    }
    Ok(s)
}

/// An image size `WxH`, each side 1 to [`MAX_IMAGE_SIDE`].
pub fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size '{text}': expected WxH, e.g. 1280x720"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("size '{text}': bad width"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("size '{text}': bad height"))?;
    if w == 0 || h == 0 || w > MAX_IMAGE_SIDE || h > MAX_IMAGE_SIDE {
        return Err(format!(
            "size '{text}': each side must be 1..={MAX_IMAGE_SIDE}"
        ));
    }
    Ok((w, h))
}

/// A scalar range `LO,HI` of finite numbers with `HI > LO`.
pub fn parse_range(text: &str) -> Result<(f32, f32), String> {
    let (lo, hi) = text
        .split_once(',')
        .ok_or_else(|| format!("'{text}': expected LO,HI"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<f32>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| format!("'{s}' is not a finite number"))
    };
    let (lo, hi) = (parse(lo)?, parse(hi)?);
    if hi <= lo {
        return Err(format!("'{text}': HI must exceed LO"));
    }
    Ok((lo, hi))
}

/// A colour `R,G,B` of non-negative numbers (absorption per unit length may exceed 1).
pub fn parse_colour(text: &str) -> Result<[f32; 3], String> {
    let values: Vec<f32> = text
        .split(',')
        .map(|v| v.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{text}': expected R,G,B"))?;
    match values[..] {
        [r, g, b] if values.iter().all(|v| v.is_finite() && *v >= 0.0) => Ok([r, g, b]),
        _ => Err(format!(
            "'{text}': expected three non-negative numbers R,G,B"
        )),
    }
}

/// A parameter range `FROM,TO` of a user function; the ends may be multiples of pi or tau
/// (`0,2pi`), as in the file's range lines. Whether FROM < TO is the domain's to check.
pub fn parse_param_range(text: &str) -> Result<[f32; 2], String> {
    let (a, b) = text
        .split_once(',')
        .ok_or_else(|| format!("'{text}': expected FROM,TO"))?;
    let end = |t: &str| parse_end(t).ok_or_else(|| format!("'{t}' is not a number"));
    Ok([end(a)?, end(b)?])
}

/// An SH basis by DIPY's name: `descoteaux07`, `tournier07`, each also `-legacy`.
pub fn parse_basis(text: &str) -> Result<ShBasis, String> {
    match text {
        "descoteaux07" => Ok(ShBasis::Descoteaux07 { legacy: false }),
        "descoteaux07-legacy" => Ok(ShBasis::Descoteaux07 { legacy: true }),
        "tournier07" => Ok(ShBasis::Tournier07 { legacy: false }),
        "tournier07-legacy" => Ok(ShBasis::Tournier07 { legacy: true }),
        _ => Err(format!(
            "SH basis '{text}': choose descoteaux07, descoteaux07-legacy, tournier07 or \
             tournier07-legacy"
        )),
    }
}

/// A glyph radius mapping by name: `minmax`, `abs` or `clamp`.
pub fn parse_glyph_radius(text: &str) -> Result<RadiusNormalization, String> {
    match text {
        "minmax" => Ok(RadiusNormalization::MinMax),
        "abs" => Ok(RadiusNormalization::MaxAbs),
        "clamp" => Ok(RadiusNormalization::PositiveLobes),
        _ => Err(format!(
            "glyph radius '{text}': choose minmax, abs or clamp"
        )),
    }
}

/// Byte order of raw files: `little` or `big`.
pub fn parse_endian(text: &str) -> Result<Endian, String> {
    match text {
        "little" => Ok(Endian::Little),
        "big" => Ok(Endian::Big),
        _ => Err(format!("byte order '{text}': choose little or big")),
    }
}

/// What rays accumulate through a tet mesh ([`IntegrandChoice::parse`]).
pub fn parse_integrand(text: &str) -> Result<IntegrandChoice, String> {
    IntegrandChoice::parse(text).map_err(|e| e.to_string())
}

#[cfg(test)]
#[path = "parse_tests.rs"]
mod tests;
