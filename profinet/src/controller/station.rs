// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's own station on its interface, as DCP sees it: an engineering tool's or a
//! network manager's Identify finds it (DeviceRole IO controller, its NameOfStation, IP
//! suite, type of station, the alias its LLDP neighbour gives it), a Get reads it, and a
//! Signal makes it flash its LED. A Set of its name or address is carried out where the
//! configuration lets them change ([`super::InterfaceSetup`]), and refused ("set not
//! possible") where it does not; a reset to factory is refused always, as the controller
//! cannot be without a name.

use super::{Controller, ControllerAction, DeviceEvent};
use crate::port::dcp_station::{
    DcpAnswers, DcpIdentity, DcpRequest, ROLE_IO_CONTROLLER, Settable, answer_set,
    is_request_frame_id,
};
use crate::wire::MacAddress;
use crate::wire::dcp::{self, BlockRepr, ServiceType};
use crate::wire::ethernet::{ETHERTYPE_PROFINET, Frame};
use std::net::Ipv4Addr;

/// The controller's station and its pending Identify responses.
#[derive(Debug)]
pub(super) struct OwnStation {
    identity: DcpIdentity,
    answers: DcpAnswers,
}

impl Controller {
    /// Makes the controller's own station answer DCP, as `type_of_station` with the
    /// controller's name, MAC and IP suite (its netmask and gateway those of
    /// [`set_up_interface`](Self::set_up_interface)), from now on (off until called).
    pub fn answer_dcp(&mut self, type_of_station: &str) {
        self.station = Some(OwnStation {
            identity: DcpIdentity {
                mac: self.id.mac,
                name: self.id.station_name.clone(),
                ip: self.id.ip.octets(),
                mask: self.interface.mask,
                gateway: self.interface.gateway,
                vendor_id: self.id.vendor_id,
                device_id: self.id.device_id,
                instance: self.id.instance,
                type_of_station: type_of_station.to_owned(),
                role: ROLE_IO_CONTROLLER,
                hello: false,
                alias: None,
            },
            answers: DcpAnswers::default(),
        });
    }

    /// A DCP request to the controller's own station: answered (`true`); `false` for any
    /// other frame.
    pub(super) fn on_station_frame(
        &mut self,
        eth: &Frame<&[u8]>,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) -> bool {
        let Some(station) = self.station.as_mut() else {
            return false;
        };
        if eth.ethertype() != ETHERTYPE_PROFINET || eth.src() == station.identity.mac {
            return false;
        }
        let (dst, src, pdu) = (eth.dst(), eth.src(), eth.payload());
        // Requests only: a device's Set response has the Set request's FrameID, and is the
        // controller's DCP client's.
        let request = dcp::Packet::new_checked(pdu).is_ok_and(|p| {
            is_request_frame_id(p.frame_id()) && p.service_type() == ServiceType::Request
        });
        if !request || (dst != station.identity.mac && dst != MacAddress::DCP_IDENTIFY) {
            return false;
        }
        let mut frames = Vec::new();
        let req = station
            .answers
            .on_pdu(&station.identity, dst, src, pdu, now, &mut frames);
        if let DcpRequest::Set(req) = req {
            let settable = self.dcp_settable();
            let Some(station) = self.station.as_mut() else {
                return true;
            };
            // A reset to factory would leave the controller without a name: refused.
            let reset = req.blocks.iter().any(|b| {
                matches!(
                    b.value,
                    BlockRepr::ResetToFactory(_) | BlockRepr::FactoryReset(_)
                )
            });
            let allow = if reset {
                Settable::all(false)
            } else {
                settable
            };
            let changes = answer_set(&mut station.identity, src, &req, allow, &mut frames);
            let id = &station.identity;
            let name = changes.name.then(|| id.name.clone());
            let ip_suite = changes
                .ip
                .then(|| [id.ip, id.mask, id.gateway].map(Ipv4Addr::from));
            if name.is_some() || ip_suite.is_some() {
                let permanent = changes.store_name || changes.store_ip;
                self.on_dcp_address(name, ip_suite, permanent, out);
            }
            if changes.signal {
                out.push(ControllerAction::Event(DeviceEvent::Signal));
            }
        }
        out.extend(frames.into_iter().map(ControllerAction::Frame));
        true
    }

    /// Brings the DCP side up to date with the controller's name, address and neighbour.
    pub(super) fn sync_station_identity(&mut self) {
        let alias = self.neighbours.alias_name();
        if let Some(station) = self.station.as_mut() {
            let id = &mut station.identity;
            id.name.clone_from(&self.id.station_name);
            id.ip = self.id.ip.octets();
            id.mask = self.interface.mask;
            id.gateway = self.interface.gateway;
            id.alias = alias;
        }
    }

    /// Sends the station's Identify responses whose delay is over.
    pub(super) fn poll_station(&mut self, now: u64, out: &mut Vec<ControllerAction>) {
        if let Some(station) = self.station.as_mut() {
            let mut frames = Vec::new();
            station.answers.poll(now, &mut frames);
            out.extend(frames.into_iter().map(ControllerAction::Frame));
        }
    }

    /// When the station's next delayed response is due.
    pub(super) fn station_deadline_ns(&self) -> Option<u64> {
        self.station.as_ref()?.answers.next_deadline_ns()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controller::plan::ControllerIdentity;
    use crate::wire::dcp::{Block, BlockRepr, ServiceId, block_error};
    use crate::wire::ethernet::profinet_frame;
    use std::net::Ipv4Addr;

    const TOOL: MacAddress = MacAddress([2, 0, 0, 0, 0, 0x77]);
    const OWN: MacAddress = MacAddress([2, 0, 0, 0, 0, 1]);

    fn controller() -> Controller {
        let id = ControllerIdentity {
            mac: OWN,
            ip: Ipv4Addr::new(192, 168, 0, 1),
            station_name: "plc-line-1".into(),
            vendor_id: 0x0493,
            device_id: 0x0fff,
            instance: 1,
        };
        let mut c = Controller::new(id, Vec::new(), 0, 1);
        c.set_up_interface(crate::controller::InterfaceSetup {
            netmask: Ipv4Addr::new(255, 255, 255, 0),
            ..Default::default()
        });
        c.answer_dcp("procimg controller");
        c
    }

    /// A DCP request from the tool to `dst`.
    fn request(dst: MacAddress, frame_id: u16, service: ServiceId, blocks: Vec<Block>) -> Vec<u8> {
        let repr = dcp::Repr {
            frame_id,
            service_id: service,
            service_type: ServiceType::Request,
            xid: 0x1234,
            response_delay: 0,
            blocks,
        };
        profinet_frame(dst, TOOL, None, &repr.to_vec().unwrap())
    }

    /// What the controller sent back, parsed.
    fn answers(out: &[ControllerAction]) -> Vec<dcp::Repr> {
        out.iter()
            .filter_map(|a| match a {
                ControllerAction::Frame(f) => {
                    let eth = Frame::new_checked(&f[..]).ok()?;
                    assert_eq!((eth.dst(), eth.src()), (TOOL, OWN));
                    let p = dcp::Packet::new_checked(eth.payload()).ok()?;
                    dcp::Repr::parse(&p).ok()
                }
                _ => None,
            })
            .collect()
    }

    #[test]
    fn identify_finds_the_controllers_station_as_an_io_controller() {
        let mut c = controller();
        let mut out = Vec::new();
        let by_name = request(
            MacAddress::DCP_IDENTIFY,
            dcp::FRAME_ID_IDENTIFY_REQUEST,
            ServiceId::Identify,
            vec![Block::bare(BlockRepr::NameOfStation("plc-line-1".into()))],
        );
        c.on_frame(&by_name, 0, &mut out);
        c.poll(10_000_000_000, &mut out);
        let res = answers(&out);
        assert_eq!(res.len(), 1, "one Identify response");
        let values: Vec<&BlockRepr> = res[0].blocks.iter().map(|b| &b.value).collect();
        assert!(values.contains(&&BlockRepr::NameOfStation("plc-line-1".into())));
        assert!(values.contains(&&BlockRepr::DeviceVendor("procimg controller".into())));
        assert!(values.contains(&&BlockRepr::DeviceRole {
            role: ROLE_IO_CONTROLLER,
            reserved: 0
        }));
        assert!(values.contains(&&BlockRepr::IpParameter {
            ip: [192, 168, 0, 1],
            mask: [255, 255, 255, 0],
            gateway: [0; 4]
        }));

        // Another name, or the IO device role, is not this station.
        out.clear();
        let other = request(
            MacAddress::DCP_IDENTIFY,
            dcp::FRAME_ID_IDENTIFY_REQUEST,
            ServiceId::Identify,
            vec![Block::bare(BlockRepr::DeviceRole {
                role: 0x01,
                reserved: 0,
            })],
        );
        c.on_frame(&other, 0, &mut out);
        c.poll(10_000_000_000, &mut out);
        assert!(answers(&out).is_empty());
    }

    #[test]
    fn a_signal_flashes_the_led_and_the_name_stays_the_configurations() {
        let mut c = controller();
        let mut out = Vec::new();
        let set = request(
            OWN,
            dcp::FRAME_ID_GET_SET,
            ServiceId::Set,
            vec![
                Block::new(0, BlockRepr::ControlSignal(0x0100)),
                Block::new(1, BlockRepr::NameOfStation("renamed".into())),
            ],
        );
        c.on_frame(&set, 0, &mut out);
        assert!(
            out.iter()
                .any(|a| matches!(a, ControllerAction::Event(DeviceEvent::Signal)))
        );
        let res = answers(&out);
        let errors: Vec<u8> = res[0]
            .blocks
            .iter()
            .filter_map(|b| match b.value {
                BlockRepr::ControlResponse { error, .. } => Some(error),
                _ => None,
            })
            .collect();
        assert_eq!(errors, [block_error::OK, block_error::SET_NOT_POSSIBLE]);

        // A device's Set response (the same FrameID) is not the station's.
        out.clear();
        let mut response =
            dcp::Repr::parse(&dcp::Packet::new_checked(&set[14..]).unwrap()).unwrap();
        response.service_type = ServiceType::Success;
        let frame = profinet_frame(OWN, TOOL, None, &response.to_vec().unwrap());
        let eth = Frame::new_checked(&frame[..]).unwrap();
        assert!(!c.on_station_frame(&eth, 0, &mut out));
    }
}
