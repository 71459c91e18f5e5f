// SPDX-License-Identifier: MIT OR Apache-2.0
//! The text of a configuration being read and where it came from: what every checking step
//! (validation, address assignment, GSDML import) needs to name file, line and key in its
//! errors.

use std::ops::Range;
use std::path::Path;

use toml::Spanned;

use super::error::ConfigError;
use super::gsdml::GsdmlError;
use super::span::{key_path_at, line_of};

/// The text being parsed and its name, for error messages.
pub(super) struct Cx<'a> {
    pub text: &'a str,
    pub origin: &'a str,
    /// Where relative GSDML paths start.
    pub dir: &'a Path,
    /// Check what depends on the machine the configuration is for, too: that its `network`
    /// interface exists, by asking this.
    pub interface: Option<super::InterfaceCheck<'a>>,
}

impl Cx<'_> {
    /// The 1-based line of byte `offset`.
    pub fn line(&self, offset: usize) -> usize {
        line_of(self.text, offset)
    }

    /// An [`ConfigError::Invalid`] about the value at `span`.
    pub fn invalid(
        &self,
        span: Range<usize>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> ConfigError {
        ConfigError::Invalid {
            origin: self.origin.to_owned(),
            line: self.line(span.start),
            key: key.into(),
            message: message.into(),
        }
    }

    /// A [`ConfigError::Gsdml`]: the GSDML file reached through the value at `span` has a
    /// problem.
    pub fn gsdml_error(&self, span: Range<usize>, key: &str, error: GsdmlError) -> ConfigError {
        ConfigError::Gsdml {
            origin: self.origin.to_owned(),
            line: self.line(span.start),
            key: key.to_owned(),
            error: Box::new(error),
        }
    }

    /// A [`ConfigError::Invalid`] for a required key missing from the table at `span`, with
    /// the wording of the TOML layer's own message for missing keys.
    pub fn missing(&self, span: Range<usize>, table: &str, key: &str, hint: &str) -> ConfigError {
        self.invalid(span, table, format!("missing field `{key}`; {hint}"))
    }

    /// A [`ConfigError::Syntax`] from a TOML or deserialization error.
    pub fn toml_error(&self, error: &toml::de::Error) -> ConfigError {
        let span = error.span();
        // A key the document does not hold (a duplicate, say) is named by its own text.
        let bare_key = |s: &Range<usize>| {
            self.text.get(s.clone()).filter(|k| {
                !k.is_empty()
                    && k.chars()
                        .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
            })
        };
        let key = span.as_ref().and_then(|s| {
            key_path_at(self.text, s.start).or_else(|| bare_key(s).map(str::to_owned))
        });
        ConfigError::Syntax {
            origin: self.origin.to_owned(),
            line: span.as_ref().map(|s| self.line(s.start)),
            key,
            message: explain(error.message()),
        }
    }

    pub fn check<T, V>(
        &self,
        value: &Spanned<V>,
        key: impl Into<String>,
        result: Result<T, String>,
    ) -> Result<T, ConfigError> {
        result.map_err(|message| self.invalid(value.span(), key, message))
    }
}

/// Makes a serde/TOML message speak the configuration's language and say what to do.
fn explain(message: &str) -> String {
    let mut message = message.trim_end().replace('\n', "; ");
    for (ty, range) in [
        ("u8", "an integer from 0 to 255"),
        ("u16", "an integer from 0 to 65535 (0xFFFF)"),
        ("u32", "an integer from 0 to 4294967295 (0xFFFFFFFF)"),
        ("usize", "a non-negative integer"),
        ("i64", "an integer"),
    ] {
        if let Some(stem) = message.strip_suffix(&format!("expected {ty}")) {
            message = format!("{stem}expected {range}");
        }
    }
    let hint = if message.starts_with("unknown field") {
        "remove it or correct its spelling"
    } else if message.starts_with("missing field") {
        "add it"
    } else if message.starts_with("duplicate key") {
        "give each key once; remove or rename one of them"
    } else if message.contains("expected a sequence") {
        "write [[device]] and [[device.submodule]] with double brackets, or give an array"
    } else if message.starts_with("invalid type") || message.starts_with("invalid value") {
        "correct the value; `procimgd --print-demo-config` shows an example of every key"
    } else {
        "correct the TOML syntax (see https://toml.io)"
    };
    format!("{message}; {hint}")
}

#[cfg(test)]
mod tests {
    use super::explain;

    #[test]
    fn explanations_have_hints() {
        assert_eq!(
            explain("invalid value: integer `70000`, expected u16"),
            "invalid value: integer `70000`, expected an integer from 0 to 65535 (0xFFFF); \
             correct the value; `procimgd --print-demo-config` shows an example of every key"
        );
        assert!(explain("unknown field `x`, expected `y`").ends_with("correct its spelling"));
    }
}
