// SPDX-License-Identifier: MIT OR Apache-2.0
//! From byte offsets in the TOML text to lines and key paths.

use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// The 1-based line holding byte `offset` of `text` (the last line if `offset` is past the end).
pub(super) fn line_of(text: &str, offset: usize) -> usize {
    let bytes = text.as_bytes();
    let end = offset.min(bytes.len());
    bytes[..end].iter().filter(|&&b| b == b'\n').count() + 1
}

/// The key path (`device[1].submodule[0].slot`) of the innermost key, value or table header
/// of `text` that holds byte `offset`, as far as `text` can be parsed.
pub(super) fn key_path_at(text: &str, offset: usize) -> Option<String> {
    let (root, _errors) = DeTable::parse_recoverable(text);
    let mut best: Option<Vec<Segment<'_>>> = None;
    let mut path = Vec::new();
    walk_table(root.get_ref(), offset, &mut path, &mut best);
    best.filter(|p| !p.is_empty()).map(|p| render(&p))
}

#[derive(Clone)]
enum Segment<'a> {
    Key(&'a str),
    Index(usize),
}

fn render(path: &[Segment<'_>]) -> String {
    let mut out = String::new();
    for segment in path {
        match segment {
            Segment::Key(k) => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(k);
            }
            Segment::Index(i) => {
                out.push('[');
                out.push_str(&i.to_string());
                out.push(']');
            }
        }
    }
    out
}

fn holds(span: &core::ops::Range<usize>, offset: usize) -> bool {
    span.start <= offset && offset < span.end.max(span.start + 1)
}

fn consider<'a>(
    span: core::ops::Range<usize>,
    offset: usize,
    path: &[Segment<'a>],
    best: &mut Option<Vec<Segment<'a>>>,
) {
    if holds(&span, offset) && best.as_ref().is_none_or(|b| path.len() > b.len()) {
        *best = Some(path.to_vec());
    }
}

fn walk_table<'a>(
    table: &'a DeTable<'_>,
    offset: usize,
    path: &mut Vec<Segment<'a>>,
    best: &mut Option<Vec<Segment<'a>>>,
) {
    for (key, value) in table.iter() {
        path.push(Segment::Key(key.get_ref()));
        consider(key.span(), offset, path, best);
        walk_value(value, offset, path, best);
        path.pop();
    }
}

fn walk_value<'a>(
    value: &'a Spanned<DeValue<'_>>,
    offset: usize,
    path: &mut Vec<Segment<'a>>,
    best: &mut Option<Vec<Segment<'a>>>,
) {
    consider(value.span(), offset, path, best);
    match value.get_ref() {
        DeValue::Table(table) => walk_table(table, offset, path, best),
        DeValue::Array(array) => {
            for (i, element) in array.iter().enumerate() {
                path.push(Segment::Index(i));
                walk_value(element, offset, path, best);
                path.pop();
            }
        }
        _ => {}
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines() {
        assert_eq!(line_of("", 0), 1);
        assert_eq!(line_of("a\nb\n", 2), 2);
        assert_eq!(line_of("a\nb\n", 99), 3);
    }

    #[test]
    fn paths() {
        let text = "a = 1\n[[device]]\nname = \"x\"\n[[device]]\nname = \"y\"\n\
                    [[device.submodule]]\nslot = 1\nrecords = [{ index = 1 }]\n";
        let at = |needle: &str| key_path_at(text, text.rfind(needle).unwrap());
        assert_eq!(at("a =").as_deref(), Some("a"));
        assert_eq!(at("\"y\"").as_deref(), Some("device[1].name"));
        assert_eq!(at("[[device]]").as_deref(), Some("device[1]"));
        assert_eq!(
            at("[[device.submodule]]").as_deref(),
            Some("device[1].submodule[0]")
        );
        assert_eq!(
            at("index").as_deref(),
            Some("device[1].submodule[0].records[0].index")
        );
        assert_eq!(key_path_at(text, 9999), None);
    }
}
