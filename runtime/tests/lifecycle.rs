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
    // Another client follows the cycles alongside the whole time. It is asynchronous, so it
    // is never waited for and can get no OPFAULT: every OPFAULT counted is the hung client's,
    // whatever else this shared machine does meanwhile.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let bystander = {
        let (instance, stop) = (server.instance.clone(), stop.clone());
        std::thread::spawn(move || {
            let mut c =
                Client::attach(&instance, AttachOptions::asynchronous("bystander")).unwrap();
            let mut cycles = Vec::new();
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                if let Ok(cycle) = c.wait_startop(Duration::from_millis(100)) {
                    cycles.push((Instant::now(), cycle.number()));
                }
            }
            cycles
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
    // Let the deadline of the hung cycle pass: its OPFAULT is counted; then kill it inside its
    // window.
    std::thread::sleep(Duration::from_millis(20));
    let hung = server.status();
    let doomed_hung = hung
        .clients
        .iter()
        .find(|c| c.name == "doomed")
        .expect("the hung client is still registered")
        .opfaults;
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
    let seen = bystander.join().unwrap();
    assert!(
        later.cycle_count > after.cycle_count + 150,
        "the server stopped cycling"
    );
    // The killed client: exactly one OPFAULT, for the cycle it hung in; a suspended client is
    // not waited for again, so the kill and the reaping add none.
    assert_eq!(
        doomed_hung - doomed_before,
        1,
        "OPFAULTs of the hung client"
    );
    // Nobody else got one: the total rose by exactly that one.
    assert_eq!(
        later.opfaults - before.opfaults,
        1,
        "OPFAULTs counted for others"
    );
    // The other client kept getting its cycles through the kill and the reaping.
    let around: Vec<u64> = seen
        .iter()
        .filter(|(t, _)| *t >= killed_at && *t <= reaped_at + Duration::from_millis(300))
        .map(|(_, k)| *k)
        .collect();
    let span = (reaped_at + Duration::from_millis(300) - killed_at).as_millis() as usize;
    assert!(
        around.len() * 2 >= span,
        "the other client saw {} cycles in {span} ms after the kill",
        around.len()
    );
    assert!(around.windows(2).all(|w| w[0] < w[1]));

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

#[test]
fn an_asynchronous_client_reattaches_and_reports_the_gap() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut server = Server::demo("async-restart");
    let mut c = Client::attach(
        &server.instance,
        AttachOptions::asynchronous("async-survivor"),
    )
    .unwrap();
    let mut buf = [0u8; 4];
    let until = Instant::now() + Duration::from_secs(2);
    while c
        .data_read(16, &mut buf, procimg_client::Ioxs::Good)
        .is_err()
    {
        assert!(Instant::now() < until);
        std::thread::sleep(Duration::from_millis(5));
    }
    server.kill();
    // Reads stop returning the old image once the server is found gone.
    let until = Instant::now() + Duration::from_secs(2);
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
    let until = Instant::now() + Duration::from_secs(3);
    while c
        .data_read(16, &mut buf, procimg_client::Ioxs::Good)
        .is_err()
    {
        assert!(
            Instant::now() < until,
            "the asynchronous client never re-attached"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    assert!(
        c.events()
            .iter()
            .any(|e| matches!(e, Event::Reattached { .. }))
    );
}
