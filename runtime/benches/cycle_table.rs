// SPDX-License-Identifier: MIT OR Apache-2.0
//! Prints one table of the cycle's server-side work, case by case: the median ns per
//! cycle, the bytes the server copies per cycle and ns per KiB copied; then the linear fits
//! of the cost against image bytes, submodules, clients and devices.
//!
//! `cargo bench -p procimg-runtime --bench cycle_table` (about 20 s after the build; `-- --quick`
//! runs fewer cycles per case, `-- --test` only proves every case runs).
//!
//! Each case is timed cycle by cycle with CLOCK_MONOTONIC over a fixed number of cycles after
//! a warm-up; the median is robust against the preemptions of a busy machine.

mod support;

use procimg_runtime::sys::clock::now_ns;
use support::cases::{self, Copied};
use support::leftovers;
use support::rig::{Io, PnioRig, PublishRig, Rig};
use support::shape::Shape;

const BENCH: &str = "t";

/// Cycles per case (warm-up, measured).
#[derive(Clone, Copy)]
struct Runs {
    warm: usize,
    measured: usize,
}

/// The median of `n` timings of `f`.
fn median(runs: Runs, mut f: impl FnMut() -> u64) -> f64 {
    for _ in 0..runs.warm {
        f();
    }
    let mut ns: Vec<u64> = (0..runs.measured).map(|_| f()).collect();
    ns.sort_unstable();
    ns[ns.len() / 2] as f64
}

fn timed(mut f: impl FnMut()) -> impl FnMut() -> u64 {
    move || {
        let t0 = now_ns();
        f();
        now_ns() - t0
    }
}

/// One row of the table.
struct Row {
    part: &'static str,
    case: String,
    ns: f64,
    bytes: usize,
}

impl Row {
    fn print(&self) {
        let per_kib = if self.bytes > 0 {
            format!("{:10.1}", self.ns / (self.bytes as f64 / 1024.0))
        } else {
            format!("{:>10}", "-")
        };
        println!(
            "{:<18} {:<22} {:>12.0} {:>12} {}",
            self.part, self.case, self.ns, self.bytes, per_kib
        );
    }
}

/// Least squares of y = a + b·x: (b, a).
fn fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x, sy + y));
    let (mx, my) = (sx / n, sy / n);
    let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(sxy, sxx), (x, y)| {
        (sxy + (x - mx) * (y - my), sxx + (x - mx) * (x - mx))
    });
    let b = sxy / sxx;
    (b, my - b * mx)
}

fn cycle_median(runs: Runs, shape: Shape, io: Io, clients: usize) -> f64 {
    let mut rig = Rig::new(&leftovers::instance(BENCH), shape, io, clients);
    let ns = median(runs, || {
        rig.prepare();
        rig.cycle()
    });
    rig.verify();
    ns
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let has = |a: &str| args.iter().any(|x| x == a);
    // `cargo bench` passes --bench; `cargo test --benches` passes nothing: only prove then
    // that every case runs, as criterion does.
    let runs = if has("--test") || !has("--bench") {
        Runs {
            warm: 1,
            measured: 3,
        }
    } else if has("--quick") {
        Runs {
            warm: 50,
            measured: 300,
        }
    } else {
        Runs {
            warm: 200,
            measured: 2000,
        }
    };
    let mut rows = Vec::new();
    let mut fits = Vec::new();

    // Input publication alone.
    let mut points = Vec::new();
    for shape in cases::SIZES {
        let mut rig = PublishRig::new(&leftovers::instance(BENCH), shape);
        let ns = median(runs, timed(|| assert!(rig.publish())));
        points.push((rig.bytes() as f64, ns));
        rows.push(Row {
            part: "publish",
            case: cases::label(shape),
            ns,
            bytes: rig.bytes(),
        });
    }
    fits.push(("publish vs payload bytes", "KiB", fit(&points)));

    // The whole cycle, with the null and the PROFINET IO system.
    let mut merge_points = Vec::new();
    for (part, io, clients) in [
        ("cycle null 0 cl.", Io::Null, 0),
        ("cycle null 1 cl.", Io::Null, 1),
        ("cycle pnio 1 cl.", Io::Pnio, 1),
        ("cycle device 1 cl.", Io::PnioDevice, 1),
    ] {
        let mut points = Vec::new();
        for shape in cases::SIZES {
            if io != Io::Null && !shape.fits_profinet() {
                continue;
            }
            // The device role has one AR: one device.
            if io == Io::PnioDevice && shape.devices != 1 {
                continue;
            }
            let ns = cycle_median(runs, shape, io, clients);
            points.push((shape.bytes as f64, ns));
            if clients == 1 && io == Io::Null {
                merge_points.push((shape, ns));
            }
            rows.push(Row {
                part,
                case: cases::label(shape),
                ns,
                bytes: Copied::cycle(shape, io, clients).total(),
            });
        }
        // Two sizes only for the device role (one AR): no fit.
        if io != Io::PnioDevice {
            fits.push((part, "KiB of image (inputs)", fit(&points)));
        }
    }
    // The merge's share: the same engine with and without the client.
    for (shape, with) in merge_points {
        let without = rows
            .iter()
            .find(|r| r.part == "cycle null 0 cl." && r.case == cases::label(shape))
            .map_or(0.0, |r| r.ns);
        rows.push(Row {
            part: "merge (1cl − 0cl)",
            case: cases::label(shape),
            ns: with - without,
            bytes: Copied::cycle(shape, Io::Null, 1).merge,
        });
    }

    // Submodules: the engine with one client owning all, and without.
    let mut with_points = Vec::new();
    let mut without_points = Vec::new();
    for shape in cases::SUBMODULES {
        let with = cycle_median(runs, shape, Io::Null, 1);
        let without = cycle_median(runs, shape, Io::Null, 0);
        with_points.push((shape.submodules as f64, with));
        without_points.push((shape.submodules as f64, without));
        for (part, ns, clients) in [
            ("subm. null 0 cl.", without, 0),
            ("subm. null 1 cl.", with, 1),
        ] {
            rows.push(Row {
                part,
                case: cases::label(shape),
                ns,
                bytes: Copied::cycle(shape, Io::Null, clients).total(),
            });
        }
    }
    fits.push(("engine, 0 clients", "submodule", fit(&without_points)));
    fits.push(("engine, 1 client", "submodule", fit(&with_points)));

    // Clients sharing the submodules.
    let mut points = Vec::new();
    let shape = cases::CLIENT_SHAPE;
    for clients in cases::CLIENTS {
        let ns = cycle_median(runs, shape, Io::Null, clients);
        points.push((clients as f64, ns));
        rows.push(Row {
            part: "clients null",
            case: format!("{clients} cl. {}", cases::label(shape)),
            ns,
            bytes: Copied::cycle(shape, Io::Null, clients).total(),
        });
    }
    fits.push(("engine, 4096 subm.", "client", fit(&points)));

    // The PROFINET IO system alone.
    for (name, shapes, x) in [
        ("devices", &cases::DEVICES[..], "device"),
        ("frames", &cases::FRAMES[..], "KiB of image (inputs)"),
    ] {
        let (mut rx_points, mut tx_points) = (Vec::new(), Vec::new());
        for &shape in shapes {
            let mut rig = PnioRig::new(shape);
            let rx = median(runs, timed(|| rig.receive()));
            let tx = median(runs, timed(|| rig.send()));
            rig.verify();
            let at = if name == "devices" {
                shape.devices as f64
            } else {
                shape.bytes as f64
            };
            rx_points.push((at, rx));
            tx_points.push((at, tx));
            let input = cases::tables(shape).layout.input_size as usize;
            rows.push(Row {
                part: "pnio receive",
                case: cases::label(shape),
                ns: rx,
                bytes: input,
            });
            rows.push(Row {
                part: "pnio send",
                case: cases::label(shape),
                ns: tx,
                bytes: Copied::frames(shape),
            });
        }
        fits.push(("pnio receive", x, fit(&rx_points)));
        fits.push(("pnio send", x, fit(&tx_points)));
    }

    println!(
        "{:<18} {:<22} {:>12} {:>12} {:>10}",
        "part", "case (bytes/dev/subm)", "ns/cycle", "B copied", "ns/KiB"
    );
    for r in &rows {
        r.print();
    }
    println!();
    println!("linear fits: ns = fixed + slope × x");
    for (what, x, (slope, fixed)) in fits {
        let slope = if x.starts_with("KiB") {
            slope * 1024.0
        } else {
            slope
        };
        println!("{what:<26} {slope:10.1} ns per {x:<22} fixed {fixed:10.0} ns");
    }
    leftovers::assert_none(BENCH);
}
