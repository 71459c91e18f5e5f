// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station's topology: LLDPDUs received on a port (the input as length-prefixed PDUs,
//! one a second) into its neighbour table, which never grows past its bound and ages
//! empty; and the physical device's records and the AR records as blocks: what parses
//! emits back and parses the same.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::port::neighbours::{MAX_NEIGHBOURS, Neighbours};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::record::{
    ApiData, ArData, LogBookData, MultipleBlockHeader, PdInterfaceDataReal, PdPortDataAdjust,
    PdPortDataCheck, PdPortDataReal, PdPortStatistic,
};

const S: u64 = 1_000_000_000;

fuzz_target!(|data: &[u8]| {
    neighbours(data);
    records(data);
});

fn neighbours(data: &[u8]) {
    let mut n = Neighbours::default();
    let mut rest = data;
    let mut now = 0;
    while let [hi, lo, tail @ ..] = rest {
        let len = usize::from(u16::from_be_bytes([*hi, *lo])).min(tail.len());
        let (pdu, r) = tail.split_at(len);
        let _ = n.on_lldpdu(MacAddress([0x02, 0, 0, 0, 0, 0x01]), pdu, now);
        assert!(n.entries().len() <= MAX_NEIGHBOURS);
        for e in n.entries() {
            let _ = (
                e.peer_chassis_id(),
                e.peer_port_id(),
                e.mac(),
                e.line_delay_ns(),
            );
        }
        let _ = n.alias_name();
        now += S;
        let _ = n.age(now);
        rest = r;
    }
    let _ = n.age(u64::MAX);
    assert!(n.entries().is_empty());
}

/// Parses `data` as `parse` does, emits it with `emit`, and parses that again: the same.
fn again<T: PartialEq + core::fmt::Debug, E: core::fmt::Debug>(
    data: &[u8],
    parse: impl Fn(&[u8]) -> Result<T, procimg_profinet::wire::Error>,
    emit: impl Fn(&T) -> Result<Vec<u8>, E>,
) {
    if let Ok(v) = parse(data) {
        let bytes = emit(&v).expect("a parsed block emits");
        assert_eq!(parse(&bytes).expect("an emitted block parses"), v);
    }
}

fn records(data: &[u8]) {
    again(data, PdPortDataCheck::parse, PdPortDataCheck::to_vec);
    again(data, PdPortDataAdjust::parse, PdPortDataAdjust::to_vec);
    again(data, PdPortDataReal::parse, PdPortDataReal::to_vec);
    again(
        data,
        PdInterfaceDataReal::parse,
        PdInterfaceDataReal::to_vec,
    );
    again(data, PdPortStatistic::parse, PdPortStatistic::to_vec);
    again(data, ArData::parse, ArData::to_vec);
    again(data, ApiData::parse, ApiData::to_vec);
    again(data, LogBookData::parse, LogBookData::to_vec);
    // A MultipleBlockHeader re-emits only whole 4-byte blocks.
    if let Ok(m) = MultipleBlockHeader::parse(data)
        && m.blocks.len().is_multiple_of(4)
    {
        let bytes = m.to_vec().expect("aligned blocks emit");
        assert_eq!(MultipleBlockHeader::parse(&bytes), Ok(m));
    }
}
