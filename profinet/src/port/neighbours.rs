// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device port's LLDP neighbours, sans-IO: what each neighbour announced (IEEE 802.1AB's
//! remote systems data), kept for its time to live.
//!
//! Every LLDPDU received on the port (from any source address, to the nearest-bridge group
//! address 01:80:C2:00:00:0E) updates the entry of its sender, identified as the LLDP-MIB
//! does by its Chassis ID and Port ID; the entry goes when its TTL runs out without a
//! newer frame, at once on a TTL of 0 (the sender's shutdown), or when the table is full
//! and a new sender comes (the entry closest to its end makes room: IEEE 802.1AB's "too
//! many neighbours" leaves the choice to the implementation). A PROFINET port is a
//! point-to-point link, so one neighbour is the normal case; more mean an unmanaged switch
//! or a hub between, which the topology check reports.
//!
//! What PROFINET makes of a neighbour ([`Neighbour::peer_station`], [`Neighbour::peer_port`]):
//! a PROFINET device announces either `Chassis ID = NameOfStation, Port ID = port-001`, or
//! `Port ID = port-001.<NameOfStation>` with the station name after the first dot (the
//! PDInterfaceAdjust naming modes, see [`super::lldp`]); both give the peer's station name
//! and port name, which PDPortDataReal reports and PDPortDataCheck compares, and which make
//! the device's alias name `<peer port>.<peer station>` (DCP answers an Identify for it).

use crate::wire::MacAddress;
use crate::wire::lldp::{self, Id, MacPhyStatus, Packet, TlvRepr};

/// Neighbours kept per port: enough for a port behind an unmanaged switch with a few
/// PROFINET stations on it, and a bound against a flood of made-up senders.
pub const MAX_NEIGHBOURS: usize = 4;

/// What one neighbour announced, as received last.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Neighbour {
    /// The LLDP-MIB's lldpRemIndex: a number given to the neighbour when it first came,
    /// counting up from 1 for the port's life.
    pub index: u32,
    /// The Ethernet source address of its frames.
    pub source: MacAddress,
    /// Its Chassis ID.
    pub chassis_id: Id,
    /// Its Port ID.
    pub port_id: Id,
    /// Its time to live, in seconds, as announced last.
    pub ttl: u16,
    /// The optional TLVs of its last frame, in order.
    pub tlvs: Vec<TlvRepr>,
    /// When it first came (the LLDP-MIB's lldpRemTimeMark), in the caller's ns.
    pub since_ns: u64,
    /// When its last frame came.
    pub updated_ns: u64,
}

impl Neighbour {
    /// When the entry ages out without a newer frame.
    pub fn expires_ns(&self) -> u64 {
        self.updated_ns
            .saturating_add(u64::from(self.ttl).saturating_mul(1_000_000_000))
    }

    /// The neighbour's station name: the text after the first dot of a locally assigned
    /// Port ID (`port-001.plc`), else a locally assigned Chassis ID, else its System Name.
    pub fn peer_station(&self) -> Option<&str> {
        if let Some((_, station)) = self.port_id.local().and_then(|p| p.split_once('.')) {
            return Some(station);
        }
        self.chassis_id.local().or_else(|| self.system_name())
    }

    /// The neighbour's port name: a locally assigned Port ID up to its first dot
    /// (`port-001`), or the Port ID's text.
    pub fn peer_port(&self) -> Option<&str> {
        let port = self.port_id.local()?;
        Some(port.split_once('.').map_or(port, |(p, _)| p))
    }

    /// The Port ID as PDPortDataReal's PeerPortID carries it: [`Neighbour::peer_port`], or
    /// the MAC address as text for a Port ID of that subtype.
    pub fn peer_port_id(&self) -> String {
        match (&self.port_id, self.peer_port()) {
            (_, Some(p)) => p.to_owned(),
            (Id::MacAddress(m), None) => m.to_string(),
            (other, None) => other.to_string(),
        }
    }

    /// The Chassis ID as PDPortDataReal's PeerChassisID carries it: [`Neighbour::peer_station`],
    /// or the MAC address as text.
    pub fn peer_chassis_id(&self) -> String {
        match (&self.chassis_id, self.peer_station()) {
            (_, Some(s)) => s.to_owned(),
            (Id::MacAddress(m), None) => m.to_string(),
            (other, None) => other.to_string(),
        }
    }

    /// The interface MAC address: the PROFINET ChassisMAC TLV's, else the frames' source.
    pub fn mac(&self) -> MacAddress {
        self.find(|t| match t {
            TlvRepr::ProfinetChassisMac(m) => Some(*m),
            _ => None,
        })
        .unwrap_or(self.source)
    }

    /// The System Name TLV's text.
    pub fn system_name(&self) -> Option<&str> {
        self.find(|t| match t {
            TlvRepr::SystemName(s) => Some(s.as_str()),
            _ => None,
        })
    }

    /// The first IPv4 management address.
    pub fn management_ipv4(&self) -> Option<[u8; 4]> {
        self.find(|t| match t {
            TlvRepr::ManagementAddress(m) => m.as_ipv4(),
            _ => None,
        })
    }

    /// The IEEE 802.3 MAC/PHY TLV: its MAU type and auto-negotiation.
    pub fn mac_phy(&self) -> Option<MacPhyStatus> {
        self.find(|t| match t {
            TlvRepr::MacPhy(s) => Some(*s),
            _ => None,
        })
    }

    /// The PROFINET port status TLV: RTClass2 and RTClass3 port status.
    pub fn port_status(&self) -> Option<(u16, u16)> {
        self.find(|t| match t {
            TlvRepr::ProfinetPortStatus { rtclass2, rtclass3 } => Some((*rtclass2, *rtclass3)),
            _ => None,
        })
    }

    /// The PROFINET line delay the neighbour measured (ns), if it announced one (PROFINET
    /// Delay TLV, subtype 1: RxDelayLocal, RxDelayRemote, TxDelayLocal, TxDelayRemote,
    /// CableDelayLocal, in ns); 0 when none.
    pub fn line_delay_ns(&self) -> u32 {
        self.find(|t| match t {
            TlvRepr::OrgSpecific { oui, subtype, data }
                if *oui == lldp::OUI_PROFINET && *subtype == 1 && data.len() >= 20 =>
            {
                Some(u32::from_be_bytes([data[16], data[17], data[18], data[19]]))
            }
            _ => None,
        })
        .unwrap_or(0)
    }

    fn find<'a, T>(&'a self, pick: impl Fn(&'a TlvRepr) -> Option<T>) -> Option<T> {
        self.tlvs.iter().find_map(pick)
    }
}

/// What a received frame changed in the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NeighbourChange {
    /// A new neighbour (index).
    Added(u32),
    /// A known neighbour announced something else (index).
    Changed(u32),
    /// A neighbour went: its TTL ran out, it sent TTL 0, or a new one took its place.
    Removed(u32),
}

/// The neighbours of one port.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Neighbours {
    entries: Vec<Neighbour>,
    next_index: u32,
    /// Counts for the LLDP-MIB's statistics: frames taken, frames discarded (malformed),
    /// entries aged out, entries inserted, deleted, dropped for lack of room.
    pub stats: NeighbourStats,
    /// Bumped on every change: a caller that mirrors the table copies it again when it
    /// grows.
    pub changes: u64,
}

/// The LLDP-MIB's receive statistics of a port (lldpStatsRxPort…) and its table's
/// (lldpStatsRemTables…).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NeighbourStats {
    /// LLDPDUs received and taken.
    pub frames_in: u64,
    /// LLDPDUs discarded as malformed.
    pub frames_discarded: u64,
    /// Entries whose TTL ran out.
    pub ageouts: u64,
    /// Entries inserted.
    pub inserts: u64,
    /// Entries deleted (aged out, TTL 0, or replaced).
    pub deletes: u64,
    /// Senders that found the table full.
    pub drops: u64,
}

impl Neighbours {
    /// The neighbours, oldest first.
    pub fn entries(&self) -> &[Neighbour] {
        &self.entries
    }

    /// Takes an LLDPDU (the Ethernet payload) from `source` at `now_ns`; what it changed.
    /// A malformed one is counted and changes nothing.
    pub fn on_lldpdu(
        &mut self,
        source: MacAddress,
        pdu: &[u8],
        now_ns: u64,
    ) -> Option<NeighbourChange> {
        let Ok(repr) = Packet::new_checked(pdu).and_then(|p| lldp::Repr::parse(&p)) else {
            self.stats.frames_discarded += 1;
            return None;
        };
        self.stats.frames_in += 1;
        let at = self
            .entries
            .iter()
            .position(|e| e.chassis_id == repr.chassis_id && e.port_id == repr.port_id);
        if repr.ttl == 0 {
            let e = self.entries.remove(at?);
            return Some(self.removed(e.index));
        }
        if let Some(i) = at {
            let e = &mut self.entries[i];
            e.updated_ns = now_ns;
            e.source = source;
            let same = e.ttl == repr.ttl && e.tlvs == repr.tlvs;
            e.ttl = repr.ttl;
            e.tlvs = repr.tlvs;
            if same {
                return None;
            }
            self.changes += 1;
            return Some(NeighbourChange::Changed(self.entries[i].index));
        }
        if self.entries.len() == MAX_NEIGHBOURS {
            // The one closest to its end makes room.
            self.stats.drops += 1;
            let soonest = (0..self.entries.len()).min_by_key(|&i| self.entries[i].expires_ns())?;
            self.entries.remove(soonest);
            self.stats.deletes += 1;
        }
        self.next_index = self.next_index.wrapping_add(1).max(1);
        let index = self.next_index;
        self.entries.push(Neighbour {
            index,
            source,
            chassis_id: repr.chassis_id,
            port_id: repr.port_id,
            ttl: repr.ttl,
            tlvs: repr.tlvs,
            since_ns: now_ns,
            updated_ns: now_ns,
        });
        self.stats.inserts += 1;
        self.changes += 1;
        Some(NeighbourChange::Added(index))
    }

    /// Ages the table at `now_ns`: the neighbours whose TTL ran out go. Their indices.
    pub fn age(&mut self, now_ns: u64) -> Vec<u32> {
        let mut gone = Vec::new();
        self.entries.retain(|e| {
            let keep = now_ns < e.expires_ns();
            if !keep {
                gone.push(e.index);
            }
            keep
        });
        for _ in &gone {
            self.stats.ageouts += 1;
            self.stats.deletes += 1;
            self.changes += 1;
        }
        gone
    }

    /// When the next entry ages out, if any.
    pub fn next_deadline_ns(&self) -> Option<u64> {
        self.entries.iter().map(Neighbour::expires_ns).min()
    }

    /// Forgets every neighbour (the link went down). Their indices.
    pub fn clear(&mut self) -> Vec<u32> {
        let gone: Vec<u32> = self.entries.drain(..).map(|e| e.index).collect();
        for _ in &gone {
            self.stats.deletes += 1;
            self.changes += 1;
        }
        gone
    }

    /// The device's alias name from its one neighbour: `<peer port>.<peer station>`, as
    /// PROFINET's topology-based naming derives it; `None` without exactly one PROFINET
    /// neighbour.
    pub fn alias_name(&self) -> Option<String> {
        let [n] = self.entries.as_slice() else {
            return None;
        };
        Some(format!("{}.{}", n.peer_port()?, n.peer_station()?))
    }

    fn removed(&mut self, index: u32) -> NeighbourChange {
        self.stats.deletes += 1;
        self.changes += 1;
        NeighbourChange::Removed(index)
    }
}

#[cfg(test)]
mod tests;
