// SPDX-License-Identifier: MIT OR Apache-2.0
//! A small XML element tree and its text: just what the GSDML writer needs (elements,
//! attributes, text, indentation), with every string escaped so that any station gives a
//! well-formed document.

/// An XML element with its attributes (in the order given) and its content.
#[derive(Clone, Debug)]
pub(super) struct El {
    name: &'static str,
    attrs: Vec<(&'static str, String)>,
    text: Option<String>,
    children: Vec<El>,
}

impl El {
    pub(super) fn new(name: &'static str) -> El {
        El {
            name,
            attrs: Vec::new(),
            text: None,
            children: Vec::new(),
        }
    }

    /// With the attribute `name="value"`.
    pub(super) fn attr(mut self, name: &'static str, value: impl ToString) -> El {
        self.attrs.push((name, value.to_string()));
        self
    }

    /// With the attribute only if there is a value.
    pub(super) fn attr_opt(self, name: &'static str, value: Option<impl ToString>) -> El {
        match value {
            Some(v) => self.attr(name, v),
            None => self,
        }
    }

    /// With text content (then without child elements).
    pub(super) fn text(mut self, text: impl ToString) -> El {
        self.text = Some(text.to_string());
        self
    }

    /// With `child` as its last child.
    pub(super) fn child(mut self, child: El) -> El {
        self.children.push(child);
        self
    }

    /// With `children` after the ones it has.
    pub(super) fn children(mut self, children: impl IntoIterator<Item = El>) -> El {
        self.children.extend(children);
        self
    }

    /// Appends the element, indented by `depth` levels of two blanks, and a line end.
    pub(super) fn write(&self, out: &mut String, depth: usize) {
        for _ in 0..depth {
            out.push_str("  ");
        }
        out.push('<');
        out.push_str(self.name);
        for (name, value) in &self.attrs {
            out.push(' ');
            out.push_str(name);
            out.push_str("=\"");
            escape(value, out);
            out.push('"');
        }
        match (&self.text, self.children.is_empty()) {
            (Some(text), _) => {
                out.push('>');
                escape(text, out);
                close(self.name, out);
            }
            (None, true) => out.push_str("/>"),
            (None, false) => {
                out.push_str(">\n");
                for child in &self.children {
                    child.write(out, depth + 1);
                }
                for _ in 0..depth {
                    out.push_str("  ");
                }
                close(self.name, out);
            }
        }
        out.push('\n');
    }
}

fn close(name: &str, out: &mut String) {
    out.push_str("</");
    out.push_str(name);
    out.push('>');
}

/// Appends `text` escaped for an attribute value or element content. Line ends and tabs
/// become character references, so that attribute value normalization gives them back;
/// characters XML 1.0 does not allow at all (other control characters, U+FFFE, U+FFFF) become
/// U+FFFD, since no escape can carry them.
pub(super) fn escape(text: &str, out: &mut String) {
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\n' => out.push_str("&#xA;"),
            '\r' => out.push_str("&#xD;"),
            '\t' => out.push_str("&#x9;"),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_what_xml_needs() {
        let mut out = String::new();
        escape("a<b>&\"c\"\n\u{1}\tä", &mut out);
        assert_eq!(out, "a&lt;b&gt;&amp;&quot;c&quot;&#xA;\u{FFFD}&#x9;ä");
    }

    #[test]
    fn nests_and_closes() {
        let el = El::new("A")
            .attr("x", 1)
            .child(El::new("B").text("t&"))
            .child(El::new("C").attr_opt("y", None::<u8>));
        let mut out = String::new();
        el.write(&mut out, 0);
        assert_eq!(out, "<A x=\"1\">\n  <B>t&amp;</B>\n  <C/>\n</A>\n");
    }
}
