// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station its program defines: procimgd with `[station] gsdml` and no submodules waits,
//! OFFLINE with the device access point only; a program's tree that the GSDML does not allow
//! is refused naming the ident and the file, and changes nothing; an accepted tree runs the
//! station anew (a client attached before follows the new layout) and the demo PLC
//! connects it; a second program and a definition during the AR are refused; the program's
//! end aborts the AR and the station waits again; a control request that meets the end of
//! a generation is answered or refused at once. A module only the GSDML file has is
//! connected by the demo PLC, which plans it from the file, and its data flows. What the
//! program said before it defined the station holds from the station's first moment. And —
//! as root — the same over a veth pair with procimg's controller, configured from the
//! station's GSDML file, as the PLC.

use procimg_client::{
    ArState, AttachOptions, Client, ControlError, DeviceState, Event, Notification, Refusal,
    ServiceOptions, Services, StationTreeEntry, StatusReport, TreeRecords,
};
use procimg_config::gsdml::export::{GsdmlDate, module_item_id, station_gsdml, submodule_item_id};
use procimg_config::{Config, StationConfig};
use procimg_shm_layout::Mode;
use procimg_testkit::Launch;
use procimg_testkit::exchange::{
    controller_pattern, device_echo, next_device_event, until_the_plc_answers,
};
use procimg_testkit::netns::TestNet;
use procimg_testkit::tshark::{LiveCapture, fields_matching, flagged, frames_matching};
use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Set for the child process that plays a station's program: the instance to define.
const CHILD_ENV: &str = "PROCIMG_TEST_STATION_PROGRAM";

/// Generous: a loaded machine may be slow to connect.
const BRING_UP: Duration = Duration::from_secs(30);

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

/// The GSDML file of `described`, written into `dir`: its path and its name.
fn gsdml_of(dir: &Path, described: &StationConfig) -> (PathBuf, String) {
    let file = station_gsdml(
        described,
        Config::demo_device().cycle_ns,
        GsdmlDate::new(2026, 11, 28).unwrap(),
    )
    .unwrap();
    let path = dir.join(&file.file_name);
    std::fs::write(&path, file.xml).unwrap();
    (path, file.file_name)
}

/// The demo station's GSDML file, written into `dir`: its path and its name.
fn demo_gsdml(dir: &Path) -> (PathBuf, String) {
    gsdml_of(dir, Config::demo_device().station.as_ref().unwrap())
}

/// The config of a station its program defines on `network`, at `ip`, from GSDML file
/// `gsdml`.
fn station_toml(network: &str, ip: &str, gsdml: &Path) -> String {
    format!(
        "role = \"device\"\ncycle_time = \"1ms\"\nnetwork = \"{network}\"\n[station]\n\
         name = \"procimg-device\"\nip = \"{ip}\"\ngsdml = \"{}\"\n",
        gsdml.display()
    )
}

/// The config of a station its program defines, with the demo station's GSDML written into
/// `dir`: the TOML and the file's name.
fn waiting_station(dir: &Path) -> (String, String) {
    let (gsdml, file_name) = demo_gsdml(dir);
    (station_toml("sim", "192.168.0.50", &gsdml), file_name)
}

/// [`waiting_station`] with the GSDML file of `described`.
fn waiting_station_of(dir: &Path, described: &StationConfig) -> (String, String) {
    let (gsdml, file_name) = gsdml_of(dir, described);
    (station_toml("sim", "192.168.0.50", &gsdml), file_name)
}

/// A station's program in a child process: this test binary again, running
/// `child_station_program` on an instance. Started, it has defined the station; dropped, it
/// is killed (its process's end is what the station sees) and reaped, also when the test
/// fails.
struct ProgramProcess(Child);

impl ProgramProcess {
    /// Starts the program on `instance` and returns once it has defined the station.
    fn start(instance: &str) -> ProgramProcess {
        let mut child = Command::new(std::env::current_exe().unwrap())
            .args(["--exact", "child_station_program", "--nocapture"])
            .env(CHILD_ENV, instance)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let program = ProgramProcess(child);
        // Read in a thread of its own, so that a program that hangs fails the test rather
        // than stopping it; the thread ends at the line or at the child's end.
        let (said, heard) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let defined = std::io::BufReader::new(stdout)
                .lines()
                .map_while(Result::ok)
                .any(|line| line == "DEFINED");
            let _ = said.send(defined);
        });
        match heard.recv_timeout(BRING_UP) {
            Ok(true) => program,
            Ok(false) => panic!("the program ended without defining the station"),
            Err(_) => panic!("the program did not define the station within {BRING_UP:?}"),
        }
    }
}

impl Drop for ProgramProcess {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
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

/// Whether the station's AR is in data exchange.
fn in_data(s: &StatusReport) -> bool {
    s.station
        .as_ref()
        .and_then(|st| st.ar.as_ref())
        .is_some_and(|ar| ar.state == ArState::Data)
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
    let running = server.wait_status("the AR in data exchange", in_data);
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
    let program = ProgramProcess::start(&server.instance);
    let up = server.wait_status("the AR in data exchange", in_data);
    assert_ne!(up.layout_hash, waiting);
    drop(program);
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
    until_the_plc_answers(&mut client, module, &written, BRING_UP);
    drop(program);
}

/// procimg's controller configured for the demo station from its GSDML file `gsdml`: the
/// station `procimg-device` at 10.47.0.50 on `network`, its submodules named by the file's
/// items at the places the program plugs them.
///
/// The watchdog allows 100 frames (100 ms), for both sides (the station takes its data hold
/// time from the Connect): two cycle threads of a test build and their clients share two
/// virtual CPUs with the machine's other work here, whose stalls reach several ms (the
/// cycle threads' own wake-up latency shows them); the default 3 ms would count those
/// stalls, where the test counts what procimgd does.
fn controller_toml(network: &str, gsdml: &Path) -> String {
    let mut toml = format!(
        "cycle_time = \"1ms\"\nnetwork = \"{network}\"\n[[device]]\nname = \"procimg-device\"\n\
         ip = \"10.47.0.50\"\ngsdml = \"{}\"\nwatchdog_factor = 100\n",
        gsdml.display()
    );
    for e in demo_tree(&Config::demo_device().station.unwrap()) {
        toml += &format!(
            "[[device.submodule]]\napi = {}\nslot = {}\nsubslot = {}\nmodule = \"{}\"\n\
             submodule = \"{}\"\n",
            e.api,
            e.slot,
            e.subslot,
            module_item_id(e.module_ident),
            submodule_item_id(e.module_ident, e.subslot)
        );
    }
    toml
}

/// The network counters that must not move while the AR runs: the consumer watchdog's
/// expiries of the controller and of the station, and the station's aborted ARs.
fn losses(controller: &StatusReport, station: &StatusReport) -> (u64, u64, u64) {
    (
        controller.network.watchdog_expiries,
        station.network.watchdog_expiries,
        station.station.as_ref().map_or(0, |s| s.aborted_ars),
    )
}

/// Asserts that the station's layout, as a client attached to `instance` sees it, is the
/// device access point's slot 0 only.
fn assert_slot_0_only(instance: &str) {
    let watcher = Client::attach(instance, AttachOptions::asynchronous("watcher"))
        .expect("attach to the station");
    let submodules = &watcher.layout().submodules;
    assert!(submodules.iter().all(|e| e.slot == 0), "{submodules:?}");
}

/// The number of the first frame of `pcap` that matches display filter `filter`, if any.
fn first_frame(pcap: &Path, filter: &str) -> Option<u64> {
    fields_matching(pcap, filter, &["frame.number"])
        .first()
        .and_then(|f| f.first())
        .and_then(|n| n.parse().ok())
}

/// The notifications `services` has now, without waiting for more.
fn pending(services: &mut Services) -> Vec<Notification> {
    std::iter::from_fn(|| services.next(Duration::from_millis(10))).collect()
}

#[test]
#[ignore = "needs root: network namespaces, veth, AF_PACKET"]
fn procimg_controller_connects_a_station_its_program_defines_over_a_veth_pair() {
    let net = TestNet::new("sp", true);
    net.address(0, "10.47.0.1/24");
    let dir = procimg_testkit::files::temp_dir("station-program-veth");
    let (gsdml, _) = demo_gsdml(dir.path());
    // Every frame on the wire, from before the station starts.
    let pcap = dir.path().join("wire.pcapng");
    let capture = LiveCapture::start(&net.ns[0], &net.ifs[0], &pcap);

    // The station waits for its program: slot 0 only, off the wire; the PLC's Connects are
    // refused meanwhile.
    let station = Launch::config("spd", &station_toml(&net.ifs[1], "10.47.0.50", &gsdml))
        .netns(&net.ns[1])
        .until_cycling()
        .start();
    let waiting = station.status();
    assert!(waiting.station.as_ref().unwrap().ar.is_none());
    let station_mac = waiting.station.as_ref().unwrap().mac.clone();
    let plc = Launch::config("spc", &controller_toml(&net.ifs[0], &gsdml))
        .netns(&net.ns[0])
        .until_cycling()
        .start();
    let mut plc_events = Services::open(&plc.instance, ServiceOptions::new("plc-events"))
        .expect("the controller's services");
    // The PLC found the station by its name, and its Connect failed.
    let mut states = Vec::new();
    while !states.ends_with(&[DeviceState::Connecting, DeviceState::Failed]) {
        match plc_events.next(BRING_UP) {
            Some(Notification::DeviceState { state, .. }) => states.push(state),
            Some(_) => {}
            None => panic!("no refused Connect within {BRING_UP:?}: {states:?}"),
        }
    }
    assert_slot_0_only(&station.instance);

    // The program defines the station: the PLC connects it.
    let program = ProgramProcess::start(&station.instance);
    plc.wait_devices_running(BRING_UP);
    let running = station.wait_status("the station's AR in data exchange", in_data);
    assert_ne!(running.layout_hash, waiting.layout_hash);
    let ar_uuid = running.station.unwrap().ar.unwrap().ar_uuid;

    // 10 s at 1 ms, data both ways: the controller's patterns come back through a client of
    // the station, in one AR, without a watchdog expiry on either side.
    let _ = pending(&mut plc_events);
    let before = losses(&plc.status(), &station.status());
    let echo = device_echo(station.instance.clone(), 11_000);
    let seen = controller_pattern(&plc.instance, "procimg-device", 10_000);
    let echoed = echo.join().expect("the station's client");
    let after = losses(&plc.status(), &station.status());
    assert_eq!(seen.cycles, 10_000);
    assert_eq!(seen.wrong, 0, "{seen:?}");
    assert!(seen.echoes > 1_000, "{seen:?}");
    assert!(
        echoed > 1_000,
        "the station's client saw GOOD Q data {echoed} times"
    );
    assert_eq!(
        after, before,
        "(controller watchdog expiries, station watchdog expiries, station aborted ARs)"
    );
    let same_ar = station.status().station.unwrap().ar.map(|a| a.ar_uuid);
    assert_eq!(same_ar, Some(ar_uuid));
    let failures: Vec<_> = pending(&mut plc_events)
        .into_iter()
        .filter(|n| matches!(n, Notification::DeviceFailure { .. }))
        .collect();
    assert!(failures.is_empty(), "{failures:?}");

    // The program killed: the station aborts the AR, and the PLC hears it as the device's
    // abort (not as its watchdog's expiry); the station waits again with slot 0 only.
    drop(program);
    let failure = next_device_event(&mut plc_events, "failure");
    let Notification::DeviceFailure { reason, .. } = &failure else {
        panic!("not a failure: {failure:?}");
    };
    assert!(reason.contains("the device aborted the AR"), "{reason}");
    let gone = station.wait_status("the station waiting after its program's end", |s| {
        s.layout_hash == waiting.layout_hash
            && s.mode == Mode::Offline
            && s.station.as_ref().is_some_and(|s| s.ar.is_none())
    });
    assert_ne!(gone.generation, waiting.generation);
    assert_slot_0_only(&station.instance);
    assert_ne!(plc.status().devices[0].state, DeviceState::Running);

    // The program started again: it defines the station again, the PLC's AR comes back.
    let program = ProgramProcess::start(&station.instance);
    let back = next_device_event(&mut plc_events, "return");
    assert!(
        matches!(back, Notification::DeviceReturn { .. }),
        "{back:?}"
    );
    plc.wait_devices_running(BRING_UP);
    station.wait_status("the station's AR in data exchange again", in_data);
    let echo = device_echo(station.instance.clone(), 2_000);
    let seen = controller_pattern(&plc.instance, "procimg-device", 1_000);
    let _ = echo.join();
    assert_eq!(seen.wrong, 0, "{seen:?}");
    assert!(seen.echoes > 0, "{seen:?}");

    // The PLC stops first (it releases the AR), then the program and the station.
    drop(plc);
    drop(program);
    drop(station);
    let pcap = capture.stop();
    let bad = flagged(&pcap);
    assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
    // The station's cyclic frames (the FrameIDs below the alarms' 0xFC01), none before its
    // answer to the PLC's first Connect, a refusal (a negative PNIOStatus in the Connect
    // response); and its ERR-RTA AbortRequest (PDUType 4, ErrorCode2 0x0D) when its program
    // was killed.
    let from_station = format!("eth.src == {station_mac}");
    let cyclic = format!("{from_station} && pn_rt.frame_id >= 0x0100 && pn_rt.frame_id < 0xfc00");
    let frames = frames_matching(&pcap, &cyclic).lines().count();
    assert!(frames > 10_000, "{frames} cyclic frames from the station");
    let refused = format!(
        "{from_station} && dcerpc.pkt_type == 2 && dcerpc.opnum == 0 && pn_io.error_code != 0"
    );
    let refused = first_frame(&pcap, &refused).expect("a refused Connect on the wire");
    let exchanged = first_frame(&pcap, &cyclic).expect("cyclic frames on the wire");
    assert!(
        refused < exchanged,
        "the waiting station sent cyclic frames (frame {exchanged}) before it refused the \
         Connect (frame {refused})"
    );
    let abort = frames_matching(
        &pcap,
        &format!(
            "eth.src == {station_mac} && pn_io.pdu_type.type == 4 && pn_io.error_code2 == 0x0d"
        ),
    );
    assert!(
        !abort.trim().is_empty(),
        "no ERR-RTA AbortRequest from the station ({station_mac}) on the wire"
    );
}

#[test]
fn a_control_request_across_the_stations_new_generations_is_answered_or_refused_at_once() {
    let dir = procimg_testkit::files::temp_dir("station-program-requests");
    let (toml, _) = waiting_station(dir.path());
    let server = Launch::config("station-requests", &toml)
        .until_cycling()
        .start();
    // One handle, asking all along: some of its requests meet a generation's end.
    let instance = server.instance.clone();
    let done = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let asking = {
        let done = done.clone();
        std::thread::spawn(move || {
            let control = procimg_client::ControlHandle::open(&instance, "asker").unwrap();
            let (mut answered, mut unanswered) = (0, Vec::new());
            while !done.load(std::sync::atomic::Ordering::Relaxed) {
                match control.status() {
                    Ok(_) => answered += 1,
                    // Between two generations no server takes the request: said at once.
                    Err(ControlError::NoServer { .. }) => {}
                    Err(e) => unanswered.push(e.to_string()),
                }
                std::thread::sleep(Duration::from_millis(2));
            }
            (answered, unanswered)
        })
    };
    // Each definition and each end of the program runs a new generation.
    for _ in 0..5 {
        let program = ProgramProcess::start(&server.instance);
        server.wait_status("the AR in data exchange", in_data);
        drop(program);
        server.wait_status("the station waiting", |s| {
            s.station.as_ref().is_some_and(|s| s.ar.is_none()) && s.mode == Mode::Offline
        });
    }
    done.store(true, std::sync::atomic::Ordering::Relaxed);
    let (answered, unanswered) = asking.join().unwrap();
    assert!(answered > 0);
    assert!(unanswered.is_empty(), "{unanswered:?}");
}

#[test]
fn the_program_gives_the_station_its_name_and_address_with_its_tree() {
    let dir = procimg_testkit::files::temp_dir("station-program-identity");
    let (toml, _) = waiting_station(dir.path());
    let server = Launch::config("station-identity", &toml)
        .until_cycling()
        .start();
    let program = Services::open(&server.instance, ServiceOptions::new("the-program")).unwrap();
    let tree = demo_tree(&Config::demo_device().station.unwrap());
    let bad = procimg_client::DefinedIdentity {
        name: Some("Host_Board".into()),
        ..Default::default()
    };
    let m = refusal(program.define_station_as(&tree, &bad));
    assert!(m.contains("name:") && m.contains("host_board"), "{m}");
    let identity = procimg_client::DefinedIdentity {
        name: Some("gs20-host".into()),
        ip: Some([[192, 168, 0, 60], [255, 255, 255, 0], [0, 0, 0, 0]]),
        serial_number: Some("SN-0042".into()),
    };
    program.define_station_as(&tree, &identity).unwrap();
    let st = server.wait_status("the AR in data exchange", in_data);
    let station = st.station.unwrap();
    assert_eq!(
        (station.name.as_str(), station.ip.as_str()),
        ("gs20-host", "192.168.0.60")
    );
}
