// SPDX-License-Identifier: MIT OR Apache-2.0
//! Multi-process tests: the real procimgd, clients in this process.

use procimg_client::{
    AttachError, AttachOptions, Client, ControlError, ControlHandle, Event, Ioxs, Mode, Refusal,
};
use procimg_testkit::{Procimgd, pattern, pattern_value};
use std::collections::HashMap;
use std::sync::{Arc, Barrier, Mutex};
use std::time::{Duration, Instant};

/// The cycle of the newest image an asynchronous client has, once it has one.
fn newest_cycle(client: &mut Client) -> procimg_client::CycleInfo {
    let until = Instant::now() + Duration::from_secs(20);
    let mut buf = [0u8; 1];
    loop {
        // Any read takes the newest image.
        let _ = client.data_read(16, &mut buf, Ioxs::Good);
        if let Some(info) = client.cycle_info().filter(|i| i.cycle_number > 0) {
            return info;
        }
        assert!(Instant::now() < until, "no image in 20 s");
        std::thread::sleep(Duration::from_millis(5));
    }
}

/// The echo inputs a client saw, by cycle number.
type EchoByCycle = HashMap<u64, Vec<u8>>;

const STARTOP_TIMEOUT: Duration = Duration::from_millis(500);

#[test]
fn demo_cycles_at_1ms_in_operate_and_status_reports_it() {
    let server = Procimgd::demo("status");
    let mut client =
        Client::attach(&server.instance, AttachOptions::asynchronous("clock")).unwrap();
    let a = newest_cycle(&mut client);
    let b = server.wait_status("100 more cycles", |s| s.cycle_count >= a.cycle_number + 100);
    assert_eq!(b.mode, Mode::Operate);
    assert_eq!(b.cycle_ns, 1_000_000);
    // Cycle k is due at epoch + k·1 ms: the images say so exactly, whatever the machine did
    // meanwhile (a cycle lost to an overrun is skipped, not delayed).
    let c = newest_cycle(&mut client);
    assert!(c.cycle_number > a.cycle_number);
    assert_eq!(
        c.cycle_start_ns - a.cycle_start_ns,
        (c.cycle_number - a.cycle_number) * 1_000_000,
        "cycles {} and {} are not planned 1 ms apart",
        a.cycle_number,
        c.cycle_number
    );
    assert_eq!(
        b.rt_heap_allocations, 0,
        "the cycle thread called the heap allocator"
    );
    assert!(b.wakeup_latency.count > 0);
}

#[test]
fn attach_errors_say_what_is_wrong() {
    match Client::attach("no-such-instance-xyz", AttachOptions::asynchronous("t")) {
        Err(AttachError::NoServer { instance }) => assert_eq!(instance, "no-such-instance-xyz"),
        Err(e) => panic!("wrong error: {e}"),
        Ok(_) => panic!("attached to a server that does not exist"),
    }
    let server = Procimgd::demo("hash");
    let opts = AttachOptions::asynchronous("t").expect_layout_hash(0x1234);
    match Client::attach(&server.instance, opts) {
        Err(e @ AttachError::LayoutHash { .. }) => {
            let msg = e.to_string();
            assert!(msg.contains("0000000000001234"), "{msg}");
        }
        Err(e) => panic!("wrong error: {e}"),
        Ok(_) => panic!("attached despite a different layout hash"),
    }
    // The refused client left no registration behind.
    assert!(server.status().clients.is_empty());
}

#[test]
fn a_second_claim_is_refused_naming_the_holder() {
    let server = Procimgd::demo("claims");
    let mut a = Client::attach(&server.instance, AttachOptions::asynchronous("holder-a")).unwrap();
    let mut b = Client::attach(&server.instance, AttachOptions::asynchronous("other-b")).unwrap();
    let echo = a.layout().find("echo", 1, 1).unwrap();
    a.claim(&[echo]).unwrap();
    match b.claim(&[echo]) {
        Err(ControlError::Refused(Refusal::ClaimHeld {
            holder, holder_pid, ..
        })) => {
            assert_eq!(holder, "holder-a");
            assert_eq!(holder_pid, std::process::id());
        }
        other => panic!("second claim not refused: {other:?}"),
    }
    let err = b.claim(&[echo]).unwrap_err().to_string();
    assert!(err.contains("holder-a"), "{err}");
    // Writing without the claim is refused on the client side.
    assert!(b.data_write(0, &[0; 16], Ioxs::Good).is_err());
    // After release, b gets it.
    a.release(&[echo]).unwrap();
    b.claim(&[echo]).unwrap();
    let st = server.status();
    let holder = st.clients.iter().find(|c| c.name == "other-b").unwrap();
    assert_eq!(holder.claims.len(), 1);
    assert_eq!(holder.claims[0].device, "echo");
}

#[test]
fn asynchronous_write_reaches_the_echo_device_whole() {
    let server = Procimgd::demo("async");
    let mut c = Client::attach(&server.instance, AttachOptions::asynchronous("async")).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    c.claim(&[echo]).unwrap();
    let data: Vec<u8> = (1..=16).collect();
    c.data_write(0, &data, Ioxs::Good).unwrap();
    let until = Instant::now() + Duration::from_secs(20);
    let mut buf = [0u8; 16];
    loop {
        let r = c.data_read(0, &mut buf, Ioxs::Good).unwrap();
        if buf[..] == data[..] {
            assert_eq!(r.remote, Ioxs::Good);
            assert_eq!(r.len, 16);
            break;
        }
        assert!(
            Instant::now() < until,
            "echo never returned the written bytes: {buf:?}"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    // A slice write changes only its bytes.
    c.data_write(3, &[0xaa, 0xbb], Ioxs::Good).unwrap();
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let mut out = [0u8; 16];
        let r = c.output_data_read(0, &mut out).unwrap();
        if out[3] == 0xaa {
            assert_eq!(&out[..3], &data[..3]);
            assert_eq!(out[4], 0xbb);
            assert_eq!(&out[5..], &data[5..]);
            assert_eq!(r.local, Ioxs::Good);
            break;
        }
        assert!(Instant::now() < until);
        std::thread::sleep(Duration::from_millis(2));
    }
}

#[test]
fn mode_changes_are_confirmed_step_by_step() {
    let server = Procimgd::demo("mode");
    let mut c = Client::attach(&server.instance, AttachOptions::asynchronous("mode")).unwrap();
    let mut seen = Vec::new();
    let wait_for = |c: &mut Client, target: Mode, seen: &mut Vec<Mode>| {
        let until = Instant::now() + Duration::from_secs(20);
        while !seen.contains(&target) {
            let _ = c.wait_startop(Duration::from_millis(50));
            for e in c.events() {
                if let Event::Mode(m) = e {
                    seen.push(m);
                }
            }
            assert!(
                Instant::now() < until,
                "no MODE event for {target}: {seen:?}"
            );
        }
    };
    c.set_mode(Mode::Offline).unwrap();
    wait_for(&mut c, Mode::Offline, &mut seen);
    assert_eq!(seen, [Mode::Clear, Mode::Offline]);
    // In OFFLINE the devices are not connected: inputs are BAD.
    let mut buf = [0u8; 4];
    let _ = c.wait_startop(Duration::from_millis(50));
    assert_eq!(
        c.data_read(16, &mut buf, Ioxs::Good).unwrap().remote,
        Ioxs::Bad
    );
    seen.clear();
    c.set_mode(Mode::Operate).unwrap();
    wait_for(&mut c, Mode::Operate, &mut seen);
    assert_eq!(seen, [Mode::Clear, Mode::Operate]);
}

/// One synchronous writer and seven readers: every client sees the same data for the same
/// cycle, and no image is ever torn.
#[test]
fn eight_clients_see_the_same_consistent_untorn_images() {
    clients_see_the_same_untorn_images("eight", [false; 8]);
}

/// The same with a busy-polling writer and two busy-polling readers, which find the images
/// through the handshake block and hold them by their marks (`procimg_shm_layout::pins`),
/// as the sleeping writer of the test above does, beside sleeping asynchronous readers that
/// receive them through iceoryx2.
#[test]
fn busy_polling_clients_see_the_same_untorn_images_as_sleeping_ones() {
    let busy = [true, true, false, true, false, false, false, false];
    clients_see_the_same_untorn_images("busy8", busy);
}

fn clients_see_the_same_untorn_images(tag: &str, busy: [bool; 8]) {
    let server = Procimgd::demo(tag);
    let instance = server.instance.clone();
    // Counted in cycles, not seconds: the writer runs 500 cycles, and on until every reader
    // has seen 20 images (a loaded machine may keep one from running for a while); the
    // readers run until then.
    let writer_cycles = 500;
    let writer_done = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let readers_going = Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let seen: Arc<Mutex<Vec<(usize, EchoByCycle)>>> = Arc::default();
    let start = Arc::new(Barrier::new(8));
    let mut threads = Vec::new();
    for (i, busy) in busy.into_iter().enumerate() {
        let (instance, seen, start) = (instance.clone(), seen.clone(), start.clone());
        let (writer_done, readers_going) = (writer_done.clone(), readers_going.clone());
        threads.push(std::thread::spawn(move || {
            let opts = if i == 0 {
                AttachOptions::synchronous("writer")
            } else {
                AttachOptions::asynchronous(&format!("reader-{i}"))
            }
            .busy_poll(busy);
            let mut c = Client::attach(&instance, opts).unwrap();
            let echo = c.layout().find("echo", 1, 1).unwrap();
            let counter = c.layout().find("counter", 1, 1).unwrap();
            if i == 0 {
                c.claim(&[echo]).unwrap();
            }
            start.wait();
            let mut mine = HashMap::new();
            let mut last = 0;
            let mut last_cnt = 0;
            // A bound for a machine so loaded that it would never get there.
            let until = Instant::now() + Duration::from_secs(120);
            let running = |mine: &HashMap<u64, Vec<u8>>| {
                Instant::now() < until
                    && if i == 0 {
                        mine.len() < writer_cycles
                            || readers_going.load(std::sync::atomic::Ordering::Acquire) < 7
                    } else {
                        !writer_done.load(std::sync::atomic::Ordering::Acquire)
                    }
            };
            while running(&mine) {
                let Ok(mut cycle) = c.wait_startop(STARTOP_TIMEOUT) else {
                    continue;
                };
                let k = cycle.number();
                assert!(k > last, "cycle numbers must rise: {last} then {k}");
                last = k;
                // The counter device counts its frames: it never goes back in one view.
                let cnt = u32::from_be_bytes(cycle.input(counter).unwrap().try_into().unwrap());
                assert!(cnt >= last_cnt, "counter went back: {last_cnt} then {cnt}");
                last_cnt = cnt;
                let e = cycle.input(echo).unwrap().to_vec();
                if e != [0u8; 16] {
                    assert!(
                        pattern_value(&e).is_some(),
                        "torn echo input in cycle {k}: {e:02x?}"
                    );
                }
                // Clients compare the whole image of a cycle: echo and counter.
                mine.insert(k, [e, cnt.to_be_bytes().to_vec()].concat());
                if i != 0 && mine.len() == 20 {
                    readers_going.fetch_add(1, std::sync::atomic::Ordering::AcqRel);
                }
                if i == 0 {
                    cycle
                        .output_mut(echo)
                        .unwrap()
                        .copy_from_slice(&pattern(k, 16));
                    cycle.set_opdone().unwrap();
                }
            }
            if i == 0 {
                writer_done.store(true, std::sync::atomic::Ordering::Release);
            }
            seen.lock().unwrap().push((i, mine));
        }));
    }
    for t in threads {
        t.join().expect("a client thread failed");
    }
    // The synchronous writer's OPDONE samples, busy or sleeping, are taken where it wrote
    // them (the first is sent, for the server to learn where they lie); none torn.
    let status = server.status();
    assert!(
        status.outputs_in_place >= writer_cycles as u64 / 2,
        "{} of the writer's {writer_cycles} outputs taken in place",
        status.outputs_in_place
    );
    assert_eq!(status.rejected_writes, 0);
    let seen = seen.lock().unwrap();
    assert_eq!(seen.len(), 8);
    let writer = &seen
        .iter()
        .find(|(i, _)| *i == 0)
        .expect("the writer's images")
        .1;
    assert!(
        writer.len() >= writer_cycles,
        "the writer ran only {} cycles in 120 s",
        writer.len()
    );
    // Every reader agrees with the writer on every cycle both saw, and saw some of them
    // (how many depends on how the machine schedules the readers, not on procimg).
    for (_, other) in seen.iter().filter(|(i, _)| *i != 0) {
        let mut compared = 0;
        for (k, data) in writer {
            if let Some(d) = other.get(k) {
                assert_eq!(d, data, "clients disagree about cycle {k}");
                compared += 1;
            }
        }
        assert!(compared > 0, "a reader saw none of the writer's cycles");
    }
}

/// A busy client that holds a cycle's image while the server publishes many newer ones sees
/// it unchanged, header and all: procimgd keeps the sample its mark holds unwritten, and the
/// header (which iceoryx2 rewrites whenever it loans the sample) was copied while the image
/// was the newest.
#[test]
fn a_busy_client_holding_an_image_sees_it_unchanged_while_newer_ones_come() {
    let server = Procimgd::demo("busyhold");
    let opts = AttachOptions::asynchronous("holder").busy_poll(true);
    let mut c = Client::attach(&server.instance, opts).unwrap();
    // The busy path begins once the client has learnt where the images lie, from one it
    // received: a few cycles in.
    for _ in 0..20 {
        let _ = c.wait_startop(STARTOP_TIMEOUT);
    }
    for _ in 0..5 {
        let cycle = c.wait_startop(Duration::from_secs(10)).unwrap();
        let (number, info, inputs) = (cycle.number(), cycle.info(), cycle.inputs().to_vec());
        assert!(number > 0);
        // Held while 20 newer images are published: the samples come round for loans.
        server.wait_status("20 newer cycles", |s| s.cycle_count >= number + 20);
        assert_eq!(cycle.number(), number);
        assert_eq!(cycle.info(), info);
        assert_eq!(
            cycle.inputs(),
            &inputs[..],
            "the inputs of cycle {number} changed"
        );
    }
}

/// The read path hands out slices of the shared-memory segment itself: their addresses lie in
/// a mapping of a procimg file in /dev/shm, not in this process's heap.
#[test]
fn the_read_path_copies_no_image_bytes() {
    let server = Procimgd::demo("zerocopy");
    let mut c = Client::attach(&server.instance, AttachOptions::synchronous("zc")).unwrap();
    let cycle = c.wait_startop(STARTOP_TIMEOUT).unwrap();
    let inputs = cycle.inputs().as_ptr() as usize;
    let echo = cycle.input(1).unwrap().as_ptr() as usize;
    let maps = std::fs::read_to_string("/proc/self/maps").unwrap();
    let in_shm = |addr: usize| {
        maps.lines().any(|l| {
            let mut f = l.split_whitespace();
            let range = f.next().unwrap_or("");
            let path = l.split_whitespace().nth(5).unwrap_or("");
            let (a, b) = range.split_once('-').unwrap_or(("0", "0"));
            let (a, b) = (
                usize::from_str_radix(a, 16).unwrap_or(0),
                usize::from_str_radix(b, 16).unwrap_or(0),
            );
            addr >= a && addr < b && path.starts_with("/dev/shm/procimg_")
        })
    };
    assert!(
        in_shm(inputs),
        "inputs() is not in a /dev/shm/procimg_ mapping"
    );
    assert!(
        in_shm(echo),
        "input(s) is not in a /dev/shm/procimg_ mapping"
    );
    drop(cycle);
}

#[test]
fn sigterm_puts_outputs_in_clear_then_removes_the_shared_memory() {
    let mut server = Procimgd::demo("term");
    let instance = server.instance.clone();
    let ready = Arc::new(Barrier::new(2));
    let waiter = {
        let (instance, ready) = (instance.clone(), ready.clone());
        std::thread::spawn(move || {
            let mut c = Client::attach(&instance, AttachOptions::asynchronous("watcher")).unwrap();
            let _ = c.wait_startop(STARTOP_TIMEOUT);
            let _ = c.events();
            ready.wait();
            let mut events = Vec::new();
            let until = Instant::now() + Duration::from_secs(20);
            while Instant::now() < until && !events.contains(&Event::ServerShutdown) {
                let _ = c.wait_startop(Duration::from_millis(20));
                events.extend(c.events());
            }
            events
        })
    };
    ready.wait();
    let status = server.terminate();
    let events = waiter.join().unwrap();
    assert!(status.success(), "procimgd exited with {status:?}");
    let clear = events.iter().position(|e| *e == Event::Mode(Mode::Clear));
    let shutdown = events.iter().position(|e| *e == Event::ServerShutdown);
    assert!(clear.is_some() && shutdown.is_some(), "events: {events:?}");
    assert!(
        clear < shutdown,
        "CLEAR must come before shutdown: {events:?}"
    );
    // The control service is gone with the server (no client holds it any more).
    std::thread::sleep(Duration::from_millis(100));
    match ControlHandle::open(&instance, "after") {
        Err(AttachError::NoServer { .. }) => {}
        Err(e) => panic!("unexpected error: {e}"),
        Ok(_) => panic!("the control service of {instance} still exists"),
    }
}

/// NEWCYCLE reaches only clients that asked for it; the whole-output view writes the claimed
/// submodules and the server ignores the bytes of the others.
#[test]
fn newcycle_on_request_and_the_whole_output_view_respects_claims() {
    let server = Procimgd::demo("newcycle");
    let mut asks = Client::attach(
        &server.instance,
        AttachOptions::synchronous("asks").newcycle(true),
    )
    .unwrap();
    let mut quiet = Client::attach(&server.instance, AttachOptions::asynchronous("quiet")).unwrap();
    let echo = asks.layout().find("echo", 1, 1).unwrap();
    asks.claim(&[echo]).unwrap();
    let mut newcycles = 0;
    for _ in 0..50 {
        let mut cycle = asks.wait_startop(STARTOP_TIMEOUT).unwrap();
        let q = cycle.outputs_mut().unwrap();
        assert_eq!(q.len(), 18, "the demo has 18 output bytes");
        q[..16].fill(0x42); // echo, claimed
        q[16..].fill(0xff); // dio, not claimed: ignored
        cycle.set_opdone().unwrap();
        newcycles += asks
            .events()
            .iter()
            .filter(|e| **e == Event::NewCycle)
            .count();
        let _ = quiet.wait_startop(Duration::from_millis(1));
    }
    assert!(
        newcycles > 10,
        "only {newcycles} NEWCYCLE events for the client that asked"
    );
    assert!(!quiet.events().contains(&Event::NewCycle));
    let mut echo_in = [0u8; 16];
    quiet.data_read(0, &mut echo_in, Ioxs::Good).unwrap();
    assert_eq!(echo_in, [0x42; 16]);
    let mut dio_out = [0u8; 2];
    let r = quiet.output_data_read(16, &mut dio_out).unwrap();
    assert_eq!(dio_out, [0, 0], "unclaimed outputs were written");
    assert_eq!(r.local, Ioxs::Bad, "never-written outputs go out invalid");
    assert!(server.status().rejected_writes == 0);
}

/// A submodule's outputs start as last sent when the program first touches them in a cycle,
/// and keep what it wrote since; a whole overwrite and a partial write both reach the device.
#[test]
fn outputs_start_as_last_sent_only_where_the_program_touches_them() {
    let server = Procimgd::demo("last-sent");
    let mut c = Client::attach(&server.instance, AttachOptions::synchronous("writer")).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    c.claim(&[echo]).unwrap();
    let mut pattern = [0u8; 16];
    pattern
        .iter_mut()
        .enumerate()
        .for_each(|(i, b)| *b = i as u8 + 1);
    // Overwritten whole, until the image's mirror shows it went out.
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let mut cycle = c.wait_startop(STARTOP_TIMEOUT).unwrap();
        let sent = cycle.outputs_sent(echo).unwrap() == pattern;
        cycle
            .output_overwrite(echo)
            .unwrap()
            .copy_from_slice(&pattern);
        cycle.set_opdone().unwrap();
        if sent {
            break;
        }
        assert!(Instant::now() < until, "the overwrite never went out");
    }
    // Touched again: starts as last sent; a change of one byte keeps the others, and so does
    // the whole view taken after it. Until it went out: a cycle that came late on a busy
    // machine (an OPFAULT) is not sent, and the next starts from what was.
    let mut touched = pattern;
    touched[3] = 0xee;
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let mut cycle = c.wait_startop(STARTOP_TIMEOUT).unwrap();
        let last_sent = cycle.outputs_sent(echo).unwrap().to_vec();
        let out = cycle.output_mut(echo).unwrap();
        assert_eq!(
            out,
            &last_sent[..],
            "the outputs did not start as last sent"
        );
        out[3] = 0xee;
        let q = cycle.outputs_mut().unwrap();
        assert_eq!(q[3], 0xee, "the whole view lost what was written before it");
        assert_eq!(q[..3], pattern[..3]);
        cycle.set_opdone().unwrap();
        if last_sent[..] == touched[..] {
            break;
        }
        assert!(Instant::now() < until, "the touched outputs never went out");
    }
    // A partial write inside the window keeps the rest as last sent.
    let mut expected = touched;
    expected[8..10].copy_from_slice(&[0xab, 0xcd]);
    let until = Instant::now() + Duration::from_secs(20);
    loop {
        let mut cycle = c.wait_startop(STARTOP_TIMEOUT).unwrap();
        let sent = cycle.outputs_sent(echo).unwrap() == expected;
        let base = output_address(&cycle, echo);
        cycle.write(base + 8, &[0xab, 0xcd], Ioxs::Good).unwrap();
        cycle.set_opdone().unwrap();
        if sent {
            break;
        }
        assert!(
            Instant::now() < until,
            "the partial write never went out as expected"
        );
    }
}

fn output_address(cycle: &procimg_client::Cycle<'_>, s: usize) -> u32 {
    cycle.layout().submodules[s].output_address
}

/// A busy client whose OPDONE samples are taken where it wrote them still has an
/// asynchronous write taken: procimgd looks at its port whenever it counted a send, so the
/// write goes out (and shows as last sent) while the cycle's outputs keep being taken in
/// place, none refused.
#[test]
fn a_busy_clients_asynchronous_write_goes_out_beside_outputs_taken_in_place() {
    let server = Procimgd::demo("busyasync");
    let opts = AttachOptions::synchronous("busy-writer").busy_poll(true);
    let mut c = Client::attach(&server.instance, opts).unwrap();
    let echo = c.layout().find("echo", 1, 1).unwrap();
    let dio = c.layout().find("dio", 2, 1).unwrap();
    let dio_address = c.layout().submodules[dio].output_address;
    c.claim(&[echo, dio]).unwrap();
    let written = [0x5a, 0xa5];
    let mut sent = false;
    let until = Instant::now() + Duration::from_secs(60);
    for round in 1u64.. {
        assert!(
            Instant::now() < until,
            "after {round} cycles: in place {}, asynchronous write sent {sent}",
            server.status().outputs_in_place
        );
        let Ok(mut cycle) = c.wait_startop(STARTOP_TIMEOUT) else {
            continue;
        };
        let k = cycle.number();
        cycle
            .output_mut(echo)
            .unwrap()
            .copy_from_slice(&pattern(k, 16));
        cycle.set_opdone().unwrap();
        if !sent && round % 10 == 0 && server.status().outputs_in_place >= 10 {
            // Between two cycles: a write of its own sample, sent through iceoryx2.
            c.data_write(dio_address, &written, Ioxs::Good).unwrap();
            sent = true;
        } else if sent {
            let mut out = [0u8; 2];
            c.output_data_read(dio_address, &mut out).unwrap();
            if out == written {
                break;
            }
        }
    }
    let status = server.status();
    assert_eq!(status.rejected_writes, 0);
    assert!(status.outputs_in_place >= 10);
}

/// A cycle whose image another call already fetched (an event, a data_read) is still handed
/// out by wait_startop: nothing is skipped, so the client does not miss its window.
#[test]
fn wait_startop_hands_out_a_cycle_another_call_already_fetched() {
    let server = Procimgd::demo("fetched");
    let mut c = Client::attach(&server.instance, AttachOptions::synchronous("fetched")).unwrap();
    // With the bug, wait_startop never handed out the cycle data_read had fetched (it waited
    // for the next one); now it does, unless a newer cycle arrived in between (then that one,
    // which a loaded machine makes common: only the bug makes it every time).
    let mut same = 0;
    for _ in 0..20 {
        let cycle = c.wait_startop(STARTOP_TIMEOUT).unwrap();
        cycle.set_opdone().unwrap();
        // Let the next cycle start, then fetch its image by another route.
        std::thread::sleep(Duration::from_millis(1));
        let mut buf = [0u8; 4];
        c.data_read(16, &mut buf, Ioxs::Good).unwrap();
        let seen = c.cycle_info().unwrap().cycle_number;
        let cycle = c.wait_startop(STARTOP_TIMEOUT).unwrap();
        assert!(cycle.number() >= seen, "an older cycle was handed out");
        if cycle.number() == seen {
            same += 1;
        }
        cycle.set_opdone().unwrap();
    }
    assert!(
        same > 0,
        "the fetched cycle was never handed out in 20 tries: wait_startop skips it"
    );
}

#[test]
fn as_many_clients_as_the_limit_attach_and_one_more_is_told_why_not() {
    // Each client is a node of its own in iceoryx2's services: their node limit must not be
    // lower than procimg's client limit.
    let server = Procimgd::demo("many");
    let max = procimg_shm_layout::MAX_CLIENTS;
    let clients: Vec<Client> = (0..max)
        .map(|i| {
            Client::attach(
                &server.instance,
                AttachOptions::asynchronous(&format!("c{i}")),
            )
            .unwrap_or_else(|e| panic!("client {i} of {max}: {e}"))
        })
        .collect();
    assert_eq!(server.status().clients.len(), max);
    match Client::attach(
        &server.instance,
        AttachOptions::asynchronous("one-too-many"),
    ) {
        Err(e) => assert!(e.to_string().contains(&max.to_string()), "{e}"),
        Ok(_) => panic!("client {} attached beyond the limit of {max}", max + 1),
    }
    drop(clients);
}

#[test]
fn requests_and_attaches_ring_the_servers_doorbell_which_goes_with_the_server() {
    use procimg_control::doorbell::{Doorbell, doorbell_path};
    let server = Procimgd::demo("doorbell");
    let instance = server.instance.clone();
    let bell = Doorbell::open(&instance).expect("procimgd made its doorbell");
    let control = server.control(Duration::from_secs(20));

    // A request wakes the control thread: it rings before it waits for the answer.
    let before = bell.rung();
    control.status().unwrap();
    assert_ne!(bell.rung(), before, "a request did not ring");

    // An attach rings for the registration and again for the layout its subscriber waits for.
    let before = bell.rung();
    let client = Client::attach(&instance, AttachOptions::asynchronous("bell")).unwrap();
    assert!(
        bell.rung().wrapping_sub(before) >= 2,
        "an attach rang {} times",
        bell.rung().wrapping_sub(before)
    );
    drop(client);
    drop(control);

    drop(server);
    assert!(
        !doorbell_path(&instance).exists(),
        "the doorbell outlived procimgd"
    );
}
