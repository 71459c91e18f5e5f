// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station its program defines: procimgd with `[station] gsdml` and no submodules waits,
//! OFFLINE with the device access point only; a program's tree that the GSDML does not allow
//! is refused naming the ident and the file, and changes nothing; an accepted tree runs the
//! station anew (a client attached before follows the new layout) and the demo PLC
//! connects it; a second program and a definition during the AR are refused; the program's
//! end aborts the AR and the station waits again. A module only the GSDML file has is
//! connected by the demo PLC, which plans it from the file, and its data flows.

use procimg_client::{
    ArState, AttachOptions, Client, ControlError, Event, Ioxs, Notification, Refusal,
    ServiceOptions, Services, StationTreeEntry, TreeRecords,
};
use procimg_config::gsdml::export::{GsdmlDate, station_gsdml};
use procimg_config::{Config, StationConfig};
use procimg_shm_layout::Mode;
use procimg_testkit::Launch;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Set for the child process that plays a station's program: the instance to define.
const CHILD_ENV: &str = "PROCIMG_TEST_STATION_PROGRAM";

/// The demo station's tree (after slot 0), as a program plugs it.
fn demo_tree(station: &StationConfig) -> Vec<StationTreeEntry> {
    let entry = |p: procimg_config::PlannedSubmodule| StationTreeEntry {
        api: p.api,
        slot: p.slot,
        subslot: p.subslot,
        module_ident: p.module_ident,
        submodule_ident: p.submodule_ident,
        records: TreeRecords::Station,
    };
    station.tree().into_iter().map(entry).collect()
}

/// Polls `client` (so that it re-attaches) until `done` says yes of its events so far.
fn follow(client: &mut Client, events: &mut Vec<Event>, done: impl Fn(&[Event]) -> bool) {
    let until = Instant::now() + Duration::from_secs(30);
    while !done(events) {
        assert!(Instant::now() < until, "not within 30 s: {events:?}");
        let _ = client.wait_startop(Duration::from_millis(20));
        events.extend(client.events());
    }
}

/// The config of a station its program defines, with the demo station's GSDML written into
/// `dir`: the TOML and the file's name.
fn waiting_station(dir: &std::path::Path) -> (String, String) {
    waiting_station_of(dir, Config::demo_device().station.as_ref().unwrap())
}

/// [`waiting_station`] with the GSDML file of `described`.
fn waiting_station_of(dir: &std::path::Path, described: &StationConfig) -> (String, String) {
    let file = station_gsdml(
        described,
        Config::demo_device().cycle_ns,
        GsdmlDate::new(2026, 11, 28).unwrap(),
    )
    .unwrap();
    let gsdml = dir.join(&file.file_name);
    std::fs::write(&gsdml, file.xml).unwrap();
    let toml = format!(
        "role = \"device\"\ncycle_time = \"1ms\"\nnetwork = \"sim\"\n[station]\n\
         name = \"procimg-device\"\nip = \"192.168.0.50\"\ngsdml = \"{}\"\n",
        gsdml.display()
    );
    (toml, file.file_name)
}

/// Run as a child process only (`PROCIMG_TEST_STATION_PROGRAM` set): defines the demo
/// station on that instance, says so, and lives until killed.
#[test]
fn child_station_program() {
    let Ok(instance) = std::env::var(CHILD_ENV) else {
        return;
    };
    let program = Services::open(&instance, ServiceOptions::new("child-program")).unwrap();
    let station = Config::demo_device().station.unwrap();
    program.define_station(&demo_tree(&station)).unwrap();
    println!("DEFINED");
    loop {
        std::thread::sleep(Duration::from_secs(1));
    }
}

fn refusal(r: Result<(), ControlError>) -> String {
    match r {
        Err(ControlError::Refused(Refusal::BadRequest { message })) => message,
        other => panic!("not refused with a message: {other:?}"),
    }
}

#[test]
fn a_program_defines_the_station_from_its_gsdml_and_its_end_takes_it_off_the_wire() {
    let demo_station = Config::demo_device().station.unwrap();
    let dir = procimg_testkit::files::temp_dir("station-program");
    let (toml, file_name) = waiting_station(dir.path());
    let server = Launch::config("station-program", &toml)
        .until_cycling()
        .start();
    let instance = server.instance.clone();

    // Waiting: OFFLINE, the device access point only, VendorID and DeviceID from the file.
    let st = server.status();
    let station = st.station.clone().expect("a station");
    assert_eq!(
        (station.vendor_id, station.device_id),
        (demo_station.vendor_id, demo_station.device_id)
    );
    assert!(station.ar.is_none());
    let program_report = station.program.expect("a station its program defines");
    assert!(program_report.gsdml.ends_with(&file_name));
    assert_eq!(program_report.defined_by, None);
    assert_eq!(server.mode(), Mode::Offline);
    // OPERATE asked for by hand does not put the waiting station on the wire: the PLC's
    // Connects stay refused.
    server.set_mode(Mode::Operate);
    std::thread::sleep(Duration::from_millis(300));
    assert!(server.status().station.unwrap().ar.is_none());
    server.set_mode(Mode::Offline);
    let mut watcher = Client::attach(&instance, AttachOptions::asynchronous("watcher")).unwrap();
    assert_eq!(watcher.layout().submodules.len(), 3, "slot 0 only");
    let waiting_hash = watcher.layout().hash();

    let program = Services::open(&instance, ServiceOptions::new("the-program")).unwrap();
    // An ident the GSDML lacks: refused naming it and the file; nothing changes.
    let mut tree = demo_tree(&demo_station);
    let mut wrong = tree.clone();
    wrong[0].module_ident = 0x4242;
    let m = refusal(program.define_station(&wrong));
    assert!(
        m.contains("module ident 0x00004242") && m.contains(&file_name),
        "{m}"
    );
    // A slot beyond the DAP's PhysicalSlots.
    let mut far = tree.clone();
    far[0].slot = 60;
    let m = refusal(program.define_station(&far));
    assert!(m.contains("PhysicalSlots"), "{m}");
    assert_eq!(server.mode(), Mode::Offline);

    // The program's tree: the station runs anew with it, the PLC connects it.
    program.define_station(&tree).unwrap();
    let mut events = Vec::new();
    follow(&mut watcher, &mut events, |e| {
        e.iter().any(|e| matches!(e, Event::LayoutChanged { .. }))
    });
    assert_eq!(
        watcher.layout().submodules.len(),
        demo_station.submodules.len()
    );
    let running = server.wait_status("the AR in data exchange", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.ar.as_ref())
            .is_some_and(|a| a.state == ArState::Data)
    });
    assert_eq!(running.mode, Mode::Operate);
    let defined_by = running
        .station
        .unwrap()
        .program
        .unwrap()
        .defined_by
        .unwrap();
    assert!(defined_by.contains("the-program"), "{defined_by}");

    // A second program, and a definition during the AR: refused.
    let other = Services::open(&instance, ServiceOptions::new("another-program")).unwrap();
    let m = refusal(other.define_station(&tree));
    assert!(m.contains("defined by the-program"), "{m}");
    tree.pop();
    let m = refusal(program.define_station(&tree));
    assert!(m.contains("an AR with the PLC runs"), "{m}");

    // The program's end: the AR ends with an abort, the station waits again, OFFLINE with
    // slot 0 only, and the watcher follows.
    program.release_station().unwrap();
    let mut events = Vec::new();
    follow(&mut watcher, &mut events, |e| {
        e.iter()
            .any(|e| matches!(e, Event::LayoutChanged { now, .. } if *now == waiting_hash))
    });
    let st = server.wait_status("the station waiting", |s| {
        s.station.as_ref().is_some_and(|s| s.ar.is_none()) && s.mode == Mode::Offline
    });
    assert!(st.station.unwrap().aborted_ars <= 1);
}

#[test]
fn the_programs_process_gone_aborts_the_ar_and_the_station_waits() {
    let dir = procimg_testkit::files::temp_dir("station-program-gone");
    let (toml, _) = waiting_station(dir.path());
    let server = Launch::config("station-gone", &toml)
        .until_cycling()
        .start();
    let waiting = server.status().layout_hash;
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args(["--exact", "child_station_program", "--nocapture"])
        .env(CHILD_ENV, &server.instance)
        .stdout(Stdio::null())
        .spawn()
        .unwrap();
    // Ended and reaped whatever happens below.
    struct Reap<'a>(&'a mut std::process::Child);
    impl Drop for Reap<'_> {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let child = Reap(&mut child);
    let up = server.wait_status("the AR in data exchange", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.ar.as_ref())
            .is_some_and(|a| a.state == ArState::Data)
    });
    assert_ne!(up.layout_hash, waiting);
    drop(child);
    // The station runs without the tree again: slot 0 only, OFFLINE, no AR.
    server.wait_status("the station waiting after its program's end", |s| {
        s.layout_hash == waiting
            && s.mode == Mode::Offline
            && s.station.as_ref().is_some_and(|s| s.ar.is_none())
    });
}

/// The next notification of `services` that `pick` takes, within 30 s.
fn next_picked<T>(
    services: &mut Services,
    what: &str,
    pick: impl Fn(Notification) -> Option<T>,
) -> T {
    let until = Instant::now() + Duration::from_secs(30);
    while Instant::now() < until {
        if let Some(found) = services.next(Duration::from_millis(200)).and_then(&pick) {
            return found;
        }
    }
    panic!("no {what} within 30 s");
}

#[test]
fn what_the_program_said_holds_from_the_defined_stations_first_moment() {
    let demo_station = Config::demo_device().station.unwrap();
    let dir = procimg_testkit::files::temp_dir("station-program-say");
    let (toml, _) = waiting_station(dir.path());
    let server = Launch::config("station-say", &toml).until_cycling().start();
    let mut program = Services::open(&server.instance, ServiceOptions::new("the-program")).unwrap();
    // Checked, not defined: nothing changes.
    let mut tree = demo_tree(&demo_station);
    program.check_station_tree(&tree).unwrap();
    let mut wrong = tree.clone();
    wrong[0].submodule_ident = 0x4243;
    let m = refusal(program.check_station_tree(&wrong));
    assert!(m.contains("0x00004243"), "{m}");
    assert_eq!(server.mode(), Mode::Offline);

    // The program checks ARs and holds the ApplicationReady in the waiting station, and
    // takes slot 1's records with the tree.
    program.check_ars(true).unwrap();
    program.hold_application_ready(true).unwrap();
    tree[0].records = TreeRecords::Program;
    let slot1 = (tree[0].api, tree[0].slot, tree[0].subslot);
    let before = program.control().status().unwrap().generation;
    program.define_station(&tree).unwrap();
    // A request right after the definition, which the ending server does not take, is
    // answered by the station's new server rather than timing out.
    let after = program.control().status().expect("the new server answers");
    assert!(
        after.generation == before || after.station.unwrap().program.unwrap().defined_by.is_some()
    );

    // The PLC's first Connect to the new station waits for the program's check.
    let check = next_picked(&mut program, "AR check", |n| match n {
        Notification::StationArCheck { check, .. } => Some(check),
        _ => None,
    });
    program.answer_ar_check(&check, Ok(())).unwrap();
    // Its parameter record of slot 1 is the program's to answer.
    let job = next_picked(&mut program, "record job of slot 1", |n| match n {
        Notification::StationRecord { job, .. }
            if (job.api, job.slot, job.subslot) == slot1 && job.write =>
        {
            Some(job)
        }
        _ => None,
    });
    program.answer_record(&job, Ok(&[])).unwrap();
    // The ApplicationReady waits for the program: no data exchange before it says so.
    server.wait_status("the AR parameterized", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.ar.as_ref())
            .is_some_and(|a| a.state == ArState::Parameterized)
    });
    program.application_ready().unwrap();
    server.wait_status("the AR in data exchange", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.ar.as_ref())
            .is_some_and(|a| a.state == ArState::Data)
    });
}

/// A module the demo's configuration does not have, with other IO lengths than its modules.
const ONLY_IN_THE_FILE: u32 = 0x4242;
/// Its input and output bytes.
const ONLY_IN_THE_FILE_LEN: usize = 40;

/// The station's program plugs a module that only the station's GSDML file describes; the
/// demo PLC, which reads the tree and plans it from the file, connects it, and its data
/// flows both ways: Q = I + 1 on its 40 bytes.
#[test]
fn the_demo_plc_connects_a_module_only_the_gsdml_file_has() {
    let mut described = Config::demo_device().station.unwrap();
    let mut extra = described.submodules.last().unwrap().clone();
    extra.submodule.slot = 3;
    extra.submodule.module_ident = ONLY_IN_THE_FILE;
    extra.submodule.submodule_ident = 1;
    extra.submodule.input_length = ONLY_IN_THE_FILE_LEN as u16;
    extra.submodule.output_length = ONLY_IN_THE_FILE_LEN as u16;
    extra.accepts.clear();
    described.submodules.push(extra);
    let dir = procimg_testkit::files::temp_dir("station-program-file-module");
    let (toml, _) = waiting_station_of(dir.path(), &described);
    let server = Launch::config("station-file-module", &toml)
        .until_cycling()
        .start();
    // Lives to the end: its close would take the station off the wire.
    let program = Services::open(&server.instance, ServiceOptions::new("the-program")).unwrap();
    let tree = [StationTreeEntry {
        api: 0,
        slot: 3,
        subslot: 1,
        module_ident: ONLY_IN_THE_FILE,
        submodule_ident: 1,
        records: TreeRecords::Station,
    }];
    program.define_station(&tree).unwrap();
    server.wait_status("the AR in data exchange", |s| {
        s.station
            .as_ref()
            .and_then(|s| s.ar.as_ref())
            .is_some_and(|a| a.state == ArState::Data)
    });

    let mut client =
        Client::attach(&server.instance, AttachOptions::synchronous("file-module")).unwrap();
    let module = client
        .layout()
        .submodules
        .iter()
        .position(|e| (e.slot, e.subslot) == (3, 1))
        .expect("the program's module in the layout");
    let mine = client.claim_i_data().expect("claim the I data");
    assert!(mine.contains(&module), "slot 3 has I data: {mine:?}");
    let written: Vec<u8> = (0..ONLY_IN_THE_FILE_LEN as u8)
        .map(|i| i.wrapping_mul(37).wrapping_add(5))
        .collect();
    let wanted: Vec<u8> = written.iter().map(|b| b.wrapping_add(1)).collect();
    let until = Instant::now() + Duration::from_secs(30);
    loop {
        let mut cycle = client
            .wait_startop(Duration::from_secs(5))
            .expect("STARTOP");
        let last = cycle.q_data(module).expect("Q data").to_vec();
        let good = cycle.q_status(module).expect("Q status") == Ioxs::Good;
        cycle
            .i_data_mut(module)
            .expect("I data")
            .copy_from_slice(&written);
        cycle.set_opdone().expect("OPDONE");
        if good && last == wanted {
            break;
        }
        assert!(
            Instant::now() < until,
            "the PLC's Q data never answered the I data: last Q {last:02x?}"
        );
    }
    drop(program);
}
