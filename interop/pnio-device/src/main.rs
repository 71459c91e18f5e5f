// SPDX-License-Identifier: MIT OR Apache-2.0
//! `pnio-interop-device`: a PROFINET IO device of the independent `pnio` stack, for interop
//! tests of procimgd as IO controller.
//!
//! ```text
//! pnio-interop-device --iface IF --name STATION --ip A.B.C.D [--gsdml-out PATH [--gsdml-only]]
//!                     [--print-config] [--cpu N] [--rt-priority P] [--lock-memory] [--serial S]
//! ```
//!
//! The device (see the library's documentation for its slots and idents) answers DCP
//! Identify on `IF`, accepts a Connect on UDP 34964 and exchanges 8 bytes each way. The
//! address `A.B.C.D` must already be on `IF`: the device only advertises it (mask
//! 255.255.255.0, gateway = the address itself) and never changes the interface.
//!
//! Standard output carries one line per event, flushed at once:
//!
//! - `READY`: the sockets are open; the device answers DCP and waits for a Connect.
//! - `STATE connected`, `STATE data`, `STATE aborted <reason>`: the AR changed state
//!   (reasons: `controller-release`, `controller-reconnect`, `activity-timeout`,
//!   `app-ready-timeout`, `app-ready-rejected 0x…`, `watchdog`, `controller-err-rta 0x…`,
//!   `alarm-send-failed`, `rt-socket`, `shutdown`, `external <text>`).
//! - `DATA <no-data|fresh|stopped|stale> iops=<good|bad>`: what the controller's cyclic
//!   frames say about the output submodule changed (only while an AR exchanges data).
//! - `OUT <hex>`: the controller's outputs changed and are valid (fresh, provider running,
//!   IOPS good); the first valid outputs of every AR are printed too. The inputs become each
//!   output byte plus one, wrapping (zero until the first valid outputs of an AR).
//!
//! - `DIAG raised`, `DIAG cleared`: SIGUSR1 raised (or, the next time, cleared) a channel
//!   diagnosis (line break, channel 0, a fault) on the input submodule; pnio reports it to the
//!   controller with a diagnosis alarm (held back until an AR is in data exchange).
//! - `ALARMS acked <n>`: the controller acknowledged another of the device's alarms (`n`
//!   counts all of this process's life, over every AR).
//!
//! `--print-config` prints the procimgd `[[device]]` table for this device and exits;
//! `--gsdml-out` writes the GSDML file and goes on (or exits with `--gsdml-only`). SIGTERM or
//! SIGINT end the device cleanly (the controller gets an ERR-RTA "AR removed" if an AR is up)
//! with exit status 0.

use anyhow::{Context, bail};
use clap::Parser;
use pnio::cm::{AbortReason, ArState};
use pnio::config::{DeviceConfig, Direction};
use pnio::device::{Device, DiagCommand, DiagShared, RtOptions};
use pnio::diag::{ChannelError, Diagnosis, Severity};
use pnio::eth::{AfPacketTransport, MacAddr, bpf::acyclic_filter};
use pnio::rpc::{PNIO_UDP_PORT, UdpRpcTransport};
use pnio::rt::{Freshness, IoImage};
use procimg_interop_pnio_device as iop;
use std::io::Write as _;
use std::net::{Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// Command line.
#[derive(Parser)]
#[command(
    version,
    about = "A PROFINET IO device of the pnio crate, for interop tests"
)]
struct Args {
    /// Network interface facing the controller.
    #[arg(long, required_unless_present_any = ["print_config", "gsdml_only"])]
    iface: Option<String>,
    /// NameOfStation.
    #[arg(long)]
    name: String,
    /// IPv4 address of the device, already configured on the interface.
    #[arg(long)]
    ip: Ipv4Addr,
    /// Write the device's GSDML file here.
    #[arg(long)]
    gsdml_out: Option<PathBuf>,
    /// Exit after writing the GSDML file.
    #[arg(long, requires = "gsdml_out")]
    gsdml_only: bool,
    /// Print the procimgd `[[device]]` table for this device and exit.
    #[arg(long)]
    print_config: bool,
    /// Pin the cyclic thread to this CPU (default: not pinned).
    #[arg(long)]
    cpu: Option<usize>,
    /// SCHED_FIFO priority of the cyclic thread, 1 to 99; 0 leaves it SCHED_OTHER. Without
    /// the privilege it stays SCHED_OTHER with a warning.
    #[arg(long, default_value_t = 60, value_parser = clap::value_parser!(u8).range(0..=99))]
    rt_priority: u8,
    /// Lock the process memory (mlockall) for the cyclic thread.
    #[arg(long)]
    lock_memory: bool,
    /// I&M0 serial number (ASCII, at most 16 bytes).
    #[arg(long, default_value = iop::DEFAULT_SERIAL)]
    serial: String,
}

/// Writes one line to standard output and flushes it; a closed output is ignored (the
/// device keeps running for its controller).
fn emit(line: &str) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    match run(args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("pnio-interop-device: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    let cfg = iop::declaration(&args.name, &args.serial)
        .with_context(|| format!("declaring device {:?}", args.name))?;
    if let Some(path) = &args.gsdml_out {
        std::fs::write(path, iop::gsdml(&cfg))
            .with_context(|| format!("writing the GSDML file {}", path.display()))?;
    }
    if args.print_config {
        print!("{}", iop::procimgd_device_toml(&cfg, args.ip));
        return Ok(());
    }
    if args.gsdml_only {
        return Ok(());
    }
    let Some(iface) = args.iface.clone() else {
        bail!("--iface is required to run the device");
    };
    init_logging();
    serve(&args, &iface, cfg)
}

/// Log records of pnio (AR transitions, warnings) go to standard error; `RUST_LOG` filters.
fn init_logging() {
    let filter = tracing_subscriber::EnvFilter::try_from_default_env()
        .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info"));
    let _ = tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(false)
        .try_init();
}

/// The MAC address of `iface`, from sysfs (of the network namespace sysfs was mounted for).
fn read_mac(iface: &str) -> anyhow::Result<MacAddr> {
    let path = format!("/sys/class/net/{iface}/address");
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("reading {path}: is there an interface {iface:?} here?"))?;
    let octets: Vec<u8> = text
        .trim()
        .split(':')
        .map(|p| u8::from_str_radix(p, 16))
        .collect::<Result<_, _>>()
        .with_context(|| format!("{path} holds {:?}, not a MAC address", text.trim()))?;
    let mac: [u8; 6] = octets
        .try_into()
        .map_err(|_| anyhow::anyhow!("{path} holds {:?}, not a MAC address", text.trim()))?;
    Ok(MacAddr(mac))
}

/// Runs the device until SIGTERM/SIGINT.
fn serve(args: &Args, iface: &str, cfg: DeviceConfig) -> anyhow::Result<()> {
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGTERM, signal_hook::consts::SIGINT] {
        signal_hook::flag::register(sig, stop.clone()).context("installing a signal handler")?;
    }

    let mac = read_mac(iface)?;
    let eth = AfPacketTransport::open(iface)
        .with_context(|| format!("opening a raw socket on {iface} (needs CAP_NET_RAW)"))?;
    eth.attach_filter(&acyclic_filter())
        .context("attaching the BPF filter")?;
    let rpc = UdpRpcTransport::bind(SocketAddr::from(([0, 0, 0, 0], PNIO_UDP_PORT)))
        .with_context(|| format!("binding UDP port {PNIO_UDP_PORT}"))?;
    let rt = RtOptions {
        iface: iface.to_string(),
        cpu_pin: args.cpu,
        rt_priority: (args.rt_priority > 0).then_some(args.rt_priority),
        lock_memory: args.lock_memory,
    };
    let ip = args.ip.octets();
    let mut device = Device::new(cfg.setup(mac, ip, Some(rt)), eth, rpc);
    let (events_tx, events) = mpsc::channel();
    device.on_state_change(move |state, reason| {
        let _ = events_tx.send((state, reason));
    });
    let image = device.image();
    let stats = device.rt_stats();
    let toggle = Arc::new(AtomicBool::new(false));
    signal_hook::flag::register(signal_hook::consts::SIGUSR1, toggle.clone())
        .context("installing a signal handler")?;
    let mut diagnosis = DiagnosisToggle::new(device.diag_shared());
    let acyclic = {
        let stop = stop.clone();
        std::thread::Builder::new()
            .name("pnio-acyclic".into())
            .spawn(move || device.run(&stop))
            .context("starting the acyclic thread")?
    };
    let mac_text = mac.0.map(|b| format!("{b:02x}")).join(":");
    eprintln!(
        "pnio-interop-device: {} on {iface} ({mac_text}), {}, vendor 0x{:04X} device 0x{:04X}",
        cfg.station_name(),
        args.ip,
        cfg.vendor_id(),
        cfg.device_id()
    );
    emit("READY");

    let mut app = App::default();
    while !stop.load(Ordering::Relaxed) && !acyclic.is_finished() {
        while let Ok((state, reason)) = events.try_recv() {
            app.on_state(state, reason);
        }
        app.exchange(&image);
        if toggle.swap(false, Ordering::Relaxed) {
            diagnosis.toggle();
        }
        diagnosis.count_acks();
        std::thread::sleep(Duration::from_millis(1));
    }
    stop.store(true, Ordering::Relaxed);
    let result = acyclic.join();
    while let Ok((state, reason)) = events.try_recv() {
        app.on_state(state, reason);
    }
    let s = stats.snapshot();
    // When a watchdog expired, missed ticks tell a held-up cyclic thread from a controller
    // that went quiet (the largest interval between its frames).
    eprintln!(
        "pnio-interop-device: cyclic frames sent {}, accepted {}, ignored {}, dropped {}, \
         invalid {}, watchdog expirations {}, missed ticks {}, largest tick lateness {} µs, \
         largest cycle work {} µs, largest interval between controller frames {} µs",
        s.tx,
        s.rx_accepted,
        s.rx_ignored,
        s.rx_dropped,
        s.rx_invalid,
        s.watchdog_expirations,
        s.missed_ticks,
        s.max_tick_lateness_ns / 1000,
        s.max_cycle_work_ns / 1000,
        s.max_rx_interval_ns / 1000
    );
    match result {
        Ok(Ok(())) => Ok(()),
        Ok(Err(e)) => Err(e).context("the device loop failed"),
        Err(_) => bail!("the device loop panicked"),
    }
}

/// The diagnosis SIGUSR1 raises and clears, and the alarm acknowledgements counted over the
/// process's life (pnio's counters start again with every AR).
struct DiagnosisToggle {
    shared: Arc<DiagShared>,
    raised: bool,
    acked_total: u64,
    acked_in_ar: u64,
}

impl DiagnosisToggle {
    fn new(shared: Arc<DiagShared>) -> DiagnosisToggle {
        DiagnosisToggle {
            shared,
            raised: false,
            acked_total: 0,
            acked_in_ar: 0,
        }
    }

    /// Raises the diagnosis, or clears it when it is raised.
    fn toggle(&mut self) {
        let command = if self.raised {
            DiagCommand::Clear {
                slot: iop::INPUT_SLOT,
                channel: 0,
                error: ChannelError::LineBreak,
            }
        } else {
            DiagCommand::Raise(Diagnosis {
                slot: iop::INPUT_SLOT,
                channel: 0,
                error: ChannelError::LineBreak,
                severity: Severity::Fault,
                direction: Direction::Input,
            })
        };
        self.shared
            .queue
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push_back(command);
        self.raised = !self.raised;
        emit(if self.raised {
            "DIAG raised"
        } else {
            "DIAG cleared"
        });
    }

    /// Prints the total when the controller acknowledged another alarm.
    fn count_acks(&mut self) {
        let acked = self.shared.acked.load(Ordering::Relaxed);
        // A smaller figure is a new AR's counter.
        let new = if acked < self.acked_in_ar {
            acked
        } else {
            acked - self.acked_in_ar
        };
        self.acked_in_ar = acked;
        if new > 0 {
            self.acked_total += new;
            emit(&format!("ALARMS acked {}", self.acked_total));
        }
    }
}

/// What the application side of the device remembers between polls.
#[derive(Default)]
struct App {
    /// Between a `Data` notification and the end of that AR: only then is the image the
    /// current AR's (after an abort it keeps the old layout until the cyclic thread stops).
    in_data: bool,
    /// The last valid outputs printed in this AR.
    last_out: Option<[u8; iop::IO_LEN]>,
    /// The inputs to publish: the answer to `last_out`, zero before.
    inputs: [u8; iop::IO_LEN],
    /// Whether `inputs` is in the current AR's image.
    published: bool,
    /// The last `DATA` line's content in this AR.
    last_data: Option<(Freshness, bool)>,
}

impl App {
    /// An AR state change: print it. The end of an AR forgets its outputs, so the next AR
    /// starts with zero inputs and prints its first valid outputs.
    fn on_state(&mut self, state: ArState, reason: Option<AbortReason>) {
        let line = match (state, reason) {
            (ArState::Connected, _) => "STATE connected".to_string(),
            (ArState::AppReadySent, _) => "STATE app-ready-sent".to_string(),
            (ArState::Data, _) => "STATE data".to_string(),
            (ArState::Idle, Some(r)) => format!("STATE aborted {}", reason_text(r)),
            (ArState::Idle, None) => "STATE idle".to_string(),
        };
        emit(&line);
        match state {
            ArState::Idle => *self = App::default(),
            ArState::Data => self.in_data = true,
            ArState::Connected | ArState::AppReadySent => self.in_data = false,
        }
    }

    /// One poll of the IO image: report the output validity, print changed valid outputs
    /// and publish the answer as inputs. Does nothing while no AR exchanges data.
    fn exchange(&mut self, image: &IoImage) {
        if !self.in_data {
            return;
        }
        let cells = image.cells();
        let Some(out_cell) = cells
            .iter()
            .find(|c| c.slot == iop::OUTPUT_SLOT.0 && c.subslot == iop::IO_SUBSLOT)
        else {
            return;
        };
        let Some(off) = out_cell.output_off else {
            return;
        };
        // One snapshot of the output C-SDU gives data, IOPS and validity of the same frame.
        let mut csdu = vec![0u8; off + iop::IO_LEN + 1];
        let validity = image.snapshot_outputs(&mut csdu);
        let iops_good = csdu[off + iop::IO_LEN] & 0x80 != 0;
        let freshness = validity.freshness();
        if self.last_data != Some((freshness, iops_good)) {
            self.last_data = Some((freshness, iops_good));
            emit(&format!(
                "DATA {} iops={}",
                freshness_text(freshness),
                if iops_good { "good" } else { "bad" }
            ));
        }
        if freshness == Freshness::Fresh && iops_good {
            let mut out = [0u8; iop::IO_LEN];
            out.copy_from_slice(&csdu[off..off + iop::IO_LEN]);
            if self.last_out != Some(out) {
                self.last_out = Some(out);
                emit(&format!("OUT {}", iop::hex(&out)));
                self.inputs = iop::answer(&out);
                self.published = false;
            }
        }
        if !self.published {
            // Fails only while the layout is being replaced; retried at the next poll.
            self.published = image
                .write_inputs(iop::INPUT_SLOT.0, iop::IO_SUBSLOT, &self.inputs)
                .is_ok();
        }
    }
}

/// The text of a `STATE aborted` reason.
fn reason_text(r: AbortReason) -> String {
    match r {
        AbortReason::ControllerRelease => "controller-release".into(),
        AbortReason::AppReadyFailed => "app-ready-timeout".into(),
        AbortReason::AppReadyRejected(s) => format!("app-ready-rejected 0x{:08x}", s.to_u32()),
        AbortReason::ActivityTimeout => "activity-timeout".into(),
        AbortReason::ControllerReconnect => "controller-reconnect".into(),
        AbortReason::RtWatchdog => "watchdog".into(),
        AbortReason::External(why) => format!("external {why}"),
        AbortReason::ControllerErrRta(s) => format!("controller-err-rta 0x{:08x}", s.to_u32()),
        AbortReason::AlarmSendFailed => "alarm-send-failed".into(),
        AbortReason::RtSocket => "rt-socket".into(),
        AbortReason::Shutdown => "shutdown".into(),
    }
}

/// The text of a freshness in a `DATA` line.
fn freshness_text(f: Freshness) -> &'static str {
    match f {
        Freshness::NoData => "no-data",
        Freshness::Fresh => "fresh",
        Freshness::Stopped => "stopped",
        Freshness::Stale => "stale",
    }
}
