// SPDX-License-Identifier: MIT OR Apache-2.0
//! Learning the device's module tree before the Connect, as an engineering tool does when it
//! reads a station's configuration: a ReadImplicit of its RealIdentificationData (record
//! 0xF000), after which the planned positions expect the ident numbers that are really
//! plugged there. Positions the device lacks keep their planned ident numbers (the Connect
//! response then reports them missing); positions the plan lacks are left alone, since
//! the image has no place for them. The data lengths stay the plan's.
//!
//! Off by default: a controller expects what it was configured with. procimgd's demo PLC
//! turns it on, so that whatever the device's managing client plugged is connected and
//! cycled. A device that does not answer, or answers something unreadable, is connected
//! with the plan as it is.

use super::*;
use crate::wire::record::IdentificationData;

/// RealIdentificationData: what is plugged in the whole device.
const INDEX_REAL_IDENTIFICATION: u16 = 0xF000;
/// The most RealIdentificationData read (an IOD header and a large tree).
const MAX_IDENTIFICATION_LEN: u32 = 4096;

impl DeviceAr {
    /// Whether the device's RealIdentificationData is read before every Connect and the
    /// expected ident numbers follow it (see the module docs). Off from the start.
    pub fn learn_real_identification(&mut self, on: bool) {
        self.learn_tree = on;
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
            follow(&mut self.plan, &real);
        }
        self.connect(id, now, out);
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
    use crate::wire::record::{IdentApi, IdentificationKind, RecordVersion};

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
        let spec = DeviceSpec {
            name: "dev".into(),
            ip: None,
            vendor_id: 1,
            device_id: 2,
            instance: 1,
            reduction_ratio: 1,
            watchdog_factor: 3,
            submodules: vec![sub(1, 0x10, 0x1), sub(2, 0x20, 0x2)],
        };
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
