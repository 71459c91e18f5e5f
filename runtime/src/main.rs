// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimgd`: the process-image server.
//!
//! Loads a configuration (or the built-in demo), starts the real-time cycle thread, serves
//! clients over iceoryx2 shared memory, and on SIGINT/SIGTERM puts the outputs in a safe
//! state (CLEAR) before removing its shared memory.

use anyhow::{Context, bail};
use clap::error::ErrorKind;
use clap::{CommandFactory, Parser};
use procimg_control::doorbell::{Doorbell, doorbell_path};
use procimg_runtime::config::{self, Config};
use procimg_runtime::cycle::{self, Command, EngineSettings, Shared};
use procimg_runtime::image::Tables;
use procimg_runtime::roles;
use procimg_runtime::roles::device::program::{Next, StationProgram};
use procimg_runtime::server::restart::{ConfigSource, Restart};
use procimg_runtime::server::{Control, ServerInfo};
use procimg_runtime::shm::access::GroupAccess;
use procimg_runtime::shm::{ControlPorts, cleanup_dead_nodes};
use procimg_runtime::stats::stats_channel;
use procimg_runtime::sys::rt::lock_memory;
use procimg_runtime::sys::rt_alloc::RtAllocator;
use procimg_shm_layout::Mode;
use std::io::{IsTerminal, Write as _};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tracing::{debug, info, warn};

/// The control thread's round when nothing rings its doorbell: it reaps dead clients, gathers
/// the cycle's statistics and checks alarm deadlines; a request or a role event wakes it at
/// once.
const CONTROL_POLL: Duration = Duration::from_millis(2);

#[global_allocator]
static ALLOCATOR: RtAllocator = RtAllocator;

mod demo_view;

/// The procimg process-image server.
#[derive(Parser, Debug)]
#[command(name = "procimgd", version, about, long_about = None)]
struct Args {
    /// Configuration file (TOML); see `--print-demo-config` for a commented example. `-`
    /// reads it from standard input, up to its end or to a NUL byte (relative `gsdml` paths
    /// then start at the current directory).
    #[arg(short, long, value_name = "FILE")]
    config: Option<PathBuf>,
    /// Run the built-in demo: simulated devices on an in-process network, no root needed.
    #[arg(long, conflicts_with = "config")]
    demo: bool,
    /// Run the built-in demo of the IO device role: procimgd is a PROFINET device, and
    /// procimg's own IO controller plays the PLC on an in-process network; no root needed.
    #[arg(long, conflicts_with_all = ["config", "demo"])]
    demo_device: bool,
    /// Run the built-in demo of the IO device role with a station its program defines: the
    /// station waits off the wire, with its device access point only, until a device
    /// program (the IO-Base DevEasy example, device_app) plugs its modules, which the demo
    /// station's own GSDML file describes; no root needed.
    #[arg(long, conflicts_with_all = ["config", "demo", "demo_device"])]
    demo_device_program: bool,
    /// Print the built-in demo configuration (a commented example file) and exit.
    #[arg(long)]
    print_demo_config: bool,
    /// Print the commented example configuration of the IO device role (`role = "device"`)
    /// and exit.
    #[arg(long)]
    print_demo_device_config: bool,
    /// Check the configuration for this machine (its network interface must exist), print the
    /// resulting image layout and exit.
    #[arg(long)]
    check: bool,
    /// Use this instance name instead of the configuration's.
    #[arg(long, value_name = "NAME")]
    instance: Option<String>,
    /// The network interface a program chose for this procimgd (IO-Base's SERV_CP_startup
    /// picks its adapter by MAC address or PCI location): it replaces the configuration's
    /// `network` interface, which then need not exist on this machine. A configuration that
    /// simulates its network (`network = "sim"`) keeps its simulation, so a program can be
    /// tried against a simulated plant.
    #[arg(long, value_name = "INTERFACE")]
    adapter: Option<String>,
    /// Stop, as on SIGTERM, when standard input reaches its end: the program that started
    /// procimgd as its stack (IO-Base's SERV_CP_startup) holds the other end of the pipe, so
    /// procimgd stops when that program ends, however it ends.
    #[arg(long)]
    exit_with_stdin: bool,
    /// Do not print the live one-line view of the demo.
    #[arg(long)]
    quiet: bool,
}

/// What `procimgd` alone is told: how to start.
const NO_CONFIGURATION: &str = "no configuration: give one with -c FILE, or run `procimgd --demo` \
     for the built-in demo (no root, no hardware); `procimgd --print-demo-config` prints a \
     template";

fn main() {
    procimg_runtime::sys::populate::fault_code_page_by_page();
    let args = Args::parse();
    if args.config.is_none()
        && !args.demo
        && !args.demo_device
        && !args.demo_device_program
        && !args.print_demo_config
        && !args.print_demo_device_config
    {
        Args::command()
            .error(ErrorKind::MissingRequiredArgument, NO_CONFIGURATION)
            .exit();
    }
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(colour_on_stderr())
        // A log line that cannot be written is lost, not a reason to stop: procimgd goes on
        // (and stops cleanly) when whoever read its standard error has gone, as a program
        // that started it as its stack may have (the fallback would panic on that stderr).
        .log_internal_errors(false)
        .init();
    if let Err(e) = run(args) {
        // Said plainly, as a command line tool says why it stops; the log lines before it
        // have told what happened until then.
        let _ = writeln!(std::io::stderr(), "procimgd: {e:#}");
        std::process::exit(exit_status(&e));
    }
}

/// Whether log lines get colours: only on a terminal, and not when `NO_COLOR` is set to
/// anything but the empty string (<https://no-color.org>).
fn colour_on_stderr() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
}

/// sysexits.h's EX_CONFIG: the configuration cannot be used. A program that starts procimgd
/// (SERV_CP_startup) tells a bad configuration from a failed start by it.
const EXIT_CONFIGURATION: i32 = 78;

/// The exit status for the error that ended `run`.
fn exit_status(e: &anyhow::Error) -> i32 {
    let configuration = e
        .chain()
        .any(|c| c.is::<config::ConfigError>() || c.is::<procimg_shm_layout::LayoutError>());
    if configuration { EXIT_CONFIGURATION } else { 1 }
}

/// The configuration `-c` names: a file, or with `-` the text on standard input up to its
/// end or a NUL byte (the rest of standard input is left for `--exit-with-stdin`). With an
/// `--adapter` the configuration's `network` interface need not exist here: the adapter
/// replaces it.
fn load_configuration(path: &std::path::Path, adapter: bool) -> anyhow::Result<Config> {
    let any_interface = |_: &str| Ok(());
    let interface: config::InterfaceCheck<'_> = if adapter {
        &any_interface
    } else {
        &procimg_nic::interfaces::check
    };
    if path != std::path::Path::new("-") {
        return Ok(config::load(path, interface)?);
    }
    let mut text = Vec::new();
    std::io::BufRead::read_until(&mut std::io::stdin().lock(), 0, &mut text)
        .context("cannot read the configuration from standard input")?;
    if text.last() == Some(&0) {
        text.pop();
    }
    let text =
        String::from_utf8(text).context("the configuration on standard input is not UTF-8 text")?;
    let dir = std::env::current_dir().unwrap_or_default();
    Ok(config::parse_for_machine(
        &text,
        "standard input",
        &dir,
        interface,
    )?)
}

/// With `--exit-with-stdin`: sets `term` when standard input ends, as SIGTERM would.
fn stop_with_stdin(term: Arc<AtomicBool>) {
    let watch = move || {
        let mut sink = [0u8; 256];
        let mut stdin = std::io::stdin().lock();
        // Whatever the starting program writes is read and dropped; only its end counts.
        while matches!(std::io::Read::read(&mut stdin, &mut sink), Ok(n) if n > 0) {}
        info!("standard input closed: the program that started procimgd has ended; stopping");
        term.store(true, Ordering::Release);
    };
    if let Err(e) = std::thread::Builder::new()
        .name("stdin-watch".into())
        .spawn(watch)
    {
        warn!("cannot watch standard input ({e}); procimgd stops by signal only");
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    if args.print_demo_config {
        print!("{}", config::DEMO_TOML);
        return Ok(());
    }
    if args.print_demo_device_config {
        print!("{}", config::DEMO_DEVICE_TOML);
        return Ok(());
    }
    let mut config = match &args.config {
        Some(path) => load_configuration(path, args.adapter.is_some())?,
        None if args.demo_device => Config::demo_device(),
        None if args.demo_device_program => Config::demo_device_program(),
        None => Config::demo(),
    };
    if let Some(name) = args.instance {
        config.instance = name;
    }
    if let Some(interface) = args.adapter.clone() {
        procimg_nic::interfaces::check(&interface)
            .map_err(|e| anyhow::anyhow!("--adapter {interface}: {e}"))?;
        if config.network == config::Network::Sim {
            info!("adapter {interface} chosen; the configuration's network is simulated (sim)");
        } else {
            config.network = config::Network::Interface(interface);
        }
    }
    let tables = Tables::from_config(&config).with_context(|| {
        format!(
            "{}: the IO system does not fit in a process image",
            config.origin
        )
    })?;
    if args.check {
        print_layout(&config, &tables);
        return Ok(());
    }
    let source = ConfigSource {
        path: args
            .config
            .clone()
            .filter(|p| p != std::path::Path::new("-")),
        instance: config.instance.clone(),
        adapter: args.adapter.clone(),
        network: config.network.clone(),
    };
    serve(
        config,
        tables,
        source,
        args.demo && !args.quiet,
        args.exit_with_stdin,
    )
}

fn print_layout(config: &Config, tables: &Tables) {
    if let Some(station) = &config.station {
        print_station(config, station);
        return;
    }
    println!(
        "{}: instance \"{}\", cycle {} ns, OPDONE deadline {} ns, {} devices, {} submodules",
        config.origin,
        config.instance,
        config.cycle_ns,
        config.opdone_deadline_ns,
        tables.devices.len(),
        tables.submodules.len()
    );
    println!(
        "image: {} input bytes, {} output bytes, layout hash {:016x}",
        tables.layout.input_size, tables.layout.output_size, tables.hash
    );
    println!(
        "{:<4} {:<24} {:>5} {:>7} {:>12} {:>12}",
        "#", "device", "slot", "subslot", "I addr", "Q addr"
    );
    for (i, s) in tables.submodules.iter().enumerate() {
        println!(
            "{:<4} {:<24} {:>5} {:>7} {:>12} {:>12}",
            i,
            tables.device_name(s.device as usize),
            s.slot,
            s.subslot,
            s.address_text(false),
            s.address_text(true)
        );
    }
}

/// The device role's `--check`: the station and its submodules with their logical addresses
/// (I: what the device provides, Q: what the PLC writes).
fn print_station(config: &Config, station: &config::StationConfig) {
    println!(
        "{}: instance \"{}\", role device, station \"{}\" (vendor 0x{:04X}, device 0x{:04X}), \
         cycle {} ns, {} submodules",
        config.origin,
        config.instance,
        station.name,
        station.vendor_id,
        station.device_id,
        config.cycle_ns,
        station.submodules.len()
    );
    println!(
        "{:>5} {:>7} {:>10} {:>10} {:>5} {:>5} {:>12} {:>12}",
        "slot", "subslot", "module", "submodule", "I len", "Q len", "I addr", "Q addr"
    );
    let address = |a: u32| {
        if a == procimg_shm_layout::NO_ADDRESS {
            "-".to_owned()
        } else {
            a.to_string()
        }
    };
    for s in station.submodule_configs() {
        println!(
            "{:>5} {:>#7x} {:>#10x} {:>#10x} {:>5} {:>5} {:>12} {:>12}",
            s.slot,
            s.subslot,
            s.module_ident,
            s.submodule_ident,
            s.input_length,
            s.output_length,
            address(s.input_address),
            address(s.output_address)
        );
    }
}

fn generation() -> u64 {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos() as u64)
        .unwrap_or(0);
    now ^ ((std::process::id() as u64) << 40)
}

fn serve(
    mut config: Config,
    mut tables: Tables,
    source: ConfigSource,
    live_view: bool,
    exit_with_stdin: bool,
) -> anyhow::Result<()> {
    let instance = config.instance.clone();
    // Before the first file: iceoryx2's directory becomes the access group's.
    let mut group_access =
        GroupAccess::set_up(&config.access).with_context(|| config.origin.clone())?;
    let cleaned = cleanup_dead_nodes(&instance)?;
    // No other server of the instance runs (checked above): the handshake blocks of killed
    // predecessors are left-overs.
    procimg_shm_layout::handshake_map::remove_stale_blocks(&instance);
    if !cleaned.is_empty() {
        info!(
            "removed what {} dead process(es) left in shared memory",
            cleaned.len()
        );
    }
    if config.cycle_thread.lock_memory
        && let Err(w) = lock_memory(config.cycle_thread.prefault_all)
    {
        warn!("{w}");
    }
    // Held open for the server's lifetime: closing it gives up the latency request.
    let _dma_latency = match procimg_runtime::sys::rt::hold_cpu_dma_latency_zero() {
        Ok(f) => Some(f),
        Err(w) => {
            warn!("{w}");
            None
        }
    };
    let term = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, term.clone())
            .with_context(|| format!("cannot install the handler for signal {sig}"))?;
    }
    // SIGHUP (systemctl reload): the configuration file is read again and taken into use.
    let hangup = Arc::new(AtomicBool::new(false));
    signal_hook::flag::register(signal_hook::consts::SIGHUP, hangup.clone())
        .context("cannot install the handler for SIGHUP")?;
    if exit_with_stdin {
        stop_with_stdin(term.clone());
    }
    // A station its program defines: waiting (OFFLINE, the device access point only) until
    // the program sends its tree; each tree, and each end of the program, runs a generation
    // anew.
    let mut program = config
        .station
        .as_ref()
        .and_then(|s| StationProgram::of(s, &tables));
    let mut configured_mode = config.start_mode;
    if program.is_some() {
        config.start_mode = Mode::Offline;
        info!("the station waits for its program to define it (OFFLINE until then)");
    }
    let mut ready = false;
    loop {
        let end = run_generation(
            &config,
            &tables,
            &source,
            live_view,
            &term,
            &hangup,
            &mut group_access,
            program.as_ref(),
            &mut ready,
        )?;
        match end {
            End::Stop => return Ok(()),
            End::Restart(restart, type_of_station) => {
                if let Restart::With(new, _) = restart {
                    let new_tables = Tables::from_config(&new).with_context(|| {
                        format!(
                            "{}: the IO system does not fit in a process image",
                            new.origin
                        )
                    })?;
                    config = *new;
                    tables = new_tables;
                    program = config
                        .station
                        .as_ref()
                        .and_then(|s| StationProgram::of(s, &tables));
                    configured_mode = config.start_mode;
                    if program.is_some() {
                        config.start_mode = Mode::Offline;
                    }
                }
                if let Some(text) = type_of_station {
                    config.set_type_of_station(&text);
                }
                info!(
                    "instance \"{}\" starts anew from {}",
                    config.instance, config.origin
                );
            }
            End::Program(next) => {
                let Some(program) = &program else {
                    return Ok(());
                };
                let (next, mode) = match next {
                    Next::Defined(defined) => (*defined, configured_mode),
                    Next::Waiting => (program.waiting().clone(), Mode::Offline),
                };
                config.station = Some(next.station);
                config.start_mode = mode;
                tables = next.tables;
                info!(
                    "the station runs anew: {} submodules, {} bytes of Q data and {} of I data",
                    tables.submodules.len(),
                    tables.layout.input_size,
                    tables.layout.output_size
                );
            }
        }
    }
}

/// SIGHUP: the configuration file read again and taken into use, as a download would be
/// (the programs attached asked to stop first). Said in the log when it cannot be.
fn reload(control: &mut Control, source: &ConfigSource) {
    let Some(path) = &source.path else {
        warn!("SIGHUP: procimgd has no configuration file to read again (demo or standard input)");
        return;
    };
    let text = match std::fs::read_to_string(path) {
        Ok(t) => t,
        Err(e) => {
            warn!(
                "SIGHUP: cannot read {}: {e}; the running configuration stays",
                path.display()
            );
            return;
        }
    };
    info!("SIGHUP: {} read again", path.display());
    if let Err(r) = control.restart_with(text) {
        warn!("SIGHUP: {r}; the running configuration stays");
    }
}

/// How a generation of the server ended.
enum End {
    /// procimgd stops (a signal, its standard input's end).
    Stop,
    /// The station's program asked for another station.
    Program(Next),
    /// A reset or a download: the server starts anew, with the type of station a program
    /// set meanwhile.
    Restart(Restart, Option<String>),
}

/// Runs one generation of the server: its image, cycle thread, role and data services, until
/// a signal ends procimgd (`None`) or the station's program asks for another station.
#[allow(clippy::too_many_arguments)]
fn run_generation(
    config: &Config,
    tables: &Tables,
    source: &ConfigSource,
    live_view: bool,
    term: &Arc<AtomicBool>,
    hangup: &Arc<AtomicBool>,
    group_access: &mut Option<GroupAccess>,
    program: Option<&Arc<StationProgram>>,
    ready: &mut bool,
) -> anyhow::Result<End> {
    let instance = config.instance.clone();
    let tables = tables.clone();
    let generation = generation();
    // The control thread's doorbell (after the left-overs are gone: a killed predecessor's
    // is taken over, so its clients' mappings stay right).
    let shared = Shared::new(tables.submodules.len());
    let shared = Arc::new(match Doorbell::create(&instance) {
        Ok(doorbell) => shared.with_doorbell(doorbell),
        Err(e) => {
            warn!(
                "cannot create {} ({e}): client requests are answered every {} ms instead of \
                 at once",
                doorbell_path(&instance).display(),
                CONTROL_POLL.as_millis()
            );
            shared
        }
    });
    shared
        .target_mode
        .store(config.start_mode.as_u32(), Ordering::Release);
    let (recorder, collector) = stats_channel();
    let ports = ControlPorts::create(
        &instance,
        generation,
        &tables,
        config.cycle_ns,
        config.opdone_deadline_ns,
    )?;
    let settings = EngineSettings {
        cycle_ns: config.cycle_ns,
        opdone_deadline_ns: config.opdone_deadline_ns,
        late_policy: config.late_policy,
        output_timing: config.output_timing,
        opdone_wait: config.cycle_thread.opdone_wait,
        opdone_spin_ns: config.cycle_thread.opdone_spin_ns,
        generation,
    };
    let mut role = match config.role {
        config::Role::Controller => roles::controller::start(config, shared.clone())?,
        config::Role::Device => roles::device::start(config, shared.clone(), program.cloned())?,
    };
    let io = role.io.take().context("the IO system was already taken")?;
    let services = role
        .services
        .take()
        .context("the role's services were already taken")?;
    let (cycle_thread, rt) = cycle::thread::spawn(
        settings,
        cycle::thread::ThreadSettings {
            instance: instance.clone(),
            cpu: config.cycle_thread.cpu,
            priority: config.cycle_thread.priority,
        },
        tables.clone(),
        io,
        shared.clone(),
        recorder,
    )?;
    for w in &rt.warnings {
        warn!("{w}");
    }
    info!(
        "instance \"{instance}\" cycling every {} µs on {} ({} devices, {} submodules, {} input and \
         {} output bytes), real-time: {}",
        config.cycle_ns as f64 / 1000.0,
        config.network,
        tables.devices.len(),
        tables.submodules.len(),
        tables.layout.input_size,
        tables.layout.output_size,
        if rt.realtime { "yes" } else { "no" },
    );
    let mut control = Control::new(
        ServerInfo {
            instance: instance.clone(),
            generation,
            cycle_ns: config.cycle_ns,
            opdone_deadline_ns: config.opdone_deadline_ns,
        },
        tables.clone(),
        ports,
        shared.clone(),
        collector,
        services,
    )
    .with_source(source.clone());
    let mut view = live_view.then(|| demo_view::DemoView::new(&instance, generation, &tables));
    let mut last_mode = shared.mode();
    let mut last_view = Instant::now();
    // This thread answers `procimg status` and turns the PROFINET thread's events into client
    // events: it follows the cycle at the status priority (after the other threads are
    // started, so that none inherits it).
    let status_priority = config.cycle_thread.status_priority;
    if status_priority > 0
        && let Err(w) =
            procimg_runtime::sys::rt::set_fifo_named("the control thread", status_priority)
    {
        warn!("{w}");
    }
    // Start-up is over: the code it ran is let go, to be locked again only as it runs again.
    let released = procimg_runtime::sys::start_up_code::release_start_up_code();
    if released.bytes > 0 {
        debug!(
            "start-up done: {} KiB of code and read-only data unmapped, locked again as used",
            released.bytes / 1024
        );
    }
    released.warnings.iter().for_each(|w| warn!("{w}"));
    let mut next = End::Stop;
    while !term.load(Ordering::Acquire) {
        if let Some(n) = program.and_then(|p| p.take_next()) {
            next = End::Program(n);
            break;
        }
        if hangup.swap(false, Ordering::AcqRel) {
            reload(&mut control, source);
        }
        if let Some(r) = control.take_restart() {
            next = End::Restart(r, control.type_of_station().map(str::to_owned));
            break;
        }
        if let Some(access) = group_access.as_mut() {
            access.share();
        }
        if !*ready {
            // Clients can attach from here: tell systemd (Type=notify), a no-op elsewhere.
            *ready = true;
            let _ = sd_notify::notify(false, &[sd_notify::NotifyState::Ready]);
        }
        for gone in control.poll() {
            info!("client {gone} is gone: its claims are released");
        }
        let mode = shared.mode();
        if mode != last_mode {
            info!("mode {mode}");
            last_mode = mode;
        }
        if let Some(v) = view.as_mut()
            && last_view.elapsed() >= Duration::from_secs(1)
        {
            last_view = Instant::now();
            v.print(&control.status());
        }
        control.idle(CONTROL_POLL);
    }

    // Outputs to a safe state first: CLEAR sends them marked invalid. From OFFLINE nothing is
    // connected and nothing goes out, so the server stays there.
    let safe = if shared.mode() == Mode::Offline {
        Mode::Offline
    } else {
        Mode::Clear
    };
    match next {
        End::Stop => {
            let _ = sd_notify::notify(false, &[sd_notify::NotifyState::Stopping]);
            info!("stopping: outputs to {safe} first");
        }
        End::Program(_) => info!(
            "the station's tree changes: outputs to {safe}, the AR ends, the station runs anew"
        ),
        End::Restart(..) => info!("restarting: outputs to {safe} first"),
    }
    shared.target_mode.store(safe.as_u32(), Ordering::Release);
    shared.command(Command::SetMode(safe));
    let until = Instant::now() + Duration::from_secs(2);
    while shared.mode() != safe && Instant::now() < until {
        control.poll();
        std::thread::sleep(Duration::from_millis(1));
    }
    // Two more cycles so the CLEAR outputs are on the wire.
    std::thread::sleep(Duration::from_nanos(2 * config.cycle_ns));
    // Connections are released while the cycle still runs, so that each device gets its
    // Release before its cyclic data ends (else it sees a watchdog expiry first).
    shared.release_all.store(true, Ordering::Release);
    let until = Instant::now() + Duration::from_secs(1);
    while !control.released() && Instant::now() < until {
        control.poll();
        std::thread::sleep(Duration::from_millis(1));
    }
    std::thread::sleep(Duration::from_nanos(2 * config.cycle_ns));
    shared.stop.store(true, Ordering::Release);
    if cycle_thread.join().is_err() {
        bail!("the cycle thread panicked");
    }
    role.join();
    // The AR's end, which the role reported while releasing, for the subscribers.
    control.finish();
    // The requests that came while the threads ended are answered before the control
    // server goes: else their askers would wait for an answer until their timeout.
    control.poll();
    drop(view);
    drop(control);
    if matches!(next, End::Stop) {
        info!("stopped; shared memory of instance \"{instance}\" released");
    }
    Ok(next)
}
