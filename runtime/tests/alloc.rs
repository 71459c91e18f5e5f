// SPDX-License-Identifier: MIT OR Apache-2.0
//! Steady-state cycles allocate nothing: the cycle engine runs on this test's thread, with
//! procimgd's allocator installed and a demo's PROFINET IO system, while a synchronous and an
//! asynchronous client work against it; over 2000 cycles neither the cycle thread nor the
//! synchronous client's cycle loop (wait for STARTOP, write outputs, OPDONE) may call the
//! system allocator once. In the controller role the IO system is the demo's (the
//! controller on its thread, the simulated devices exchanging cyclic frames); in the device
//! role the device demo's (the station's engine on its thread, procimg's controller as the
//! PLC exchanging cyclic frames with the cycle).

use procimg_client::{AttachOptions, Client, Ioxs};
use procimg_runtime::config::Config;
use procimg_runtime::cycle::{Engine, EngineSettings, Shared};
use procimg_runtime::image::Tables;
use procimg_runtime::roles::RoleSystem;
use procimg_runtime::roles::controller::ControllerServices;
use procimg_runtime::roles::{controller, device};
use procimg_runtime::server::{Control, ServerInfo};
use procimg_runtime::shm::{ControlPorts, CyclePorts};
use procimg_runtime::stats::stats_channel;
use procimg_runtime::sys::clock::{now_ns, sleep_until_ns};
use procimg_runtime::sys::rt_alloc::{
    RtAllocator, clear_current_thread_realtime, mark_current_thread_realtime, pool_allocations,
    rt_heap_allocations, rt_setup_allocations,
};
use procimg_shm_layout::Mode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

#[global_allocator]
static ALLOCATOR: RtAllocator = RtAllocator;

/// Where the clients work: the synchronous one writes all of a submodule each cycle, the
/// asynchronous one writes 2 bytes at an address and reads 4 at another.
#[derive(Clone, Copy)]
struct Work {
    /// (station, slot, subslot) of the synchronous client's submodule.
    sync: (&'static str, u16, u16),
    /// (station, slot, subslot) of the asynchronous client's submodule.
    async_sub: (&'static str, u16, u16),
    /// The asynchronous client's write address and read address.
    addresses: (u32, u32),
    /// Cyclic frames the IO system takes in per cycle at least.
    frames_per_cycle: u64,
}

#[test]
fn steady_state_cycles_allocate_nothing() {
    let work = Work {
        sync: ("echo", 1, 1),
        async_sub: ("dio", 2, 1),
        addresses: (16, 16),
        frames_per_cycle: 3,
    };
    steady_state(Config::demo(), work, |config, shared| {
        controller::start(config, shared).unwrap()
    });
}

#[test]
fn steady_state_cycles_of_the_device_role_allocate_nothing() {
    let work = Work {
        sync: ("procimg-device", 1, 1),
        async_sub: ("procimg-device", 2, 1),
        // I 8..9 (slot 2's I data, which the client provides), Q 0..3 (slot 1's, the PLC's).
        addresses: (8, 0),
        frames_per_cycle: 1,
    };
    steady_state(Config::demo_device(), work, |config, shared| {
        device::start(config, shared, None).unwrap()
    });
}

/// One measurement at a time: the allocation counters are the process's.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn steady_state(
    mut config: Config,
    work: Work,
    start: impl FnOnce(&Config, Arc<Shared>) -> RoleSystem,
) {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    config.instance = procimg_testkit::unique_instance("alloc");
    let instance = config.instance.clone();
    let tables = Tables::from_config(&config).unwrap();
    let generation = now_ns();
    let shared = Arc::new(Shared::new(tables.submodules.len()));
    shared
        .target_mode
        .store(Mode::Operate.as_u32(), Ordering::Release);
    let (recorder, collector) = stats_channel();
    let stop = Arc::new(AtomicBool::new(false));

    // The control side on its own thread (iceoryx2 ports stay on the thread that made them).
    let control = {
        let (tables, shared, stop, instance) = (
            tables.clone(),
            shared.clone(),
            stop.clone(),
            instance.clone(),
        );
        let (ready_tx, ready_rx) = std::sync::mpsc::channel();
        let handle = std::thread::spawn(move || {
            let ports =
                ControlPorts::create(&instance, generation, &tables, 1_000_000, 500_000).unwrap();
            let info = ServerInfo {
                instance,
                generation,
                cycle_ns: 1_000_000,
                opdone_deadline_ns: 500_000,
            };
            let services = Box::new(ControllerServices::unlinked(&tables));
            let mut control = Control::new(info, tables, ports, shared, collector, services);
            ready_tx.send(()).unwrap();
            while !stop.load(Ordering::Acquire) {
                control.poll();
                std::thread::sleep(Duration::from_millis(1));
            }
        });
        ready_rx.recv().unwrap();
        handle
    };

    let ports = CyclePorts::create(&instance, generation, &tables).unwrap();
    let settings = EngineSettings {
        cycle_ns: 1_000_000,
        opdone_deadline_ns: 500_000,
        late_policy: config.late_policy,
        output_timing: config.output_timing,
        opdone_wait: config.cycle_thread.opdone_wait,
        opdone_spin_ns: config.cycle_thread.opdone_spin_ns,
        generation,
    };
    let mut pnio = start(&config, shared.clone());
    let io = (pnio.io.take().unwrap())();
    let mut engine = Engine::new(settings, &tables, ports, io, shared.clone(), recorder);

    // A synchronous writer and an asynchronous reader/writer.
    let clients: Vec<_> = [true, false]
        .into_iter()
        .map(|synchronous| {
            let (instance, stop) = (instance.clone(), stop.clone());
            let (write_at, read_at) = work.addresses;
            std::thread::spawn(move || {
                let opts = if synchronous {
                    AttachOptions::synchronous("alloc-sync")
                } else {
                    AttachOptions::asynchronous("alloc-async")
                };
                let mut c = Client::attach(&instance, opts).unwrap();
                let (name, slot, subslot) = if synchronous {
                    work.sync
                } else {
                    work.async_sub
                };
                let sub = c.layout().find(name, slot, subslot).unwrap();
                c.claim(&[sub]).unwrap();
                if synchronous {
                    // The synchronous client's cycle loop counts with the server's: its
                    // heap allocations in the measured cycles must be 0 too.
                    mark_current_thread_realtime();
                }
                let mut buf = [0u8; 4];
                let mut n = 0u8;
                while !stop.load(Ordering::Acquire) {
                    match c.wait_startop(Duration::from_millis(50)) {
                        Ok(mut cycle) if synchronous => {
                            // Both ways of writing outputs in place, in turn.
                            let k = cycle.number();
                            if k % 2 == 0 {
                                cycle.output_mut(sub).unwrap().fill(k as u8);
                            } else {
                                let at = cycle.layout().submodules[sub].output_offset as usize;
                                cycle.outputs_mut().unwrap()[at] = k as u8;
                            }
                            cycle.set_opdone().unwrap();
                        }
                        Ok(cycle) => {
                            drop(cycle);
                            n = n.wrapping_add(1);
                            let _ = c.data_write(write_at, &[n, !n], Ioxs::Good);
                            let _ = c.data_read(read_at, &mut buf, Ioxs::Good);
                        }
                        Err(_) => {}
                    }
                }
            })
        })
        .collect();

    let cycle_ns = 1_000_000;
    let epoch = now_ns();
    let run = |engine: &mut Engine, from: u64, to: u64| {
        for k in from..to {
            let t0 = epoch + k * cycle_ns;
            sleep_until_ns(t0 - 100_000);
            engine.maintain_connections();
            sleep_until_ns(t0);
            engine.run_cycle(k, t0);
        }
    };
    // The loop runs as procimgd's cycle thread does, SCHED_FIFO (where permitted): beside
    // other tests' servers and their real-time threads, a normal thread can stall for over
    // 100 ms, and a client that sees no image for that long checks whether the server is
    // alive, which allocates (not a steady-state cycle any more).
    if let Err(w) = procimg_runtime::sys::rt::set_fifo_named("the test's cycle loop", 80) {
        eprintln!("{w}");
    }
    // Warm-up: clients attach, connect and claim; the mode steps to OPERATE.
    run(&mut engine, 1, 1000);
    assert_eq!(engine.mode(), Mode::Operate);
    let handshakes_before = shared.counters.cycles.load(Ordering::Relaxed);

    let services = pnio.services.take().unwrap();
    let frames = || services.network().cyclic_frames;
    let frames_before = frames();

    mark_current_thread_realtime();
    let (heap_before, pool_before) = (rt_heap_allocations(), pool_allocations());
    let setup_before = rt_setup_allocations();
    run(&mut engine, 1000, 3000);
    let (heap_after, pool_after) = (rt_heap_allocations(), pool_allocations());
    let setup_after = rt_setup_allocations();
    let frames_after = frames();
    // Negative control: the counter does see an allocation on this thread.
    let probe = std::hint::black_box(vec![0u8; 4096]);
    let heap_probe = rt_heap_allocations();
    clear_current_thread_realtime();
    drop(probe);

    stop.store(true, Ordering::Release);
    for c in clients {
        c.join().unwrap();
    }
    control.join().unwrap();
    shared.stop.store(true, Ordering::Release);
    drop(engine);
    pnio.join();

    assert!(handshakes_before > 0);
    // A frame per device (or the PLC) per cycle: the cycle really exchanged PROFINET frames.
    assert!(
        frames_after - frames_before > work.frames_per_cycle * 1500,
        "only {} cyclic frames in 2000 cycles",
        frames_after - frames_before
    );
    assert_eq!(
        heap_after - heap_before,
        0,
        "the cycle thread and the synchronous client's cycle loop called the system allocator \
         {} times in 2000 steady-state cycles",
        heap_after - heap_before
    );
    // iceoryx2's port calls allocate only while clients connect: not here.
    assert_eq!(
        setup_after - setup_before,
        0,
        "iceoryx2's calls on the cycle thread allocated {} times in 2000 steady-state cycles",
        setup_after - setup_before
    );
    assert!(
        pool_after - pool_before >= 2000,
        "iceoryx2's per-loan allocation should have come from the pool ({} times)",
        pool_after - pool_before
    );
    assert_eq!(
        heap_probe - heap_after,
        1,
        "the allocation counter does not count"
    );
}
