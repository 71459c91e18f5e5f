// SPDX-License-Identifier: MIT OR Apache-2.0
//! The program's diagnosis (`PNIO_diag_channel_add`, `PNIO_diag_ext_channel_add`,
//! `PNIO_diag_generic_add` and their `_remove`, `PNIO_build_channel_properties`): the checks
//! of the device's state and the program's submodule, over the DiagTag rules of
//! [`IoBaseDevice`](procimg_client::iobase::IoBaseDevice) (an entry goes into procimgd's
//! store at once, without an alarm; two tags with the same entry are one there, which goes
//! with the last of them; a remove of an unknown DiagTag is no error; DiagTag 0 removes all
//! the submodule's entries of the function's kind).

use super::Pos;
use super::state::{Device, Life};
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use procimg_client::DiagnosisEntry;
use procimg_client::iobase::DiagTagError;
pub(crate) use procimg_client::iobase::DiagTagKind as DiagFn;
pub(crate) use procimg_client::iobase::{channel_entry, channel_properties, generic_entry};

/// Where the program's submodule at `at` is, checked that the device may take diagnosis.
fn submodule(f: &str, dev: &Device, at: Pos) -> Result<(), u32> {
    let c = lock(&dev.config);
    if matches!(c.life, Life::Stopping | Life::Stopped) {
        return Err(fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("the device is {}", c.life.name()),
        ));
    }
    if !c.subs.contains_key(&at) {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!(
                "the program has no submodule plugged at API {} slot {} subslot {:#06x}",
                at.0, at.1, at.2
            ),
        ));
    }
    Ok(())
}

/// The code of a failed diagnosis call.
fn failure(f: &str, e: DiagTagError) -> u32 {
    let code = match e {
        DiagTagError::TagZero => PNIO_ERR_PRM_INVALIDARG,
        DiagTagError::Refused(_) => PNIO_ERR_PRM_ADD,
        DiagTagError::NotRemoved(_) => PNIO_ERR_INTERNAL,
    };
    fail(f, code, e)
}

/// Adds the program's entry with `tag` to the submodule at `at`.
pub(crate) fn add(
    f: &str,
    dev: &Device,
    at: Pos,
    tag: u16,
    kind: DiagFn,
    entry: DiagnosisEntry,
) -> u32 {
    if tag == 0 {
        return failure(f, DiagTagError::TagZero);
    }
    if let Err(code) = submodule(f, dev, at) {
        return code;
    }
    match dev.iobase.add_diagnosis(at, tag, kind, entry) {
        Ok(()) => PNIO_OK,
        Err(e) => failure(f, e),
    }
}

/// Removes the program's entry with `tag` (0: all of `kind`) from the submodule at `at`.
pub(crate) fn remove(f: &str, dev: &Device, at: Pos, tag: u16, kind: DiagFn) -> u32 {
    if let Err(code) = submodule(f, dev, at) {
        return code;
    }
    match dev.iobase.remove_diagnosis(at, tag, kind) {
        Ok(()) => PNIO_OK,
        Err(e) => failure(f, e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iobase::device_types::*;

    #[test]
    fn the_headers_constants_build_the_properties() {
        let p = channel_properties(
            PNIO_DIAG_CHANPROP_TYPE_SUBMOD as u16,
            PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS as u16,
            PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE as u16,
        );
        assert_eq!(p, 0x0800);
        let p = channel_properties(
            PNIO_DIAG_CHANPROP_TYPE_BYTE as u16,
            PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE as u16,
            PNIO_DIAG_CHAN_DIRECTION_OUTPUT as u16,
        );
        assert_eq!(p, 0x04 | (2 << 11) | (2 << 13));
    }
}
