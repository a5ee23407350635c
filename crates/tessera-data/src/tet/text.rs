//! A byte cursor for the text (and mixed text/binary) mesh formats that keeps track of
//! line numbers, so errors can say where the problem is.

use std::path::Path;
use std::str::FromStr;

use crate::error::{DataError, Result};

#[derive(Clone)]
pub(crate) struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    /// Line (1-based) at `pos`.
    line: usize,
    /// Line of the last token returned.
    token_line: usize,
    /// A byte that starts a comment running to the end of the line.
    comment: Option<u8>,
    path: &'a Path,
}

impl<'a> Cursor<'a> {
    pub fn new(data: &'a [u8], path: &'a Path, comment: Option<u8>) -> Self {
        Cursor {
            data,
            pos: 0,
            line: 1,
            token_line: 1,
            comment,
            path,
        }
    }

    /// Line of the last token (or line) returned.
    pub fn last_line(&self) -> usize {
        self.token_line
    }

    /// Byte offset of the next unread byte.
    pub fn offset(&self) -> usize {
        self.pos
    }

    /// Bytes not read yet: an upper bound on how many values a count in a header can
    /// honestly announce, checked before anything is allocated for them.
    pub fn remaining(&self) -> usize {
        self.data.len() - self.pos
    }

    /// A format error at the line of the last token.
    pub fn err(&self, message: impl std::fmt::Display) -> DataError {
        self.err_at(self.token_line, message)
    }

    pub fn err_at(&self, line: usize, message: impl std::fmt::Display) -> DataError {
        DataError::format(self.path, format!("line {line}: {message}"))
    }

    /// A format error at a byte offset (binary sections, where lines mean nothing).
    pub fn err_at_byte(&self, offset: usize, message: impl std::fmt::Display) -> DataError {
        DataError::format(self.path, format!("byte {offset}: {message}"))
    }

    fn skip_space(&mut self) {
        while let Some(&b) = self.data.get(self.pos) {
            if b == b'\n' {
                self.line += 1;
            } else if Some(b) == self.comment {
                while self.data.get(self.pos).is_some_and(|&c| c != b'\n') {
                    self.pos += 1;
                }
                continue;
            } else if !b.is_ascii_whitespace() {
                break;
            }
            self.pos += 1;
        }
    }

    /// The next whitespace-separated token, `None` at the end of the data.
    pub fn token(&mut self) -> Option<&'a str> {
        self.skip_space();
        if self.pos >= self.data.len() {
            self.token_line = self.line;
            return None;
        }
        let start = self.pos;
        while self
            .data
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace() && Some(*b) != self.comment)
        {
            self.pos += 1;
        }
        self.token_line = self.line;
        Some(std::str::from_utf8(&self.data[start..self.pos]).unwrap_or("<non-text bytes>"))
    }

    /// The next token without consuming it.
    pub fn peek(&self) -> Option<&'a str> {
        self.clone().token()
    }

    /// The next token, or an "unexpected end of file" error naming what was expected.
    pub fn expect(&mut self, what: &str) -> Result<&'a str> {
        self.token()
            .ok_or_else(|| self.err(format!("file ends early: expected {what}")))
    }

    /// The next token parsed as `T`.
    pub fn parse<T: FromStr>(&mut self, what: &str) -> Result<T> {
        let token = self.expect(what)?;
        token
            .parse()
            .map_err(|_| self.err(format!("expected {what}, found {token:?}")))
    }

    /// The next non-blank line (comments removed), split into fields, with its number.
    pub fn record(&mut self) -> Option<(usize, Vec<&'a str>)> {
        loop {
            let (line, text) = self.next_line()?;
            let text = match self.comment {
                Some(c) => text.split(c as char).next().unwrap_or(""),
                None => text,
            };
            let fields: Vec<&str> = text.split_whitespace().collect();
            if !fields.is_empty() {
                return Some((line, fields));
            }
        }
    }

    /// The rest of the current line (without its line break) and its number.
    pub fn next_line(&mut self) -> Option<(usize, &'a str)> {
        if self.pos >= self.data.len() {
            return None;
        }
        let start = self.pos;
        let end = self.data[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.data.len(), |n| start + n);
        let line = self.line;
        self.token_line = line;
        self.pos = (end + 1).min(self.data.len());
        if end < self.data.len() {
            self.line += 1;
        }
        let text = std::str::from_utf8(&self.data[start..end]).unwrap_or("<non-text bytes>");
        Some((line, text.trim_end_matches('\r')))
    }

    /// Moves past the end of the current line.
    pub fn skip_line_end(&mut self) {
        while let Some(&b) = self.data.get(self.pos) {
            self.pos += 1;
            if b == b'\n' {
                self.line += 1;
                return;
            }
        }
    }

    /// `n` raw bytes from the current position (binary sections).
    pub fn bytes(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        let available = self.data.len() - self.pos;
        if available < n {
            return Err(self.err(format!(
                "file ends early: {what} needs {n} bytes from byte {}, only {available} left",
                self.pos
            )));
        }
        let slice = &self.data[self.pos..self.pos + n];
        self.line += slice.iter().filter(|&&b| b == b'\n').count();
        self.pos += n;
        Ok(slice)
    }
}

/// A token for a message: quoted, or "the end of the file" when there is none.
pub(crate) fn quoted(token: Option<&str>) -> String {
    token.map_or_else(|| "the end of the file".to_string(), |t| format!("{t:?}"))
}

/// Parses one field of a line-based record.
pub(crate) fn field<T: FromStr>(
    cursor: &Cursor,
    line: usize,
    fields: &[&str],
    index: usize,
    what: &str,
) -> Result<T> {
    let text = fields.get(index).ok_or_else(|| {
        cursor.err_at(
            line,
            format!(
                "expected {what} in column {}, the line has {} fields",
                index + 1,
                fields.len()
            ),
        )
    })?;
    text.parse()
        .map_err(|_| cursor.err_at(line, format!("expected {what}, found {text:?}")))
}
