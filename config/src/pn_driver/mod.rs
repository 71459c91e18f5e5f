// SPDX-License-Identifier: MIT OR Apache-2.0
//! TIA Portal's configuration for PN Driver (`…PNDriverConfiguration.xml`, what a PN Driver
//! program hands to `SERV_CP_startup`) imported as procimgd's own configuration.
//!
//! The format is the one Siemens' "PROFINET Driver Engineering Interface" manual (v3.1.0)
//! documents: a generic tree of objects (class IDs, keys, attribute IDs) whose values are
//! numbers and hex records, the connect parameters precomputed as Siemens' PNIO data blocks.
//! What is read:
//!
//! - the PN Driver's interface: its NameOfStation and IP suite, whether programs may change
//!   them ("set directly at the device"), and the hardware identifiers of the interface and
//!   its port, which become their diagnostic addresses;
//! - per IO device: its NameOfStation and IP address (network parameters), its identity
//!   (PNIOD_PROPERTIES), its update time and watchdog (IOCR_DATA), its submodules with ident
//!   numbers and IO lengths (EXPECTED_SUBMODULE_DATA), their logical addresses (IOmapping),
//!   their parameter records in the order the project writes them, the hardware identifiers
//!   of submodules without IO data as their diagnostic addresses, and whether the device is
//!   deactivated in the project (procimg's `optional`).
//!
//! What procimgd does itself: the wire plan (frame IDs, phases, frame offsets, AR UUID and
//! properties, alarm CR), as any RT controller does. What is refused, naming the line: IRT
//! and isochronous mode, multicast IOCRs, shared devices, and more than one interface. A
//! project's AR records for fast start-up are left out (the device starts up as usual).
//!
//! The import writes TOML ([`import`]); [`crate::parse`] and [`crate::load`] take the XML
//! directly and check the result as any configuration, naming the imported text's lines,
//! whose comments give the project's.

mod blocks;
mod project;
mod toml_text;
mod tree;

#[cfg(test)]
mod tests;

use crate::ConfigError;

/// The `network` an import names when it is given none: a PN Driver program chooses its
/// adapter (`SERV_CP_startup`'s `CpList`, procimgd's `--adapter`), so the project names
/// none. procimgd refuses it with what to give instead.
pub const ADAPTER_PLACEHOLDER: &str = "pnd-adapter";

/// Whether `text` is XML rather than TOML (no TOML document starts with `<`).
pub fn is_xml(text: &str) -> bool {
    text.trim_start_matches('\u{feff}')
        .trim_start()
        .starts_with('<')
}

/// Imports the PN Driver configuration `text` (named `origin` in messages) as procimgd's
/// TOML configuration on interface `network` ([`ADAPTER_PLACEHOLDER`] when `None`).
///
/// An error names the XML's line and object. The TOML is not checked here: [`crate::parse`]
/// of the result does that.
pub fn import(text: &str, origin: &str, network: Option<&str>) -> Result<String, ConfigError> {
    let refuse = |p: project::Problem| ConfigError::PnDriver {
        origin: origin.to_owned(),
        line: p.line,
        element: p.element,
        message: p.message,
    };
    let root = tree::parse(text).map_err(|e| refuse(e.into()))?;
    let project = project::read(&root).map_err(refuse)?;
    toml_text::write(&project, origin, network.unwrap_or(ADAPTER_PLACEHOLDER)).map_err(refuse)
}
