// SPDX-License-Identifier: MIT OR Apache-2.0
//! Learning the device's module tree before the Connect, as an engineering tool does when it
//! reads a station's configuration: a ReadImplicit of its RealIdentificationData (record
//! 0xF000), and then one of two things.
//!
//! - *Following* ([`DeviceAr::learn_real_identification`]): the planned positions expect
//!   the ident numbers that are really plugged there. Positions the device lacks keep their
//!   planned ident numbers (the Connect response then reports them missing); positions the
//!   plan lacks are left alone, since the image has no place for them. The data lengths
//!   stay the plan's.
//! - *Planning* ([`DeviceAr::plan_from_real_identification`]): the owner's [`TreePlanner`]
//!   makes a whole plan of the tree read (the owner knows where lengths and records come
//!   from, a GSDML file say; this crate does not), and that plan is connected: its expected
//!   submodules, IO CRs, records and, after the Connect, its cyclic exchange. The planner
//!   is asked anew before every Connect, always with the plan the device was configured
//!   with, so that each AR follows the tree as it is then; when it has no plan for the tree
//!   the configured plan is connected, following the tree as above.
//!
//! Off by default: a controller expects what it was configured with. procimgd's demo PLC
//! turns it on, so that whatever the device's managing client plugged is connected and
//! cycled; for a station its program defines it plans, from the tree read and the
//! station's GSDML file, as a PLC with only that file would. A device that does not
//! answer, or answers something unreadable, is connected with the plan as it is (the last
//! Connect's).

use super::*;
use crate::wire::record::IdentificationData;

/// RealIdentificationData: what is plugged in the whole device.
const INDEX_REAL_IDENTIFICATION: u16 = 0xF000;
/// The most RealIdentificationData read (an IOD header and a large tree).
const MAX_IDENTIFICATION_LEN: u32 = 4096;

/// Plans a device from the tree it reports ([`DeviceAr::plan_from_real_identification`]):
/// given the plan the device was configured with and its RealIdentificationData, the plan
/// to connect, or `None` to connect the configured one with its ident numbers following the
/// tree. The plan must keep the configured plan's `device` and `first_submodule` (the
/// events, the cyclic exchange and the owner's submodule table know the device by them;
/// its submodules become table entries `first_submodule..`, as many as it has); one that
/// does not is not used.
pub type TreePlanner = Box<dyn Fn(&DevicePlan, &IdentificationData) -> Option<DevicePlan> + Send>;

/// A [`TreePlanner`] and the plan it starts from each time.
pub(super) struct Planning {
    planner: TreePlanner,
    configured: DevicePlan,
}

impl DeviceAr {
    /// Whether the device's RealIdentificationData is read before every Connect and the
    /// expected ident numbers follow it, or the [`TreePlanner`] given plans from it (see
    /// the module docs). Off from the start; off again, the plan of the last Connect stays.
    pub fn learn_real_identification(&mut self, on: bool) {
        self.learn_tree = on;
    }

    /// Reads the device's RealIdentificationData before every Connect and connects the plan
    /// `planner` makes of it (see the module docs), from now on; the plan the device has now
    /// is the configured one it starts from (the first planner's, if it had one: not a plan
    /// a planner made).
    pub fn plan_from_real_identification(&mut self, planner: TreePlanner) {
        let configured = match self.planning.take() {
            Some(p) => p.configured,
            None => self.plan.clone(),
        };
        self.planning = Some(Box::new(Planning {
            planner,
            configured,
        }));
        self.learn_tree = true;
    }

    /// The device has its address: Connect, after reading its tree if asked to. Its MAC
    /// address goes to the driver first, so that the calls to it need not wait for ARP.
    pub(super) fn connect_or_learn(
        &mut self,
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        if let (Some(ip), Some(mac)) = (self.ip, self.mac) {
            out.push(ControllerAction::Neighbour { ip, mac });
        }
        let Some(ip) = self.ip.filter(|_| self.learn_tree) else {
            return self.connect(id, now, out);
        };
        let header = IodHeader::read_request(
            0,
            Uuid::NIL,
            0,
            0,
            0,
            INDEX_REAL_IDENTIFICATION,
            MAX_IDENTIFICATION_LEN,
        );
        let activity = self.uuids.next_uuid();
        match RpcCall::new(
            self.plan.object_uuid(),
            activity,
            0,
            opnum::READ_IMPLICIT,
            &header.to_bytes(),
            MAX_IDENTIFICATION_LEN,
            now,
        ) {
            Ok(call) => {
                call.send(SocketAddrV4::new(ip, rpc::RPC_PORT), out);
                self.step = Step::Learn { call };
            }
            Err(_) => self.connect(id, now, out),
        }
    }

    /// The device's answer to the read: the plan follows it, then the Connect.
    pub(super) fn learned(
        &mut self,
        answer: Answer,
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        if let Answer::Response { status, blocks } = answer
            && status.is_ok()
            && let Ok((header, data, _)) = IodHeader::split(&blocks)
            && header.status.is_ok()
            && let Ok(real) = IdentificationData::parse(data)
        {
            match &self.planning {
                Some(p) => self.plan = p.plan(&real),
                None => follow(&mut self.plan, &real),
            }
        }
        self.connect(id, now, out);
    }
}

impl Planning {
    /// The plan to connect for the tree `real`: the planner's, or the configured one
    /// following `real`.
    fn plan(&self, real: &IdentificationData) -> DevicePlan {
        let c = &self.configured;
        match (self.planner)(c, real) {
            Some(p) if (p.device, p.first_submodule) == (c.device, c.first_submodule) => p,
            _ => {
                let mut p = c.clone();
                follow(&mut p, real);
                p
            }
        }
    }
}

/// Makes `plan` expect, at each of its positions, the module and submodule ident numbers
/// `real` has there.
fn follow(plan: &mut DevicePlan, real: &IdentificationData) {
    for block in &mut plan.expected {
        for m in &mut block.modules {
            let Some(rm) = real
                .apis
                .iter()
                .filter(|a| a.api == m.api)
                .flat_map(|a| a.modules.iter())
                .find(|rm| rm.slot == m.slot)
            else {
                continue;
            };
            m.module_ident = rm.module_ident;
            for s in &mut m.submodules {
                if let Some(rs) = rm.submodules.iter().find(|rs| rs.subslot == s.subslot) {
                    s.submodule_ident = rs.submodule_ident;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::controller::plan::{DeviceSpec, SubmoduleSpec};
    use crate::controller::uuids::UuidSource;
    use crate::wire::connect::{ConnectRequest, ExpectedSubmodule};
    use crate::wire::record::{IdentApi, IdentificationKind, RecordVersion};
    use crate::wire::rpc::{Header, PacketType};

    const MS: u64 = 1_000_000;

    fn spec(submodules: Vec<SubmoduleSpec>) -> DeviceSpec {
        DeviceSpec {
            name: "dev".into(),
            ip: None,
            vendor_id: 1,
            device_id: 2,
            instance: 1,
            reduction_ratio: 1,
            watchdog_factor: 3,
            submodules,
            ..Default::default()
        }
    }

    fn real(tree: &[(u16, u32, u32)]) -> IdentificationData {
        IdentificationData {
            kind: IdentificationKind::Real,
            version: RecordVersion::V1_1,
            apis: IdentApi::group(tree.iter().map(|&(slot, m, s)| (0, slot, m, 1, s))),
        }
    }

    /// The device's positive answer to the read of `real`.
    fn answer(real: &IdentificationData) -> Answer {
        let data = real.to_vec().unwrap();
        let header = IodHeader::read_request(
            0,
            Uuid::NIL,
            0,
            0,
            0,
            INDEX_REAL_IDENTIFICATION,
            MAX_IDENTIFICATION_LEN,
        )
        .response(data.len() as u32);
        let mut blocks = header.to_bytes().to_vec();
        blocks.extend_from_slice(&data);
        Answer::Response {
            status: PnioStatus::OK,
            blocks,
        }
    }

    /// The Connect request among `out`.
    fn connect_request(out: &[ControllerAction]) -> ConnectRequest {
        let payload = out
            .iter()
            .find_map(|a| match a {
                ControllerAction::Datagram { payload, .. } => Some(payload),
                _ => None,
            })
            .expect("a Connect call");
        let packet = rpc::Packet::new_checked(&payload[..]).unwrap();
        let h = Header::parse(&packet).unwrap();
        assert_eq!(h.opnum, opnum::CONNECT);
        let (_, blocks) = rpc::parse_body(PacketType::Request, h.little_endian, packet.body())
            .expect("an NDR request");
        ConnectRequest::parse(blocks).unwrap()
    }

    /// A device planned with `plan`, found at its address, that plans from its tree with
    /// `planner`.
    fn learning(plan: DevicePlan, planner: TreePlanner) -> DeviceAr {
        let mut d = DeviceAr::new(plan, UuidSource::new(7));
        d.ip = Some(Ipv4Addr::new(192, 168, 0, 50));
        d.mac = Some(MacAddress([2, 0, 0, 0, 0, 0x50]));
        d.plan_from_real_identification(planner);
        d
    }

    fn controller() -> ControllerIdentity {
        ControllerIdentity {
            mac: MacAddress([2, 0, 0, 0, 0, 1]),
            ip: Ipv4Addr::new(192, 168, 0, 1),
            station_name: "plc".into(),
            vendor_id: 3,
            device_id: 4,
            instance: 1,
        }
    }

    /// The test's planner: 2 input bytes per submodule, 40 in and 40 out for module 0x55,
    /// no plan for a tree with module 0xBAD.
    fn by_ident(current: &DevicePlan, real: &IdentificationData) -> Option<DevicePlan> {
        let mut submodules = Vec::new();
        for m in real.apis.iter().flat_map(|a| a.modules.iter()) {
            if m.module_ident == 0xBAD {
                return None;
            }
            let (input_length, output_length) = if m.module_ident == 0x55 {
                (40, 40)
            } else {
                (2, 0)
            };
            for s in &m.submodules {
                submodules.push(SubmoduleSpec {
                    api: 0,
                    slot: m.slot,
                    subslot: s.subslot,
                    module_ident: m.module_ident,
                    submodule_ident: s.submodule_ident,
                    input_length,
                    output_length,
                    records: vec![(1, vec![m.slot as u8])],
                });
            }
        }
        DevicePlan::new(
            current.device,
            current.first_submodule,
            &spec(submodules),
            MS,
        )
        .ok()
    }

    #[test]
    fn a_position_the_plan_lacks_is_connected_with_the_planners_lengths() {
        let sub = SubmoduleSpec {
            api: 0,
            slot: 1,
            subslot: 1,
            module_ident: 0x10,
            submodule_ident: 0x1,
            input_length: 2,
            output_length: 0,
            records: Vec::new(),
        };
        // Device 3 of a controller, its submodules from table entry 7.
        let configured = DevicePlan::new(3, 7, &spec(vec![sub]), MS).unwrap();
        let mut d = learning(configured.clone(), Box::new(by_ident));
        let mut out = Vec::new();
        d.learned(
            answer(&real(&[(1, 0x10, 0x1), (5, 0x55, 0x5)])),
            &controller(),
            0,
            &mut out,
        );

        // The Connect expects slot 5 with the planner's lengths, and its CRs carry them.
        let req = connect_request(&out);
        let slot5 = req
            .expected
            .iter()
            .flat_map(|b| b.modules.iter())
            .find(|m| m.slot == 5)
            .expect("slot 5 expected");
        assert_eq!(slot5.module_ident, 0x55);
        assert_eq!(
            slot5.submodules,
            vec![ExpectedSubmodule::with_io(1, 0x5, 40, 40)]
        );
        let lengths: Vec<u16> = req.iocrs.iter().map(|c| c.data_length).collect();
        assert_eq!(
            lengths,
            [
                d.plan.layout.input.data_length,
                d.plan.layout.output.data_length
            ]
        );
        assert_ne!(lengths[1], configured.layout.output.data_length);

        // What follows the Connect uses the same plan: the same device and table entries,
        // the planner's records, the cyclic exchange's maps.
        assert_eq!((d.plan.device, d.plan.first_submodule), (3, 7));
        assert_eq!(
            d.plan.records.iter().map(|r| r.slot).collect::<Vec<_>>(),
            [1, 5]
        );
        let mac = MacAddress([2, 0, 0, 0, 0, 0x50]);
        let cyclic = CyclicAr::new(&d.plan, 1, controller().mac, mac, d.plan.frame_ids);
        assert_eq!(cyclic.device, 3);
        let of_slot5 = 7 + d.plan.submodules.iter().position(|s| s.slot == 5).unwrap();
        for cr in [&cyclic.input, &cyclic.output] {
            assert!(
                cr.objects
                    .iter()
                    .any(|o| o.submodule == of_slot5 && o.len == 40),
                "{cr:?}"
            );
        }
    }

    #[test]
    fn without_the_planners_plan_the_configured_one_follows_the_tree() {
        let sub = |slot: u16, module_ident: u32| SubmoduleSpec {
            api: 0,
            slot,
            subslot: 1,
            module_ident,
            submodule_ident: 0x1,
            input_length: 2,
            output_length: 0,
            records: Vec::new(),
        };
        let configured = DevicePlan::new(0, 0, &spec(vec![sub(1, 0x10)]), MS).unwrap();
        let mut d = learning(configured, Box::new(by_ident));
        let id = controller();
        let mut out = Vec::new();
        d.learned(answer(&real(&[(5, 0x55, 0x5)])), &id, 0, &mut out);
        assert!(d.plan.has_submodule(0, 5, 1));
        // The next tree has no plan: the configured plan, not the last one, is connected,
        // its ident numbers following the tree.
        out.clear();
        d.learned(
            answer(&real(&[(1, 0x77, 0x78), (6, 0xBAD, 0x1)])),
            &id,
            0,
            &mut out,
        );
        let req = connect_request(&out);
        let modules: Vec<(u16, u32, u32)> = req
            .expected
            .iter()
            .flat_map(|b| b.modules.iter())
            .map(|m| (m.slot, m.module_ident, m.submodules[0].submodule_ident))
            .collect();
        assert_eq!(modules, [(1, 0x77, 0x78)]);

        // A plan for another device (or other table entries) is not taken either.
        let mut d = learning(
            DevicePlan::new(0, 0, &spec(vec![sub(1, 0x10)]), MS).unwrap(),
            Box::new(|c: &DevicePlan, r: &IdentificationData| {
                let mut p = by_ident(c, r)?;
                p.first_submodule += 1;
                Some(p)
            }),
        );
        out.clear();
        d.learned(answer(&real(&[(5, 0x55, 0x5)])), &id, 0, &mut out);
        assert!(!d.plan.has_submodule(0, 5, 1));
        assert_eq!(d.plan.first_submodule, 0);
    }

    #[test]
    fn the_plan_expects_what_is_plugged_at_its_own_positions_only() {
        let sub = |slot: u16, module_ident: u32, submodule_ident: u32| SubmoduleSpec {
            api: 0,
            slot,
            subslot: 1,
            module_ident,
            submodule_ident,
            input_length: 2,
            output_length: 0,
            records: Vec::new(),
        };
        let spec = spec(vec![sub(1, 0x10, 0x1), sub(2, 0x20, 0x2)]);
        let mut plan = DevicePlan::all(&[spec], 1_000_000).unwrap().remove(0);
        let real = IdentificationData {
            kind: IdentificationKind::Real,
            version: RecordVersion::V1_1,
            apis: IdentApi::group([
                (0, 1, 0x77, 1, 0x78),
                // Not planned: left alone.
                (0, 9, 0x99, 1, 0x99),
            ]),
        };
        follow(&mut plan, &real);
        let at = |slot: u16| {
            plan.expected
                .iter()
                .flat_map(|b| b.modules.iter())
                .find(|m| m.slot == slot)
                .map(|m| (m.module_ident, m.submodules[0].submodule_ident))
        };
        assert_eq!(at(1), Some((0x77, 0x78)));
        // Slot 2 is not in the real tree: the plan's ident numbers stay.
        assert_eq!(at(2), Some((0x20, 0x2)));
        assert_eq!(at(9), None);
    }
}
