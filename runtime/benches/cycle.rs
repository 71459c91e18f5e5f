// SPDX-License-Identifier: MIT OR Apache-2.0
//! Criterion benchmarks of one cycle's server-side work as the IO system grows: the input
//! publication, the output merge (through the real engine, against the number of
//! submodules and of clients), the PROFINET frame receive and send (against the number of
//! devices and the frame size), and the whole cycle with the null and the PROFINET IO
//! system. Throughput is the bytes the server copies in the part measured (see
//! `support::cases::Copied`); `cycle_table` prints the same cases as one table.
//!
//! `cargo bench -p procimg-runtime --bench cycle` (add `-- --quick` for a short run).

mod support;

use criterion::{BenchmarkId, Criterion, Throughput};
use std::time::Duration;
use support::cases::{self, Copied};
use support::leftovers;
use support::rig::{Io, PnioRig, PublishRig, Rig};

const BENCH: &str = "c";

fn publish(c: &mut Criterion) {
    let mut g = c.benchmark_group("publish");
    for shape in cases::SIZES {
        let mut rig = PublishRig::new(&leftovers::instance(BENCH), shape);
        g.throughput(Throughput::Bytes(rig.bytes() as u64));
        g.bench_function(BenchmarkId::from_parameter(cases::label(shape)), |b| {
            b.iter(|| assert!(rig.publish()))
        });
    }
}

/// The whole cycle, engine alone and with PROFINET, with and without a client writing.
fn cycle(c: &mut Criterion) {
    for (name, io, clients) in [
        ("cycle_null_0c", Io::Null, 0),
        ("cycle_null_1c", Io::Null, 1),
        ("cycle_pnio_1c", Io::Pnio, 1),
    ] {
        let mut g = c.benchmark_group(name);
        for shape in cases::SIZES {
            if io == Io::Pnio && !shape.fits_profinet() {
                continue;
            }
            let copied = Copied::cycle(shape, io, clients);
            g.throughput(Throughput::Bytes(copied.total() as u64));
            let mut rig = Rig::new(&leftovers::instance(BENCH), shape, io, clients);
            g.bench_function(BenchmarkId::from_parameter(cases::label(shape)), |b| {
                b.iter_custom(|iters| rig.timed_cycles(iters))
            });
            rig.verify();
        }
    }
}

/// The merge against submodules (one client owning all) and against clients (sharing
/// 4096 submodules); the engine with the null IO system.
fn merge(c: &mut Criterion) {
    let mut g = c.benchmark_group("merge_submodules");
    for shape in cases::SUBMODULES {
        let copied = Copied::cycle(shape, Io::Null, 1);
        g.throughput(Throughput::Bytes(copied.total() as u64));
        let mut rig = Rig::new(&leftovers::instance(BENCH), shape, Io::Null, 1);
        g.bench_function(BenchmarkId::from_parameter(cases::label(shape)), |b| {
            b.iter_custom(|iters| rig.timed_cycles(iters))
        });
        rig.verify();
    }
    drop(g);
    let mut g = c.benchmark_group("merge_clients");
    let shape = cases::CLIENT_SHAPE;
    for clients in cases::CLIENTS {
        let copied = Copied::cycle(shape, Io::Null, clients);
        g.throughput(Throughput::Bytes(copied.total() as u64));
        let mut rig = Rig::new(&leftovers::instance(BENCH), shape, Io::Null, clients);
        g.bench_function(BenchmarkId::from_parameter(clients), |b| {
            b.iter_custom(|iters| rig.timed_cycles(iters))
        });
        rig.verify();
    }
}

/// The PROFINET IO system alone: receive (frames → image) and send (image → frames).
fn pnio(c: &mut Criterion) {
    for (name, shapes) in [
        ("pnio_devices", &cases::DEVICES[..]),
        ("pnio_frames", &cases::FRAMES[..]),
    ] {
        let mut g = c.benchmark_group(name);
        for &shape in shapes {
            let mut rig = PnioRig::new(shape);
            let input = cases::tables(shape).layout.input_size as u64;
            g.throughput(Throughput::Bytes(input));
            let id = format!("receive/{}", cases::label(shape));
            g.bench_function(id, |b| b.iter(|| rig.receive()));
            g.throughput(Throughput::Bytes(Copied::frames(shape) as u64));
            let id = format!("send/{}", cases::label(shape));
            g.bench_function(id, |b| b.iter(|| rig.send()));
            rig.verify();
        }
    }
}

fn main() {
    // Short by default: the figures are per cycle (µs at most) and the whole run should
    // take a few minutes; criterion's command line (--quick, --measurement-time) still
    // applies on top.
    let mut c = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .configure_from_args();
    publish(&mut c);
    cycle(&mut c);
    merge(&mut c);
    pnio(&mut c);
    c.final_summary();
    leftovers::assert_none(BENCH);
}
