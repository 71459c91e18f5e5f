// SPDX-License-Identifier: MIT OR Apache-2.0
//! IO data status (IOPS/IOCS) as IO-Base's `PNIO_IOXS`, and reading it from an image.

use procimg_shm_layout::{IOXS_BAD_BY_CONTROLLER, IOXS_GOOD, SubmoduleEntry, ioxs_is_good};

/// A data status: GOOD (valid) or BAD (invalid), as IO-Base's `PNIO_IOXS`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ioxs {
    /// `PNIO_S_GOOD`.
    Good,
    /// `PNIO_S_BAD`.
    Bad,
}

impl Ioxs {
    /// From an IOPS/IOCS byte (its DataState bit).
    pub const fn from_byte(b: u8) -> Ioxs {
        if ioxs_is_good(b) {
            Ioxs::Good
        } else {
            Ioxs::Bad
        }
    }

    /// The byte a client sends: GOOD, or BAD detected by the controller application.
    pub const fn byte(self) -> u8 {
        match self {
            Ioxs::Good => IOXS_GOOD,
            Ioxs::Bad => IOXS_BAD_BY_CONTROLLER,
        }
    }
}

/// The four status bytes of submodule `e` in an input-image payload.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubmoduleIoxs {
    /// Remote status of the inputs (the device's IOPS).
    pub input_remote: Ioxs,
    /// Local status of the inputs as sent (our IOCS).
    pub input_local: Ioxs,
    /// Local status of the outputs as sent (our IOPS).
    pub output_local: Ioxs,
    /// Remote status of the outputs (the device's IOCS, previous cycle).
    pub output_remote: Ioxs,
}

/// Reads the status bytes of `e` from an input-image payload (BAD if out of range).
pub fn read_status(payload: &[u8], e: &SubmoduleEntry) -> SubmoduleIoxs {
    let at = e.status_offset as usize;
    let b = payload.get(at..at + 4).unwrap_or(&[0, 0, 0, 0]);
    SubmoduleIoxs {
        input_remote: Ioxs::from_byte(b[0]),
        input_local: Ioxs::from_byte(b[1]),
        output_local: Ioxs::from_byte(b[2]),
        output_remote: Ioxs::from_byte(b[3]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_status_byte_reads_by_its_data_state_and_is_sent_as_iobase_does() {
        assert_eq!(Ioxs::from_byte(IOXS_GOOD), Ioxs::Good);
        assert_eq!(Ioxs::from_byte(IOXS_BAD_BY_CONTROLLER), Ioxs::Bad);
        assert_eq!(Ioxs::from_byte(0), Ioxs::Bad);
        for s in [Ioxs::Good, Ioxs::Bad] {
            assert_eq!(Ioxs::from_byte(s.byte()), s);
        }
    }

    #[test]
    fn the_four_statuses_come_from_the_submodules_bytes_and_are_bad_out_of_range() {
        let e = SubmoduleEntry {
            status_offset: 4,
            ..SubmoduleEntry::EMPTY
        };
        let mut payload = [0u8; 8];
        payload[4..8].copy_from_slice(&[IOXS_GOOD, 0, IOXS_GOOD, IOXS_BAD_BY_CONTROLLER]);
        let s = read_status(&payload, &e);
        assert_eq!(
            (
                s.input_remote,
                s.input_local,
                s.output_local,
                s.output_remote
            ),
            (Ioxs::Good, Ioxs::Bad, Ioxs::Good, Ioxs::Bad)
        );
        // A payload that ends inside the bytes: all BAD, no panic.
        let s = read_status(&payload[..6], &e);
        assert_eq!(s.input_remote, Ioxs::Bad);
        assert_eq!(s.output_local, Ioxs::Bad);
    }
}
