// SPDX-License-Identifier: MIT OR Apache-2.0
//! Clients and servers that die: a synchronous client killed inside its window, a server
//! killed and restarted under running clients.
//!
//! The killed client is this test binary run again with `PROCIMG_TEST_CHILD` set, so the
//! test needs no extra program.

mod support;

use procimg_client::{AttachOptions, Client, Event};
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use support::Server;

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
        let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
        n += 1;
        if n == 200 {
            println!("cycling");
        }
        if n > 200 && trigger.exists() {
            // Hang between STARTOP and OPDONE until killed.
            println!("in-window");
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
    let server = Server::demo("kill");
    // A well-behaved synchronous client runs alongside the whole time.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let bystander = {
        let (instance, stop) = (server.instance.clone(), stop.clone());
        std::thread::spawn(move || {
            let _ = procimg_client::realtime::make_current_thread_realtime(60);
            let mut c = Client::attach(&instance, AttachOptions::synchronous("bystander")).unwrap();
            let mut faults = Vec::new();
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                if let Ok(cycle) = c.wait_startop(Duration::from_millis(100)) {
                    cycle.set_opdone().unwrap();
                }
                for e in c.events() {
                    if let Event::OpFault { cycle } = e {
                        faults.push((Instant::now(), cycle));
                    }
                }
            }
            faults
        })
    };
    let trigger = std::env::temp_dir().join(format!("{}.hang", server.instance));
    let _ = std::fs::remove_file(&trigger);
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "child_sync_client_that_hangs_in_its_window",
            "--nocapture",
        ])
        .env(CHILD_ENV, &server.instance)
        .env(TRIGGER_ENV, &trigger)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    let mut wait_for = |what: &str| {
        assert!(
            lines.any(|l| l.map(|l| l.contains(what)).unwrap_or(false)),
            "the child client never printed {what}"
        );
    };
    wait_for("cycling");
    let before = server.status();
    let doomed_before = before
        .clients
        .iter()
        .find(|c| c.name == "doomed")
        .unwrap()
        .opfaults;
    assert_eq!(before.clients.len(), 2);
    std::fs::write(&trigger, b"hang").unwrap();
    wait_for("in-window");
    let _ = std::fs::remove_file(&trigger);
    // Let the deadline of the hung cycle pass, then kill it inside its window.
    std::thread::sleep(Duration::from_millis(20));
    let killed_at = Instant::now();
    child.kill().unwrap();
    let _ = child.wait();

    // The server keeps cycling, reaps the client and frees its claim.
    let until = Instant::now() + Duration::from_secs(3);
    let after = loop {
        let s = server.status();
        if s.clients.iter().all(|c| c.name != "doomed") {
            break s;
        }
        assert!(Instant::now() < until, "the killed client was never reaped");
        std::thread::sleep(Duration::from_millis(20));
    };
    let reaped_at = Instant::now();
    std::thread::sleep(Duration::from_millis(300));
    let later = server.status();
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    let bystander_faults: Vec<String> = bystander
        .join()
        .unwrap()
        .iter()
        .map(|(t, k)| {
            let rel = |a: Instant, b: Instant| {
                if a >= b {
                    (a - b).as_secs_f64() * 1e3
                } else {
                    -((b - a).as_secs_f64() * 1e3)
                }
            };
            format!(
                "cycle {k}: {:+.1} ms after kill, {:+.1} ms after reap",
                rel(*t, killed_at),
                rel(*t, reaped_at)
            )
        })
        .collect();
    assert!(
        later.cycle_count > after.cycle_count + 150,
        "the server stopped cycling"
    );
    // One OPFAULT for the cycle the client hung in, none after, none for anybody else.
    assert_eq!(
        later.opfaults - before.opfaults,
        1,
        "OPFAULTs before {} (doomed {doomed_before}), after {}; bystander faults {bystander_faults:?}",
        before.opfaults,
        later.opfaults
    );
    let faults = |s: &procimg_client::StatusReport| {
        s.clients
            .iter()
            .find(|c| c.name == "bystander")
            .map_or(0, |c| c.opfaults)
    };
    assert_eq!(
        faults(&later),
        faults(&before),
        "the other client got OPFAULTs: {later:?}"
    );

    // A new client takes the same outputs.
    let mut c = Client::attach(&server.instance, AttachOptions::synchronous("successor")).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    c.claim(&[echo])
        .expect("the killed client's claim was not freed");
    let mut cycle = c.wait_startop(Duration::from_secs(1)).unwrap();
    cycle.output_mut(echo).unwrap().fill(1);
    cycle.set_opdone().unwrap();
}

#[test]
fn a_running_client_reattaches_within_a_second_of_a_server_restart() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut server = Server::demo("restart");
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
            restarted.elapsed() < Duration::from_secs(5),
            "no re-attachment"
        );
    };
    assert!(
        reattached < Duration::from_secs(1),
        "re-attached after {reattached:?}"
    );
    assert_ne!(c.generation(), first_generation);
    // Cycles flow again, and the claim was taken again.
    let mut cycles = 0;
    let until = Instant::now() + Duration::from_secs(2);
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
