//! Just enough XML for VTK files: elements with attributes, the text inside them, comments
//! and declarations skipped, and the raw `<AppendedData>` section (which may hold any bytes,
//! so no XML parser can read it) left untouched after its `_` marker.

/// One element of the document.
pub(crate) struct Element {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    pub parent: Option<usize>,
    /// Indices of the child elements, in document order (so that lookups by parent stay
    /// linear in files with many pieces).
    pub children: Vec<usize>,
    /// Byte range of the text directly after the start tag (up to the next tag).
    pub text: (usize, usize),
    /// Byte offset of the start tag.
    pub pos: usize,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

pub(crate) struct Document {
    pub elements: Vec<Element>,
    /// Offset of the first byte after `_` in `<AppendedData>`, and its `encoding`.
    pub appended: Option<(usize, String)>,
}

/// 1-based line of byte offset `pos`.
pub(crate) fn line_of(data: &[u8], pos: usize) -> usize {
    1 + data[..pos.min(data.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
}

fn find(data: &[u8], from: usize, pattern: &[u8]) -> Option<usize> {
    data.get(from..)?
        .windows(pattern.len())
        .position(|w| w == pattern)
        .map(|p| from + p)
}

/// Parses the element structure; errors carry the byte offset they concern.
pub(crate) fn parse(data: &[u8]) -> Result<Document, (usize, String)> {
    let mut doc = Document {
        elements: Vec::new(),
        appended: None,
    };
    let mut stack: Vec<usize> = Vec::new();
    let mut pos = 0;
    while let Some(lt) = find(data, pos, b"<") {
        let rest = &data[lt..];
        let skip_to = |end: &[u8]| {
            find(data, lt, end).map(|e| e + end.len()).ok_or((
                lt,
                format!("unterminated {}", String::from_utf8_lossy(&rest[..2])),
            ))
        };
        if rest.starts_with(b"<?") {
            pos = skip_to(b"?>")?;
        } else if rest.starts_with(b"<!--") {
            pos = skip_to(b"-->")?;
        } else if rest.starts_with(b"<!") {
            pos = skip_to(b">")?;
        } else if rest.starts_with(b"</") {
            let gt = find(data, lt, b">").ok_or((lt, "unterminated end tag".to_string()))?;
            let name = String::from_utf8_lossy(&data[lt + 2..gt])
                .trim()
                .to_string();
            match stack.pop() {
                Some(open) if doc.elements[open].name == name => {}
                Some(open) => {
                    return Err((
                        lt,
                        format!("</{name}> closes <{}>", doc.elements[open].name),
                    ))
                }
                None => return Err((lt, format!("</{name}> without a start tag"))),
            }
            pos = gt + 1;
        } else {
            let (element, end, closed) = start_tag(data, lt)?;
            let index = doc.elements.len();
            let name = element.name.clone();
            let encoding = element.attr("encoding").unwrap_or("raw").to_string();
            let parent = stack.last().copied();
            if let Some(p) = parent {
                doc.elements[p].children.push(index);
            }
            doc.elements.push(Element { parent, ..element });
            pos = end;
            if name == "AppendedData" {
                let underscore = find(data, end, b"_")
                    .ok_or((lt, "AppendedData without the '_' marker".to_string()))?;
                doc.appended = Some((underscore + 1, encoding));
                return Ok(doc);
            }
            if !closed {
                stack.push(index);
                let next = find(data, end, b"<").unwrap_or(data.len());
                doc.elements[index].text = (end, next);
            }
        }
    }
    if let Some(&open) = stack.last() {
        return Err((
            doc.elements[open].pos,
            format!(
                "<{}> is never closed (truncated file?)",
                doc.elements[open].name
            ),
        ));
    }
    Ok(doc)
}

/// Parses the start tag at `lt`: the element, the offset after `>`, and whether it was `/>`.
fn start_tag(data: &[u8], lt: usize) -> Result<(Element, usize, bool), (usize, String)> {
    let mut i = lt + 1;
    let word = |i: &mut usize| {
        let start = *i;
        while data
            .get(*i)
            .is_some_and(|b| !b.is_ascii_whitespace() && !b"/>=".contains(b))
        {
            *i += 1;
        }
        String::from_utf8_lossy(&data[start..*i]).into_owned()
    };
    let name = word(&mut i);
    let mut attrs = Vec::new();
    loop {
        while data.get(i).is_some_and(u8::is_ascii_whitespace) {
            i += 1;
        }
        match data.get(i) {
            None => return Err((lt, format!("unterminated <{name}> tag"))),
            Some(b'>') => {
                return Ok((
                    Element {
                        name,
                        attrs,
                        parent: None,
                        children: Vec::new(),
                        text: (i + 1, i + 1),
                        pos: lt,
                    },
                    i + 1,
                    false,
                ))
            }
            Some(b'/') if data.get(i + 1) == Some(&b'>') => {
                return Ok((
                    Element {
                        name,
                        attrs,
                        parent: None,
                        children: Vec::new(),
                        text: (i + 2, i + 2),
                        pos: lt,
                    },
                    i + 2,
                    true,
                ))
            }
            _ => {}
        }
        let key = word(&mut i);
        if key.is_empty() || data.get(i) != Some(&b'=') {
            return Err((i, format!("malformed attribute in <{name}>")));
        }
        let quote = *data
            .get(i + 1)
            .ok_or((i, format!("unterminated <{name}> tag")))?;
        if quote != b'"' && quote != b'\'' {
            return Err((i, format!("attribute {key} of <{name}> is not quoted")));
        }
        let end =
            find(data, i + 2, &[quote]).ok_or((i, format!("unterminated attribute {key}")))?;
        let value = String::from_utf8_lossy(&data[i + 2..end])
            .replace("&lt;", "<")
            .replace("&gt;", ">")
            .replace("&quot;", "\"")
            .replace("&apos;", "'")
            .replace("&amp;", "&");
        attrs.push((key, value));
        i = end + 1;
    }
}
