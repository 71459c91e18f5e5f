// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd in the IO device role, as its users see it: the demo (procimg's own controller
//! as the PLC) with a client that provides the I data and reads the Q data, and — as root —
//! procimg as controller against procimg as device, each in a network namespace of its own
//! on a veth pair: the station named by DCP as an engineering tool does it, data both ways
//! through a client on each side, a diagnosis, the device killed and restarted with its name
//! kept, and every frame on the wire dissected by tshark.

use procimg_client::{
    AR_REFUSED_NO_RESOURCES, AlarmReport, ArState, AttachOptions, Client, ControlError,
    DiagnosisDirection, DiagnosisEntry, Ioxs, Mode, Notification, RecordRefusal, RecordTarget,
    Refusal, ServiceOptions, Services, StationRecordJob,
};
use procimg_profinet::wire::alarm::AlarmItem;
use procimg_profinet::wire::record::DiagnosisData;
use procimg_testkit::Launch;
use procimg_testkit::exchange::{
    at, controller_pattern, device_echo, next_device_event, until_the_plc_answers,
};
use procimg_testkit::netns::TestNet;
use procimg_testkit::tshark::{LiveCapture, flagged, frames_matching};
use procimg_testkit::veth_station::{CONTROLLER_TOML, DEVICE_TOML};
use std::time::{Duration, Instant};

/// Generous: a loaded machine may be slow to connect.
const BRING_UP: Duration = Duration::from_secs(30);

#[test]
fn the_device_demo_gives_its_clients_the_plcs_data_and_the_plc_theirs() {
    let server = Launch::demo_device("devdemo").start();
    let status = server.status();
    assert_eq!(status.role, "device");
    let station = status.station.expect("a station in the device role");
    assert_eq!((station.vendor_id, station.device_id), (0x0493, 0x0100));
    assert_eq!(station.name, "procimg-device");
    assert_eq!(station.ar.map(|a| a.state), Some(ArState::Data));
    // The demo PLC lays out the station's frame as an S7-1500 does, as the image holds it:
    // every frame to it goes out from the image, where the clients' data is.
    let until = Instant::now() + BRING_UP;
    let mut network = server.status().network;
    while network.sent_in_place == 0 && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(20));
        network = server.status().network;
    }
    assert!(network.sent_in_place > 0, "{network:?}");
    assert_eq!(network.sent_copied, 0, "{network:?}");

    let mut client = Client::attach(&server.instance, AttachOptions::synchronous("devapp"))
        .expect("attach to the device");
    assert!(client.is_device());
    let mine = client.claim_i_data().expect("claim the I data");
    let echo = at(&client, 1, 1);
    assert!(mine.contains(&echo), "slot 1 has I data: {mine:?}");
    // The demo's PLC answers every I byte with that byte plus one in the Q data.
    let written = [0x10, 0x21, 0x32, 0x43, 0x54, 0x65, 0x76, 0x87];
    until_the_plc_answers(&mut client, echo, &written, BRING_UP);

    // The device's services are the station's events; the controller's, asked for, say so.
    let services = Services::open(&server.instance, ServiceOptions::new("devapp-services"))
        .expect("the device's services");
    let message = services
        .diagnosis()
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(message.contains("IO device role"), "{message}");
    assert_eq!(server.status().network.watchdog_expiries, 0);
}

#[test]
fn a_device_program_knows_when_the_station_sends_what_it_wrote() {
    let server = Launch::demo_device("devapplied").start();
    let mut client = Client::attach(&server.instance, AttachOptions::asynchronous("applied"))
        .expect("attach to the device");
    client.claim_i_data().expect("claim the I data");
    let slot1 = client.layout().submodules[at(&client, 1, 1)];
    let data = [0xa5u8; 8];
    // Written into the cache only: not sent, so not applied.
    client
        .data_write_cache(slot1.output_address, &data, Ioxs::Good)
        .unwrap();
    assert!(!client.outputs_applied().unwrap());
    client.data_write_cache_flush().unwrap();
    assert!(
        client.wait_outputs_applied(BRING_UP).unwrap(),
        "procimgd did not apply the write"
    );
    let mut back = [0u8; 8];
    let read = client
        .output_data_read(slot1.output_address, &mut back)
        .unwrap();
    assert_eq!((back, read.local), (data, Ioxs::Good));
}

/// The next station notification, skipping the others; `None` after `within`.
fn next_station(services: &mut Services, within: Duration) -> Option<Notification> {
    let until = Instant::now() + within;
    while Instant::now() < until {
        if let Some(
            n @ (Notification::StationAr { .. }
            | Notification::StationArEnded { .. }
            | Notification::StationPlcRunning { .. }
            | Notification::StationBlink
            | Notification::StationIdentity { .. }),
        ) = services.next(Duration::from_millis(100))
        {
            return Some(n);
        }
    }
    None
}

/// The AR states reported until one reaches data exchange: those of the AR that did (a
/// loaded machine may see an attempt fail first), and its ARUUID.
fn states_until_data(services: &mut Services) -> (Vec<ArState>, String) {
    let mut states = Vec::new();
    loop {
        let n = next_station(services, BRING_UP).expect("the AR's states within 30 s");
        match n {
            Notification::StationAr { state, ar_uuid, .. } => {
                if state == ArState::Connected {
                    states.clear();
                }
                states.push(state);
                if state == ArState::Data {
                    return (states, ar_uuid);
                }
            }
            Notification::StationArEnded { .. } => states.clear(),
            _ => {}
        }
    }
}

#[test]
fn a_device_program_follows_the_ar_through_the_station_notifications() {
    let mut server = Launch::demo_device("devnote").start();
    let first = server
        .status()
        .station
        .and_then(|s| s.ar)
        .expect("the demo's AR");
    // Subscribed after the demo's AR came up: the handle sees what follows, whatever the
    // timing, because the test makes the AR end and come again itself.
    let mut services = Services::open(
        &server.instance,
        ServiceOptions::new("devnote").acknowledge_alarms(true),
    )
    .expect("the device's services");
    // Listed; alarm acknowledgement, asked for, means nothing here: the PLC acknowledges.
    let listed = server.status().subscribers;
    assert!(
        listed
            .iter()
            .any(|s| s.name == "devnote" && s.pid == std::process::id() && !s.acknowledges_alarms),
        "{listed:?}"
    );

    // OFFLINE: the station ends the AR on purpose.
    server.set_mode(Mode::Offline);
    let (ar_uuid, reason, aborted, planned, abort_code) = loop {
        match next_station(&mut services, BRING_UP) {
            Some(Notification::StationArEnded {
                ar_uuid,
                reason,
                aborted,
                planned,
                abort_code,
            }) => break (ar_uuid, reason, aborted, planned, abort_code),
            Some(Notification::StationPlcRunning { .. }) => {}
            Some(other) => panic!("before the AR's end: {other:?}"),
            None => panic!("the AR did not end within 30 s of OFFLINE"),
        }
    };
    assert_eq!(
        (ar_uuid, aborted, planned),
        (first.ar_uuid.clone(), true, true)
    );
    assert!(reason.contains("stopped taking part"), "{reason}");
    // The station's own abort: the RTA abort code "AR abort.req" (0x0d), IO-Base's
    // PNIO_AR_REASON_ABORT.
    assert_eq!(abort_code, Some(0x0d));

    // OPERATE: the PLC connects again, and every step of the new AR is reported.
    server.set_mode(Mode::Operate);
    let (states, uuid) = states_until_data(&mut services);
    assert_eq!(
        states,
        [
            ArState::Connected,
            ArState::Parameterized,
            ArState::WaitingForApplicationReadyConfirm,
            ArState::Data
        ]
    );
    assert_ne!(uuid, first.ar_uuid);
    let ar = server.status().station.and_then(|s| s.ar).expect("an AR");
    assert_eq!((ar.state, &ar.ar_uuid), (ArState::Data, &uuid));
    // The demo's PLC is in RUN once its data flows, the primary, without a station problem.
    let next = next_station(&mut services, BRING_UP);
    assert_eq!(
        next,
        Some(Notification::StationPlcRunning {
            running: true,
            station_problem: false,
            backup: false
        }),
        "after data exchange"
    );

    // procimgd stops (SIGTERM): its last notification is the AR's planned end.
    let exit = server.terminate();
    assert!(exit.success(), "procimgd exited with {exit}");
    let mut after = Vec::new();
    while let Some(n) = next_station(&mut services, Duration::from_secs(2)) {
        after.push(n);
    }
    let ends: Vec<&Notification> = after
        .iter()
        .filter(|n| matches!(n, Notification::StationArEnded { .. }))
        .collect();
    assert_eq!(ends.len(), 1, "{after:?}");
    assert!(
        matches!(ends[0], Notification::StationArEnded { ar_uuid, aborted: true, planned: true, .. }
            if *ar_uuid == uuid),
        "{after:?}"
    );
    assert!(
        !after
            .iter()
            .any(|n| matches!(n, Notification::StationAr { .. })),
        "{after:?}"
    );
}

/// Whether the station's AR is in data exchange.
fn in_data(s: &procimg_client::StatusReport) -> bool {
    s.station
        .as_ref()
        .and_then(|st| st.ar.as_ref())
        .is_some_and(|ar| ar.state == ArState::Data)
}

/// OFFLINE until the station's AR has ended, then OPERATE: the demo PLC connects again.
fn end_the_ar_and_let_the_plc_connect_again(server: &procimg_testkit::Procimgd) {
    server.set_mode(Mode::Offline);
    server.wait_status("the AR's end", |s| {
        s.station.as_ref().is_some_and(|st| st.ar.is_none())
    });
    server.set_mode(Mode::Operate);
}

/// The next notification for `services` that `pick` takes, skipping the others; panics
/// naming `what` after 30 s.
fn next_picked<T>(
    services: &mut Services,
    what: &str,
    pick: impl Fn(Notification) -> Option<T>,
) -> T {
    let until = Instant::now() + BRING_UP;
    while Instant::now() < until {
        if let Some(t) = services.next(Duration::from_millis(20)).and_then(&pick) {
            return t;
        }
    }
    panic!("no {what} within 30 s");
}

/// The next record job for `services`.
fn next_job(services: &mut Services) -> StationRecordJob {
    next_picked(services, "record job", |n| match n {
        Notification::StationRecord { job, .. } => Some(job),
        _ => None,
    })
}

#[test]
fn a_device_program_answers_the_plcs_records_and_holds_its_application_ready() {
    let server = Launch::demo_device("devrec").debug_log().start();
    server.wait_devices_running(BRING_UP);
    let mut services =
        Services::open(&server.instance, ServiceOptions::new("devrec")).expect("services");
    let other = Services::open(&server.instance, ServiceOptions::new("devrec-2")).expect("other");
    services.take_records((0, 1, 1)).expect("slot 1's records");
    let e = other
        .take_records((0, 1, 1))
        .expect_err("taken by the first handle");
    assert!(
        matches!(&e, ControlError::Refused(Refusal::RecordsTaken { by, .. }) if by == "devrec"),
        "{e}"
    );
    let e = services.take_records((0, 9, 1)).expect_err("no slot 9");
    assert!(
        matches!(
            e,
            ControlError::Refused(Refusal::NoSuchStationSubmodule { slot: 9, .. })
        ),
        "{e}"
    );

    // The demo PLC's program writes record 1 of slot 1 every 2 s: refused once, then taken.
    let job = next_job(&mut services);
    assert_eq!(
        (job.write, job.index, job.slot, job.data.len()),
        (true, 1, 1, 4)
    );
    services
        .answer_record(
            &job,
            Err(RecordRefusal::new(RecordRefusal::INVALID_PARAMETER)),
        )
        .expect("the answer");
    let e = services
        .answer_record(&job, Ok(&[]))
        .expect_err("a job is answered once");
    assert!(
        matches!(e, ControlError::Refused(Refusal::StaleRecordJob { .. })),
        "{e}"
    );
    let e = other
        .answer_record(&job, Ok(&[]))
        .expect_err("not the other handle's job");
    assert!(
        matches!(e, ControlError::Refused(Refusal::StaleRecordJob { .. })),
        "{e}"
    );
    // What the PLC's program last heard of its writes, in its log.
    let last_write = || {
        server
            .log()
            .lines()
            .rev()
            .find(|l| l.contains("demo PLC: ") && l.contains("record 1 of station"))
            .map(str::to_owned)
            .unwrap_or_default()
    };
    server.wait_status("the PLC's log of the refused write", |_| {
        last_write().contains("failed: Write failed: access: invalid parameter")
    });
    let job = next_job(&mut services);
    services.answer_record(&job, Ok(&[])).expect("the answer");
    server.wait_status("the PLC's log of the taken write", |_| {
        last_write().ends_with("written")
    });

    // Held: after the PLC's PrmEnd the station waits for this handle; the PLC's parameter
    // writes in the new AR come here too.
    services.hold_application_ready(true).expect("hold");
    end_the_ar_and_let_the_plc_connect_again(&server);
    let until = Instant::now() + BRING_UP;
    let mut parameter_writes = 0;
    loop {
        assert!(Instant::now() < until, "no PrmEnd within 30 s");
        match services.next(Duration::from_millis(100)) {
            Some(Notification::StationRecord { job, .. }) => {
                parameter_writes += u32::from(job.write);
                services.answer_record(&job, Ok(&[])).expect("the answer");
            }
            Some(Notification::StationAr {
                state: ArState::Parameterized,
                ..
            }) => break,
            _ => {}
        }
    }
    assert!(
        parameter_writes >= 1,
        "the PLC writes the configured record"
    );
    // It stays held (up to 10 s): the status shows it parameterized, not in data exchange.
    let ar = server.status().station.and_then(|s| s.ar).expect("the AR");
    assert_eq!(ar.state, ArState::Parameterized);
    services.application_ready().expect("ready");
    let (states, _) = states_until_data(&mut services);
    assert_eq!(states.last(), Some(&ArState::Data));
    assert_eq!(server.status().network.watchdog_expiries, 0);
    drop(other);
    drop(services);
}

#[test]
fn a_device_program_refuses_a_new_ar_and_accepts_the_next() {
    let server = Launch::demo_device("devchk").start();
    server.wait_devices_running(BRING_UP);
    let mut services =
        Services::open(&server.instance, ServiceOptions::new("devchk")).expect("services");
    let other = Services::open(&server.instance, ServiceOptions::new("devchk-2")).expect("other");
    services.check_ars(true).expect("check ARs");
    let e = other.check_ars(true).expect_err("one handle checks");
    assert!(
        matches!(&e, ControlError::Refused(Refusal::ArChecksTaken { by }) if by == "devchk"),
        "{e}"
    );
    end_the_ar_and_let_the_plc_connect_again(&server);
    let next_check = |services: &mut Services| {
        next_picked(services, "AR check", |n| match n {
            Notification::StationArCheck { check, .. } => Some(check),
            _ => None,
        })
    };
    let first = next_check(&mut services);
    assert_eq!(first.controller_name, "demo-plc");
    // Slot 1 as the PLC expects it, and what is plugged there.
    let slot1 = first
        .expected
        .iter()
        .find(|e| (e.slot, e.subslot) == (1, 1))
        .expect("slot 1 expected");
    assert_eq!(
        slot1.plugged,
        Some((slot1.module_ident, slot1.submodule_ident))
    );
    services
        .answer_ar_check(&first, Err(AR_REFUSED_NO_RESOURCES))
        .expect("refused");
    let e = services
        .answer_ar_check(&first, Ok(()))
        .expect_err("answered once");
    assert!(
        matches!(e, ControlError::Refused(Refusal::StaleArCheck { .. })),
        "{e}"
    );
    // The PLC tries again; this time the program takes the AR.
    let second = next_check(&mut services);
    services.answer_ar_check(&second, Ok(())).expect("accepted");
    let (states, uuid) = states_until_data(&mut services);
    assert_eq!(states.last(), Some(&ArState::Data));
    assert_eq!(uuid, second.ar_uuid);
    assert!(
        server
            .status()
            .station
            .is_some_and(|s| s.ar.is_some_and(|a| a.ar_uuid == uuid))
    );
    drop(other);
}

/// The PLC gives up an AR in its start-up: this handle took slot 1's records and leaves the
/// PLC's parameter write unanswered, the station answers it "resource busy" after its record
/// timeout, and the PLC's write has failed. The PLC aborts that AR towards the station, which
/// ends it at once, so that the PLC's next Connect is taken instead of refused "out of AR
/// resources" until the AR's CMI timeout; with the records the station's again, the AR
/// reaches data exchange.
#[test]
fn a_plc_that_gives_up_an_ar_in_start_up_is_taken_again_at_its_next_connect() {
    let server = Launch::demo_device("devgiveup").debug_log().start();
    server.wait_devices_running(BRING_UP);
    let mut services =
        Services::open(&server.instance, ServiceOptions::new("devgiveup")).expect("services");
    services.take_records((0, 1, 1)).expect("slot 1's records");
    let first = server
        .status()
        .station
        .and_then(|s| s.ar)
        .expect("the demo's AR");
    services.abort_ar(&first.ar_uuid).expect("the AR ends");

    // The PLC connects again and writes its parameter record here (the program's writes in
    // the first AR may come before: they are not the one), unanswered.
    let unanswered = next_picked(
        &mut services,
        "the next AR's parameter write",
        |n| match n {
            Notification::StationRecord { job, .. }
                if job.write && job.ar_uuid != first.ar_uuid =>
            {
                Some(job)
            }
            _ => None,
        },
    );
    let (reason, planned, abort_code) =
        next_picked(&mut services, "the end of the given-up AR", |n| match n {
            Notification::StationArEnded {
                ar_uuid,
                reason,
                aborted: true,
                planned,
                abort_code,
            } if ar_uuid == unanswered.ar_uuid => Some((reason, planned, abort_code)),
            _ => None,
        });
    // Ended by the PLC's ERR-RTA, with the abort code of a refused start-up ("AR protocol
    // violation"), not by the station's CMI timeout (0x06), which the PLC would wait for.
    assert_eq!((abort_code, planned), (Some(0x12), false), "{reason}");

    services.give_back_records((0, 1, 1)).expect("give back");
    // A job of the next attempt that reached this handle before is answered all the same.
    let until = Instant::now() + BRING_UP;
    let uuid = loop {
        assert!(Instant::now() < until, "no data exchange within 30 s");
        match services.next(Duration::from_millis(100)) {
            Some(Notification::StationRecord { job, .. }) => {
                let _ = services.answer_record(&job, Ok(&[]));
            }
            Some(Notification::StationAr {
                state: ArState::Data,
                ar_uuid,
                ..
            }) => break ar_uuid,
            _ => {}
        }
    };
    assert_ne!(uuid, unanswered.ar_uuid);
    assert!(in_data(&server.status()));
    let refused = server.log_lines("out of AR resources");
    assert!(refused.is_empty(), "{refused:#?}");
}

#[test]
fn a_device_call_on_a_controller_is_an_error() {
    let server = Launch::demo("devctl").start();
    let mut client = Client::attach(&server.instance, AttachOptions::asynchronous("devctl"))
        .expect("attach to the controller");
    assert!(!client.is_device());
    let e = client
        .claim_i_data()
        .expect_err("a controller has no I data to claim");
    assert!(e.to_string().contains("IO controller"), "{e}");
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn a_device_program_vetoes_a_dcp_name_change_and_allows_the_next() {
    let net = TestNet::new("dk", true);
    for (i, ip) in [(0, "10.47.0.1/24"), (1, "10.47.0.50/24")] {
        net.address(i, ip);
    }
    let dir = procimg_testkit::files::temp_dir("device-role-dcp-veto");
    let device_toml = DEVICE_TOML.replace("IFACE", &net.ifs[1]).replace(
        "STATE",
        &dir.path().join("station.toml").display().to_string(),
    );
    let device = Launch::config("dkd", &device_toml)
        .netns(&net.ns[1])
        .until_cycling()
        .start();
    let mut services =
        Services::open(&device.instance, ServiceOptions::new("dk-veto")).expect("services");
    services.verify_dcp_sets(true).expect("verify DCP");
    let mac = device.status().station.expect("a station").mac;
    let procimg = procimg_testkit::workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    // The engineering tool names the station; it waits for the DCP response meanwhile.
    let set_name = |name: &str| {
        std::process::Command::new("ip")
            .args(["netns", "exec", &net.ns[0]])
            .arg(&procimg)
            .args(["dcp", "--iface", &net.ifs[0], "set-name", &mac, name])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("procimg dcp set-name")
    };
    let next_check = |services: &mut Services| {
        next_picked(services, "DCP Set check", |n| match n {
            Notification::StationDcpSetCheck { check, .. } => Some(check),
            _ => None,
        })
    };
    let tool = set_name("vetoed-name");
    let check = next_check(&mut services);
    assert_eq!(
        (check.name.as_deref(), check.ip_suite.clone(), check.reset),
        (Some("vetoed-name"), None, false)
    );
    // Answered within the station's 500 ms unless the machine stalls; then the Set went
    // ahead and the answer is stale, which the test tells apart below.
    let vetoed = services.answer_dcp_set(&check, false);
    let out = tool.wait_with_output().expect("the tool's end");
    match vetoed {
        Ok(()) => {
            assert!(!out.status.success(), "a vetoed name was set");
            assert_eq!(
                device.status().station.map(|s| s.name),
                Some("fresh-device".into())
            );
        }
        Err(e) => assert!(
            matches!(e, ControlError::Refused(Refusal::StaleDcpCheck { .. })),
            "{e}"
        ),
    }
    let tool = set_name("allowed-name");
    let check = next_check(&mut services);
    let _ = services.answer_dcp_set(&check, true);
    let out = tool.wait_with_output().expect("the tool's end");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    wait_station_name(&device, "allowed-name");
}

/// Waits until `done`, for at most 5 s.
fn wait_for(mut done: impl FnMut() -> bool, what: &str) {
    let until = Instant::now() + Duration::from_secs(5);
    while !done() {
        assert!(Instant::now() < until, "{what} did not show within 5 s");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Waits until the device's station has `name`.
fn wait_station_name(device: &procimg_testkit::Procimgd, name: &str) {
    let until = Instant::now() + BRING_UP;
    loop {
        let now = device.status().station.map(|s| s.name).unwrap_or_default();
        if now == name {
            return;
        }
        assert!(
            Instant::now() < until,
            "the station is {now:?}, not {name:?}"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The next alarm among the controller's notifications.
fn next_alarm(services: &mut Services) -> AlarmReport {
    let until = Instant::now() + Duration::from_secs(5);
    while Instant::now() < until {
        match services.next(Duration::from_millis(100)) {
            Some(Notification::Alarm(a)) => return a,
            Some(failure @ Notification::DeviceFailure { .. }) => {
                panic!("the AR ended while an alarm was awaited: {failure:?}")
            }
            _ => {}
        }
    }
    panic!("no alarm within 5 s");
}

/// Ends the device's AR (the controller deactivates it) and sets it up again; what the new
/// AR's ModuleDiffBlock listed, as the controller's client is told it.
fn reconnect(services: &mut Services) -> Vec<procimg_client::SubmoduleDiff> {
    services.activate(0, false).expect("deactivate the device");
    let failure = next_device_event(services, "failure");
    assert!(
        matches!(failure, Notification::DeviceFailure { .. }),
        "{failure:?}"
    );
    services.activate(0, true).expect("activate the device");
    let mut listed = Vec::new();
    let until = Instant::now() + BRING_UP;
    loop {
        assert!(Instant::now() < until, "no return within {BRING_UP:?}");
        match services.next(Duration::from_millis(100)) {
            Some(Notification::ModuleDiff { submodules, .. }) => listed = submodules,
            Some(Notification::DeviceReturn { .. }) => return listed,
            _ => {}
        }
    }
}

/// The (channel, error type) pairs of record 0x800A of slot 1 subslot 1, read by the
/// controller from the device.
fn channel_errors(services: &mut Services) -> Vec<(u16, u16)> {
    let target = RecordTarget {
        device: 0,
        api: 0,
        slot: 1,
        subslot: 1,
        index: 0x800A,
    };
    // On a loaded machine the 10 ms watchdog may give up the AR at any time (the data test
    // above reports how often); a program then reads again once it is set up again.
    let until = Instant::now() + BRING_UP;
    let data = loop {
        match services.read_record(target, 4096, Duration::from_secs(5)) {
            Ok(data) => break data,
            Err(e) => assert!(Instant::now() < until, "read record 0x800A: {e:?}"),
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    DiagnosisData::parse_record(&data)
        .expect("DiagnosisData blocks")
        .into_iter()
        .flat_map(|d| match d.item {
            AlarmItem::Diagnosis(diag) => diag
                .entries
                .iter()
                .map(|e| (e.channel_number, e.channel_error_type))
                .collect(),
            AlarmItem::Other { .. } => Vec::new(),
        })
        .collect()
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn procimg_controller_and_procimg_device_exchange_data_over_a_veth_pair() {
    let net = TestNet::new("dv", true);
    for (i, ip) in [(0, "10.47.0.1/24"), (1, "10.47.0.50/24")] {
        net.address(i, ip);
    }
    // Every frame on the wire, from before the device starts.
    let dir = procimg_testkit::files::temp_dir("device-role-veth");
    let pcap = dir.path().join("wire.pcapng");
    let capture = LiveCapture::start(&net.ns[0], &net.ifs[0], &pcap);

    let state = dir.path().join("station.toml");
    let device_toml = DEVICE_TOML
        .replace("IFACE", &net.ifs[1])
        .replace("STATE", &state.display().to_string());
    let mut device = Launch::config("dvd", &device_toml)
        .netns(&net.ns[1])
        .until_cycling()
        .start();
    // Commissioning: the engineering tool names the station for good; the device's program
    // hears of it.
    let mut station_events = Services::open(&device.instance, ServiceOptions::new("dev-events"))
        .expect("the device's services");
    let mac = device.status().station.expect("a station").mac;
    let procimg = procimg_testkit::workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    let named = std::process::Command::new("ip")
        .args(["netns", "exec", &net.ns[0]])
        .arg(&procimg)
        .args([
            "dcp",
            "--iface",
            &net.ifs[0],
            "set-name",
            &mac,
            "pc-device",
            "--permanent",
        ])
        .output()
        .expect("procimg dcp set-name");
    assert!(
        named.status.success(),
        "{}",
        String::from_utf8_lossy(&named.stderr)
    );
    wait_station_name(&device, "pc-device");
    let Some(Notification::StationIdentity {
        name,
        ip,
        permanent,
        factory_reset,
        ..
    }) = next_station(&mut station_events, BRING_UP)
    else {
        panic!("no notification of the new name");
    };
    assert_eq!(
        (name.as_str(), ip.as_str(), permanent, factory_reset),
        ("pc-device", "10.47.0.50", true, false)
    );
    drop(station_events);
    assert!(
        std::fs::read_to_string(&state)
            .unwrap()
            .contains("pc-device")
    );
    let controller = Launch::config("dvc", &CONTROLLER_TOML.replace("IFACE", &net.ifs[0]))
        .netns(&net.ns[0])
        .start();
    // Whatever a loaded machine did to the AR meanwhile: the station in data exchange.
    device.wait_status("the station's AR in data exchange", in_data);

    // 10 s at 1 ms: the controller's patterns come back through the device's client.
    let expiries = |s: &procimg_client::StatusReport| s.network.watchdog_expiries;
    let before = (expiries(&controller.status()), expiries(&device.status()));
    let echo = device_echo(device.instance.clone(), 11_000);
    let seen = controller_pattern(&controller.instance, "pc-device", 10_000);
    let echoed = echo.join().expect("the device's client");
    let after = (expiries(&controller.status()), expiries(&device.status()));
    assert_eq!(seen.cycles, 10_000);
    assert_eq!(seen.wrong, 0, "{seen:?}");
    // A loaded machine (the other tests' servers run beside these) may starve a cycle past
    // the 10 ms watchdog; the AR is set up again then, and the data is right throughout.
    // How often that happens is the scheduler's; that the data comes back is the test's.
    let expired = (after.0 - before.0, after.1 - before.1);
    assert!(
        seen.echoes > 1_000,
        "{seen:?}, watchdog expiries (controller, device) {expired:?}"
    );
    assert!(
        echoed > 1_000,
        "the device's client saw GOOD Q data {echoed} times; watchdog expiries {expired:?}"
    );

    // The controller's port announces itself by LLDP: the station knows its neighbour (the
    // controller's name, port and address) and takes its alias name from it.
    let with_neighbour = device.wait_status("the controller as the LLDP neighbour", |s| {
        s.station
            .as_ref()
            .is_some_and(|st| !st.neighbours.is_empty())
    });
    let station = with_neighbour.station.unwrap();
    let n = &station.neighbours[0];
    let controller_name = format!("procimgd-{}", controller.instance.to_ascii_lowercase());
    assert_eq!(
        (n.station.as_deref(), n.port.as_deref(), n.ip.as_deref()),
        (
            Some(controller_name.as_str()),
            Some("port-001"),
            Some("10.47.0.1")
        ),
        "{n:?}"
    );
    assert!(n.ttl_left_s <= 20, "{n:?}");
    assert_eq!(
        station.alias_name,
        Some(format!("port-001.{controller_name}"))
    );

    // The PLC's STOP (its controller in CLEAR) and RUN reach the device's status.
    let plc_running = |device: &procimg_testkit::Procimgd| {
        device
            .status()
            .station
            .and_then(|s| s.ar)
            .and_then(|a| a.plc_running)
    };
    assert_eq!(plc_running(&device), Some(true));
    controller.set_mode(procimg_client::Mode::Clear);
    wait_for(|| plc_running(&device) == Some(false), "the PLC's STOP");
    controller.set_mode(procimg_client::Mode::Operate);
    wait_for(|| plc_running(&device) == Some(true), "the PLC's RUN");

    // With no client providing the device's I data, the PLC gets it BAD; a new owner makes
    // it GOOD again.
    let mut watcher = Client::attach(&controller.instance, AttachOptions::asynchronous("watch"))
        .expect("attach to the controller");
    let s = at(&watcher, 1, 1);
    let wait_remote = |watcher: &mut Client, want: Ioxs| {
        let until = Instant::now() + Duration::from_secs(5);
        loop {
            let st = watcher
                .newest_status(s)
                .ok()
                .flatten()
                .map(|st| st.input_remote);
            if st == Some(want) {
                return;
            }
            assert!(
                Instant::now() < until,
                "the I data did not turn {want:?}: {st:?}"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
    };
    wait_remote(&mut watcher, Ioxs::Bad);
    let again = device_echo(device.instance.clone(), 500);
    wait_remote(&mut watcher, Ioxs::Good);
    let _ = again.join();
    // Keep the device's I data owned while the diagnosis goes through.
    let again = device_echo(device.instance.clone(), 60_000);

    // A diagnosis the device's client adds reaches the controller's client as an alarm and
    // in record 0x800A of the submodule; its removal too.
    let mut services = Services::open(
        &controller.instance,
        ServiceOptions::new("ctl-services").acknowledge_alarms(true),
    )
    .expect("the controller's services");
    let dev_client = Client::attach(&device.instance, AttachOptions::asynchronous("dev-diag"))
        .expect("attach to the device");
    let wire_break = DiagnosisEntry {
        channel: 3,
        error_type: 6,
        direction: DiagnosisDirection::Input,
        data_type: 1,
        ..DiagnosisEntry::default()
    };
    dev_client
        .add_diagnosis((0, 1, 1), wire_break.clone())
        .expect("add a diagnosis");
    let alarm = next_alarm(&mut services);
    assert_eq!(
        (alarm.alarm_type, alarm.slot, alarm.subslot),
        (1, 1, 1),
        "{alarm:?}"
    );
    services.acknowledge(&alarm).expect("acknowledge the alarm");
    assert_eq!(channel_errors(&mut services), [(3, 6)]);
    dev_client
        .remove_diagnosis((0, 1, 1), wire_break)
        .expect("remove the diagnosis");
    let gone = next_alarm(&mut services);
    assert_eq!((gone.slot, gone.subslot), (1, 1), "{gone:?}");
    services.acknowledge(&gone).expect("acknowledge the alarm");
    assert_eq!(channel_errors(&mut services), []);
    // A process alarm (high priority) reaches the controller's client with its data; the
    // acknowledgement reaches the device.
    dev_client
        .raise_process_alarm((0, 2, 1), 0x0042, &[1, 2, 3])
        .expect("raise a process alarm");
    let process = next_alarm(&mut services);
    assert_eq!(
        (process.alarm_type, process.slot, process.high_priority),
        (2, 2, true)
    );
    assert!(process.payload.ends_with(&[1, 2, 3]), "{process:?}");
    services
        .acknowledge(&process)
        .expect("acknowledge the alarm");
    wait_for(
        || {
            device
                .status()
                .station
                .is_some_and(|s| s.alarms_acknowledged >= 3)
        },
        "the PLC's acknowledgement of three alarms",
    );
    // An alarm of the device client's own making (IO-Base's PNIO_diag_alarm_send): a
    // diagnosis kept without an alarm, then its alarm; the acknowledgement comes back to
    // the sender with the alarm's tag.
    let mut dev_services = Services::open(&device.instance, ServiceOptions::new("dev-alarms"))
        .expect("the device's services");
    let change = procimg_client::StationDiagnosisChange::Add {
        api: 0,
        slot: 1,
        subslot: 1,
        entry: DiagnosisEntry {
            channel: 0x8000,
            error_type: 5,
            ..DiagnosisEntry::default()
        },
    };
    dev_services
        .keep_diagnosis(change)
        .expect("keep a diagnosis");
    dev_services
        .send_alarm(
            (0, 1, 1),
            procimg_client::StationAlarmKind::DiagnosisAppears,
            0x8000,
            &[0x80, 0x00, 0x08, 0x00, 0x00, 0x05],
            77,
        )
        .expect("send the diagnosis alarm");
    let own = next_alarm(&mut services);
    assert_eq!(
        (own.alarm_type, own.slot, own.subslot),
        (1, 1, 1),
        "{own:?}"
    );
    services.acknowledge(&own).expect("acknowledge the alarm");
    let until = Instant::now() + Duration::from_secs(5);
    let done = loop {
        assert!(Instant::now() < until, "no StationAlarmDone within 5 s");
        if let Some(Notification::StationAlarmDone { tag, status, .. }) =
            dev_services.next(Duration::from_millis(100))
        {
            break (tag, status);
        }
    };
    assert_eq!(done, (77, Some([0, 0, 0, 0])));
    assert_eq!(channel_errors(&mut services), [(0x8000, 5)]);
    // A diagnosis present when an AR is set up is not an alarm: the Connect response's
    // ModuleDiffBlock lists the submodule, right but with diagnosis, and the record has it.
    let listed = reconnect(&mut services);
    let diag: Vec<_> = listed
        .iter()
        .map(|d| (d.api, d.slot, d.subslot, d.state, d.text.as_str()))
        .collect();
    assert_eq!(
        diag,
        [(
            0,
            1,
            1,
            0x8040,
            "the expected submodule, owned by this AR, diagnosis available"
        )]
    );
    assert_eq!(channel_errors(&mut services), [(0x8000, 5)]);
    dev_client
        .clear_diagnosis((0, 1, 1))
        .expect("clear the diagnosis");
    let cleared = next_alarm(&mut services);
    services
        .acknowledge(&cleared)
        .expect("acknowledge the alarm");
    // The device's managing client pulls slot 1: the controller's client gets the Pull
    // alarm and the I data BAD; plugged again, the Plug alarm, the controller writes its
    // parameters (the plug sub-cycle) and the I data is GOOD again.
    dev_client.pull_submodule((0, 1, 1)).expect("pull slot 1");
    let pull = next_alarm(&mut services);
    assert_eq!(
        (pull.alarm_type, pull.slot, pull.subslot),
        (3, 1, 1),
        "{pull:?}"
    );
    services.acknowledge(&pull).expect("acknowledge the alarm");
    wait_remote(&mut watcher, Ioxs::Bad);
    dev_client
        .plug_submodule((0, 1, 1), 0x10, 0x1)
        .expect("plug slot 1");
    let plug = next_alarm(&mut services);
    assert_eq!(
        (plug.alarm_type, plug.slot, plug.subslot),
        (4, 1, 1),
        "{plug:?}"
    );
    services.acknowledge(&plug).expect("acknowledge the alarm");
    wait_remote(&mut watcher, Ioxs::Good);
    drop(dev_client);

    // The device dies: the controller reports DEV_FAILURE; restarted, it comes back under
    // the name the state file kept, and the controller reports DEV_RETURN.
    while services.next(Duration::from_millis(10)).is_some() {}
    device.kill();
    // The device's echo thread ends with its server (its wait for STARTOP runs out), before
    // the restart it would otherwise follow: a thread still running when the test binary
    // exits leaves its client's iceoryx2 files behind.
    let _ = again.join();
    let failure = next_device_event(&mut services, "failure");
    assert!(
        matches!(failure, Notification::DeviceFailure { .. }),
        "{failure:?}"
    );
    device.restart();
    wait_station_name(&device, "pc-device");
    let back = next_device_event(&mut services, "return");
    assert!(
        matches!(back, Notification::DeviceReturn { .. }),
        "{back:?}"
    );
    controller.wait_devices_running(BRING_UP);

    // The device stalls (SIGSTOP): the controller's watchdog expires and it tells the
    // device with an ERR-RTA "consumer data hold time expired"; resumed, the device frees
    // the AR and is back in data exchange after the controller's short back-off.
    while services.next(Duration::from_millis(10)).is_some() {}
    /// Resumes the stopped process when dropped, also when the test fails meanwhile.
    struct Resume(u32);
    impl Drop for Resume {
        fn drop(&mut self) {
            procimg_testkit::signal::send(self.0, libc::SIGCONT);
        }
    }
    let resume = Resume(device.pid());
    procimg_testkit::signal::send(device.pid(), libc::SIGSTOP);
    let failure = next_device_event(&mut services, "failure");
    drop(resume);
    assert!(
        matches!(failure, Notification::DeviceFailure { .. }),
        "{failure:?}"
    );
    let resumed = Instant::now();
    let back = next_device_event(&mut services, "return");
    assert!(
        matches!(back, Notification::DeviceReturn { .. }),
        "{back:?}"
    );
    eprintln!(
        "the stalled device was back in data exchange {} ms after it resumed",
        resumed.elapsed().as_millis()
    );
    controller.wait_devices_running(BRING_UP);
    drop(services);
    let controller_mac = ip_show(&net.ns[0], &["-o", "link", "show"], &net.ifs[0])
        .split_whitespace()
        .skip_while(|w| *w != "link/ether")
        .nth(1)
        .expect("the controller's MAC address")
        .to_owned();

    drop(watcher);
    drop(controller);
    drop(device);
    std::thread::sleep(Duration::from_millis(500));
    let pcap = capture.stop();
    assert!(pcap.exists(), "tshark wrote no capture");
    let bad = flagged(&pcap);
    assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
    // ERR-RTA (PDUType 4) from the controller, ErrorCode2 5: consumer DHT expired.
    let abort = frames_matching(
        &pcap,
        &format!(
            "eth.src == {controller_mac} && pn_io.pdu_type.type == 4 && pn_io.error_code2 == 0x05"
        ),
    );
    assert!(
        !abort.trim().is_empty(),
        "no ERR-RTA \"consumer DHT expired\" from the controller ({controller_mac}) on the wire"
    );
    // The controller stopped (SIGTERM) after the device's answer to its Release: no "port
    // unreachable" from its address.
    let icmp = frames_matching(&pcap, "icmp.type == 3 && ip.src == 10.47.0.1");
    assert!(
        icmp.trim().is_empty(),
        "the controller answered with ICMP:\n{icmp}"
    );
}

/// What `ip -n NS CMD... dev IF` prints.
fn ip_show(ns: &str, args: &[&str], interface: &str) -> String {
    let out = std::process::Command::new("ip")
        .args(["-n", ns])
        .args(args)
        .args(["dev", interface])
        .output()
        .expect("the ip command (iproute2)");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `procimg dcp --iface IF ARGS` in namespace `ns`; panics if it fails.
fn dcp(ns: &str, interface: &str, args: &[&str]) {
    let procimg = procimg_testkit::workspace_bin("procimg", "PROCIMG_BIN", "procimg-tools");
    let out = std::process::Command::new("ip")
        .args(["netns", "exec", ns])
        .arg(&procimg)
        .args(["dcp", "--iface", interface])
        .args(args)
        .output()
        .expect("procimg dcp");
    assert!(
        out.status.success(),
        "procimg dcp {}: {}",
        args.join(" "),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A station as it leaves the factory: no address in its configuration, none on its
/// interface; only its name, as the engineering tool gave it.
fn fresh_device_toml(interface: &str, state: &std::path::Path) -> String {
    DEVICE_TOML
        .replace("fresh-device", "pc-device")
        .replace("ip = \"10.47.0.50\"\n", "")
        .replace("IFACE", interface)
        .replace("STATE", &state.display().to_string())
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET, interface addresses"]
fn the_plc_gives_a_fresh_station_its_address_and_dcp_changes_it_on_the_interface() {
    let net = TestNet::new("da", true);
    procimg_testkit::netns::ip(&[
        "-n",
        &net.ns[0],
        "addr",
        "add",
        "10.47.0.1/24",
        "dev",
        &net.ifs[0],
    ]);
    let (dev_ns, dev_if) = (net.ns[1].clone(), net.ifs[1].clone());
    let addresses = || ip_show(&dev_ns, &["-4", "addr", "show"], &dev_if);
    let default_route = || ip_show(&dev_ns, &["-4", "route", "show", "default"], &dev_if);
    let dir = procimg_testkit::files::temp_dir("device-role-address");
    let state = dir.path().join("station.toml");
    let toml = fresh_device_toml(&dev_if, &state);
    assert!(!toml.contains("ip ="), "{toml}");
    let mut device = Launch::config("dva", &toml)
        .netns(&dev_ns)
        .until_cycling()
        .start();
    assert!(!addresses().contains("inet "), "{}", addresses());
    let station = device.status().station.expect("a station");
    assert_eq!(station.ip, "0.0.0.0");

    // The PLC finds the station by its name, sets its address by DCP (for now, as a PLC
    // does) and connects to it.
    let controller = Launch::config("dvac", &CONTROLLER_TOML.replace("IFACE", &net.ifs[0]))
        .netns(&net.ns[0])
        .start();
    controller.wait_devices_running(BRING_UP);
    // Whatever a loaded machine did to the AR meanwhile: the station in data exchange.
    let station = device
        .wait_status("the station's AR in data exchange", in_data)
        .station
        .expect("a station");
    assert_eq!(station.ip, "10.47.0.50");
    assert!(
        addresses().contains("inet 10.47.0.50/24"),
        "{}",
        addresses()
    );
    drop(controller);

    // A reset to factory takes it away; the answer comes once it is gone.
    dcp(&net.ns[0], &net.ifs[0], &["reset", &station.mac]);
    assert!(!addresses().contains("inet "), "{}", addresses());
    assert_eq!(device.status().station.expect("a station").ip, "0.0.0.0");

    // An address for good, with a router: the interface gets both.
    dcp(
        &net.ns[0],
        &net.ifs[0],
        &[
            "set-ip",
            &station.mac,
            "10.47.0.60",
            "255.255.255.0",
            "10.47.0.1",
            "--permanent",
        ],
    );
    assert!(
        addresses().contains("inet 10.47.0.60/24"),
        "{}",
        addresses()
    );
    assert!(!addresses().contains("10.47.0.50"), "{}", addresses());
    let route = default_route();
    assert!(
        route.contains("via 10.47.0.1") && route.contains("metric 34964"),
        "{route}"
    );

    // Stopped, the station takes its address and route along; restarted, it comes back with
    // the address the state file kept.
    assert!(device.terminate().success());
    assert!(!addresses().contains("inet "), "{}", addresses());
    assert!(default_route().is_empty(), "{}", default_route());
    device.restart();
    assert!(
        addresses().contains("inet 10.47.0.60/24"),
        "{}",
        addresses()
    );
    assert!(
        default_route().contains("via 10.47.0.1"),
        "{}",
        default_route()
    );
    drop(device);
    assert!(!addresses().contains("inet "), "{}", addresses());
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET, interface addresses"]
fn a_station_does_not_share_its_interface_with_other_addresses() {
    let net = TestNet::new("dx", true);
    let (ns, interface) = (&net.ns[1], &net.ifs[1]);
    procimg_testkit::netns::ip(&["-n", ns, "addr", "add", "192.0.2.7/24", "dev", interface]);
    let dir = procimg_testkit::files::temp_dir("device-role-foreign");
    let config = dir.path().join("device.toml");
    std::fs::write(
        &config,
        fresh_device_toml(interface, &dir.path().join("state.toml")),
    )
    .unwrap();
    let out = std::process::Command::new("ip")
        .args(["netns", "exec", ns])
        .arg(procimg_testkit::procimgd_bin())
        .arg("--config")
        .arg(&config)
        .args(["--instance", &procimg_testkit::unique_instance("dvx")])
        .env("NO_COLOR", "1")
        .output()
        .expect("procimgd");
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{said}");
    assert!(
        said.contains(&format!("\"{interface}\" carries 192.0.2.7/24"))
            && said.contains(&format!("ip -4 addr flush dev {interface}")),
        "{said}"
    );
    // Left as it was.
    let kept = ip_show(ns, &["-4", "addr", "show"], interface);
    assert!(kept.contains("inet 192.0.2.7/24"), "{kept}");
}

/// Runs cycles (I data echoed from nothing: zeros) until the Q status of submodule `s` is
/// `want`, that is until the PLC's side of it is exchanged (GOOD) or not (BAD).
fn until_q_status(client: &mut Client, s: usize, want: Ioxs, what: &str) {
    let until = Instant::now() + BRING_UP;
    loop {
        let cycle = client
            .wait_startop(Duration::from_secs(5))
            .expect("STARTOP");
        let now = cycle.q_status(s).expect("Q status");
        cycle.set_opdone().expect("OPDONE");
        if now == want {
            return;
        }
        assert!(
            Instant::now() < until,
            "{what}: the Q status stayed {now:?}"
        );
    }
}

/// The next plug notification.
fn next_plug(services: &mut Services) -> (bool, u32, String) {
    next_picked(services, "plug notification", |n| match n {
        Notification::StationPlug {
            plugged,
            submodule_ident,
            alarm,
            ..
        } => Some((plugged, submodule_ident, alarm)),
        _ => None,
    })
}

#[test]
fn a_managing_client_pulls_and_plugs_a_submodule_and_the_plc_follows() {
    let server = Launch::demo_device("devplug").start();
    let mut services = Services::open(&server.instance, ServiceOptions::new("devplug-events"))
        .expect("the device's services");
    let mut client = Client::attach(&server.instance, AttachOptions::synchronous("devplug"))
        .expect("attach to the device");
    client.claim_i_data().expect("claim the I data");
    let echo = at(&client, 1, 1);
    until_q_status(&mut client, echo, Ioxs::Good, "before the pull");

    // Pulled: the PLC gets a Pull alarm, the submodule's data turns BAD.
    client.pull_submodule((0, 1, 1)).expect("pull slot 1");
    assert_eq!(next_plug(&mut services), (false, 0, "pull".to_owned()));
    until_q_status(&mut client, echo, Ioxs::Bad, "after the pull");
    let again = client.pull_submodule((0, 1, 1)).unwrap_err().to_string();
    assert!(again.contains("no submodule is plugged at"), "{again}");

    // Plugged again, the expected one: a Plug alarm, the PLC's parameters, GOOD again.
    client
        .plug_submodule((0, 1, 1), 0x10, 0x1)
        .expect("plug slot 1");
    assert_eq!(next_plug(&mut services), (true, 0x1, "plug".to_owned()));
    until_q_status(&mut client, echo, Ioxs::Good, "after the plug");

    // Only configured positions exist.
    let elsewhere = client
        .plug_submodule((0, 9, 1), 0x10, 0x1)
        .unwrap_err()
        .to_string();
    assert!(
        elsewhere.contains("no submodule is configured at API 0 slot 9"),
        "{elsewhere}"
    );
    let status = server.status();
    assert_eq!(
        status.station.and_then(|s| s.ar).map(|a| a.state),
        Some(ArState::Data),
        "the AR stayed up through pull and plug"
    );
    assert_eq!(status.network.watchdog_expiries, 0);
}

/// The demo device's configuration with slot 1 not plugged at start.
fn slot_1_unplugged() -> String {
    let toml = procimg_config::DEMO_DEVICE_TOML.replacen(
        "input_length = 8\noutput_length = 8\n",
        "input_length = 8\noutput_length = 8\nplugged = false\n",
        1,
    );
    assert_ne!(toml, procimg_config::DEMO_DEVICE_TOML);
    toml
}

#[test]
fn a_submodule_not_plugged_at_start_waits_for_its_client() {
    let server = Launch::config("devunplugged", &slot_1_unplugged()).start();
    let mut services = Services::open(&server.instance, ServiceOptions::new("unplugged-events"))
        .expect("the device's services");
    let mut client = Client::attach(&server.instance, AttachOptions::synchronous("unplugged"))
        .expect("attach to the device");
    client.claim_i_data().expect("claim the I data");
    // The PLC connected all the same, without slot 1.
    let echo = at(&client, 1, 1);
    until_q_status(&mut client, echo, Ioxs::Bad, "before the plug");
    client
        .plug_submodule((0, 1, 1), 0x10, 0x1)
        .expect("plug slot 1");
    assert_eq!(next_plug(&mut services), (true, 0x1, "plug".to_owned()));
    until_q_status(&mut client, echo, Ioxs::Good, "after the plug");
}

#[test]
fn the_demo_plc_connects_what_the_client_plugged_as_an_engineering_tool_learns_it() {
    let server = Launch::config("devlearn", &slot_1_unplugged()).start();
    let mut services = Services::open(&server.instance, ServiceOptions::new("learn-events"))
        .expect("the device's services");
    let mut client = Client::attach(&server.instance, AttachOptions::synchronous("learn"))
        .expect("attach to the device");
    client.claim_i_data().expect("claim the I data");
    let echo = at(&client, 1, 1);
    // Another submodule than the configuration's: wrong for the running AR.
    client
        .plug_submodule((0, 1, 1), 0x10, 0x5)
        .expect("plug slot 1");
    assert_eq!(
        next_plug(&mut services),
        (true, 0x5, "plug wrong submodule".to_owned())
    );
    // The PLC's next AR reads the station's RealIdentificationData first and expects
    // what is plugged: slot 1 is exchanged.
    end_the_ar_and_let_the_plc_connect_again(&server);
    server.wait_status("the station's AR in data exchange", in_data);
    until_q_status(
        &mut client,
        echo,
        Ioxs::Good,
        "after the PLC learnt the tree",
    );
}
