//! VTK XML files, as the unstructured-grid (`.vtu`) and image-data (`.vti`) loaders share
//! them: the `<VTKFile>` element and its byte order, header type and compressor, and
//! `DataArray`s in every encoding (`ascii`, inline base64 `binary`, `appended` raw or
//! base64, each optionally zlib-compressed).

mod decode;
mod scan;

use std::path::Path;

pub(crate) use decode::DataType;
use decode::{read_stream, Layout, Stream};
use scan::{line_of, parse, Document, Element};

use crate::error::{DataError, Result};

/// A parsed VTK XML file.
pub(crate) struct VtkXml<'a> {
    data: &'a [u8],
    doc: Document,
    layout: Layout,
    path: &'a Path,
}

/// How many values an array must hold, and why, for messages.
#[derive(Clone, Copy)]
pub(crate) struct Need<'s> {
    pub tuples: usize,
    pub components: usize,
    /// Where the tuple count comes from, e.g. `NumberOfPoints="8"`.
    pub source: &'s str,
}

/// How a `DataArray` is stored: numbers as text, or a binary stream.
enum Encoded<'a> {
    Text(&'a [u8]),
    Binary(Stream<'a>),
}

/// The contents of a `DataArray`: numbers from text, or bytes of its type in the file's
/// byte order.
pub(crate) enum Contents {
    Text(Vec<f64>),
    Binary(Vec<u8>),
}

impl<'a> VtkXml<'a> {
    /// Parses `data` and checks that it is a `<VTKFile type="{kind}">`; `taken_for` (such as
    /// "a tetrahedral mesh") says in messages what the file was read as.
    pub fn open(data: &'a [u8], path: &'a Path, kind: &str, taken_for: &str) -> Result<Self> {
        let doc = parse(data).map_err(|(pos, msg)| at_line(path, data, pos, msg))?;
        let root = doc
            .elements
            .first()
            .filter(|e| e.name == "VTKFile")
            .ok_or_else(|| {
                DataError::format(
                    path,
                    format!(
                        "not a VTK XML file (no <VTKFile> element); it was read as {taken_for}"
                    ),
                )
            })?;
        let fail = |msg: String| at_line(path, data, root.pos, msg);
        let found = root.attr("type").unwrap_or("");
        if found != kind {
            return Err(fail(format!(
                "VTKFile type {found:?}: the file was read as {taken_for}, which needs type {kind:?}"
            )));
        }
        let layout = Layout {
            big_endian: match root.attr("byte_order").unwrap_or("LittleEndian") {
                "LittleEndian" => false,
                "BigEndian" => true,
                other => return Err(fail(format!("unknown byte_order {other:?}"))),
            },
            header_size: match root.attr("header_type").unwrap_or("UInt32") {
                "UInt32" => 4,
                "UInt64" => 8,
                other => return Err(fail(format!("unsupported header_type {other:?}"))),
            },
            compressed: match root.attr("compressor") {
                None | Some("") => false,
                Some("vtkZLibDataCompressor") => true,
                Some(other) => {
                    return Err(fail(format!(
                        "compressor {other:?} is not supported (only vtkZLibDataCompressor)"
                    )))
                }
            },
        };
        Ok(VtkXml {
            data,
            doc,
            layout,
            path,
        })
    }

    pub fn element(&self, index: usize) -> &Element {
        &self.doc.elements[index]
    }

    /// The root `<VTKFile>` element (index 0).
    pub fn root(&self) -> usize {
        0
    }

    pub fn big_endian(&self) -> bool {
        self.layout.big_endian
    }

    /// An error at the line of element `index`.
    pub fn err(&self, index: usize, msg: impl std::fmt::Display) -> DataError {
        at_line(self.path, self.data, self.element(index).pos, msg)
    }

    /// Children of `parent` named `name`, in document order.
    pub fn children<'s>(
        &'s self,
        parent: usize,
        name: &'s str,
    ) -> impl Iterator<Item = usize> + 's {
        self.element(parent)
            .children
            .iter()
            .copied()
            .filter(move |&c| self.element(c).name == name)
    }

    /// The first child of `parent` named `name`.
    pub fn child(&self, parent: usize, name: &str) -> Option<usize> {
        self.children(parent, name).next()
    }

    /// The `DataArray`s of the `section` child (`PointData`, `Points`, …) of `parent`.
    pub fn arrays(&self, parent: usize, section: &str) -> Vec<usize> {
        self.children(parent, section)
            .flat_map(|s| self.children(s, "DataArray"))
            .collect()
    }

    /// An error about `DataArray` `index`, naming it.
    pub fn array_err(&self, index: usize, msg: impl std::fmt::Display) -> DataError {
        let e = self.element(index);
        let what = match (e.attr("Name"), e.parent) {
            (Some(name), _) => format!("DataArray {name:?}"),
            (None, Some(p)) => format!("the DataArray in <{}>", self.element(p).name),
            (None, None) => "DataArray".to_string(),
        };
        self.err(index, format!("{what}: {msg}"))
    }

    /// `NumberOfComponents` of a `DataArray` (1 when absent).
    pub fn components(&self, index: usize) -> Result<usize> {
        let text = self
            .element(index)
            .attr("NumberOfComponents")
            .unwrap_or("1");
        text.trim()
            .parse()
            .map_err(|_| self.array_err(index, format!("bad NumberOfComponents {text:?}")))
    }

    pub fn data_type(&self, index: usize) -> Result<DataType> {
        let name = self.element(index).attr("type").unwrap_or("");
        DataType::from_name(name)
            .ok_or_else(|| self.array_err(index, format!("unsupported type {name:?}")))
    }

    /// The values of `DataArray` `index` as numbers, checked to be what `need` says.
    pub fn values(&self, index: usize, need: Need) -> Result<Vec<f64>> {
        let ty = self.data_type(index)?;
        Ok(match self.contents(index, need)? {
            Contents::Text(values) => values,
            Contents::Binary(bytes) => ty.values(&bytes, self.layout.big_endian),
        })
    }

    /// The contents of `DataArray` `index`, checked to hold `need.tuples` tuples of
    /// `need.components` components before anything is allocated for them.
    pub fn contents(&self, index: usize, need: Need) -> Result<Contents> {
        let ty = self.data_type(index)?;
        let comps = self.components(index)?;
        if comps != need.components {
            return Err(self.array_err(
                index,
                format!("has {comps} components, expected {}", need.components),
            ));
        }
        let wrong_count = |found: String| {
            let wanted = match need.tuples.checked_mul(need.components) {
                Some(n) if need.components == 1 => n.to_string(),
                Some(n) => format!("{n} ({} x {} components)", need.tuples, need.components),
                None => format!("{} x {} (too many)", need.tuples, need.components),
            };
            self.array_err(
                index,
                format!("holds {found}, but {} calls for {wanted}", need.source),
            )
        };
        let count = need
            .tuples
            .checked_mul(need.components)
            .ok_or_else(|| wrong_count("some values".into()))?;
        let stream = match self.encoded(index)? {
            Encoded::Text(text) => {
                let tokens = || {
                    text.split(u8::is_ascii_whitespace)
                        .filter(|t| !t.is_empty())
                };
                // Counted before anything is parsed or allocated.
                let found = tokens().count();
                if found != count {
                    return Err(wrong_count(format!("{found} values")));
                }
                return tokens()
                    .map(|t| {
                        std::str::from_utf8(t)
                            .ok()
                            .and_then(|t| t.parse::<f64>().ok())
                            .ok_or_else(|| {
                                self.array_err(
                                    index,
                                    format!("bad number {:?}", String::from_utf8_lossy(t)),
                                )
                            })
                    })
                    .collect::<Result<Vec<_>>>()
                    .map(Contents::Text);
            }
            Encoded::Binary(stream) => stream,
        };
        let bytes = count
            .checked_mul(ty.size())
            .ok_or_else(|| wrong_count("some values".into()))?;
        read_stream(stream, self.layout, bytes)
            .map(Contents::Binary)
            .map_err(|msg| {
                self.array_err(
                    index,
                    format!(
                        "{msg} ({} x {} {ty:?} values for {})",
                        need.tuples, need.components, need.source
                    ),
                )
            })
    }

    /// Where the contents of `DataArray` `index` lie, as its `format` says.
    fn encoded(&self, index: usize) -> Result<Encoded<'a>> {
        let e = self.element(index);
        let inline = &self.data[e.text.0..e.text.1];
        match e.attr("format").unwrap_or("ascii") {
            "ascii" => Ok(Encoded::Text(inline)),
            "binary" => Ok(Encoded::Binary(Stream::Base64(inline))),
            "appended" => {
                let (base, encoding) = self.doc.appended.as_ref().ok_or_else(|| {
                    self.array_err(index, "format appended but no <AppendedData>")
                })?;
                let offset: usize = e
                    .attr("offset")
                    .and_then(|v| v.trim().parse().ok())
                    .ok_or_else(|| {
                        self.array_err(index, "appended array without a numeric offset")
                    })?;
                let start = base
                    .checked_add(offset)
                    .and_then(|at| self.data.get(at..))
                    .ok_or_else(|| {
                        self.array_err(
                            index,
                            format!("offset {offset} is past the end of the file"),
                        )
                    })?;
                match encoding.as_str() {
                    "base64" => Ok(Encoded::Binary(Stream::Base64(start))),
                    "raw" => Ok(Encoded::Binary(Stream::Raw(start))),
                    other => {
                        Err(self
                            .array_err(index, format!("unknown AppendedData encoding {other:?}")))
                    }
                }
            }
            other => Err(self.array_err(index, format!("unknown format {other:?}"))),
        }
    }

    /// The one-component `DataArray`s of `section` under `parent` that may hold scalars:
    /// the one the section's `Scalars` attribute names first, then the others in order.
    pub fn scalar_candidates(&self, parent: usize, section: &str) -> Result<Vec<usize>> {
        let mut candidates = Vec::new();
        for s in self.children(parent, section) {
            for i in self.children(s, "DataArray") {
                if self.components(i)? == 1 {
                    candidates.push(i);
                }
            }
            let active = self.element(s).attr("Scalars");
            let name = |i: &usize| self.element(*i).attr("Name");
            if let Some(at) = candidates
                .iter()
                .position(|i| active.is_some() && name(i) == active)
            {
                let named = candidates.remove(at);
                candidates.insert(0, named);
            }
        }
        Ok(candidates)
    }
}

fn at_line(path: &Path, data: &[u8], pos: usize, msg: impl std::fmt::Display) -> DataError {
    DataError::format(path, format!("line {}: {msg}", line_of(data, pos)))
}
