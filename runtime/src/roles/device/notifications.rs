// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station's events as its clients get them: one [`Notification`] each, to every
//! subscriber (what GOAL's and IO-Base's device interfaces give as AR indications).

use super::station::StationEvent;
use procimg_control::services::{
    ArCr, CrDataObject, ExpectedSubmodule, Notification, StationArCheckJob, StationDcpSetJob,
    StationRecordJob,
};
use procimg_profinet::wire::rta_pdu::AbortCode;

/// Why an AR ended, when the PLC released it.
pub const RELEASED: &str = "released by the PLC";

/// The notification of `event`.
pub fn notification(event: StationEvent) -> Notification {
    match event {
        StationEvent::Ar(a) => Notification::StationAr {
            state: a.state,
            ar_uuid: a.ar_uuid,
            controller_mac: a.controller_mac,
            controller_name: a.controller_name,
        },
        StationEvent::ArEnded {
            ar_uuid,
            abort,
            planned,
        } => Notification::StationArEnded {
            ar_uuid,
            reason: abort.map_or_else(|| RELEASED.to_owned(), |code| reason(code, planned)),
            aborted: abort.is_some(),
            planned,
            abort_code: abort.map(AbortCode::raw),
        },
        StationEvent::PlcRunning {
            running,
            station_problem,
            backup,
        } => Notification::StationPlcRunning {
            running,
            station_problem,
            backup,
        },
        StationEvent::PlugParameterized(at) => Notification::StationPlugParameterized {
            api: at.api,
            slot: at.slot,
            subslot: at.subslot,
        },
        StationEvent::AlarmDone {
            subscriber,
            tag,
            status,
        } => Notification::StationAlarmDone {
            reply_to: subscriber,
            tag,
            status,
        },
        StationEvent::Blink => Notification::StationBlink,
        StationEvent::Neighbours {
            neighbours,
            alias_name,
        } => Notification::StationNeighbours {
            port: 1,
            neighbours,
            alias_name,
        },
        StationEvent::Plug { at, idents, alarm } => {
            let (module_ident, submodule_ident) = idents.unwrap_or((0, 0));
            Notification::StationPlug {
                api: at.api,
                slot: at.slot,
                subslot: at.subslot,
                plugged: idents.is_some(),
                module_ident,
                submodule_ident,
                alarm: alarm.map(|a| a.to_string()).unwrap_or_default(),
            }
        }
        StationEvent::Identity {
            identity,
            permanent,
            factory_reset,
        } => Notification::StationIdentity {
            name: identity.name,
            ip: identity.ip.to_string(),
            netmask: identity.netmask.to_string(),
            gateway: identity.gateway.to_string(),
            permanent,
            factory_reset,
        },
        // Not for everyone: the services fill in the client that checks.
        StationEvent::DcpSetCheck(c) => Notification::StationDcpSetCheck {
            reply_to: 0,
            check: StationDcpSetJob {
                job: c.job,
                from: c.from.to_string(),
                name: c.name,
                ip_suite: c
                    .ip_suite
                    .map(|s| s.map(|a| std::net::Ipv4Addr::from(a).to_string())),
                permanent: c.permanent,
                reset: c.reset,
            },
        },
        StationEvent::ArCheck(c) => Notification::StationArCheck {
            reply_to: 0,
            check: StationArCheckJob {
                job: c.job,
                ar_uuid: c.ar_uuid.to_string(),
                ar_type: c.ar_type,
                session_key: c.session_key,
                controller_mac: c.controller_mac.to_string(),
                controller_name: c.controller_name,
                controller_ip: c.controller_ip.to_string(),
                ar_properties: c.ar_properties,
                cmi_object_uuid: c.cmi_object_uuid.to_string(),
                expected: c
                    .expected
                    .iter()
                    .map(|e| ExpectedSubmodule {
                        api: e.at.api,
                        slot: e.at.slot,
                        subslot: e.at.subslot,
                        module_ident: e.module_ident,
                        submodule_ident: e.submodule_ident,
                        input_length: e.input_length,
                        output_length: e.output_length,
                        plugged: e.plugged.map(|p| (p.module_ident, p.submodule_ident)),
                    })
                    .collect(),
                crs: c
                    .crs
                    .iter()
                    .map(|cr| ArCr {
                        input: cr.input,
                        rt_class: cr.rt_class,
                        frame_id: cr.frame_id,
                        send_clock_factor: cr.send_clock_factor,
                        reduction_ratio: cr.reduction_ratio,
                        phase: cr.phase,
                        data_hold_factor: cr.data_hold_factor,
                        data_length: cr.data_length,
                        data_objects: cr
                            .data_objects
                            .iter()
                            .map(|&(at, frame_offset)| CrDataObject {
                                api: at.api,
                                slot: at.slot,
                                subslot: at.subslot,
                                frame_offset,
                            })
                            .collect(),
                    })
                    .collect(),
            },
        },
        // Not for everyone: the services fill in the client that took the records.
        StationEvent::Record(r) => Notification::StationRecord {
            reply_to: 0,
            job: StationRecordJob {
                job: r.job,
                write: r.write,
                ar_uuid: r.ar_uuid.to_string(),
                api: r.api,
                slot: r.slot,
                subslot: r.subslot,
                index: r.index,
                data: r.data,
                max_len: r.max_len,
            },
        },
    }
}

/// An abort in words: the code, and for the usual ones what it means for the program.
fn reason(code: AbortCode, planned: bool) -> String {
    let meaning = match code {
        _ if planned => "this station stopped taking part (procimgd stopping or going OFFLINE)",
        AbortCode::ConsumerDhtExpired => {
            "IO data timeout: the PLC's output frames stopped coming within its watchdog time"
        }
        AbortCode::StationNameChanged => "DCP gave the station another name or address",
        AbortCode::ResetToFactory => "DCP reset the station to factory",
        _ => return code.to_string(),
    };
    format!("{code}: {meaning}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::roles::device::identity::Identity;
    use crate::roles::device::station::reported;
    use procimg_control as control;
    use procimg_profinet::device::ArState;
    use std::net::Ipv4Addr;

    const UUID: &str = "0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2";

    fn ended(abort: Option<AbortCode>, planned: bool) -> Notification {
        notification(StationEvent::ArEnded {
            ar_uuid: UUID.into(),
            abort,
            planned,
        })
    }

    #[test]
    fn every_ar_state_of_the_engine_is_told_as_the_protocols() {
        assert_eq!(reported(ArState::Idle), None);
        for (engine, told) in [
            (ArState::Connected, control::ArState::Connected),
            (ArState::Parameterized, control::ArState::Parameterized),
            (
                ArState::WaitAppReadyConfirm,
                control::ArState::WaitingForApplicationReadyConfirm,
            ),
            (ArState::Data, control::ArState::Data),
        ] {
            assert_eq!(reported(engine), Some(told));
            let n = notification(StationEvent::Ar(control::ArReport {
                state: told,
                ar_uuid: UUID.into(),
                controller_mac: "02:50:49:fe:00:01".into(),
                controller_name: "plc-1".into(),
                plc_running: Some(true),
            }));
            assert_eq!(
                n,
                Notification::StationAr {
                    state: told,
                    ar_uuid: UUID.into(),
                    controller_mac: "02:50:49:fe:00:01".into(),
                    controller_name: "plc-1".into(),
                }
            );
        }
    }

    #[test]
    fn a_release_an_abort_and_a_planned_end_are_told_apart() {
        assert_eq!(
            ended(None, false),
            Notification::StationArEnded {
                ar_uuid: UUID.into(),
                reason: RELEASED.into(),
                aborted: false,
                planned: false,
                abort_code: None,
            }
        );
        let Notification::StationArEnded {
            reason,
            aborted: true,
            planned: false,
            abort_code: Some(0x05),
            ..
        } = ended(Some(AbortCode::ConsumerDhtExpired), false)
        else {
            panic!("an abort");
        };
        assert!(reason.contains("data hold time expired"), "{reason}");
        assert!(reason.contains("IO data timeout"), "{reason}");
        let Notification::StationArEnded {
            reason,
            aborted: true,
            planned: true,
            ..
        } = ended(Some(AbortCode::AbortRequest), true)
        else {
            panic!("a planned end");
        };
        assert!(reason.contains("stopped taking part"), "{reason}");
        let Notification::StationArEnded { reason, .. } =
            ended(Some(AbortCode::ProtocolViolation), false)
        else {
            panic!("an abort");
        };
        assert_eq!(reason, AbortCode::ProtocolViolation.to_string());
    }

    #[test]
    fn the_plc_dcp_and_identity_events_map_one_to_one() {
        assert_eq!(
            notification(StationEvent::PlcRunning {
                running: false,
                station_problem: true,
                backup: false
            }),
            Notification::StationPlcRunning {
                running: false,
                station_problem: true,
                backup: false
            }
        );
        assert_eq!(
            notification(StationEvent::Blink),
            Notification::StationBlink
        );
        assert_eq!(
            notification(StationEvent::Identity {
                identity: Identity {
                    name: "pc-device".into(),
                    ip: Ipv4Addr::new(10, 47, 0, 50),
                    netmask: Ipv4Addr::new(255, 255, 255, 0),
                    gateway: Ipv4Addr::UNSPECIFIED,
                },
                permanent: true,
                factory_reset: false,
            }),
            Notification::StationIdentity {
                name: "pc-device".into(),
                ip: "10.47.0.50".into(),
                netmask: "255.255.255.0".into(),
                gateway: "0.0.0.0".into(),
                permanent: true,
                factory_reset: false,
            }
        );
    }
}
