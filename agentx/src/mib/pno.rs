// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PROFINET extension of the LLDP-MIB (LLDP-EXT-PNO-MIB, `lldpXPnoMIB`
//! 1.0.8802.1.1.2.1.5.3791, the 2006 revision's objects), read-only:
//!
//! ```text
//! lldpXPnoLocTable .1.2.1.1.c.port               (index lldpLocPortNum)
//! lldpXPnoRemTable .1.3.1.1.c.timemark.port.index (index as lldpRemTable)
//! columns: 1 LPDValue, 2 PortTxDValue, 3 PortRxDValue (Unsigned32, ns),
//!          4 PortStatusRT2, 5 PortStatusRT3 (Integer32), 6 PortNoS (DisplayString)
//! ```
//!
//! Not served: lldpXPnoConfigTable (.1.1, the read-write TLV switches), the MRP columns
//! (7, 8) and the later revision's PTCP and RT class 3 timing columns (9 on), for which
//! procimgd has no data. The ChassisMAC that PROFINET LLDP frames carry has no object in
//! this MIB.

use super::Snapshot;
use super::builder::{Builder, octets};
use super::lldp::LLDP_MIB;
use super::snapshot::{PnoPort, RtClass2Status, RtClass3Status};
use crate::pdu::{Oid, Value};

/// `lldpXPnoMIB`: lldpExtensions (1.0.8802.1.1.2.1.5) . 3791.
pub fn lldp_x_pno_mib() -> Oid {
    Oid::from(LLDP_MIB).child(&[1, 5, 3791])
}

pub(crate) fn build(s: &Snapshot, b: &mut Builder) {
    let objects = lldp_x_pno_mib().child(&[1]);
    let local = objects.child(&[2, 1, 1]);
    let remote = objects.child(&[3, 1, 1]);
    b.columns(&local, 1..=6);
    b.columns(&remote, 1..=6);
    for port in &s.lldp.ports {
        if let Some(pno) = &port.pno {
            row(b, &local, &[port.num], pno);
        }
    }
    for r in &s.lldp.remotes {
        if let Some(pno) = &r.pno {
            row(b, &remote, &[r.time_mark, r.local_port, r.index], pno);
        }
    }
}

fn row(b: &mut Builder, entry: &Oid, index: &[u32], pno: &PnoPort) {
    b.cell(entry, 1, index, Value::Gauge32(pno.line_delay_ns));
    b.cell(entry, 2, index, Value::Gauge32(pno.tx_delay_ns));
    b.cell(entry, 3, index, Value::Gauge32(pno.rx_delay_ns));
    b.cell(entry, 4, index, Value::Integer(rt2(pno.rt_class2)));
    b.cell(entry, 5, index, Value::Integer(rt3(pno.rt_class3)));
    b.cell(entry, 6, index, octets(pno.name_of_station.as_bytes()));
}

const fn rt2(s: RtClass2Status) -> i32 {
    match s {
        RtClass2Status::Off => 0,
        RtClass2Status::Configured => 1,
        RtClass2Status::Running => 2,
    }
}

const fn rt3(s: RtClass3Status) -> i32 {
    match s {
        RtClass3Status::Off => 0,
        RtClass3Status::Configured => 1,
        RtClass3Status::Up => 2,
        RtClass3Status::Down => 3,
        RtClass3Status::Running => 4,
    }
}
