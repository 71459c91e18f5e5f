// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd as PROFINET IO controller of an independent device implementation, on a real
//! interface: `pnio-interop-device` (the device stack of the `pnio` crate) at the far end of a
//! veth pair between two network namespaces this test creates. procimgd runs in the first
//! namespace with the `[[device]]` block the device prints and a 1 ms cycle; the device runs in
//! the second. A client attached to procimgd through shared memory owns the device's outputs
//! and reads its inputs; the device answers every output byte plus one.
//!
//! The steps, one method of [`Rig`] each:
//!
//! 1. [`Rig::bring_up`]: DCP Identify, Connect, PrmEnd and ApplicationReady over the veth
//!    pair, until procimgd reports the device running and the device reports data exchange;
//!    procimgd has not made its interface promiscuous.
//! 2. [`Rig::read_identity`]: a record read of I&M0 (0xAFF0) from a client returns the
//!    device's identity.
//! 3. [`Rig::exchange`]: 10 s of cyclic exchange, values written by the client arrive at the
//!    device and its answers at the client; no watchdog expires on either side and more than
//!    9000 input frames are taken.
//! 4. [`Rig::lose_device`]: the device is SIGKILLed; within three watchdog times procimgd
//!    reports it not running and the client reads its data as BAD; the client's service
//!    handle gets DEV_FAILURE.
//! 5. [`Rig::restart_device`]: the device is started again and comes back to data exchange on
//!    its own, with neither procimgd nor the client restarted; data flows again and the
//!    service handle gets DEV_RETURN.
//! 6. [`Rig::stall_device`]: the device is stopped (SIGSTOP): procimgd's watchdog expires, it
//!    tells the device with an ERR-RTA "consumer data hold time expired" (seen on the wire),
//!    and once the device resumes (SIGCONT) the AR is back, with DEV_FAILURE and DEV_RETURN.
//! 7. [`Rig::shut_down`]: procimgd stops on SIGTERM, releasing the AR and waiting for the
//!    device's answer before it closes its socket (no ICMP "port unreachable" on the wire),
//!    and exits cleanly. tshark flags no frame of the whole run.
//!
//! Needs root (namespaces, raw sockets, real-time scheduling); skipped otherwise. Needs the
//! procimgd binary (built by `cargo build -p procimg-runtime`, or by `cargo test --workspace`)
//! beside this test's target directory, or its path in `PROCIMGD_BIN`.

// SCHED_FIFO for the test's measuring threads is a system call.
#![allow(unsafe_code)]

mod support;

use procimg_client::{
    AttachOptions, Client, ControlHandle, DeviceState, Ioxs, Notification, RecordTarget,
    ServiceOptions, Services, StatusReport,
};
use procimg_interop_pnio_device as iop;
use procimg_profinet::wire::record::Im0;
use procimg_testkit::tshark::{self, LiveCapture};
use procimg_testkit::{Launch, Procimgd};
use std::os::unix::process::ExitStatusExt as _;
use std::sync::mpsc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};
use support::Net;
use support::device::{DEVICE, Device, NAME};

/// procimgd's cycle, and the send clock of both IOCRs (reduction ratio 1).
const CYCLE: Duration = Duration::from_millis(1);
/// DataHoldFactor of both IOCRs (the device block's `watchdog_factor`): procimgd declares the
/// device lost after this many cycles without an input frame, and pnio aborts the AR after as
/// many without an output frame. With the default of 3 (3 ms) neither side lasts long on a
/// 2-vCPU VM while other tests run: procimgd's cycle thread was seen waking up to 11 ms late,
/// and the device saw gaps of up to 14 ms between procimgd's frames. With 20 ms, procimgd
/// still saw a gap of more than 20 ms in the device's frames once, in the whole suite run
/// beside `stress-ng --cpu 2`, both sides' threads at SCHED_FIFO (where the frames were held
/// up was not traced). 100 ms leaves a margin over such gaps, is a value real plants use, and
/// 3 × 100 ms still bounds the detection of a dead device well.
const WATCHDOG_FACTOR: u32 = 100;
/// The watchdog time: DataHoldFactor × send clock × reduction ratio.
const WATCHDOG: Duration = CYCLE.saturating_mul(WATCHDOG_FACTOR);
/// How long the steady exchange runs.
const EXCHANGE: Duration = Duration::from_secs(10);
/// Different values written over the exchange, one after the other.
const VALUES: u8 = 10;
/// How long one value may take from the client's write to the device and back.
const ROUND_TRIP_TIMEOUT: Duration = Duration::from_secs(2);

/// How long bringing the device up may take: generous beside the controller's DCP Identify
/// retries (backing off to 0.8 s), for a loaded machine.
const BRING_UP_TIMEOUT: Duration = Duration::from_secs(15);

/// The outputs written `k`-th: every value differs from the one before in every byte, and the
/// first ends in 0xff, whose answer wraps to 0.
fn value(k: u8) -> [u8; iop::IO_LEN] {
    [
        k.wrapping_add(1),
        k.wrapping_add(0x11),
        k.wrapping_add(0x21),
        k.wrapping_add(0x31),
        0x80 | k,
        0x55 ^ k,
        0xa5 ^ k,
        0xff - k,
    ]
}

/// The procimgd configuration: the device's own `--print-config` block on the controller's
/// end of the veth pair, with the test's watchdog factor.
/// procimgd as the controller of `net`'s device, in the controller's namespace with debug
/// logging, started without waiting for it, as instance `tag` and this process's id.
fn launch(net: &Net, tag: &str) -> Procimgd {
    Launch::config(tag, &configuration(net))
        .instance(&format!("{tag}{}", std::process::id()))
        .netns(net.controller_ns())
        .debug_log()
        .without_waiting()
        .start()
}

fn configuration(net: &Net) -> String {
    let out = std::process::Command::new(DEVICE)
        .args([
            "--name",
            NAME,
            "--ip",
            &net.device_ip.to_string(),
            "--print-config",
        ])
        .output()
        .expect("run pnio-interop-device --print-config");
    assert!(
        out.status.success(),
        "--print-config failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let block = String::from_utf8(out.stdout).expect("the printed block is UTF-8");
    let header = "[[device]]\n";
    assert_eq!(
        block.matches(header).count(),
        1,
        "one [[device]] table expected:\n{block}"
    );
    let block = block.replacen(
        header,
        &format!("{header}watchdog_factor = {WATCHDOG_FACTOR}\n"),
        1,
    );
    format!(
        "# procimgd as IO controller of pnio-interop-device (interop test)\n\
         network = \"{}\"\n\
         cycle_time = \"{}ms\"\n\n\
         {block}",
        net.controller_if(),
        CYCLE.as_millis()
    )
}

/// The calling thread at real-time priority (SCHED_FIFO) until dropped, so that it sees what
/// procimgd does when it happens, whatever else the machine does. Below the cycle threads of
/// procimgd (80) and of the device (90).
struct Realtime;

impl Realtime {
    const PRIORITY: i32 = 50;

    fn enter() -> Realtime {
        if let Err(e) = set_scheduler(libc::SCHED_FIFO, Realtime::PRIORITY) {
            // Root without CAP_SYS_NICE (a container): the measurement still holds on a quiet
            // machine.
            eprintln!("measuring at normal priority: SCHED_FIFO refused: {e}");
        }
        Realtime
    }
}

impl Drop for Realtime {
    fn drop(&mut self) {
        let _ = set_scheduler(libc::SCHED_OTHER, 0);
    }
}

/// Sets the scheduling policy of the calling thread.
fn set_scheduler(policy: i32, priority: i32) -> std::io::Result<()> {
    let param = libc::sched_param {
        sched_priority: priority,
    };
    // SAFETY: `param` is a valid sched_param that outlives the call; pid 0 is this thread.
    match unsafe { libc::sched_setscheduler(0, policy, &param) } {
        0 => Ok(()),
        _ => Err(std::io::Error::last_os_error()),
    }
}

/// What the status poller saw: the first state other than running, when its answer came,
/// and every answer.
struct StateSeen {
    state: DeviceState,
    after: Duration,
    trace: Vec<String>,
}

/// Polls procimgd's status from a real-time thread of its own (with its own connection to the
/// control service: iceoryx2 ports stay on the thread that made them) until the device is
/// reported not running, so that a slow status answer does not hold up reading the image.
struct StatePoller;

impl StatePoller {
    /// Connects a poller to `instance`; it starts when it is sent the time of the kill.
    fn spawn(instance: &str) -> (mpsc::Sender<Instant>, JoinHandle<StateSeen>) {
        let (ready_tx, ready) = mpsc::channel();
        let (start, start_rx) = mpsc::channel::<Instant>();
        let instance = instance.to_string();
        let poller = std::thread::spawn(move || {
            let _realtime = Realtime::enter();
            let control = ControlHandle::open(&instance, "interop-test-status")
                .expect("open procimgd's control service");
            let _ = ready_tx.send(());
            let killed = start_rx.recv().expect("the time of the kill");
            let mut trace = Vec::new();
            loop {
                let asked = killed.elapsed();
                let s = control.status().expect("procimgd's status");
                let after = killed.elapsed();
                let state = s.devices[0].state;
                trace.push(format!(
                    "status asked {asked:?} after the kill, answered after {after:?}: {state}"
                ));
                if state != DeviceState::Running {
                    return StateSeen {
                        state,
                        after,
                        trace,
                    };
                }
                assert!(
                    after < Duration::from_secs(20),
                    "the device is still reported running 20 s after it was killed:\n{}",
                    trace.join("\n")
                );
            }
        });
        ready.recv().expect("the status poller is connected");
        (start, poller)
    }
}

/// Where the device's data is in procimgd's image.
struct Io {
    /// Logical address of the device's inputs (I).
    i: u32,
    /// Logical address of its outputs (Q).
    q: u32,
}

/// Everything the test runs. Fields are dropped in order: the client and the status handle
/// before the server they are attached to, the processes before the namespaces they run in.
struct Rig {
    /// The client that owns the device's outputs (taken at shutdown).
    client: Option<Client>,
    /// The client's handle on the controller services: records, device events (taken at
    /// shutdown).
    services: Option<Services>,
    /// procimgd's control service, for its status.
    control: ControlHandle,
    server: Procimgd,
    device: Device,
    /// Devices that were killed, kept for their output in a failure report.
    gone: Vec<Device>,
    /// Every frame on the device's end of the veth pair, from before the device starts.
    capture: Option<LiveCapture>,
    net: Net,
    /// Where the capture goes.
    dir: procimg_testkit::files::TempDir,
    io: Io,
    /// The outputs written last.
    last_written: Option<[u8; iop::IO_LEN]>,
}

impl Rig {
    /// Step 1: the namespaces, the device, procimgd, and the device in data exchange; then a
    /// client that claims the device's outputs.
    fn bring_up() -> Rig {
        let net = Net::new("pc", 9);
        let dir = procimg_testkit::files::temp_dir("pnio-controller");
        // On the device's end: procimgd's interface must stay out of promiscuous mode.
        let capture = LiveCapture::start(
            net.device_ns(),
            net.device_if(),
            &dir.path().join("wire.pcapng"),
        );
        let mut device = Device::start(&net);
        let server = launch(&net, "iop");
        let instance = server.instance.clone();
        let control = server.control(Duration::from_secs(10));
        let since = Instant::now();
        server.wait_status_within("the device in data exchange", BRING_UP_TIMEOUT, |s| {
            s.devices
                .first()
                .is_some_and(|d| d.state == DeviceState::Running)
        });
        eprintln!(
            "the device is running {:?} after procimgd answered",
            since.elapsed()
        );
        device.wait_for("STATE data", Duration::from_secs(5));
        assert_eq!(
            net.controller_promiscuity(),
            0,
            "procimgd put its interface in promiscuous mode; a controller needs only the \
             frames sent to it"
        );

        let mut client = Client::attach(&instance, AttachOptions::asynchronous("interop-test"))
            .expect("attach a client to procimgd");
        let layout = client.layout();
        let inputs = layout
            .find(NAME, iop::INPUT_SLOT.0, iop::IO_SUBSLOT)
            .expect("the device's input submodule in procimgd's layout");
        let outputs = layout
            .find(NAME, iop::OUTPUT_SLOT.0, iop::IO_SUBSLOT)
            .expect("the device's output submodule in procimgd's layout");
        let io = Io {
            i: layout.submodules[inputs].input_address,
            q: layout.submodules[outputs].output_address,
        };
        assert_eq!(
            layout.submodules[inputs].input_length as usize,
            iop::IO_LEN,
            "input length"
        );
        assert_eq!(
            layout.submodules[outputs].output_length as usize,
            iop::IO_LEN,
            "output length"
        );
        client
            .claim(&[outputs])
            .expect("claim the device's outputs");
        let services = Services::open(&instance, ServiceOptions::new("interop-test"))
            .expect("open the controller services");
        Rig {
            client: Some(client),
            services: Some(services),
            control,
            server,
            device,
            gone: Vec::new(),
            capture: Some(capture),
            net,
            dir,
            io,
            last_written: None,
        }
    }

    fn client(&mut self) -> &mut Client {
        self.client.as_mut().expect("the client is attached")
    }

    fn services(&mut self) -> &mut Services {
        self.services.as_mut().expect("the services are open")
    }

    /// Waits for the device event `what` that `pick` recognises among the notifications.
    fn wait_notification(&mut self, what: &str, pick: impl Fn(&Notification) -> bool) {
        let until = Instant::now() + Duration::from_secs(5);
        let mut seen = Vec::new();
        while Instant::now() < until {
            if let Some(n) = self.services().next(Duration::from_millis(100)) {
                if pick(&n) {
                    return;
                }
                seen.push(n);
            }
        }
        panic!("no {what} notification within 5 s; seen: {seen:?}");
    }

    /// Step 2: a record read of I&M0 from a client, through procimgd's AR, returns the
    /// identity the device was started with.
    fn read_identity(&mut self) {
        let im0 = RecordTarget {
            device: 0,
            api: 0,
            slot: 0,
            subslot: 1,
            index: 0xAFF0,
        };
        let data = self
            .services()
            .read_record(im0, 4096, Duration::from_secs(5))
            .expect("read I&M0 of the device");
        let im0 = Im0::parse(&data).expect("the device's answer is an I&M0 block");
        assert_eq!(im0.vendor_id, iop::VENDOR_ID);
        assert_eq!(im0.order_id_str(), Some(iop::ORDER_ID));
        assert_eq!(im0.serial_number_str(), Some(iop::DEFAULT_SERIAL));
        assert_eq!(im0.hardware_revision, iop::HARDWARE_REVISION);
    }

    fn status(&mut self) -> StatusReport {
        self.server.assert_alive();
        self.control.status().expect("procimgd's status")
    }

    /// Waits until the client reads `want` as the device's inputs with status GOOD.
    fn wait_inputs(&mut self, want: [u8; iop::IO_LEN], timeout: Duration) {
        let until = Instant::now() + timeout;
        let i = self.io.i;
        loop {
            let mut buf = [0u8; iop::IO_LEN];
            let r = self
                .client()
                .data_read(i, &mut buf, Ioxs::Good)
                .expect("read the device's inputs");
            if buf == want && r.remote == Ioxs::Good {
                return;
            }
            assert!(
                Instant::now() < until,
                "the client reads inputs {buf:02x?} with status {:?}, not {want:02x?} GOOD, \
                 {timeout:?} after the write",
                r.remote
            );
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Writes `value` as the device's outputs and waits until the device has them and the
    /// client reads the device's answer; the time both took.
    fn round_trip(&mut self, value: [u8; iop::IO_LEN]) -> (Duration, Duration) {
        let start = Instant::now();
        let q = self.io.q;
        let remote = self
            .client()
            .data_write(q, &value, Ioxs::Good)
            .expect("write the device's outputs");
        assert_eq!(
            remote,
            Ioxs::Good,
            "the device's consumer status of the outputs"
        );
        self.last_written = Some(value);
        self.device
            .wait_for_new(&format!("OUT {}", iop::hex(&value)), ROUND_TRIP_TIMEOUT);
        let at_device = start.elapsed();
        self.wait_inputs(iop::answer(&value), ROUND_TRIP_TIMEOUT);
        (at_device, start.elapsed())
    }

    /// Step 2: 10 s of cyclic exchange at 1 ms with a new value every second; every value
    /// makes the round trip, neither side's watchdog expires, the frames come at the cycle.
    fn exchange(&mut self) {
        let first_line = self.device.skip_seen();
        // procimgd counts the frames somewhere between asking for a status and its answer:
        // `outer` brackets that, `start` is where the exchange proper begins.
        let outer = Instant::now();
        let before = self.status();
        let start = Instant::now();
        let mut worst = (Duration::ZERO, Duration::ZERO);
        for k in 0..VALUES {
            let (at_device, back) = self.round_trip(value(k));
            worst = (worst.0.max(at_device), worst.1.max(back));
            // The values are spread over the whole exchange.
            let next = start + EXCHANGE.mul_f64(f64::from(k + 1) / f64::from(VALUES));
            std::thread::sleep(next.saturating_duration_since(Instant::now()));
        }
        let exchange = start.elapsed();
        let after = self.status();
        let window = outer.elapsed();
        assert!(exchange >= EXCHANGE);
        let (b, a) = (&before.network, &after.network);
        let frames = a.cyclic_frames - b.cyclic_frames;
        eprintln!(
            "exchange: {frames} input frames in {exchange:?}, {} cycles, {} overruns; worst \
             round trip: {:?} to the device, {:?} back; network {a:?}",
            after.cycle_count - before.cycle_count,
            after.overruns - before.overruns,
            worst.0,
            worst.1
        );
        assert_eq!(a.watchdog_expiries, 0, "procimgd's watchdog expired");
        assert!(
            frames > 9_000,
            "only {frames} input frames in {exchange:?} at a cycle of {CYCLE:?}"
        );
        // The device sends one frame per cycle at most (after a delay it skips the missed
        // ones): more would be frames counted twice.
        let most = window.as_micros() / CYCLE.as_micros() + 20;
        assert!(
            u128::from(frames) <= most,
            "{frames} input frames within {window:?}: more than one per cycle"
        );
        assert_eq!(a.malformed, b.malformed, "malformed frames: {a:?}");
        assert_eq!(a.stale, b.stale, "stale frames: {a:?}");
        assert_eq!(a.send_errors, b.send_errors, "send errors: {a:?}");
        assert_eq!(a.dropped, b.dropped, "dropped frames: {a:?}");
        self.device.drain();
        let state_changes: Vec<&String> = self.device.seen[first_line..]
            .iter()
            .filter(|l| l.starts_with("STATE"))
            .collect();
        assert!(
            state_changes.is_empty(),
            "the device's AR changed state during the exchange: {state_changes:?}"
        );
        assert_eq!(after.devices[0].state, DeviceState::Running);
    }

    /// Reads the device's inputs until their status is BAD: how long after `killed` (at
    /// `killed_ns` on procimgd's clock) the cycle that published that image started, and its
    /// number.
    fn wait_inputs_bad(&mut self, killed: Instant, killed_ns: u64) -> (Duration, u64) {
        let i = self.io.i;
        loop {
            let mut buf = [0u8; iop::IO_LEN];
            let r = self
                .client()
                .data_read(i, &mut buf, Ioxs::Good)
                .expect("read the device's inputs");
            if r.remote == Ioxs::Bad {
                let image = self.client().cycle_info().expect("the client has an image");
                let after = image.cycle_start_ns.saturating_sub(killed_ns);
                return (Duration::from_nanos(after), image.cycle_number);
            }
            assert!(
                killed.elapsed() < Duration::from_secs(20),
                "the client still reads the inputs of the killed device as GOOD after 20 s"
            );
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    /// Step 3: the device dies without a word (SIGKILL). Within three watchdog times procimgd
    /// has the inputs BAD in its image and reports the device no longer running; the client
    /// reads its inputs, and its consumer status of the outputs, as BAD.
    fn lose_device(&mut self) {
        let limit = WATCHDOG * 3;
        let q = self.io.q;
        let (start_polling, poller) = StatePoller::spawn(&self.server.instance);
        // What is measured is procimgd, not how long this process takes to look: on a loaded
        // machine a normal thread can wait tens of milliseconds for the CPU.
        let realtime = Realtime::enter();
        let killed_ns = procimg_client::now_ns();
        let killed = Instant::now();
        self.device.kill();
        let _ = start_polling.send(killed);
        let (bad_after, bad_cycle) = self.wait_inputs_bad(killed, killed_ns);
        drop(realtime);
        let seen = poller
            .join()
            .unwrap_or_else(|_| panic!("the status poller failed"));
        let trace = seen.trace.join("\n");
        eprintln!(
            "device killed: procimgd's image has its inputs BAD from the cycle that started \
             {bad_after:?} after the kill (cycle {bad_cycle}); procimgd reports it {} \
             {:?} after the kill (watchdog {WATCHDOG:?}):\n{trace}",
            seen.state, seen.after
        );
        // Counted in procimgd's cycles: the planned start of the first image with the inputs
        // BAD, on the cycle schedule, not when this process got to look.
        let cycles = bad_after.as_nanos() / CYCLE.as_nanos();
        let most = limit.as_nanos() / CYCLE.as_nanos();
        assert!(
            cycles <= most,
            "procimgd's image has the inputs BAD only {cycles} cycles after the device was \
             killed (cycle {bad_cycle}); three watchdog times are {most} cycles"
        );
        // How fast the status follows the image is a figure (docs/PERFORMANCE.md): the
        // status side runs at normal priority, and the machine may be loaded.
        let mut buf = [0u8; iop::IO_LEN];
        let out = self
            .client()
            .output_data_read(q, &mut buf)
            .expect("read back the device's outputs");
        assert_eq!(
            out.remote,
            Ioxs::Bad,
            "the consumer status of the outputs of a dead device"
        );
        let s = self.status();
        assert_eq!(s.network.watchdog_expiries, 1, "{:?}", s.network);
        let exit = self.device.wait_exit(Duration::from_secs(5));
        assert_eq!(
            exit.signal(),
            Some(libc::SIGKILL),
            "the device's end: {exit}"
        );
        // The same failure reaches the client as an event (IO-Base DEV_FAILURE).
        self.wait_notification("DEV_FAILURE", |n| {
            matches!(n, Notification::DeviceFailure { device: 0, .. })
        });
    }

    /// Step 4: the device is started again. procimgd finds it and brings it up on its own,
    /// with neither procimgd nor the client restarted; the outputs last written reach it
    /// without being written again, and a new value makes the round trip.
    fn restart_device(&mut self) {
        let before = self.status();
        let generation = self.client().generation();
        let device = Device::start_labelled(&self.net, "the restarted device");
        self.gone.push(std::mem::replace(&mut self.device, device));
        let since = Instant::now();
        let s = self.server.wait_status_within(
            "the restarted device in data exchange",
            BRING_UP_TIMEOUT,
            |s| {
                s.devices
                    .first()
                    .is_some_and(|d| d.state == DeviceState::Running)
            },
        );
        eprintln!(
            "the restarted device is running after {:?}",
            since.elapsed()
        );
        assert_eq!(s.pid, self.server.pid(), "procimgd was restarted");
        assert_eq!(s.pid, before.pid, "procimgd was restarted");
        assert_eq!(s.generation, before.generation, "procimgd was restarted");
        assert_eq!(
            self.client().generation(),
            generation,
            "the client re-attached"
        );
        self.device.wait_for("STATE data", Duration::from_secs(5));

        let last = self.last_written.expect("outputs were written");
        self.device
            .wait_for_new(&format!("OUT {}", iop::hex(&last)), ROUND_TRIP_TIMEOUT);
        self.wait_inputs(iop::answer(&last), ROUND_TRIP_TIMEOUT);
        self.round_trip(value(VALUES));
        let s = self.status();
        assert_eq!(s.network.watchdog_expiries, 1, "{:?}", s.network);
        assert_eq!(s.devices[0].state, DeviceState::Running);
        self.wait_notification("DEV_RETURN", |n| {
            matches!(n, Notification::DeviceReturn { device: 0, .. })
        });
    }

    /// Step 6: the device stalls (SIGSTOP) long past the watchdog time: procimgd gives the AR
    /// up and aborts it on the wire (checked at shutdown); resumed, the device frees the AR and
    /// procimgd connects again after its short back-off.
    fn stall_device(&mut self) {
        while self.services().next(Duration::from_millis(10)).is_some() {}
        /// Resumes the stopped device when dropped, also when the test fails meanwhile.
        struct Resume(u32);
        impl Drop for Resume {
            fn drop(&mut self) {
                procimg_testkit::signal::send(self.0, libc::SIGCONT);
            }
        }
        let resume = Resume(self.device.pid());
        procimg_testkit::signal::send(self.device.pid(), libc::SIGSTOP);
        self.wait_notification("DEV_FAILURE of the stalled device", |n| {
            matches!(n, Notification::DeviceFailure { device: 0, .. })
        });
        let resumed = Instant::now();
        drop(resume);
        self.wait_notification("DEV_RETURN of the resumed device", |n| {
            matches!(n, Notification::DeviceReturn { device: 0, .. })
        });
        eprintln!(
            "the stalled device was back in data exchange {} ms after it resumed",
            resumed.elapsed().as_millis()
        );
        // The resumed device may still act on what queued up while it stood (pnio was seen
        // taking procimgd's ERR-RTA for the old AR as one for the new one, and aborting that
        // too): data must flow again, whichever AR carries it.
        let until = Instant::now() + BRING_UP_TIMEOUT;
        let q = self.io.q;
        loop {
            let running = self
                .status()
                .devices
                .first()
                .is_some_and(|d| d.state == DeviceState::Running);
            let accepted = running
                && self
                    .client()
                    .data_write(q, &value(1), Ioxs::Good)
                    .is_ok_and(|remote| remote == Ioxs::Good);
            if accepted {
                break;
            }
            assert!(
                Instant::now() < until,
                "the resumed device took no outputs within {BRING_UP_TIMEOUT:?}"
            );
            std::thread::sleep(Duration::from_millis(50));
        }
        self.round_trip(value(2));
    }

    /// Step 7: the client leaves and procimgd stops on SIGTERM: it releases the AR (the device
    /// sees the release) and exits with success, its shared memory removed. On the wire: no
    /// frame tshark flags, procimgd's ERR-RTA for the stalled device, no ICMP from procimgd.
    fn shut_down(mut self) {
        drop(self.services.take());
        drop(self.client.take());
        let status = self.server.terminate();
        assert!(status.success(), "procimgd's exit: {status}");
        self.device
            .wait_for_new("STATE aborted controller-release", Duration::from_secs(5));
        let status = self.device.terminate();
        assert!(status.success(), "the device's exit: {status}");

        let pcap = self.capture.take().expect("the capture").stop();
        let bad = tshark::flagged(&pcap);
        assert!(bad.is_empty(), "tshark flags frames on the wire:\n{bad}");
        let mac = self.net.controller_mac();
        // ERR-RTA (PDUType 4) from procimgd, ErrorCode2 5: consumer data hold time expired.
        let abort = tshark::frames_matching(
            &pcap,
            &format!("eth.src == {mac} && pn_io.pdu_type.type == 4 && pn_io.error_code2 == 0x05"),
        );
        assert!(
            !abort.trim().is_empty(),
            "no ERR-RTA \"consumer DHT expired\" from procimgd ({mac}) on the wire"
        );
        // The first bring-up, the restarted device's and the resumed device's at least.
        let attempts = connects_once_per_attempt(&pcap, self.net.controller_ip);
        assert!(
            attempts >= 3,
            "{attempts} Connect attempts on the wire, 3 expected"
        );
        let icmp = tshark::frames_matching(
            &pcap,
            &format!("icmp.type == 3 && ip.src == {}", self.net.controller_ip),
        );
        assert!(
            icmp.trim().is_empty(),
            "procimgd answered with ICMP:\n{icmp}"
        );
        let _ = &self.dir;
    }
}

/// Every Connect request procimgd sent in the capture went out once per attempt: a bring-up
/// is one RPC activity, and a Connect PDU (activity, sequence number, fragment) goes out
/// again only as a retry, after the call's retry time without an answer. A Connect sent
/// twice at once makes the device take the second as a new Connect for an AR it holds and
/// abort it. Returns the number of attempts seen.
fn connects_once_per_attempt(pcap: &std::path::Path, controller: std::net::Ipv4Addr) -> usize {
    use procimg_profinet::controller::rpc_call::RETRY_NS;
    use procimg_profinet::wire::rpc::opnum;
    let filter = format!(
        "ip.src == {controller} && dcerpc.pkt_type == 0 && dcerpc.opnum == {}",
        opnum::CONNECT
    );
    let fields = [
        "dcerpc.dg_act_id",
        "dcerpc.dg_seqnum",
        "dcerpc.dg_frag_num",
        "frame.time_relative",
    ];
    let rows = tshark::fields_matching(pcap, &filter, &fields);
    assert!(
        !rows.is_empty(),
        "no Connect request from procimgd on the wire"
    );
    // (activity, sequence number, fragment) → the capture times of its sends.
    let mut sends: std::collections::BTreeMap<(String, String, String), Vec<f64>> =
        Default::default();
    for r in &rows {
        let [act, seq, frag, t] = &r[..] else {
            panic!("tshark gave {r:?} for the fields {fields:?}");
        };
        let t: f64 = t.parse().expect("frame.time_relative is a number");
        sends
            .entry((act.clone(), seq.clone(), frag.clone()))
            .or_default()
            .push(t);
    }
    // The capture's clock is not procimgd's and the frames wait for their turn on either
    // side, so a repeat is taken as one when it came after half the retry time; copies held
    // back and released together come microseconds apart.
    let retry = RETRY_NS as f64 / 1e9;
    for (key, times) in &sends {
        for pair in times.windows(2) {
            assert!(
                pair[1] - pair[0] >= retry / 2.0,
                "procimgd sent the Connect PDU (activity, sequence number, fragment) {key:?} \
                 again {:.6} s after the first, before its retry time ({retry} s); every \
                 Connect request on the wire:\n{rows:#?}",
                pair[1] - pair[0]
            );
        }
    }
    let attempts: std::collections::BTreeSet<_> = sends.keys().map(|(a, _, _)| a).collect();
    eprintln!(
        "{} Connect attempts, {} Connect PDUs on the wire",
        attempts.len(),
        rows.len()
    );
    attempts.len()
}

#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn procimgd_brings_up_the_pnio_device_and_survives_its_loss() {
    assert!(
        procimg_testkit::netns::is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let mut rig = Rig::bring_up();
    rig.read_identity();
    rig.exchange();
    rig.lose_device();
    rig.restart_device();
    rig.stall_device();
    rig.shut_down();
}

/// The device takes its address a while after it answers DCP (as p-net does after a DCP
/// Set IP): for that while nothing answers ARP for it. A Connect that waited in procimgd's
/// kernel for the address would wait there with its repeats and reach the device together
/// with them; procimgd gives its kernel the MAC address DCP found, so each goes out when it
/// is sent. The capture holds one Connect PDU per attempt, repeats only after the retry
/// time, and the device comes up.
#[test]
#[ignore = "needs root (network namespaces): run as root with --ignored"]
fn a_connect_waiting_for_the_devices_address_reaches_it_once() {
    assert!(
        procimg_testkit::netns::is_root(),
        "this test builds network namespaces, which needs root: run it as root"
    );
    let net = Net::new("pa", 10);
    let dir = procimg_testkit::files::temp_dir("pnio-arp");
    let capture = LiveCapture::start(
        net.device_ns(),
        net.device_if(),
        &dir.path().join("wire.pcapng"),
    );
    let address = |verb: &str| {
        procimg_testkit::netns::ip(&[
            "-n",
            net.device_ns(),
            "addr",
            verb,
            &format!("{}/24", net.device_ip),
            "dev",
            net.device_if(),
        ])
    };
    address("del");
    let mut device = Device::start(&net);
    let mut server = launch(&net, "iopa");
    // Waits until procimgd answers on its control service.
    let control = server.control(Duration::from_secs(10));
    server.wait_status_within("the Connect sent", BRING_UP_TIMEOUT, |s| {
        s.devices
            .first()
            .is_some_and(|d| d.state == DeviceState::Connecting)
    });
    // Past the Connect's first retry time, within the kernel's three ARP requests (one a
    // second): an address resolved only now would release the Connect and its repeat at once.
    std::thread::sleep(Duration::from_millis(1_500));
    address("add");
    server.wait_status_within("the device in data exchange", BRING_UP_TIMEOUT, |s| {
        s.devices
            .first()
            .is_some_and(|d| d.state == DeviceState::Running)
    });
    device.wait_for("STATE data", Duration::from_secs(5));
    drop(control);
    let status = server.terminate();
    assert!(status.success(), "procimgd's exit: {status}");
    let status = device.terminate();
    assert!(status.success(), "the device's exit: {status}");
    let pcap = capture.stop();
    connects_once_per_attempt(&pcap, net.controller_ip);
}
