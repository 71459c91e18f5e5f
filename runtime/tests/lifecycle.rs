// SPDX-License-Identifier: MIT OR Apache-2.0
//! Clients and servers that die: a synchronous client killed inside its window, a server
//! killed and restarted under running clients.
//!
//! The killed client is this test binary run again with `PROCIMG_TEST_CHILD` set, so the
//! test needs no extra program.

use procimg_client::{AttachOptions, Client, Event, StatusReport};
use procimg_control::ClientReport;
use procimg_testkit::Procimgd;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

const CHILD_ENV: &str = "PROCIMG_TEST_CHILD";
const TRIGGER_ENV: &str = "PROCIMG_TEST_HANG_FILE";

/// Run as a child process only: a synchronous client that claims the echo outputs, cycles
/// 200 times, then stops inside its window (after STARTOP, before OPDONE) and waits there to
/// be killed.
#[test]
fn child_sync_client_that_hangs_in_its_window() {
    let Ok(instance) = std::env::var(CHILD_ENV) else {
        return; // not the child: nothing to do
    };
    let mut c = Client::attach(&instance, AttachOptions::synchronous("doomed")).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    c.claim(&[echo]).unwrap();
    let _ = procimg_client::realtime::make_current_thread_realtime(60);
    let trigger = std::path::PathBuf::from(std::env::var(TRIGGER_ENV).unwrap());
    let mut n = 0;
    loop {
        // A loaded machine may hold this process back for a while: that is no failure here.
        let Ok(mut cycle) = c.wait_startop(Duration::from_secs(5)) else {
            continue;
        };
        n += 1;
        if n == 200 {
            println!("cycling");
        }
        if n > 200 && trigger.exists() {
            // Hang between STARTOP and OPDONE until killed.
            println!("in-window {}", cycle.number());
            std::thread::sleep(Duration::from_secs(60));
        }
        cycle.output_mut(echo).unwrap().fill(0x5a);
        cycle.set_opdone().unwrap();
    }
}

/// These tests kill and restart processes under real-time load; run them one at a time.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[test]
fn sigkill_of_a_sync_client_mid_window_costs_one_opfault_and_frees_its_claims() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let server = Procimgd::demo("kill");
    // Another client follows the cycles alongside the whole time. It is asynchronous, so it
    // is never waited for and can get no OPFAULT: every OPFAULT counted is the hung client's,
    // whatever else this shared machine does meanwhile.
    let stop = Arc::new(AtomicBool::new(false));
    let followed = Arc::new(AtomicU64::new(0));
    let bystander = {
        let (instance, stop, followed) = (server.instance.clone(), stop.clone(), followed.clone());
        std::thread::spawn(move || {
            let mut c =
                Client::attach(&instance, AttachOptions::asynchronous("bystander")).unwrap();
            let mut cycles = Vec::new();
            while !stop.load(Ordering::Relaxed) {
                if let Ok(cycle) = c.wait_startop(Duration::from_millis(100)) {
                    cycles.push(cycle.number());
                    followed.fetch_add(1, Ordering::Relaxed);
                }
            }
            cycles
        })
    };
    let trigger = std::env::temp_dir().join(format!("{}.hang", server.instance));
    let (mut child, mut lines) = start_child(&server, &trigger);
    let mut wait_for = |what: &str| -> String {
        lines
            .by_ref()
            .map_while(Result::ok)
            .find(|l| l.contains(what))
            .unwrap_or_else(|| panic!("the child client never printed {what}"))
    };
    let before = server.status();
    let doomed_before = doomed(&before).opfaults;
    assert_eq!(before.clients.len(), 2);
    std::fs::write(&trigger, b"hang").unwrap();
    let hung_cycle: u64 = wait_for("in-window")
        .trim_start_matches("in-window ")
        .trim()
        .parse()
        .expect("the child names the cycle it hangs in");
    let _ = std::fs::remove_file(&trigger);

    // A hundred cycles later (counted by the server, however long this machine takes), the
    // hung client's last OPFAULT is no later than the cycle it hangs in: a client that
    // missed its deadline is not waited for again until it answers. On a loaded machine the
    // cycle before may be the one counted (late there, the client is not waited for in the
    // cycle it then hangs in); the hang costs an OPFAULT either way.
    let hung = server.wait_status("100 cycles past the hang", |s| {
        s.cycle_count >= hung_cycle + 100
    });
    let last = doomed(&hung).last_opfault_cycle;
    assert!(
        last <= hung_cycle && doomed(&hung).opfaults > doomed_before,
        "the hung client's last OPFAULT is in cycle {last}, it hangs in {hung_cycle}; \
         OPFAULTs {} before the hang, {} after",
        doomed_before,
        doomed(&hung).opfaults
    );
    // Every OPFAULT so far was the hung client's (the bystander is never waited for).
    assert_eq!(
        hung.opfaults - before.opfaults,
        doomed(&hung).opfaults - doomed_before,
        "OPFAULTs counted for others"
    );
    let followed_at_kill = followed.load(Ordering::Relaxed);
    child.kill().unwrap();
    let _ = child.wait();

    // The server keeps cycling, reaps the client and frees its claim; the kill and the
    // reaping cost no OPFAULT.
    let later = reaped_and_150_cycles_later(&server);
    assert_eq!(
        later.opfaults, hung.opfaults,
        "OPFAULTs after the hang: the kill and the reaping must cost none"
    );
    // The other client kept getting its cycles through the kill and the reaping.
    let until = Instant::now() + Duration::from_secs(30);
    while followed.load(Ordering::Relaxed) < followed_at_kill + 50 {
        assert!(
            Instant::now() < until,
            "the other client saw only {} cycles since the kill",
            followed.load(Ordering::Relaxed) - followed_at_kill
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    stop.store(true, Ordering::Relaxed);
    let seen = bystander.join().unwrap();
    assert!(seen.windows(2).all(|w| w[0] < w[1]));

    // A new client takes the same outputs.
    let mut c = Client::attach(&server.instance, AttachOptions::synchronous("successor")).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    c.claim(&[echo])
        .expect("the killed client's claim was not freed");
    let mut cycle = c.wait_startop(Duration::from_secs(5)).unwrap();
    cycle.output_mut(echo).unwrap().fill(1);
    cycle.set_opdone().unwrap();
}

/// Starts the child client of [`child_sync_client_that_hangs_in_its_window`] on `server`,
/// with `trigger` as its hang file; returns it once it cycles, and its stdout.
fn start_child(
    server: &Procimgd,
    trigger: &std::path::Path,
) -> (
    std::process::Child,
    std::io::Lines<BufReader<std::process::ChildStdout>>,
) {
    let _ = std::fs::remove_file(trigger);
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "child_sync_client_that_hangs_in_its_window",
            "--nocapture",
        ])
        .env(CHILD_ENV, &server.instance)
        .env(TRIGGER_ENV, trigger)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    lines
        .by_ref()
        .map_while(Result::ok)
        .find(|l| l.contains("cycling"))
        .expect("the child client never printed cycling");
    (child, lines)
}

/// The handshake block's futex words hold nothing of a client killed inside a wait: a client
/// killed while it sleeps for STARTOP costs at most the one cycle it was armed for and no
/// wake-up once it is reaped; a client killed in its window, while the server waits for its
/// OPDONE, costs that cycle's OPFAULT and nothing after.
#[test]
fn a_client_killed_in_a_futex_wait_costs_at_most_its_cycle_and_leaves_nothing_behind() {
    use procimg_shm_layout::handshake_map::HandshakeMap;
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let server = Procimgd::demo("futex-kill");
    let generation = server.status().generation;
    let block = HandshakeMap::open(&server.instance, generation).unwrap();
    let trigger = std::env::temp_dir().join(format!("{}.hang", server.instance));

    // 1. Killed while sleeping for STARTOP. Stopped first, then looked at: its bit in the
    // sleeper mask proves it is inside the wait (between announcing itself and leaving).
    let (mut child, _lines) = start_child(&server, &trigger);
    let slot = doomed(&server.status()).slot;
    let bit = 1u64 << slot;
    let pid = child.id();
    let mut caught = false;
    for _ in 0..5000 {
        procimg_testkit::signal::send(pid, libc::SIGSTOP);
        // The signal is delivered when the child next runs kernel code: see it stopped.
        let until = Instant::now() + Duration::from_secs(5);
        while !stopped(pid) && Instant::now() < until {
            std::thread::yield_now();
        }
        if block.block().sleepers.0.load(Ordering::SeqCst) & bit != 0 {
            caught = true;
            break;
        }
        procimg_testkit::signal::send(pid, libc::SIGCONT);
        std::thread::sleep(Duration::from_micros(300));
    }
    assert!(caught, "the child was never caught inside its STARTOP wait");
    let at_kill = server.status();
    child.kill().unwrap();
    let _ = child.wait();
    let later = reaped_and_150_cycles_later(&server);
    assert!(
        later.opfaults <= at_kill.opfaults + 1,
        "a client killed in its STARTOP wait cost {} OPFAULTs",
        later.opfaults - at_kill.opfaults
    );
    let hs = block.block();
    assert_eq!(
        hs.sleepers.0.load(Ordering::SeqCst) & bit,
        0,
        "the killed client is still counted as sleeping: every STARTOP would wake for it"
    );
    assert_eq!(hs.fd_waiters.0.load(Ordering::SeqCst) & bit, 0);

    // 2. Killed in its window: the server is waiting for its OPDONE.
    let (mut child, mut lines) = start_child(&server, &trigger);
    std::fs::write(&trigger, b"hang").unwrap();
    let hung_cycle: u64 = lines
        .by_ref()
        .map_while(Result::ok)
        .find_map(|l| {
            l.strip_prefix("in-window ")
                .map(|n| n.trim().parse().unwrap())
        })
        .expect("the child names the cycle it hangs in");
    child.kill().unwrap();
    let _ = child.wait();
    let _ = std::fs::remove_file(&trigger);
    // Every OPFAULT of cycles before the hung one is counted by now (each at its deadline).
    let at_kill = server.status();
    if let Some(c) = at_kill.clients.iter().find(|c| c.name == "doomed") {
        assert!(
            c.last_opfault_cycle <= hung_cycle,
            "an OPFAULT for cycle {} after the client died in cycle {hung_cycle}",
            c.last_opfault_cycle
        );
    }
    let after = reaped_and_150_cycles_later(&server);
    assert!(
        after.opfaults <= at_kill.opfaults + 1,
        "a client killed in its window cost {} OPFAULTs after its cycle",
        after.opfaults - at_kill.opfaults
    );
    let hs = block.block();
    assert_eq!(hs.sleepers.0.load(Ordering::SeqCst), 0);
    assert_eq!(hs.server_sleeps.0.load(Ordering::SeqCst), 0);
}

/// Waits until the server has reaped the client "doomed" and run 150 cycles since; returns
/// the status then.
fn reaped_and_150_cycles_later(server: &Procimgd) -> StatusReport {
    let reaped = server.wait_status("the killed client reaped", |s| {
        s.clients.iter().all(|c| c.name != "doomed")
    });
    server.wait_status("150 more cycles", |s| {
        s.cycle_count > reaped.cycle_count + 150
    })
}

/// Whether process `pid` is stopped (state `T` in /proc).
fn stopped(pid: u32) -> bool {
    std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .ok()
        .and_then(|s| {
            s.rsplit_once(')')
                .map(|(_, rest)| rest.trim_start().starts_with('T'))
        })
        .unwrap_or(false)
}

/// The hung client in a status report.
fn doomed(s: &StatusReport) -> &ClientReport {
    s.clients
        .iter()
        .find(|c| c.name == "doomed")
        .expect("the hung client is still registered")
}

#[test]
fn a_running_client_reattaches_after_a_server_restart() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut server = Procimgd::demo("restart");
    let mut c = Client::attach(&server.instance, AttachOptions::synchronous("survivor")).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    c.claim(&[echo]).unwrap();
    let first_generation = c.generation();
    for _ in 0..50 {
        let cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
        cycle.set_opdone().unwrap();
    }
    server.kill();
    // The client notices; meanwhile waits fail.
    let gone = Instant::now() + Duration::from_millis(500);
    while Instant::now() < gone {
        let _ = c.wait_startop(Duration::from_millis(50));
    }
    server.restart();
    let restarted = Instant::now();
    let reattached = loop {
        if let Ok(cycle) = c.wait_startop(Duration::from_millis(50)) {
            cycle.set_opdone().unwrap();
        }
        if c.events()
            .iter()
            .any(|e| matches!(e, Event::Reattached { .. }))
        {
            break restarted.elapsed();
        }
        assert!(
            restarted.elapsed() < Duration::from_secs(30),
            "no re-attachment in 30 s"
        );
    };
    // How fast is a figure, not a test result (docs/PERFORMANCE.md).
    eprintln!("re-attached {reattached:?} after the restart");
    assert_ne!(c.generation(), first_generation);
    // Cycles flow again, and the claim was taken again.
    let mut cycles = 0;
    let until = Instant::now() + Duration::from_secs(20);
    while cycles < 50 && Instant::now() < until {
        if let Ok(mut cycle) = c.wait_startop(Duration::from_millis(100)) {
            cycle.output_mut(echo).unwrap().fill(7);
            cycle.set_opdone().unwrap();
            cycles += 1;
        }
    }
    assert_eq!(cycles, 50);
    let st = server.status();
    assert_eq!(st.clients.len(), 1);
    assert_eq!(st.clients[0].name, "survivor");
    assert_eq!(st.clients[0].claims.len(), 1);
}

#[test]
fn an_asynchronous_client_reattaches_and_reports_the_gap() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut server = Procimgd::demo("async-restart");
    let mut c = Client::attach(
        &server.instance,
        AttachOptions::asynchronous("async-survivor"),
    )
    .unwrap();
    let mut buf = [0u8; 4];
    let until = Instant::now() + Duration::from_secs(20);
    while c
        .data_read(16, &mut buf, procimg_client::Ioxs::Good)
        .is_err()
    {
        assert!(Instant::now() < until, "no image to read in 20 s");
        std::thread::sleep(Duration::from_millis(5));
    }
    server.kill();
    // Reads stop returning the old image once the server is found gone.
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        match c.data_read(16, &mut buf, procimg_client::Ioxs::Good) {
            Err(procimg_client::IoError::ServerGone { .. }) => break,
            _ => assert!(
                Instant::now() < until,
                "reads kept succeeding without a server"
            ),
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    server.restart();
    let until = Instant::now() + Duration::from_secs(30);
    while c
        .data_read(16, &mut buf, procimg_client::Ioxs::Good)
        .is_err()
    {
        assert!(
            Instant::now() < until,
            "the asynchronous client did not re-attach in 30 s"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(
        c.events()
            .iter()
            .any(|e| matches!(e, Event::Reattached { .. }))
    );
}

#[test]
fn a_client_follows_the_new_layout_of_a_server_restarted_with_another_configuration() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut server = Procimgd::demo("follow");
    let instance = server.instance.clone();
    let mut c = Client::attach(&instance, AttachOptions::synchronous("follower")).unwrap();
    let (echo, dio) = (
        c.layout().find("echo", 1, 1).unwrap(),
        c.layout().find("dio", 2, 1).unwrap(),
    );
    c.claim(&[echo, dio]).unwrap();
    let was = c.layout().hash();
    // Another configuration for the same instance: the demo's without its device "dio".
    let demo = Command::new(procimg_testkit::build::procimgd_bin())
        .arg("--print-demo-config")
        .output()
        .expect("procimgd --print-demo-config");
    let demo = String::from_utf8(demo.stdout).unwrap();
    let cut = demo
        .find("[[device]]\nname = \"dio\"")
        .expect("the demo configuration has the device dio");
    let config = demo[..cut].replacen(
        "instance = \"procimg\"",
        &format!("instance = \"{instance}\""),
        1,
    );
    server.kill();
    let _again = procimg_testkit::Launch::config("follow-b", &config)
        .instance(&instance)
        .start();
    // The client re-attaches, follows the new layout and says so; dio's claim is lost,
    // echo's taken again under its index in the new layout.
    let mut events = Vec::new();
    let until = Instant::now() + Duration::from_secs(30);
    while !events
        .iter()
        .any(|e| matches!(e, Event::LayoutChanged { .. }))
    {
        assert!(
            Instant::now() < until,
            "no layout change in 30 s: {events:?}"
        );
        // While the server is gone, and until the new one takes this client's outputs,
        // an OPDONE may not be delivered.
        if let Ok(cycle) = c.wait_startop(Duration::from_millis(50)) {
            let _ = cycle.set_opdone();
        }
        events.extend(c.events());
    }
    events.extend(c.events());
    let now = c.layout().hash();
    assert_ne!(now, was);
    let reattached = events
        .iter()
        .position(|e| matches!(e, Event::Reattached { .. }))
        .expect("Reattached");
    let changed = events
        .iter()
        .position(|e| *e == Event::LayoutChanged { was, now })
        .expect("LayoutChanged with both hashes");
    assert_eq!(changed, reattached + 1, "{events:?}");
    assert!(
        events.contains(&Event::ClaimLost { submodule: dio }),
        "{events:?}"
    );
    assert!(c.layout().find("dio", 2, 1).is_none());
    let echo_now = c.layout().find("echo", 1, 1).unwrap();
    // Cycles run with the new layout, echo's outputs written under its new index.
    let mut cycles = 0;
    let until = Instant::now() + Duration::from_secs(20);
    while cycles < 20 && Instant::now() < until {
        if let Ok(mut cycle) = c.wait_startop(Duration::from_millis(100)) {
            cycle.output_mut(echo_now).unwrap().fill(9);
            cycle.set_opdone().unwrap();
            cycles += 1;
        }
    }
    assert_eq!(cycles, 20);
}
