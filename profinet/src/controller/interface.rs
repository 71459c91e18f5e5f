// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own PROFINET interface, as IO-Base's `PNIO_interface_*` functions show
//! it to programs: the interface submodule 0x8000 and its port 0x8001 in slot 0, with
//!
//! - their records, read-only: the physical device's (PDInterfaceDataReal 0x8080,
//!   PDPortDataReal 0x802A, PDPortStatistic 0x8072, PDRealData 0xF841, the port's expected
//!   PDPortDataCheck 0x802B) and their diagnosis (0x800A–0x8013 of a submodule, 0xC00A–
//!   0xC013 of slot 0, 0xF80C);
//! - the station's NameOfStation and IP suite, set by a program or by DCP from an
//!   engineering tool where the configuration lets them change ([`InterfaceSetup`]); every
//!   change is an event, for the runtime to carry out on the host and tell the programs;
//! - the port's topology check, against the neighbour the configuration gives the
//!   controller's port and, when asked, its link: a mismatch is a diagnosis of the port,
//!   announced and withdrawn by a PortDataChangeNotification alarm (AlarmType 0x000E) as a
//!   device announces its own ([`crate::port::check`]).
//!
//! The controller has no GSDML: its interface's module and submodule idents are procimg's
//! ([`MODULE_IDENT`], [`INTERFACE_SUBMODULE_IDENT`], [`PORT_SUBMODULE_IDENT`]).

use super::{Controller, ControllerAction, DeviceEvent};
use crate::device::diagnosis::records::{DiagnosisScope, diagnosis_index};
use crate::device::diagnosis::{DiagnosisAlarm, DiagnosisStore, SubslotAddr};
use crate::device::topology::entry;
use crate::port::check::{Finding, topology_findings};
use crate::port::dcp_station::{Settable, valid_ip, valid_name};
use crate::port::physical::{Physical, PhysicalView, PortCounters, PortLink};
use crate::wire::alarm::AlarmType;
use crate::wire::record::{
    CheckedPeer, INDEX_PD_INTERFACE_DATA_REAL, INDEX_PD_PORT_DATA_CHECK, INDEX_PD_PORT_DATA_REAL,
    INDEX_PD_PORT_STATISTIC, INDEX_PD_REAL_DATA, PdPortDataCheck, PortCheck, RecordErrorCode,
};
use std::net::Ipv4Addr;

/// The interface submodule's subslot.
pub const INTERFACE_SUBSLOT: u16 = 0x8000;
/// The port submodule's subslot.
pub const PORT_SUBSLOT: u16 = 0x8001;
/// The ModuleIdentNumber of slot 0 of the controller's station.
pub const MODULE_IDENT: u32 = 0x0000_0100;
/// The interface submodule's SubmoduleIdentNumber.
pub const INTERFACE_SUBMODULE_IDENT: u32 = 0x0000_8000;
/// The port submodule's SubmoduleIdentNumber.
pub const PORT_SUBMODULE_IDENT: u32 = 0x0000_8001;

/// How the configuration sets up the controller's interface.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InterfaceSetup {
    /// What a program or DCP may change of the station.
    pub settable: Settable,
    /// The neighbour the port is to face: its NameOfStation and port (`port-001`).
    pub peer: Option<(String, String)>,
    /// Whether the port's link is checked: down is a fault.
    pub check_link: bool,
    /// The station's netmask (its address is the controller identity's).
    pub netmask: Ipv4Addr,
    /// Its default gateway (0.0.0.0: none).
    pub gateway: Ipv4Addr,
}

impl Default for InterfaceSetup {
    /// Name and address the configuration's, nothing checked.
    fn default() -> InterfaceSetup {
        InterfaceSetup {
            settable: Settable::all(false),
            peer: None,
            check_link: false,
            netmask: Ipv4Addr::UNSPECIFIED,
            gateway: Ipv4Addr::UNSPECIFIED,
        }
    }
}

/// A new NameOfStation or IP suite of the controller's station.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct StationAddress {
    /// The new name, if it changes.
    pub name: Option<String>,
    /// The new address, netmask and gateway, if they change.
    pub ip_suite: Option<[Ipv4Addr; 3]>,
    /// To be kept across a restart.
    pub permanent: bool,
}

/// Why a new name or address was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum AddressError {
    /// The configuration keeps it.
    #[error(
        "the controller's {what} is the configuration's: set `{key} = true` in [interface] to \
         let programs and DCP change it"
    )]
    NotAllowed {
        /// What was to change.
        what: &'static str,
        /// The configuration key that allows it.
        key: &'static str,
    },
    /// Not a NameOfStation.
    #[error(
        "{0:?} is not a NameOfStation: up to 240 characters of dot-separated labels of lower-case \
         letters, digits and inner hyphens, neither an IPv4 address nor a port name"
    )]
    Name(String),
    /// The controller needs a name.
    #[error("the controller's station needs a NameOfStation: an empty one is refused")]
    NoName,
    /// The host could not carry it out.
    #[error("{0}")]
    NotCarriedOut(String),
    /// Not an IP suite a station can have.
    #[error(
        "{ip} with netmask {mask} and gateway {gateway} is not an IP suite: a unicast address, a \
         contiguous netmask, and no gateway (0.0.0.0) or one in the subnet"
    )]
    Ip {
        /// The address.
        ip: Ipv4Addr,
        /// The netmask.
        mask: Ipv4Addr,
        /// The gateway.
        gateway: Ipv4Addr,
    },
}

/// The interface's state beside the controller's identity.
#[derive(Debug, Default)]
pub(super) struct OwnInterface {
    setup: InterfaceSetup,
    pub(super) physical: Physical,
    pub(super) mask: [u8; 4],
    pub(super) gateway: [u8; 4],
    /// The port's check, from the setup (none: nothing to check).
    check: Option<PdPortDataCheck>,
    /// The findings raised as diagnosis of the port.
    raised: Vec<Finding>,
    /// What the check depended on when last made (`None`: check now).
    seen: Option<(u64, bool, u16)>,
    diagnosis: DiagnosisStore,
    /// The port's alarm sequence number.
    sequence: u16,
}

impl Controller {
    /// Sets up the controller's own interface: what of its station may change, and what its
    /// port is checked against (from the next poll on).
    pub fn set_up_interface(&mut self, setup: InterfaceSetup) {
        let mut checks = Vec::new();
        if let Some((station, port)) = &setup.peer {
            checks.push(PortCheck::Peers(vec![CheckedPeer {
                port_id: port.clone(),
                chassis_id: station.clone(),
            }]));
        }
        if setup.check_link {
            checks.push(PortCheck::LinkState(1));
        }
        self.interface.check = (!checks.is_empty()).then_some(PdPortDataCheck {
            slot: 0,
            subslot: PORT_SUBSLOT,
            checks,
        });
        if !self.id.ip.is_unspecified() {
            self.interface.mask = setup.netmask.octets();
            self.interface.gateway = setup.gateway.octets();
        }
        self.interface.setup = setup;
        self.interface.seen = None;
        self.sync_station_identity();
    }

    /// Tells the controller its port's link, as its runtime reads it from the interface.
    pub fn set_port_link(&mut self, link: PortLink) {
        if self.interface.physical.link.up && !link.up {
            self.neighbours.clear();
        }
        if self.interface.physical.link.mau_type != link.mau_type
            && let Some(l) = self.lldp.as_mut()
        {
            l.update(|s| s.link.mau_type = link.mau_type);
        }
        self.interface.physical.link = link;
    }

    /// Tells the controller its interface's counters (`None`: it has none to read).
    pub fn set_port_counters(&mut self, counters: Option<PortCounters>) {
        self.interface.physical.counters = counters;
    }

    /// The station's NameOfStation and IP suite (address, netmask, gateway).
    pub fn station_address(&self) -> (&str, [Ipv4Addr; 3]) {
        (
            &self.id.station_name,
            [
                self.id.ip,
                Ipv4Addr::from(self.interface.mask),
                Ipv4Addr::from(self.interface.gateway),
            ],
        )
    }

    /// Whether `change` may be made: allowed by the configuration, a valid name and suite.
    pub fn check_station_address(&self, change: &StationAddress) -> Result<(), AddressError> {
        let allowed = self.interface.setup.settable;
        if let Some(name) = &change.name {
            if !allowed.name {
                return Err(AddressError::NotAllowed {
                    what: "NameOfStation",
                    key: "name_by_program",
                });
            }
            if name.is_empty() {
                return Err(AddressError::NoName);
            }
            if !valid_name(name) {
                return Err(AddressError::Name(name.clone()));
            }
        }
        if let Some([ip, mask, gateway]) = change.ip_suite {
            if !allowed.ip {
                return Err(AddressError::NotAllowed {
                    what: "IP suite",
                    key: "address_by_program",
                });
            }
            if ip.is_unspecified() || !valid_ip(ip.octets(), mask.octets(), gateway.octets()) {
                return Err(AddressError::Ip { ip, mask, gateway });
            }
        }
        Ok(())
    }

    /// Gives the station a new name or IP suite, where [`check_station_address`] allows
    /// it: DCP, LLDP, the interface's records and the ARs connected from now on use it.
    /// The runtime carries out the address on the host.
    ///
    /// [`check_station_address`]: Self::check_station_address
    pub fn set_station_address(&mut self, change: &StationAddress) -> Result<(), AddressError> {
        self.check_station_address(change)?;
        self.take_station_address(change);
        Ok(())
    }

    /// Takes a checked change.
    fn take_station_address(&mut self, change: &StationAddress) {
        if let Some(name) = &change.name {
            self.id.station_name.clone_from(name);
            if let Some(l) = self.lldp.as_mut() {
                l.set_name(name);
            }
        }
        if let Some([ip, mask, gateway]) = change.ip_suite {
            self.id.ip = ip;
            self.interface.mask = mask.octets();
            self.interface.gateway = gateway.octets();
            if let Some(l) = self.lldp.as_mut() {
                l.set_ip(Some(ip.octets()));
            }
        }
        self.sync_station_identity();
    }

    /// A DCP Set changed the station's name or address (`changes` says which): the rest of
    /// the controller follows, and the runtime is told.
    pub(super) fn on_dcp_address(
        &mut self,
        name: Option<String>,
        ip_suite: Option<[Ipv4Addr; 3]>,
        permanent: bool,
        out: &mut Vec<ControllerAction>,
    ) {
        let change = StationAddress {
            name,
            ip_suite,
            permanent,
        };
        self.take_station_address(&change);
        out.push(ControllerAction::Event(DeviceEvent::StationAddress {
            change,
            reference: None,
            result: Ok(()),
        }));
    }

    /// What DCP may change of the station.
    pub(super) fn dcp_settable(&self) -> Settable {
        self.interface.setup.settable
    }

    /// Reads record `index` of the interface's subslot `subslot` (0: the interface, as
    /// PDInterfaceDataReal allows), or of slot 0 as a whole where the record covers it.
    pub fn read_interface_record(
        &self,
        subslot: u16,
        index: u16,
    ) -> Result<Vec<u8>, RecordErrorCode> {
        let ours = [INTERFACE_SUBSLOT, PORT_SUBSLOT];
        let emitted =
            |r: crate::wire::EmitResult<Vec<u8>>| r.map_err(|_| RecordErrorCode::ReadError);
        let view = self.physical_view();
        match index {
            INDEX_PD_REAL_DATA => emitted(view.real_data(ours.map(|s| (0, 0, s)))),
            INDEX_PD_INTERFACE_DATA_REAL if subslot == INTERFACE_SUBSLOT || subslot == 0 => {
                emitted(view.interface_data_real().to_vec())
            }
            INDEX_PD_PORT_DATA_REAL if subslot == PORT_SUBSLOT => {
                emitted(view.port_data_real(0, PORT_SUBSLOT).to_vec())
            }
            INDEX_PD_PORT_STATISTIC if ours.contains(&subslot) => {
                emitted(view.statistic().to_vec())
            }
            INDEX_PD_PORT_DATA_CHECK if subslot == PORT_SUBSLOT => match &self.interface.check {
                Some(c) => emitted(c.to_vec()),
                None => Ok(Vec::new()),
            },
            _ if !ours.contains(&subslot) && subslot != 0 => {
                Err(RecordErrorCode::InvalidSlotSubslot)
            }
            _ => match diagnosis_index(index) {
                Some((scope, selection)) => {
                    let scope: Vec<SubslotAddr> = match scope {
                        DiagnosisScope::Subslot if subslot == 0 => {
                            return Err(RecordErrorCode::InvalidSlotSubslot);
                        }
                        DiagnosisScope::Subslot => vec![SubslotAddr::new(0, 0, subslot)],
                        _ => ours.map(|s| SubslotAddr::new(0, 0, s)).to_vec(),
                    };
                    emitted(self.interface.diagnosis.record(selection, scope))
                }
                None => Err(RecordErrorCode::InvalidIndex),
            },
        }
    }

    /// The interface as the physical records describe it.
    fn physical_view(&self) -> PhysicalView<'_> {
        PhysicalView {
            name: &self.id.station_name,
            mac: self.id.mac,
            ip_suite: [
                self.id.ip.octets(),
                self.interface.mask,
                self.interface.gateway,
            ],
            own_port_id: crate::controller::port_id(PORT_SUBSLOT),
            physical: &self.interface.physical,
            neighbours: &self.neighbours,
        }
    }

    /// Checks the port again when its neighbourhood or link changed: raises and withdraws
    /// its findings as diagnosis, each announced by a PortDataChangeNotification alarm.
    pub(super) fn check_port(&mut self, out: &mut Vec<ControllerAction>) {
        let Some(check) = &self.interface.check else {
            return;
        };
        let link = &self.interface.physical.link;
        let inputs = (self.neighbours.changes, link.up, link.mau_type);
        if self.interface.seen == Some(inputs) {
            return;
        }
        self.interface.seen = Some(inputs);
        let now = topology_findings(check, &self.neighbours, link);
        let at = SubslotAddr::new(0, 0, PORT_SUBSLOT);
        let iface = &mut self.interface;
        let mut alarms: Vec<DiagnosisAlarm> = Vec::new();
        for gone in iface.raised.iter().filter(|f| !now.contains(f)) {
            alarms.extend(iface.diagnosis.remove(at, &entry(*gone).key()));
        }
        for came in now.iter().filter(|f| !iface.raised.contains(f)) {
            if let Ok(a) = iface.diagnosis.add(at, entry(*came)) {
                alarms.extend(a);
            }
        }
        iface.raised = now;
        for mut a in alarms {
            a.alarm_type = AlarmType::PortDataChange;
            iface.sequence =
                (iface.sequence + 1) & crate::wire::alarm::AlarmSpecifier::SEQUENCE_MASK;
            let notification =
                a.notification(MODULE_IDENT, PORT_SUBMODULE_IDENT, iface.sequence, false);
            out.push(ControllerAction::Event(DeviceEvent::InterfaceAlarm(
                Box::new(notification),
            )));
        }
    }
}
