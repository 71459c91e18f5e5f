// SPDX-License-Identifier: MIT OR Apache-2.0
//! IO-Base's rules for access by logical address, as pure functions over the submodule table.
//!
//! * Reads (`PNIO_data_read`): the address may be any address inside the submodule when
//!   slice access is on, else its first address. The data is everything from the address
//!   to the end of the submodule; as much as fits is copied, and the returned length is the
//!   data length (the buffer length needed to read it all).
//! * Writes (`PNIO_data_write`): without slice access the buffer length must equal the
//!   submodule's output length, at its first address; with slice access it may be shorter, up
//!   to the bytes from the address to the end of the submodule.

use procimg_shm_layout::SubmoduleEntry;

pub use procimg_control::Space;

/// Why an access by logical address is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccessError {
    /// No submodule has this address (IO-Base `PNIO_ERR_UNKNOWN_ADDR`).
    UnknownAddress {
        /// Address space.
        space: Space,
        /// The address.
        address: u32,
        /// It is the diagnostic address of a submodule without IO data.
        diagnostic: bool,
    },
    /// The length does not fit the submodule (IO-Base `PNIO_ERR_VALUE_LEN`).
    ValueLength {
        /// The address.
        address: u32,
        /// The length asked for.
        length: usize,
        /// The length allowed at this address.
        allowed: usize,
        /// Whether slice access was on.
        slice_access: bool,
    },
}

impl core::fmt::Display for AccessError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match *self {
            AccessError::UnknownAddress {
                space,
                address,
                diagnostic: true,
            } => write!(
                f,
                "{space} {address} is the diagnostic address of a submodule without IO data: \
                 it has nothing to read or write, only records; `procimg layout` lists the \
                 addresses"
            ),
            AccessError::UnknownAddress { space, address, .. } => write!(
                f,
                "no submodule has {space} address {address}; `procimg layout` lists the \
                 addresses"
            ),
            AccessError::ValueLength {
                address,
                length,
                allowed,
                slice_access: true,
            } => write!(
                f,
                "{length} bytes do not fit at Q address {address}: at most {allowed} bytes \
                 remain to the end of the submodule"
            ),
            AccessError::ValueLength {
                address,
                length,
                allowed,
                slice_access: false,
            } => write!(
                f,
                "{length} bytes at Q address {address}: without slice access a write must be \
                 the whole submodule ({allowed} bytes); attach with slice access to write less"
            ),
        }
    }
}

impl core::error::Error for AccessError {}

/// A resolved access: submodule index, offset inside the submodule, byte count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resolved {
    /// Submodule table index.
    pub submodule: usize,
    /// Offset of the first byte inside the submodule's data.
    pub offset: usize,
    /// Bytes to copy.
    pub len: usize,
    /// For reads: bytes from the address to the end of the submodule.
    pub data_len: usize,
}

/// Finds the submodule whose range in `space` contains `address`.
pub fn find(table: &[SubmoduleEntry], space: Space, address: u32) -> Option<usize> {
    table.iter().position(|e| match space {
        Space::Input => e.has_input_address(address),
        Space::Output => e.has_output_address(address),
    })
}

/// The submodule a record job names by one of its logical addresses (IO-Base's "a module by
/// one of its logical addresses"): any address inside its range in `space`, or, in the input
/// space, the diagnostic address of a submodule without IO data.
pub fn find_module(table: &[SubmoduleEntry], space: Space, address: u32) -> Option<usize> {
    find(table, space, address).or_else(|| {
        (space == Space::Input)
            .then(|| {
                table
                    .iter()
                    .position(|e| e.diagnostic_address() == Some(address))
            })
            .flatten()
    })
}

fn start_and_len(e: &SubmoduleEntry, space: Space) -> (u32, usize) {
    match space {
        Space::Input => (e.input_address, e.input_length as usize),
        Space::Output => (e.output_address, e.output_length as usize),
    }
}

/// Resolves a read of `buf_len` bytes at `address` (`PNIO_data_read`, `PNIO_output_data_read`).
pub fn resolve_read(
    table: &[SubmoduleEntry],
    space: Space,
    address: u32,
    buf_len: usize,
    slice_access: bool,
) -> Result<Resolved, AccessError> {
    let unknown = AccessError::UnknownAddress {
        space,
        address,
        diagnostic: false,
    };
    let submodule = find(table, space, address).ok_or_else(|| AccessError::UnknownAddress {
        space,
        address,
        diagnostic: space == Space::Input
            && table
                .iter()
                .any(|e| e.diagnostic_address() == Some(address)),
    })?;
    let (start, len) = start_and_len(&table[submodule], space);
    if !slice_access && address != start {
        return Err(unknown);
    }
    let offset = (address - start) as usize;
    let data_len = len - offset;
    Ok(Resolved {
        submodule,
        offset,
        len: data_len.min(buf_len),
        data_len,
    })
}

/// Resolves a write of `buf_len` bytes at `address` (`PNIO_data_write`).
pub fn resolve_write(
    table: &[SubmoduleEntry],
    address: u32,
    buf_len: usize,
    slice_access: bool,
) -> Result<Resolved, AccessError> {
    let space = Space::Output;
    let unknown = AccessError::UnknownAddress {
        space,
        address,
        diagnostic: false,
    };
    let submodule = find(table, space, address).ok_or(unknown)?;
    let (start, len) = start_and_len(&table[submodule], space);
    let offset = (address - start) as usize;
    let allowed = len - offset;
    let fits = if slice_access {
        buf_len >= 1 && buf_len <= allowed
    } else {
        offset == 0 && buf_len == len
    };
    if !fits {
        return Err(AccessError::ValueLength {
            address,
            length: buf_len,
            allowed: if slice_access { allowed } else { len },
            slice_access,
        });
    }
    Ok(Resolved {
        submodule,
        offset,
        len: buf_len,
        data_len: allowed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_shm_layout::NO_ADDRESS;

    fn input(addr: u32, len: u16) -> SubmoduleEntry {
        SubmoduleEntry {
            input_address: addr,
            input_length: len,
            ..SubmoduleEntry::EMPTY
        }
    }

    fn output(addr: u32, len: u16) -> SubmoduleEntry {
        SubmoduleEntry {
            output_address: addr,
            output_length: len,
            input_address: NO_ADDRESS,
            ..SubmoduleEntry::EMPTY
        }
    }

    /// The manual's PNIO_data_read example: modules of 2 bytes at I 0..1 and 4 bytes at I 2..5;
    /// (address, BufLen, *pDataLen).
    #[test]
    fn iobase_data_read_table() {
        let t = [input(0, 2), input(2, 4)];
        let rows = [
            (2, 8, 4),
            (2, 2, 4),
            (3, 2, 3),
            (5, 1, 1),
            (5, 8, 1),
            (1, 2, 1),
            (1, 1, 1),
        ];
        for (addr, buf_len, data_len) in rows {
            let r = resolve_read(&t, Space::Input, addr, buf_len, true).unwrap();
            assert_eq!(r.data_len, data_len, "I {addr} BufLen {buf_len}");
            assert_eq!(r.len, data_len.min(buf_len));
        }
    }

    /// The manual's PNIO_data_write example with slice access: 2 bytes at Q 0..1, 4 bytes at
    /// Q 2..5, 4 bytes at Q 10..13; (address, BufLen, result).
    #[test]
    fn iobase_data_write_table() {
        let t = [output(0, 2), output(2, 4), output(10, 4)];
        let vl = "VALUE_LEN";
        let ua = "UNKNOWN_ADDR";
        let rows = [
            (2, 8, vl),
            (2, 2, "OK"),
            (1, 2, vl),
            (1, 1, "OK"),
            (3, 3, "OK"),
            (3, 1, "OK"),
            (3, 4, vl),
            (6, 4, ua),
            (10, 1, "OK"),
            (11, 1, "OK"),
            (9, 1, ua),
        ];
        for (addr, len, want) in rows {
            let got = match resolve_write(&t, addr, len, true) {
                Ok(_) => "OK",
                Err(AccessError::ValueLength { .. }) => vl,
                Err(AccessError::UnknownAddress { .. }) => ua,
            };
            assert_eq!(got, want, "Q {addr} BufLen {len}");
        }
        // The ExtPar example: a 4-byte module at 2, writing 2 bytes from address 3.
        let r = resolve_write(&t, 3, 2, true).unwrap();
        assert_eq!((r.submodule, r.offset, r.len), (1, 1, 2));
    }

    #[test]
    fn a_diagnostic_address_has_no_data_and_says_so() {
        // A data-less submodule (a DAP) at diagnostic address I 2, after inputs I 0..1.
        let t = [input(0, 2), input(2, 0)];
        let e = resolve_read(&t, Space::Input, 2, 1, true).unwrap_err();
        assert!(matches!(
            e,
            AccessError::UnknownAddress {
                diagnostic: true,
                ..
            }
        ));
        assert!(
            e.to_string().contains("I 2 is the diagnostic address"),
            "{e}"
        );
        let e = resolve_read(&t, Space::Input, 3, 1, true).unwrap_err();
        assert!(
            e.to_string().starts_with("no submodule has I address 3"),
            "{e}"
        );
    }

    #[test]
    fn without_slice_access_only_whole_submodules() {
        let t = [output(0, 2), output(2, 4)];
        assert!(resolve_write(&t, 2, 4, false).is_ok());
        assert!(matches!(
            resolve_write(&t, 2, 2, false),
            Err(AccessError::ValueLength { allowed: 4, .. })
        ));
        assert!(resolve_write(&t, 3, 3, false).is_err());
        let i = [input(0, 2), input(2, 4)];
        assert!(resolve_read(&i, Space::Input, 3, 4, false).is_err());
        assert_eq!(resolve_read(&i, Space::Input, 2, 4, false).unwrap().len, 4);
    }

    proptest::proptest! {
        #[test]
        fn resolved_ranges_stay_inside_the_submodule(addr in 0u32..40, len in 0usize..40, slice: bool) {
            let t = [output(0, 2), output(2, 4), output(10, 4), output(20, 17)];
            if let Ok(r) = resolve_write(&t, addr, len, slice) {
                let e = t[r.submodule];
                proptest::prop_assert!(r.offset + r.len <= e.output_length as usize);
            }
            let i = [input(0, 3), input(7, 9)];
            if let Ok(r) = resolve_read(&i, Space::Input, addr, len, slice) {
                proptest::prop_assert!(r.offset + r.len <= i[r.submodule].input_length as usize);
            }
        }
    }
}
