// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device's alarms: what its two RTA channels report, and the AlarmAck a client's
//! acknowledgement sends.

use super::*;
use crate::wire::alarm::AlarmType;

impl DeviceAr {
    pub(super) fn on_rta_events(
        &mut self,
        events: Vec<RtaEvent>,
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        for e in events {
            match e {
                RtaEvent::Send(pdu) => {
                    let Some(ar) = self.step.ar() else { continue };
                    if let Some(f) = rta_frame(id.mac, ar.peer_mac, &pdu) {
                        out.push(ControllerAction::Frame(f));
                    }
                }
                RtaEvent::Deliver(blocks) => {
                    for b in blocks {
                        if let AlarmBlock::Notification(n) = b {
                            let Some(ar) = self.step.ar_mut() else {
                                continue;
                            };
                            let priority = n.priority;
                            let n = Box::new(n);
                            // The device sends the next alarm of a priority only after the
                            // AlarmAck of this one, so one slot per priority is enough.
                            ar.unacked[priority_slot(priority)] = Some(n.clone());
                            out.push(ControllerAction::Event(DeviceEvent::Alarm {
                                device: self.plan.device,
                                notification: n,
                                ticket: AlarmTicket {
                                    device: self.plan.device,
                                    epoch: self.epoch,
                                    priority,
                                },
                            }));
                        }
                    }
                }
                RtaEvent::Confirmed => {}
                RtaEvent::Abort { code, local } => {
                    // The ERR-RTA's status, sent or received.
                    let status = ErrRta::abort(code).status;
                    let (cause, why) = if local {
                        (
                            FailureCause::ControllerAborted,
                            format!("the alarm channel failed ({code:?}); the AR was aborted"),
                        )
                    } else {
                        (
                            FailureCause::DeviceAborted,
                            format!("the device aborted the AR ({code:?})"),
                        )
                    };
                    self.fail_with(cause, &why, Some(status), now, out);
                    return;
                }
            }
        }
    }

    /// Sends the AlarmAck of the alarm `ticket` names, if it still waits for one.
    pub fn acknowledge_alarm(
        &mut self,
        ticket: AlarmTicket,
        id: &ControllerIdentity,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) -> bool {
        if ticket.epoch != self.epoch {
            return false;
        }
        let Some(ar) = self.step.ar_mut() else {
            return false;
        };
        let Some(n) = ar.unacked[priority_slot(ticket.priority)].take() else {
            return false;
        };
        let ack = AlarmAck::for_notification(&n, PnioStatus::OK);
        // A Plug alarm of a submodule we parameterize starts its sub-cycle once acknowledged
        // (a Plug Wrong Submodule alarm does not: we parameterize nothing we did not plan).
        if n.alarm_type == AlarmType::Plug && self.plan.has_submodule(n.api, n.slot, n.subslot) {
            self.plugs.push_back(Plug {
                api: n.api,
                slot: n.slot,
                subslot: n.subslot,
                seq: n.specifier.sequence_number,
            });
        }
        let mut sent = Vec::new();
        ar.channel(ticket.priority)
            .send(vec![AlarmBlock::Ack(ack)], now, &mut sent);
        for e in sent {
            if let RtaEvent::Send(pdu) = e
                && let Some(f) = rta_frame(id.mac, ar.peer_mac, &pdu)
            {
                out.push(ControllerAction::Frame(f));
            }
        }
        self.next_record(now, out);
        true
    }
}

/// An Ethernet frame around an RTA PDU: tagged with the priority of its channel.
pub(super) fn rta_frame(src: MacAddress, dst: MacAddress, pdu: &RtaPdu) -> Option<Vec<u8>> {
    let pcp = match pdu.priority {
        Priority::High => 6,
        Priority::Low => 5,
    };
    let eth = ethernet::Repr {
        dst,
        src,
        vlan: Some(VlanTag {
            pcp,
            dei: false,
            vid: 0,
        }),
        ethertype: ETHERTYPE_PROFINET,
    };
    // Padded to 64 so that the frame is still of minimum size once a switch removes the
    // tag, as PROFINET controllers send tagged frames.
    Some(eth.frame(&pdu.to_vec().ok()?, 64))
}
