// SPDX-License-Identifier: MIT OR Apache-2.0
//! Configuration control for IO systems ("tailoring", IO-Base's `PNIO_iosystem_reconfig`):
//! one engineered IO system for every variant of a machine. Some devices are optional, and
//! some ports have a programmable peer: a neighbour that depends on how the machine is
//! built. The program says which optional devices are present and which ports are joined;
//! the controller takes every device down, writes each joined port's expected neighbour as
//! its topology check (PDPortDataCheck, with the device's other parameter records at
//! connect), and brings up the mandatory devices and the optional ones present.

use super::plan::PlannedRecord;
use super::{Controller, ControllerAction, DeviceEvent};
use crate::wire::record::{CheckedPeer, INDEX_PD_PORT_DATA_CHECK, PdPortDataCheck, PortCheck};

/// One end of a port interconnection: a port submodule of a device.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PortEnd {
    /// Device index.
    pub device: usize,
    /// The port's slot (0).
    pub slot: u16,
    /// The port's subslot (0x8001 …).
    pub subslot: u16,
}

/// What a reconfiguration does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Reconfiguration {
    /// Deactivate every device (IO-Base's `PNIO_IOS_RECONFIG_MODE_DEACT`).
    Deactivate,
    /// Tailor (IO-Base's `PNIO_IOS_RECONFIG_MODE_TAILOR`): the optional devices present and
    /// the ports joined; then every mandatory device and the optional ones present come up.
    Tailor {
        /// The optional devices the machine has.
        optional_present: Vec<usize>,
        /// The ports joined, in pairs.
        links: Vec<(PortEnd, PortEnd)>,
    },
}

/// Why a tailoring was refused (nothing was changed then).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TailorError {
    /// No device of that index.
    NoSuchDevice(usize),
    /// The device is not optional: a mandatory device is always present.
    NotOptional(usize),
    /// The port has no programmable peer (it is no port, or its neighbour is fixed).
    NotProgrammable(PortEnd),
    /// The port is joined twice.
    PortTwice(PortEnd),
}

impl core::fmt::Display for TailorError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TailorError::NoSuchDevice(d) => write!(f, "there is no device {d}"),
            TailorError::NotOptional(d) => write!(
                f,
                "device {d} is not optional: name only devices configured with optional = true"
            ),
            TailorError::NotProgrammable(e) => write!(
                f,
                "slot {} subslot {:#06x} of device {} is no port with a programmable peer \
                 (programmable = true in its topology)",
                e.slot, e.subslot, e.device
            ),
            TailorError::PortTwice(e) => write!(
                f,
                "slot {} subslot {:#06x} of device {} is joined twice: a port has one neighbour",
                e.slot, e.subslot, e.device
            ),
        }
    }
}

/// The PortID a port announces by LLDP (`port-001` for subslot 0x8001).
pub fn port_id(subslot: u16) -> String {
    format!("port-{:03}", subslot & 0x00ff)
}

impl Controller {
    /// Reconfigures the IO system; the outcome comes as [`DeviceEvent::Reconfigured`].
    pub fn reconfigure(&mut self, how: Reconfiguration, now: u64, out: &mut Vec<ControllerAction>) {
        let result = match how {
            Reconfiguration::Deactivate => {
                self.bring_up(|_| false, now, out);
                Ok(false)
            }
            Reconfiguration::Tailor {
                optional_present,
                links,
            } => self
                .check_tailoring(&optional_present, &links)
                .map(|checks| {
                    self.bring_up(|_| false, now, out);
                    self.set_port_checks(checks);
                    let present = |d: usize| optional_present.contains(&d);
                    let optional: Vec<bool> =
                        self.devices.iter().map(|d| d.plan.optional).collect();
                    self.bring_up(|d| !optional[d] || present(d), now, out);
                    true
                }),
        };
        out.push(ControllerAction::Event(DeviceEvent::Reconfigured {
            result,
        }));
    }

    /// The topology checks the links give, per port; or why the tailoring is refused.
    fn check_tailoring(
        &self,
        optional_present: &[usize],
        links: &[(PortEnd, PortEnd)],
    ) -> Result<Vec<(PortEnd, Vec<u8>)>, TailorError> {
        for &d in optional_present {
            let plan = &self
                .devices
                .get(d)
                .ok_or(TailorError::NoSuchDevice(d))?
                .plan;
            if !plan.optional {
                return Err(TailorError::NotOptional(d));
            }
        }
        let mut checks: Vec<(PortEnd, Vec<u8>)> = Vec::new();
        for &(a, b) in links {
            for (end, other) in [(a, b), (b, a)] {
                let plan = &self
                    .devices
                    .get(end.device)
                    .ok_or(TailorError::NoSuchDevice(end.device))?
                    .plan;
                if end.slot != 0 || !plan.programmable_ports.contains(&end.subslot) {
                    return Err(TailorError::NotProgrammable(end));
                }
                let neighbour = &self
                    .devices
                    .get(other.device)
                    .ok_or(TailorError::NoSuchDevice(other.device))?
                    .plan;
                if checks.iter().any(|(e, _)| *e == end) {
                    return Err(TailorError::PortTwice(end));
                }
                let check = PdPortDataCheck {
                    slot: end.slot,
                    subslot: end.subslot,
                    checks: vec![PortCheck::Peers(vec![CheckedPeer {
                        port_id: port_id(other.subslot),
                        chassis_id: neighbour.name.clone(),
                    }])],
                };
                // A station name is at most 240 bytes and a port ID 8: it always fits.
                let data = check
                    .to_vec()
                    .map_err(|_| TailorError::NotProgrammable(end))?;
                checks.push((end, data));
            }
        }
        Ok(checks)
    }

    /// Replaces every programmable port's topology check with the ones given (a port left
    /// out gets none: its neighbour is not checked).
    fn set_port_checks(&mut self, checks: Vec<(PortEnd, Vec<u8>)>) {
        for d in &mut self.devices {
            let ports = d.plan.programmable_ports.clone();
            d.plan.records.retain(|r| {
                !(r.slot == 0 && r.index == INDEX_PD_PORT_DATA_CHECK && ports.contains(&r.subslot))
            });
        }
        for (end, data) in checks {
            if let Some(d) = self.devices.get_mut(end.device) {
                d.plan.records.push(PlannedRecord {
                    api: 0,
                    slot: end.slot,
                    subslot: end.subslot,
                    index: INDEX_PD_PORT_DATA_CHECK,
                    data,
                });
            }
        }
    }

    /// Activates the devices `active` says, deactivates the others (taking their ARs down).
    fn bring_up(
        &mut self,
        active: impl Fn(usize) -> bool,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        for (i, d) in self.devices.iter_mut().enumerate() {
            d.deactivated = !active(i);
            d.set_wanted(self.wanted, &self.id, now, out);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controller::plan::{ControllerIdentity, DevicePlan, DeviceSpec, SubmoduleSpec};
    use crate::controller::{ControllerAction, DeviceState};
    use crate::wire::MacAddress;
    use std::net::Ipv4Addr;

    const MS: u64 = 1_000_000;

    /// Three devices: `mandatory`, and `opt-a` and `opt-b`, optional, each with two ports
    /// whose peers are programmable (port 1 of `mandatory` is fixed).
    fn controller() -> Controller {
        let port = |subslot| SubmoduleSpec {
            slot: 0,
            subslot,
            module_ident: 1,
            submodule_ident: u32::from(subslot),
            ..Default::default()
        };
        let spec = |name: &str, optional: bool, programmable: Vec<u16>| DeviceSpec {
            name: name.into(),
            vendor_id: 0x0493,
            device_id: 1,
            instance: 1,
            reduction_ratio: 1,
            watchdog_factor: 3,
            submodules: vec![
                SubmoduleSpec {
                    slot: 0,
                    subslot: 1,
                    module_ident: 1,
                    submodule_ident: 1,
                    ..Default::default()
                },
                port(0x8001),
                port(0x8002),
            ],
            optional,
            programmable_ports: programmable,
            ..Default::default()
        };
        let specs = [
            spec("mandatory", false, vec![0x8002]),
            spec("opt-a", true, vec![0x8001, 0x8002]),
            spec("opt-b", true, vec![0x8001, 0x8002]),
        ];
        let plans = specs
            .iter()
            .enumerate()
            .map(|(d, s)| DevicePlan::new(d, 0, s, MS).expect("plannable"))
            .collect();
        let id = ControllerIdentity {
            mac: MacAddress([2, 0, 0, 0, 0, 1]),
            ip: Ipv4Addr::new(192, 168, 0, 1),
            station_name: "plc".into(),
            vendor_id: 0x0493,
            device_id: 2,
            instance: 1,
        };
        Controller::new(id, plans, 0, 1)
    }

    fn reconfigured(out: &[ControllerAction]) -> Option<Result<bool, TailorError>> {
        out.iter().find_map(|a| match a {
            ControllerAction::Event(DeviceEvent::Reconfigured { result }) => Some(result.clone()),
            _ => None,
        })
    }

    fn end(device: usize, subslot: u16) -> PortEnd {
        PortEnd {
            device,
            slot: 0,
            subslot,
        }
    }

    fn check_of(c: &Controller, d: usize, subslot: u16) -> Option<PdPortDataCheck> {
        c.plan(d)?
            .records
            .iter()
            .find(|r| r.subslot == subslot && r.index == INDEX_PD_PORT_DATA_CHECK)
            .map(|r| PdPortDataCheck::parse(&r.data).expect("a PDPortDataCheck"))
    }

    #[test]
    fn optional_devices_wait_for_tailoring_and_the_present_ones_come_up() {
        let mut c = controller();
        let mut out = Vec::new();
        c.set_online(true, 0, &mut out);
        let states: Vec<_> = c.states().collect();
        assert_eq!(
            states,
            [
                DeviceState::Searching,
                DeviceState::Deactivated,
                DeviceState::Deactivated
            ]
        );
        out.clear();
        c.reconfigure(
            Reconfiguration::Tailor {
                optional_present: vec![1],
                links: vec![(end(0, 0x8002), end(1, 0x8001))],
            },
            MS,
            &mut out,
        );
        assert_eq!(reconfigured(&out), Some(Ok(true)));
        let states: Vec<_> = c.states().collect();
        assert_eq!(
            states,
            [
                DeviceState::Searching,
                DeviceState::Searching,
                DeviceState::Deactivated
            ]
        );
        // Each end of the link checks the other as its neighbour.
        let a = check_of(&c, 0, 0x8002).expect("mandatory's port 2 is checked");
        assert_eq!(
            a.peers(),
            Some(
                &[CheckedPeer {
                    port_id: "port-001".into(),
                    chassis_id: "opt-a".into()
                }][..]
            )
        );
        let b = check_of(&c, 1, 0x8001).expect("opt-a's port 1 is checked");
        assert_eq!(
            b.peers().map(|p| p[0].chassis_id.as_str()),
            Some("mandatory")
        );
        assert_eq!(b.peers().map(|p| p[0].port_id.as_str()), Some("port-002"));

        // Another variant: the old link's checks go, the new one's come.
        out.clear();
        c.reconfigure(
            Reconfiguration::Tailor {
                optional_present: vec![2],
                links: vec![(end(0, 0x8002), end(2, 0x8001))],
            },
            2 * MS,
            &mut out,
        );
        assert_eq!(reconfigured(&out), Some(Ok(true)));
        assert!(check_of(&c, 1, 0x8001).is_none());
        assert_eq!(
            check_of(&c, 0, 0x8002).and_then(|c| c.peers().map(|p| p[0].chassis_id.clone())),
            Some("opt-b".into())
        );
        let states: Vec<_> = c.states().collect();
        assert_eq!(states[1], DeviceState::Deactivated);

        out.clear();
        c.reconfigure(Reconfiguration::Deactivate, 3 * MS, &mut out);
        assert_eq!(reconfigured(&out), Some(Ok(false)));
        assert!(c.states().all(|s| s == DeviceState::Deactivated));
    }

    #[test]
    fn a_tailoring_naming_what_is_not_tailorable_changes_nothing() {
        let mut c = controller();
        let mut out = Vec::new();
        c.set_online(true, 0, &mut out);
        let refused = |c: &mut Controller, how| {
            let mut out = Vec::new();
            c.reconfigure(how, MS, &mut out);
            reconfigured(&out)
                .expect("an outcome")
                .expect_err("refused")
        };
        let tailor = |present: Vec<usize>, links| Reconfiguration::Tailor {
            optional_present: present,
            links,
        };
        assert_eq!(
            refused(&mut c, tailor(vec![0], vec![])),
            TailorError::NotOptional(0)
        );
        assert_eq!(
            refused(&mut c, tailor(vec![7], vec![])),
            TailorError::NoSuchDevice(7)
        );
        assert_eq!(
            refused(
                &mut c,
                tailor(vec![], vec![(end(0, 0x8001), end(1, 0x8001))])
            ),
            TailorError::NotProgrammable(end(0, 0x8001)),
            "port 1 of the mandatory device has a fixed neighbour"
        );
        assert_eq!(
            refused(
                &mut c,
                tailor(
                    vec![1, 2],
                    vec![
                        (end(1, 0x8002), end(2, 0x8001)),
                        (end(1, 0x8002), end(0, 0x8002))
                    ]
                )
            ),
            TailorError::PortTwice(end(1, 0x8002))
        );
        let states: Vec<_> = c.states().collect();
        assert_eq!(
            states[0],
            DeviceState::Searching,
            "the mandatory device kept going"
        );
        assert!(check_of(&c, 1, 0x8002).is_none());
    }
}
