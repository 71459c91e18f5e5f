// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station as the network knows it: its identity (name, address, MAC, vendor and
//! device ID) as DCP answers and sets it, what DCP set to be kept across a restart, the
//! I&M records, the LLDP announcer that tells the neighbour, the DCP Hello at start-up and
//! the Signal requests. One part of the [`Device`](super::Device), which holds it as a
//! field: [`Device::station`](super::Device::station) to read it,
//! [`Device::station_mut`](super::Device::station_mut) to set it up.
//!
//! Nothing here touches the AR: a DCP change that ends it is the device's business
//! ([`Station::after_dcp`] says what changed).

use super::dcp::{self, Changes};
use super::{DeviceAction, ImRecords, KeptIdentity};
use crate::port::lldp;
use crate::port::neighbours::{NeighbourChange, Neighbours};
use crate::wire::MacAddress;
use crate::wire::record::Im0;

/// The station part of a device.
pub struct Station {
    pub(super) id: dcp::Identity,
    pub(super) kept: KeptIdentity,
    pub(super) im0: Im0,
    pub(super) im: ImRecords,
    pub(super) im_writes: u64,
    lldp: Option<lldp::Announcer>,
    /// The port's LLDP neighbours.
    neighbours: Neighbours,
    /// The PLC's PDPortDataAdjust makes the port a peer-to-peer boundary: no LLDP goes out
    /// (the neighbour's still come in).
    lldp_boundary: bool,
    /// The PLC's PDPortDataAdjust keeps DCP Hello multicasts from leaving the port.
    hello_boundary: bool,
    /// A DCP Hello request is to go out at the next poll.
    hello_due: bool,
    signals: u32,
}

impl Station {
    /// The station of `id` with I&M0 `im0`, announcing itself by LLDP.
    pub(super) fn new(id: dcp::Identity, im0: Im0) -> Station {
        let mut station = Station {
            id,
            kept: KeptIdentity::default(),
            im0,
            im: ImRecords::default(),
            im_writes: 0,
            lldp: None,
            neighbours: Neighbours::default(),
            lldp_boundary: false,
            hello_boundary: false,
            hello_due: false,
            signals: 0,
        };
        station.set_lldp(true);
        station
    }

    /// Turns the LLDP announcements of the device's port on (the default) or off. On, the
    /// port (port-001, from the device's MAC address) announces the station at the next
    /// poll, then every 5 s and at once after DCP changed its name or address; see
    /// [`lldp`].
    pub fn set_lldp(&mut self, on: bool) {
        if on == self.lldp.is_some() {
            return;
        }
        self.lldp = on.then(|| {
            let id = &self.id;
            let ip = (id.ip != [0; 4]).then_some(id.ip);
            let mut station = lldp::LldpStation::new(&id.name, id.mac, id.mac, ip, 1);
            station.system_identification =
                lldp::system_identification(&id.type_of_station, &self.im0);
            lldp::Announcer::new(station)
        });
    }

    /// Makes the device send a DCP Hello request (to 01:0E:CF:00:00:01, with its name, IP
    /// parameters, DeviceID, DeviceVendor, DeviceRole and DeviceInitiative) at its next
    /// poll: at start-up when set before the first poll, as a device with fast start-up
    /// does. Its DeviceInitiative (DCP 06/01) reads 1 while this is on. Off by default.
    pub fn set_hello(&mut self, on: bool) {
        self.id.hello = on;
        self.hello_due = on;
    }

    /// The LLDP announcer, when LLDP is on: what it announces.
    pub fn lldp(&self) -> Option<&lldp::Announcer> {
        self.lldp.as_ref()
    }

    /// The LLDP announcer, when LLDP is on, to tell it about the port (its link, its
    /// ifIndex, its own MAC address). The name and the address follow DCP; setting them
    /// here is overwritten by the next DCP change.
    pub fn lldp_mut(&mut self) -> Option<&mut lldp::Announcer> {
        self.lldp.as_mut()
    }

    /// The port's LLDP neighbours, as received.
    pub fn neighbours(&self) -> &Neighbours {
        &self.neighbours
    }

    /// The alias name the neighbour gives the station, which DCP Identify answers to.
    pub fn alias_name(&self) -> Option<&str> {
        self.id.alias.as_deref()
    }

    /// Takes an LLDPDU received from `source`.
    pub(super) fn on_lldpdu(
        &mut self,
        source: MacAddress,
        pdu: &[u8],
        now_ns: u64,
    ) -> Option<NeighbourChange> {
        let change = self.neighbours.on_lldpdu(source, pdu, now_ns);
        if change.is_some() {
            self.id.alias = self.neighbours.alias_name();
        }
        change
    }

    /// Sets the boundaries a PDPortDataAdjust asks for: no LLDP out of the port
    /// (PeerToPeerBoundary bit 0), no DCP Hello out of it (DCPBoundary bit 1).
    pub(super) fn set_boundaries(&mut self, lldp: bool, hello: bool) {
        self.lldp_boundary = lldp;
        self.hello_boundary = hello;
    }

    /// Whether the port sends no LLDP (a PDPortDataAdjust's peer-to-peer boundary).
    pub fn lldp_boundary(&self) -> bool {
        self.lldp_boundary
    }

    /// The port's link went down: its neighbours are gone with it.
    pub fn link_down(&mut self) {
        if !self.neighbours.clear().is_empty() {
            self.id.alias = None;
        }
    }

    /// Sets the DeviceVendor (type of station) text DCP reports; "procimg simulated device"
    /// by default.
    pub fn set_type_of_station(&mut self, text: &str) {
        self.id.type_of_station = text.to_string();
        let sysid = lldp::system_identification(text, &self.im0);
        if let Some(l) = self.lldp.as_mut() {
            l.update(|s| s.system_identification = sysid);
        }
    }

    /// The IP address (0.0.0.0 when none is set).
    pub fn ip(&self) -> [u8; 4] {
        self.id.ip
    }

    /// Subnet mask and default gateway (0.0.0.0 when none is set).
    pub fn mask_and_gateway(&self) -> ([u8; 4], [u8; 4]) {
        (self.id.mask, self.id.gateway)
    }

    /// Sets the address, subnet mask and gateway, before the device goes on the network
    /// (the configuration's, or what a restart keeps); no AR is touched.
    pub fn set_ip_suite(&mut self, ip: [u8; 4], mask: [u8; 4], gateway: [u8; 4]) {
        (self.id.ip, self.id.mask, self.id.gateway) = (ip, mask, gateway);
        if let Some(l) = self.lldp.as_mut() {
            l.set_ip((ip != [0; 4]).then_some(ip));
        }
    }

    /// Sets the NameOfStation before the device goes on the network (what a restart
    /// keeps); no AR is touched.
    pub fn set_name(&mut self, name: &str) {
        self.id.name = name.to_owned();
        if let Some(l) = self.lldp.as_mut() {
            l.set_name(name);
        }
    }

    /// What DCP set to be kept across a restart (a Set with the permanent qualifier, a reset
    /// to factory): the caller stores it and gives it back at the next start.
    pub fn kept_identity(&self) -> &KeptIdentity {
        &self.kept
    }

    /// The NameOfStation (empty when none is set).
    pub fn name(&self) -> &str {
        &self.id.name
    }

    /// The MAC address.
    pub fn mac(&self) -> MacAddress {
        self.id.mac
    }

    /// DCP Signal requests received (each one would flash the LED).
    pub fn signal_count(&self) -> u32 {
        self.signals
    }

    /// I&M1–I&M4 as they are now (blanks until written).
    pub fn im_records(&self) -> &ImRecords {
        &self.im
    }

    /// Sets I&M1–I&M4, e.g. to what a runtime stored before a restart.
    pub fn set_im_records(&mut self, records: ImRecords) {
        self.im = records;
    }

    /// How many writes of I&M1–I&M4 the device took since it was made: a runtime that keeps
    /// them stores [`im_records`](Self::im_records) again when this changes.
    pub fn im_write_count(&self) -> u64 {
        self.im_writes
    }

    /// Takes in what a DCP request changed: the Signal count, what is to be kept, and the
    /// name and address the neighbour learns at once.
    pub(super) fn after_dcp(&mut self, changes: &Changes) {
        if changes.signal {
            self.signals = self.signals.saturating_add(1);
        }
        if changes.store_name {
            self.kept.name = Some(self.id.name.clone());
        }
        if changes.store_ip {
            self.kept.ip_suite = Some([self.id.ip, self.id.mask, self.id.gateway]);
        }
        if changes.store_name || changes.store_ip {
            self.kept.changes += 1;
        }
        if let Some(l) = self.lldp.as_mut() {
            let ip = (self.id.ip != [0; 4]).then_some(self.id.ip);
            l.set_name(&self.id.name);
            l.set_ip(ip);
            if changes.reset {
                l.set_mode(lldp::NameOfDeviceMode::default());
            }
        }
    }

    /// Where the LLDP frames carry the name, as a PDInterfaceAdjust set it.
    pub(super) fn set_lldp_mode(&mut self, mode: lldp::NameOfDeviceMode) {
        if let Some(l) = self.lldp.as_mut() {
            l.set_mode(mode);
        }
    }

    /// The station's frames due at `now_ns`: the Hello at start-up, LLDP announcements.
    pub(super) fn poll(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if std::mem::take(&mut self.hello_due) && !self.hello_boundary {
            out.extend(dcp::hello_frame(&self.id).map(DeviceAction::Frame));
        }
        // The announcer keeps its schedule behind a boundary, so that it speaks again at
        // once when the boundary goes.
        if let Some(frame) = self.lldp.as_mut().and_then(|l| l.poll(now_ns))
            && !self.lldp_boundary
        {
            out.push(DeviceAction::Frame(frame));
        }
        if !self.neighbours.age(now_ns).is_empty() {
            self.id.alias = self.neighbours.alias_name();
        }
    }

    /// When the station needs a poll next.
    pub(super) fn next_deadline_ns(&self) -> Option<u64> {
        [
            self.hello_due.then_some(0),
            self.lldp.as_ref().map(lldp::Announcer::next_deadline_ns),
            self.neighbours.next_deadline_ns(),
        ]
        .into_iter()
        .flatten()
        .min()
    }
}
