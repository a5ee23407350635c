//! The NRRD header: the magic line, then `field: value` lines up to a blank line. Fields
//! this loader does not use (and `key:=value` pairs) are skipped.

use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};

use crate::error::{DataError, Result};
use crate::orientation::{AnatomicalSpace, Orientation, OrientationSource};
use crate::raw::{Endian, SourceType};

const MAX_HEADER_LINE: u64 = 64 * 1024;

#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Encoding {
    Raw,
    Gzip,
}

/// What the header says, after validation.
pub(super) struct Header {
    pub source: SourceType,
    pub dims: [u32; 3],
    pub encoding: Encoding,
    pub endian: Endian,
    pub spacing: [f32; 3],
    pub orientation: Orientation,
    pub data_file: Option<PathBuf>,
    pub byte_skip: i64,
    pub line_skip: u64,
}

/// Reads the magic and the header fields, leaving `reader` at the first data byte.
pub(super) fn parse_header(reader: &mut impl BufRead, path: &Path) -> Result<Header> {
    let err = |line: usize, msg: String| DataError::format(path, format!("line {line}: {msg}"));
    let mut buf = Vec::new();
    let mut next_line = || -> Result<Option<String>> {
        buf.clear();
        let n = reader
            .by_ref()
            .take(MAX_HEADER_LINE)
            .read_until(b'\n', &mut buf)
            .map_err(|e| DataError::io(path, e))?;
        if n == 0 {
            return Ok(None);
        }
        if n as u64 == MAX_HEADER_LINE && buf.last() != Some(&b'\n') {
            let msg = "header line longer than 64 KiB: not a NRRD header, or a corrupt one";
            return Err(DataError::format(path, msg));
        }
        let text = String::from_utf8_lossy(&buf);
        Ok(Some(text.trim_end_matches(['\n', '\r']).to_string()))
    };

    let magic = next_line()?.unwrap_or_default();
    let valid_magic = magic.len() == 8
        && magic.starts_with("NRRD000")
        && matches!(magic.as_bytes()[7], b'1'..=b'5');
    if !valid_magic {
        let shown: String = magic.chars().take(16).collect();
        return Err(err(
            1,
            format!("not a NRRD file: expected magic NRRD0001..NRRD0005, found {shown:?}"),
        ));
    }

    let mut fields = Fields::default();
    let mut line_no = 1;
    while let Some(line) = next_line()? {
        line_no += 1;
        if line.trim().is_empty() {
            break;
        }
        if line.starts_with('#') {
            continue;
        }
        let field_at = line.find(": ");
        let kv_at = line.find(":=");
        if kv_at.is_some_and(|k| field_at.is_none_or(|f| k < f)) {
            continue;
        }
        let Some(at) = field_at else {
            return Err(err(
                line_no,
                format!("expected 'field: value', found {line:?}"),
            ));
        };
        let name = line[..at].trim().to_ascii_lowercase();
        let value = line[at + 2..].trim().to_string();
        fields.set(&name, value, line_no, path)?;
    }
    fields.finish(path)
}

/// Header fields as given, with the line they came from.
#[derive(Default)]
struct Fields {
    source: Option<SourceType>,
    dimension: Option<(usize, usize)>,
    sizes: Option<(Vec<u64>, usize)>,
    encoding: Option<Encoding>,
    endian: Option<Endian>,
    spacings: Option<(Vec<Option<f64>>, usize)>,
    /// Per axis a world vector, or `None` for a non-spatial axis (`none`).
    directions: Option<(Vec<Option<Vec<f64>>>, usize)>,
    origin: Option<(Vec<f64>, usize)>,
    space: Option<AnatomicalSpace>,
    data_file: Option<PathBuf>,
    byte_skip: i64,
    line_skip: u64,
}

impl Fields {
    fn set(&mut self, name: &str, value: String, line: usize, path: &Path) -> Result<()> {
        let fail = |msg: String| DataError::format(path, format!("line {line}: {msg}"));
        let parse_int = |what: &str| -> Result<i64> {
            value
                .parse()
                .map_err(|_| fail(format!("bad {what} {value:?}")))
        };
        match name {
            "type" => match nrrd_type(&value) {
                Some(t) => self.source = Some(t),
                None => {
                    return Err(DataError::UnknownType {
                        path: path.to_path_buf(),
                        name: value,
                    })
                }
            },
            "dimension" => {
                let d = parse_int("dimension")?;
                self.dimension = Some((d.max(0) as usize, line));
            }
            "sizes" => {
                let sizes = value
                    .split_whitespace()
                    .map(|s| {
                        s.parse::<u64>()
                            .map_err(|_| fail(format!("bad size {s:?}")))
                    })
                    .collect::<Result<Vec<_>>>()?;
                self.sizes = Some((sizes, line));
            }
            "encoding" => {
                self.encoding = Some(match value.to_ascii_lowercase().as_str() {
                    "raw" => Encoding::Raw,
                    "gzip" | "gz" => Encoding::Gzip,
                    other => {
                        return Err(fail(format!(
                            "encoding '{other}' is not supported (supported: raw, gzip)"
                        )))
                    }
                })
            }
            "endian" => {
                self.endian = Some(match value.to_ascii_lowercase().as_str() {
                    "little" => Endian::Little,
                    "big" => Endian::Big,
                    _ => {
                        return Err(fail(format!(
                            "bad endian {value:?} (expected little or big)"
                        )))
                    }
                })
            }
            "spacings" => {
                let list = value
                    .split_whitespace()
                    .map(|s| match s.parse::<f64>() {
                        Ok(v) if v.is_nan() => Ok(None),
                        Ok(v) => Ok(Some(v.abs())),
                        Err(_) => Err(fail(format!("bad spacing {s:?}"))),
                    })
                    .collect::<Result<Vec<_>>>()?;
                self.spacings = Some((list, line));
            }
            "space directions" => {
                let dirs = parse_vectors(&value, "space directions").map_err(fail)?;
                self.directions = Some((dirs, line));
            }
            "space origin" => {
                let origin = match parse_vectors(&value, "space origin").map_err(fail)?[..] {
                    [Some(ref v)] => v.clone(),
                    _ => {
                        return Err(fail(format!(
                            "bad space origin {value:?}: expected (x,y,z)"
                        )))
                    }
                };
                self.origin = Some((origin, line));
            }
            "space" => self.space = AnatomicalSpace::from_nrrd(&value),
            "data file" | "datafile" => {
                let words: Vec<&str> = value.split_whitespace().collect();
                if words
                    .first()
                    .is_some_and(|w| w.eq_ignore_ascii_case("list"))
                {
                    return Err(fail(
                        "data split over a LIST of files is not supported".into(),
                    ));
                }
                if words.len() >= 4 && words[0].contains('%') {
                    return Err(fail(
                        "data split over numbered files is not supported".into(),
                    ));
                }
                self.data_file = Some(PathBuf::from(value));
            }
            "byte skip" | "byteskip" => {
                self.byte_skip = parse_int("byte skip")?;
                if self.byte_skip < -1 {
                    return Err(fail(format!("bad byte skip {}", self.byte_skip)));
                }
            }
            "line skip" | "lineskip" => {
                self.line_skip = u64::try_from(parse_int("line skip")?)
                    .map_err(|_| fail(format!("bad line skip {value:?}")))?;
            }
            _ => {}
        }
        Ok(())
    }

    fn finish(self, path: &Path) -> Result<Header> {
        let missing =
            |f: &str| DataError::format(path, format!("header lacks required field '{f}'"));
        let at = |line: usize, msg: String| DataError::format(path, format!("line {line}: {msg}"));
        let source = self.source.ok_or_else(|| missing("type"))?;
        let (dimension, dim_line) = self.dimension.ok_or_else(|| missing("dimension"))?;
        let (sizes, sizes_line) = self.sizes.ok_or_else(|| missing("sizes"))?;
        let encoding = self.encoding.ok_or_else(|| missing("encoding"))?;
        // A leading axis of size 1 (e.g. a one-component "vector" axis) carries no data.
        let lead = match (dimension, sizes.first()) {
            (3, _) => 0,
            (4, Some(1)) => 1,
            _ => {
                return Err(at(
                    dim_line,
                    format!(
                        "dimension {dimension} is not supported: need a 3-D scalar volume \
                     (dimension 3, or 4 with a first axis of size 1)"
                    ),
                ))
            }
        };
        if sizes.len() != dimension {
            return Err(at(
                sizes_line,
                format!("{} sizes given for dimension {dimension}", sizes.len()),
            ));
        }
        let mut dims = [0u32; 3];
        for (d, &s) in dims.iter_mut().zip(&sizes[lead..]) {
            *d = u32::try_from(s).map_err(|_| at(sizes_line, format!("size {s} is too large")))?;
        }
        if dims.iter().any(|&d| d < 2) {
            return Err(DataError::InvalidDims {
                what: path.display().to_string(),
                dims: dims.map(u64::from),
            });
        }
        let mut orientation = Orientation::default();
        let spacing = if let Some((dirs, line)) = self.directions {
            let axes: Vec<Vec<f64>> = dirs.into_iter().flatten().collect();
            if axes.len() != 3 {
                return Err(at(
                    line,
                    format!(
                        "space directions give {} spatial axes, expected 3",
                        axes.len()
                    ),
                ));
            }
            let length = |v: &[f64]| v.iter().map(|c| c * c).sum::<f64>().sqrt() as f32;
            let spacing = [0, 1, 2].map(|i| length(&axes[i]));
            if let Some(placed) = place(&axes, self.origin.as_ref(), self.space, path)? {
                orientation = placed;
            }
            spacing
        } else if let Some((list, line)) = self.spacings {
            if list.len() != dimension {
                return Err(at(
                    line,
                    format!("{} spacings given for dimension {dimension}", list.len()),
                ));
            }
            let mut s = [1.0f32; 3];
            for (o, v) in s.iter_mut().zip(&list[lead..]) {
                *o = v.map_or(1.0, |v| v as f32);
            }
            s
        } else {
            [1.0; 3]
        };
        if encoding == Encoding::Gzip && self.byte_skip < 0 {
            return Err(DataError::format(
                path,
                "byte skip -1 is only allowed with raw encoding",
            ));
        }
        Ok(Header {
            source,
            dims,
            encoding,
            endian: self.endian.unwrap_or_default(),
            spacing,
            orientation,
            data_file: self.data_file,
            byte_skip: self.byte_skip,
            line_skip: self.line_skip,
        })
    }
}

/// The orientation of three spatial `axes` in a 3-D world space, with the `space origin`
/// (0 when absent); `None` when the space has another dimension or an axis has no length.
fn place(
    axes: &[Vec<f64>],
    origin: Option<&(Vec<f64>, usize)>,
    space: Option<AnatomicalSpace>,
    path: &Path,
) -> Result<Option<Orientation>> {
    let [x, y, z] = axes else { return Ok(None) };
    let vector = |v: &[f64]| <[f64; 3]>::try_from(v).ok();
    let (Some(x), Some(y), Some(z)) = (vector(x), vector(y), vector(z)) else {
        return Ok(None);
    };
    let origin = match origin {
        None => [0.0; 3],
        Some((o, line)) => vector(o).ok_or_else(|| {
            let msg = format!(
                "line {line}: space origin has {} components, the space directions 3",
                o.len()
            );
            DataError::format(path, msg)
        })?,
    };
    Ok(Orientation::new(
        origin,
        [x, y, z],
        space,
        OrientationSource::Nrrd,
    ))
}

/// `(1,0,0) (0,2,0) none ...` -> the vectors, `None` for `none`; `field` names the field in
/// errors.
fn parse_vectors(value: &str, field: &str) -> std::result::Result<Vec<Option<Vec<f64>>>, String> {
    let mut out = Vec::new();
    let mut rest = value.trim_start();
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("none") {
            out.push(None);
            rest = r.trim_start();
        } else if let Some(r) = rest.strip_prefix('(') {
            let close = r.find(')').ok_or(format!("unclosed '(' in {field}"))?;
            let vector = r[..close]
                .split(',')
                .map(|c| {
                    c.trim()
                        .parse::<f64>()
                        .map_err(|_| format!("bad component {c:?} in {field}"))
                })
                .collect::<std::result::Result<Vec<_>, _>>()?;
            out.push(Some(vector));
            rest = r[close + 1..].trim_start();
        } else {
            return Err(format!("bad {field} {value:?}"));
        }
    }
    Ok(out)
}

/// Every spelling the NRRD format allows for the types we can convert.
fn nrrd_type(name: &str) -> Option<SourceType> {
    let name = name
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_lowercase();
    Some(match name.as_str() {
        "signed char" | "int8" | "int8_t" => SourceType::I8,
        "uchar" | "unsigned char" | "uint8" | "uint8_t" => SourceType::U8,
        "short" | "short int" | "signed short" | "signed short int" | "int16" | "int16_t" => {
            SourceType::I16
        }
        "ushort" | "unsigned short" | "unsigned short int" | "uint16" | "uint16_t" => {
            SourceType::U16
        }
        "int" | "signed int" | "int32" | "int32_t" => SourceType::I32,
        "uint" | "unsigned int" | "uint32" | "uint32_t" => SourceType::U32,
        "float" => SourceType::F32,
        "double" => SourceType::F64,
        _ => return None,
    })
}
