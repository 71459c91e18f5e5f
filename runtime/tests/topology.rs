// SPDX-License-Identifier: MIT OR Apache-2.0
//! As root: procimg's controller and procimg's device on a veth pair, the controller's
//! project with a topology (`[[device.topology]]`). The controller's port announces itself
//! by LLDP; the device checks the neighbour its PLC names against the one it has: the
//! project's check holds. A check written in data exchange that names another neighbour
//! raises the port's diagnosis and the PortDataChangeNotification alarm; the right one
//! written again clears both.

use procimg_client::pe::{PeAnswer, PeCommand};
use procimg_client::{AlarmReport, ArState, Notification, RecordTarget, ServiceOptions, Services};
use procimg_client::{RecordError, RecordRefusal};
use procimg_profinet::wire::record::pe::{
    INDEX_PE_SERVICE, PeAnswer as WireAnswer, PeCommand as WirePe, PeRequest, PeResponse,
};
use procimg_profinet::wire::record::{
    CheckedPeer, INDEX_PD_PORT_DATA_CHECK, PdPortDataCheck, PortCheck,
};
use procimg_testkit::Launch;
use procimg_testkit::netns::TestNet;
use procimg_testkit::tshark::{LiveCapture, flagged, frames_matching};
use procimg_testkit::veth_station::{CONTROLLER_TOML, DEVICE_TOML};
use std::time::{Duration, Instant};

/// AlarmType Port Data Change Notification.
const PORT_DATA_CHANGE: u16 = 0x000e;
/// ChannelErrorType remote mismatch, ExtChannelErrorType wrong peer NameOfStation.
const REMOTE_MISMATCH: u16 = 0x8001;

/// The next alarm among the controller's notifications, within 30 s.
fn next_alarm(services: &mut Services) -> AlarmReport {
    let until = Instant::now() + Duration::from_secs(30);
    while Instant::now() < until {
        if let Some(Notification::Alarm(a)) = services.next(Duration::from_millis(100)) {
            return a;
        }
    }
    panic!("no alarm within 30 s");
}

fn in_data(s: &procimg_client::StatusReport) -> bool {
    s.station
        .as_ref()
        .and_then(|st| st.ar.as_ref())
        .is_some_and(|ar| ar.state == ArState::Data)
}

/// The remote mismatches pending on the device's port.
fn mismatches(device: &procimg_testkit::Procimgd) -> Vec<u16> {
    device
        .status()
        .station
        .unwrap()
        .diagnosis
        .iter()
        .filter(|d| (d.slot, d.subslot) == (0, 0x8001) && d.entry.error_type == REMOTE_MISMATCH)
        .map(|d| d.entry.ext_error_type)
        .collect()
}

/// A station program that takes PE for the head module (slot 0, subslot 1) and answers
/// Start_Pause with mode 0x01 and End_Pause with 500 ms, until it answered both; how many PE
/// commands it answered.
fn pe_program(instance: &str) -> u32 {
    let mut s = Services::open(instance, ServiceOptions::new("pe-program")).expect("services");
    s.take_records_with((0, 0, 1), false, true)
        .expect("take the PE record");
    let mut pending: Option<PeRequest> = None;
    let mut answered = 0;
    let until = Instant::now() + Duration::from_secs(30);
    while answered < 2 && Instant::now() < until {
        let Some(Notification::StationRecord { job, .. }) = s.next(Duration::from_millis(100))
        else {
            continue;
        };
        assert_eq!(job.index, INDEX_PE_SERVICE, "{job:?}");
        if job.write {
            pending = Some(PeRequest::parse(&job.data).expect("a PE request"));
            s.answer_record(&job, Ok(&[])).expect("answer the write");
            continue;
        }
        let Some(req) = pending.take() else {
            s.answer_record(&job, Err(RecordRefusal::new(0xb5)))
                .expect("answer the read");
            continue;
        };
        let answer = match req.command {
            WirePe::StartPause { .. } => WireAnswer::StartPause { mode: 0x01 },
            WirePe::EndPause => WireAnswer::EndPause {
                time_to_operate: 500,
            },
            _ => WireAnswer::Error(0x01),
        };
        let res = PeResponse {
            service: req.command.codes().0,
            reference: req.reference,
            answer,
        };
        s.answer_record(&job, Ok(&res.to_vec().unwrap()))
            .expect("answer the read");
        answered += 1;
    }
    let _ = s.give_back_records((0, 0, 1));
    answered
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn a_topology_mismatch_raises_the_port_diagnosis_and_the_right_neighbour_clears_it() {
    let net = TestNet::new("tp", true);
    net.address(0, "10.47.0.1/24");
    let dir = procimg_testkit::files::temp_dir("topology");
    let pcap = dir.path().join("wire.pcapng");
    let capture = LiveCapture::start(&net.ns[0], &net.ifs[0], &pcap);
    let device = Launch::config(
        "tpd",
        &DEVICE_TOML
            .replace("IFACE", &net.ifs[1])
            .replace(
                "STATE",
                &dir.path().join("station.toml").display().to_string(),
            )
            .replace("fresh-device", "pc-device"),
    )
    .netns(&net.ns[1])
    .until_cycling()
    .start();
    // The PLC's project: the device's port 1 faces the controller's port-001.
    let instance = format!("tpc-{}", std::process::id());
    let controller_name = format!("procimgd-{instance}");
    let project = CONTROLLER_TOML.replace("IFACE", &net.ifs[0])
        + &format!("[[device.topology]]\nstation = \"{controller_name}\"\nport = \"port-001\"\n");
    let plc = Launch::config("tpc", &project)
        .instance(&instance)
        .netns(&net.ns[0])
        .until_cycling()
        .start();
    let mut services = Services::open(
        &plc.instance,
        ServiceOptions::new("tp-alarms").acknowledge_alarms(true),
    )
    .expect("the controller's services");
    plc.wait_devices_running(Duration::from_secs(30));
    device.wait_status("the AR in data exchange", in_data);
    // The check the project wrote at connect holds once the controller has announced itself.
    device.wait_status("the controller as the port's neighbour", |s| {
        s.station
            .as_ref()
            .is_some_and(|st| st.neighbours.len() == 1)
    });
    assert!(mismatches(&device).is_empty());

    // The PLC writes a check naming another station: the wrong name, with the alarm.
    let write_check = |services: &mut Services, station: &str| {
        let check = PdPortDataCheck {
            slot: 0,
            subslot: 0x8001,
            checks: vec![PortCheck::Peers(vec![CheckedPeer {
                port_id: "port-001".into(),
                chassis_id: station.into(),
            }])],
        };
        let target = RecordTarget {
            device: 0,
            api: 0,
            slot: 0,
            subslot: 0x8001,
            index: INDEX_PD_PORT_DATA_CHECK,
        };
        services
            .write_record(target, &check.to_vec().unwrap(), Duration::from_secs(10))
            .expect("write the check");
    };
    let port_alarm = |services: &mut Services| loop {
        let a = next_alarm(services);
        services.acknowledge(&a).expect("acknowledge");
        if a.alarm_type == PORT_DATA_CHANGE {
            return a;
        }
    };
    write_check(&mut services, "someone-else");
    let alarm = port_alarm(&mut services);
    assert_eq!((alarm.slot, alarm.subslot), (0, 0x8001), "{alarm:?}");
    assert_ne!(
        alarm.specifier & 0x0800,
        0,
        "the submodule has a diagnosis: {alarm:?}"
    );
    assert_eq!(mismatches(&device), [0x8000]);

    // The right neighbour again: the diagnosis goes, with the alarm.
    write_check(&mut services, &controller_name);
    let cleared = port_alarm(&mut services);
    assert_eq!(
        cleared.specifier & 0x0800,
        0,
        "no diagnosis left: {cleared:?}"
    );
    assert!(mismatches(&device).is_empty());
    assert_eq!(
        plc.status().devices[0].state,
        procimg_client::DeviceState::Running
    );

    // The controller's own station and its interface's counters (IO-Base's
    // CONFIG_NAME_ADDR_INFO and communication counters), reset by a program.
    let own = plc.status().controller.expect("the controller's station");
    assert_eq!(
        (
            own.station_name.as_str(),
            own.ip.as_str(),
            own.netmask.as_str()
        ),
        (controller_name.as_str(), "10.47.0.1", "255.255.255.0")
    );
    assert_eq!(own.interface, net.ifs[0]);
    let before = own.counters.expect("the interface's counters");
    assert!(
        before.frames_sent > 100 && before.frames_received > 100,
        "{before:?}"
    );
    services.reset_comm_counters().expect("reset the counters");
    let after = plc.status().controller.unwrap().counters.unwrap();
    assert!(
        after.frames_sent < before.frames_sent,
        "{before:?} then {after:?}"
    );

    // PROFIenergy to procimg's own station, which no program took PE for: the standard
    // answer of an entity without energy-saving modes, over records 0x80A0 on the wire.
    let head = RecordTarget {
        device: 0,
        api: 0,
        slot: 0,
        subslot: 1,
        index: 0x80a0,
    };
    assert_eq!(
        services
            .pe(head, PeCommand::QueryVersion)
            .expect("Query_Version"),
        PeAnswer::Version { major: 1, minor: 1 }
    );
    assert_eq!(
        services
            .pe(head, PeCommand::StartPause { pause_ms: 60_000 })
            .expect("Start_Pause"),
        PeAnswer::Error { code: 0x06 },
        "no PE energy-saving mode supported"
    );
    assert_eq!(
        services.pe(head, PeCommand::EndPause).expect("End_Pause"),
        PeAnswer::EndPause { time_to_operate: 0 }
    );

    // A program of the station takes PE for the head module and pauses for real: the
    // controller's Start_Pause and End_Pause reach it as record jobs and its answers come
    // back.
    let program = std::thread::spawn({
        let instance = device.instance.clone();
        move || pe_program(&instance)
    });
    let until = Instant::now() + Duration::from_secs(30);
    let answer = loop {
        let a = match services.pe(head, PeCommand::StartPause { pause_ms: 60_000 }) {
            Ok(a) => a,
            // The program took the record between this command's write, which the station
            // answered, and its read: holding no command, it refuses the read (state
            // conflict), as a real program would. The next command reaches it whole.
            Err(RecordError::Failed { status, .. })
                if status.error_code1 == 0xb5 && Instant::now() < until =>
            {
                std::thread::sleep(Duration::from_millis(100));
                continue;
            }
            Err(e) => panic!("Start_Pause: {e}"),
        };
        // Until the program has taken the record, the station answers itself.
        if a != (PeAnswer::Error { code: 0x06 }) || Instant::now() > until {
            break a;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    assert_eq!(
        answer,
        PeAnswer::StartPause { mode: 0x01 },
        "the program's pause"
    );
    assert_eq!(
        services.pe(head, PeCommand::EndPause).expect("End_Pause"),
        PeAnswer::EndPause {
            time_to_operate: 500
        }
    );
    assert_eq!(program.join().unwrap(), 2, "the program answered both");

    drop((services, plc, device));
    let pcap = capture.stop();
    let bad = flagged(&pcap);
    assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
    // The alarms, the check written, the controller's LLDP: all on the wire.
    for filter in [
        "pn_io.alarm_type == 0x000e",
        "pn_io.index == 0x802b",
        "pn_io.index == 0x80a0",
        "lldp && lldp.chassis.id",
    ] {
        assert!(
            !frames_matching(&pcap, filter).trim().is_empty(),
            "nothing matches {filter:?} on the wire"
        );
    }
    drop((net, dir));
}
