// SPDX-License-Identifier: MIT OR Apache-2.0
//! The configuration file: one TOML file describing the server instance, its cycle and the IO
//! system (devices, submodules, logical addresses).
//!
//! [`load`] reads, parses and validates a file; [`parse`] does the same for text in memory;
//! [`Config::demo`] is the built-in demo ([`DEMO_TOML`], also the documented example). All
//! checks happen here, before anything starts, and every [`ConfigError`] names the file, the
//! line and the key path, and says what to do.
//!
//! A device can be described by its GSDML file instead of by ident numbers: with `gsdml` on
//! the device and `module` on its submodules, the ident numbers, IO lengths and default
//! parameter records come from the file, and the device access point's own submodules
//! (slot 0: the DAP submodule, the interface and the ports) are added unless slot 0 is
//! listed. See [`gsdml`] for what is read from the file. The other way round,
//! [`gsdml::export`] writes the GSDML file of a `role = "device"` station, for the PLC's
//! engineering tool (`procimg gsdml`).
//!
//! Logical addresses: explicit `input_address`/`output_address` values are placed first; then
//! every submodule without one gets, in configuration order and for inputs (I space) and
//! outputs (Q space) independently, the lowest address at which its range fits.
//!
//! ```
//! let config = procimg_config::parse(
//!     r#"
//!     cycle_time = "2ms"
//!     [[device]]
//!     name = "io-1"
//!     vendor_id = 0x0493
//!     device_id = 0x0001
//!     [[device.submodule]]
//!     slot = 1
//!     subslot = 1
//!     module_ident = 0x20
//!     submodule_ident = 0x1
//!     input_length = 8
//!     "#,
//!     "example.toml",
//! )?;
//! assert_eq!(config.cycle_ns, 2_000_000);
//! assert_eq!(config.devices[0].submodules[0].input_address, 0);
//! # Ok::<(), procimg_config::ConfigError>(())
//! ```

mod address;
mod context;
mod duration;
mod error;
pub mod gsdml;
mod import;
pub mod pn_driver;
mod raw;
mod span;
pub mod station;
mod validate;

use std::net::Ipv4Addr;
use std::path::{Path, PathBuf};

pub use address::LAST_ADDRESS;
pub use duration::{DurationError, format_duration, parse_duration};
pub use error::ConfigError;
use procimg_shm_layout::Mode;
pub use station::{ProgramStation, SnmpMaster, StationConfig};
pub use validate::station::with_identity;
pub use validate::station_tree::{PlannedSubmodule, TreeError, dap_config, define_station};

/// The built-in demo configuration (three simulated devices on a simulated network), which is
/// also the commented example configuration.
pub const DEMO_TOML: &str = include_str!("demo.toml");

/// Origin named in messages about [`DEMO_TOML`].
pub const DEMO_ORIGIN: &str = "<built-in demo>";

/// The built-in demo of the IO device role (one station on a simulated network, with
/// procimg's own controller as the PLC), which is also the commented example of the role.
pub const DEMO_DEVICE_TOML: &str = include_str!("demo_device.toml");

/// Origin named in messages about [`DEMO_DEVICE_TOML`].
pub const DEMO_DEVICE_ORIGIN: &str = "<built-in device demo>";

/// Origin named in messages about [`Config::demo_device_program`].
pub const DEMO_DEVICE_PROGRAM_ORIGIN: &str = "<built-in device demo, defined by its program>";

/// The date of the device demo's GSDML file in [`Config::demo_device_program`] (year,
/// month, day): fixed, so that the file's name stays the same from run to run.
pub const DEMO_GSDML_DATE: (u16, u8, u8) = (2026, 11, 28);

/// Default instance name.
pub const DEFAULT_INSTANCE: &str = "procimg";
/// Default cycle time: 1 ms.
pub const DEFAULT_CYCLE_NS: u64 = 1_000_000;
/// Cycle times are whole multiples of this (31.25 µs, the PROFINET base clock).
pub const CYCLE_UNIT_NS: u64 = procimg_shm_layout::CYCLE_COUNT_UNIT_NS;
/// Longest cycle time: 512 ms.
pub const MAX_CYCLE_NS: u64 = 512_000_000;
/// Most devices in one configuration.
pub const MAX_DEVICES: usize = 256;
/// Most submodules in one configuration, over all devices.
pub const MAX_SUBMODULES: usize = 4096;

/// Whether this machine has the network interface `name`: `Ok`, or what to say about its
/// absence (that it does not exist, and which interfaces there are), to which [`load`] adds
/// the file, line and key and what to write instead. The caller asks the operating system
/// (procimgd and the tools pass `procimg_nic::interfaces::check`): this crate reads no
/// interface, so that it needs no network crate.
pub type InterfaceCheck<'a> = &'a dyn Fn(&str) -> Result<(), String>;

/// Reads, parses and validates the configuration file at `path`, for this machine: besides
/// what [`parse`] checks, a `network` interface must pass `interface` (exist here).
///
/// Messages name the file as `path` is written; relative `gsdml` paths start at the file's
/// directory.
pub fn load(path: &Path, interface: InterfaceCheck<'_>) -> Result<Config, ConfigError> {
    let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let cx = context::Cx {
        text: &text,
        origin: &path.display().to_string(),
        dir: path.parent().unwrap_or(Path::new("")),
        interface: Some(interface),
    };
    build(&cx)
}

/// Parses and validates configuration `text`; `origin` names it in messages (a file name).
///
/// Relative `gsdml` paths start at the current directory. The text is not checked against
/// this machine's network interfaces ([`load`] does that).
pub fn parse(text: &str, origin: &str) -> Result<Config, ConfigError> {
    parse_in_dir(text, origin, Path::new(""))
}

/// [`load`] for text that is not in a file (a program hands it over): parses and validates
/// `text`, named `origin` in messages, with relative `gsdml` paths starting at `dir`, and a
/// `network` interface must pass `interface`.
pub fn parse_for_machine(
    text: &str,
    origin: &str,
    dir: &Path,
    interface: InterfaceCheck<'_>,
) -> Result<Config, ConfigError> {
    build(&context::Cx {
        text,
        origin,
        dir,
        interface: Some(interface),
    })
}

/// [`parse`], with relative `gsdml` paths starting at `dir` (the directory of the file the
/// text came from).
pub fn parse_in_dir(text: &str, origin: &str, dir: &Path) -> Result<Config, ConfigError> {
    build(&context::Cx {
        text,
        origin,
        dir,
        interface: None,
    })
}

fn build(cx: &context::Cx<'_>) -> Result<Config, ConfigError> {
    if pn_driver::is_xml(cx.text) {
        // TIA Portal's PN Driver configuration: imported, then checked as any other; its
        // messages name the imported text's lines, whose comments give the project's.
        let text = pn_driver::import(cx.text, cx.origin, None)?;
        let origin = format!("{} (imported)", cx.origin);
        return build(&context::Cx {
            text: &text,
            origin: &origin,
            dir: cx.dir,
            interface: cx.interface,
        });
    }
    let raw = toml::from_str::<raw::RawConfig>(cx.text).map_err(|e| cx.toml_error(&e))?;
    validate::build(raw, cx)
}

/// A validated configuration.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Config {
    /// Where it came from (the file name as given, or [`DEMO_ORIGIN`]).
    pub origin: String,
    /// The PROFINET role the server plays (key `role`: `"controller"` (default) or
    /// `"device"`).
    pub role: Role,
    /// Name of the server instance (key `instance`, default `"procimg"`): 1 to 32 characters of
    /// `A-Z a-z 0-9 _ -`.
    pub instance: String,
    /// Cycle time in ns (key `cycle_time`, default `"1ms"`): a multiple of 31.25 µs, at most
    /// 512 ms.
    pub cycle_ns: u64,
    /// OPDONE deadline in ns after the cycle start (key `opdone_deadline`, default half the
    /// cycle time): more than 0 and less than the cycle time.
    pub opdone_deadline_ns: u64,
    /// What happens to the outputs of a client that missed the deadline (key
    /// `late_client_policy`).
    pub late_policy: LatePolicy,
    /// When output frames are sent (key `send_outputs`).
    pub output_timing: OutputTiming,
    /// Mode at start (key `start_mode`: `"offline"`, `"clear"`, `"operate"` (default)).
    pub start_mode: Mode,
    /// The network (key `network`: `"sim"` (default) or an interface name).
    pub network: Network,
    /// The cycle thread (table `[cycle_thread]`).
    pub cycle_thread: CycleThreadConfig,
    /// Access to the shared memory (table `[access]`).
    pub access: AccessConfig,
    /// The IO devices (array of tables `[[device]]`), in configuration order; with
    /// `role = "controller"` only.
    pub devices: Vec<DeviceConfig>,
    /// This server as an IO device (table `[station]`); with `role = "device"`, and only
    /// then.
    pub station: Option<StationConfig>,
    /// The controller's own PROFINET interface (table `[interface]`); with
    /// `role = "controller"` only (the defaults otherwise).
    pub interface: InterfaceConfig,
}

/// The controller's own PROFINET interface (table `[interface]`): its station as DCP, LLDP
/// and its programs see it (IO-Base's `PNIO_interface_*`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct InterfaceConfig {
    /// The controller's NameOfStation (key `station_name`; default `procimgd-<instance>`,
    /// see [`Config::controller_station_name`]).
    pub station_name: Option<String>,
    /// Whether a program (`PNIO_interface_set_ip_and_nos`) or an engineering tool (DCP Set)
    /// may change the NameOfStation (key `name_by_program`, default `false`): TIA Portal's
    /// "PROFINET device name is set directly at the device".
    pub name_by_program: bool,
    /// Whether they may change the IP suite (key `address_by_program`, default `false`):
    /// "IP address is set directly at the device". procimgd then carries the address out
    /// on the interface.
    pub address_by_program: bool,
    /// Whether the port's link is checked (key `check_link`, default `false`): a link down
    /// is a diagnosis of the port, with an alarm to the programs.
    pub check_link: bool,
    /// The interface submodule's diagnostic address (key `diagnostic_address`, default
    /// [`DEFAULT_INTERFACE_ADDRESS`], or where a device's inputs have that one, the highest
    /// free address below it, above all inputs when none is), an address of the I space.
    pub diagnostic_address: u32,
    /// The port submodule's diagnostic address (key `port_diagnostic_address`, default
    /// [`DEFAULT_PORT_ADDRESS`]).
    pub port_diagnostic_address: u32,
    /// The type of station DCP reports (key `type_of_station`, default
    /// [`DEFAULT_TYPE_OF_STATION`]; IO-Base's `SERV_CP_set_type_of_station`), at most 255
    /// bytes.
    pub type_of_station: String,
}

/// The type of station the controller reports by default.
pub const DEFAULT_TYPE_OF_STATION: &str = "procimg controller";

/// The controller interface's default diagnostic address.
pub const DEFAULT_INTERFACE_ADDRESS: u32 = 16382;
/// The controller port's default diagnostic address.
pub const DEFAULT_PORT_ADDRESS: u32 = 16381;
/// The largest diagnostic address of the controller's interface (IO-Base's interface
/// functions take logical addresses up to 0x7FFF).
pub const MAX_INTERFACE_ADDRESS: u32 = 0x7fff;

impl Default for InterfaceConfig {
    fn default() -> InterfaceConfig {
        InterfaceConfig {
            station_name: None,
            name_by_program: false,
            address_by_program: false,
            check_link: false,
            diagnostic_address: DEFAULT_INTERFACE_ADDRESS,
            port_diagnostic_address: DEFAULT_PORT_ADDRESS,
            type_of_station: DEFAULT_TYPE_OF_STATION.to_owned(),
        }
    }
}

impl Config {
    /// The built-in demo: [`DEMO_TOML`] parsed, with origin [`DEMO_ORIGIN`].
    pub fn demo() -> Config {
        // DEMO_TOML is a constant that a test parses; it sets no CPU, the only check that
        // depends on the machine.
        parse(DEMO_TOML, DEMO_ORIGIN).expect("the built-in demo configuration is valid")
    }

    /// The built-in demo of the device role: [`DEMO_DEVICE_TOML`] parsed, with origin
    /// [`DEMO_DEVICE_ORIGIN`].
    pub fn demo_device() -> Config {
        // A constant that a test parses, with no CPU set.
        parse(DEMO_DEVICE_TOML, DEMO_DEVICE_ORIGIN)
            .expect("the built-in device demo configuration is valid")
    }

    /// The built-in demo of the device role with a station its program defines: the device
    /// demo's identity and device access point, its tree left to a program (an IO-Base
    /// device program's plugs, or [`PlannedSubmodule`]s over the client services), and the
    /// demo station's own GSDML file (what `procimg gsdml` writes for [`DEMO_DEVICE_TOML`],
    /// dated [`DEMO_GSDML_DATE`]) as the station's description. Until a program defines
    /// it the station waits off the wire.
    pub fn demo_device_program() -> Config {
        let mut config = Config::demo_device();
        config.origin = DEMO_DEVICE_PROGRAM_ORIGIN.to_owned();
        let Some(station) = config.station.as_mut() else {
            unreachable!("the device demo has a station")
        };
        let (year, month, day) = DEMO_GSDML_DATE;
        let date = gsdml::export::GsdmlDate::new(year, month, day).expect("a valid date");
        // The built-in demo is checked by a test: none of these fail.
        let file = gsdml::export::station_gsdml(station, config.cycle_ns, date)
            .expect("the device demo has a GSDML file");
        let parsed =
            gsdml::Gsdml::parse(&file.xml, &file.file_name).expect("procimg's GSDML file reads");
        let waiting = define_station(station, &parsed, &parsed.daps[0], &[])
            .expect("the demo's device access point alone is a station");
        *station = StationConfig {
            program: Some(ProgramStation {
                gsdml: PathBuf::from(file.file_name),
                dap: parsed.daps[0].id.clone(),
                dap_index: 0,
                file: std::sync::Arc::new(parsed),
            }),
            ..waiting
        };
        config
    }

    /// The controller's NameOfStation: `[interface] station_name`, or from the instance
    /// name: `procimgd-` and the name in lower case, other characters as '-', as DCP names
    /// allow.
    pub fn controller_station_name(&self) -> String {
        if let Some(name) = &self.interface.station_name {
            return name.clone();
        }
        let s: String = self
            .instance
            .chars()
            .map(|c| match c.to_ascii_lowercase() {
                c @ ('a'..='z' | '0'..='9' | '-') => c,
                _ => '-',
            })
            .collect();
        format!("procimgd-{}", s.trim_matches('-'))
    }

    /// The neighbour the configuration gives the controller's port: the device whose
    /// `[[device.topology]]` names the controller's station and its port `port-001`, and
    /// that device's port subslot.
    pub fn controller_port_peer(&self) -> Option<(&str, u16)> {
        let own = self.controller_station_name();
        self.devices.iter().find_map(|d| {
            d.topology.iter().find_map(|t| match &t.peer {
                Peer::Fixed { station, port } if *station == own && port == "port-001" => {
                    Some((d.name.as_str(), t.subslot))
                }
                _ => None,
            })
        })
    }

    /// Makes `text` the type of station of the server's own station: the controller's, or
    /// the device role station's device type.
    pub fn set_type_of_station(&mut self, text: &str) {
        match self.station.as_mut() {
            Some(station) => station.device_type = text.to_owned(),
            None => self.interface.type_of_station = text.to_owned(),
        }
    }

    /// Number of submodules in the image: over all devices, or the station's.
    pub fn submodule_count(&self) -> usize {
        match &self.station {
            Some(station) => station.submodules.len(),
            None => self.devices.iter().map(|d| d.submodules.len()).sum(),
        }
    }
}

/// The PROFINET role of the server (key `role`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Role {
    /// `"controller"` (default): the server is the IO controller of the `[[device]]`s.
    #[default]
    Controller,
    /// `"device"`: the server is the IO device `[station]` describes, for a PLC to connect.
    Device,
}

impl Role {
    /// The spelling in the configuration file.
    pub const fn as_str(self) -> &'static str {
        match self {
            Role::Controller => "controller",
            Role::Device => "device",
        }
    }
}

/// What happens to a late client's outputs (key `late_client_policy`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LatePolicy {
    /// `"hold-last-outputs"` (default): its submodules keep the last outputs.
    HoldLastOutputs,
    /// `"iops-bad"`: its submodules go IOPS BAD.
    IopsBad,
}

impl LatePolicy {
    /// The spelling in the configuration file.
    pub const fn as_str(self) -> &'static str {
        match self {
            LatePolicy::HoldLastOutputs => "hold-last-outputs",
            LatePolicy::IopsBad => "iops-bad",
        }
    }
}

/// When the output frames are sent (key `send_outputs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OutputTiming {
    /// `"immediately"` (default): once every client is done or the deadline has passed.
    Immediately,
    /// `"at-next-cycle-start"`: at the start of the next cycle, for minimal wire jitter.
    AtNextCycleStart,
}

impl OutputTiming {
    /// The spelling in the configuration file.
    pub const fn as_str(self) -> &'static str {
        match self {
            OutputTiming::Immediately => "immediately",
            OutputTiming::AtNextCycleStart => "at-next-cycle-start",
        }
    }
}

/// The network the IO system is on (key `network`).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Network {
    /// `"sim"` (default): a simulated in-process network with simulated devices.
    Sim,
    /// A Linux network interface, by name (1 to 15 bytes, no `/`, `:` or blanks).
    Interface(String),
}

impl core::fmt::Display for Network {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Network::Sim => f.write_str("sim"),
            Network::Interface(name) => f.write_str(name),
        }
    }
}

/// The cycle thread's CPU and scheduling (table `[cycle_thread]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CycleThreadConfig {
    /// CPU to pin it to (key `cpu`, default none: not pinned); below the number of CPUs.
    pub cpu: Option<usize>,
    /// SCHED_FIFO priority, 1 to 99 (key `priority`, default 80).
    pub priority: u8,
    /// SCHED_FIFO priority of the threads that turn the cycle's reports into device states,
    /// `procimg status` and client events (the PROFINET thread and the control thread); 0:
    /// normal priority (key `status_priority`, default 40: below the cycle thread and
    /// synchronous clients, above everything else).
    pub status_priority: u8,
    /// Lock all memory with `mlockall` (key `lock_memory`, default true).
    pub lock_memory: bool,
    /// With `lock_memory`: fault in and lock every page of the process before the first
    /// cycle (key `prefault_all`, default false). By default the code and read-only data of
    /// procimgd and its libraries, and the stacks of threads other than the cycle thread, are
    /// locked as they are first used: some 4 MiB less locked RAM, since the cycle runs a
    /// small part of the program; the price is a minor page fault the first time a path
    /// that never ran before runs in a cycle (an error the cycle had not met yet), or a
    /// read from the disk if memory pressure had dropped that page of the program from the
    /// page cache. With `true` no path ever faults.
    pub prefault_all: bool,
    /// How the thread waits for OPDONE (key `opdone_wait`, default `"event"`).
    pub opdone_wait: OpdoneWait,
    /// With `opdone_wait = "event"`: how long after STARTOP the thread polls for OPDONE
    /// before it sleeps, in ns (key `opdone_spin`, a duration, default `"20us"`; `"0"`
    /// sleeps at once). A client that answers within it is seen at once, without the
    /// wake-up of a sleeping CPU; the thread's CPU is busy for at most that long a cycle.
    /// Only while fewer synchronous clients are waited for than the process has CPUs: with
    /// more, some share the cycle thread's CPU and could not answer while it polls.
    pub opdone_spin_ns: u64,
}

/// How long the cycle thread polls for OPDONE before it sleeps, by default: on this project's
/// measurements (docs/PERFORMANCE.md) a sleeping CPU takes some 10 µs longer to see a
/// client's OPDONE than a polling one, and a client's window is mostly shorter than this.
pub const DEFAULT_OPDONE_SPIN_NS: u64 = 20_000;

/// How the cycle thread waits for the synchronous clients' OPDONE.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum OpdoneWait {
    /// Polls for `opdone_spin`, then sleeps until an OPDONE or the deadline (`"event"`,
    /// default): the CPU is free for others meanwhile.
    #[default]
    Event,
    /// Polls for output samples without sleeping until every client is done or the deadline
    /// (`"busy-poll"`): a few µs less per round trip, at the price of the cycle thread's CPU
    /// during the OPDONE window. For a cycle thread pinned to a CPU of its own.
    BusyPoll,
}

impl Default for CycleThreadConfig {
    fn default() -> Self {
        CycleThreadConfig {
            cpu: None,
            priority: 80,
            status_priority: 40,
            lock_memory: true,
            prefault_all: false,
            opdone_wait: OpdoneWait::Event,
            opdone_spin_ns: DEFAULT_OPDONE_SPIN_NS,
        }
    }
}

/// Access to the shared memory (table `[access]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AccessConfig {
    /// Permission bits (key `mode`, an octal string, default `"0600"`, or `"0660"` when a
    /// group is named); only `0o777` bits.
    pub mode: u32,
    /// Owning group (key `group`, default none: the server's group); not resolved here.
    pub group: Option<String>,
}

impl Default for AccessConfig {
    fn default() -> Self {
        AccessConfig {
            mode: 0o600,
            group: None,
        }
    }
}

/// One IO device (an entry of `[[device]]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceConfig {
    /// NameOfStation (key `name`), unique in the configuration.
    pub name: String,
    /// IPv4 address given to the device (key `ip`), if any.
    pub ip: Option<Ipv4Addr>,
    /// PROFINET vendor ID (key `vendor_id`, or the GSDML file's).
    pub vendor_id: u16,
    /// PROFINET device ID (key `device_id`, or the GSDML file's).
    pub device_id: u16,
    /// The GSDML file and device access point the device was described with (keys `gsdml`
    /// and `dap`), if any.
    pub gsdml: Option<GsdmlSource>,
    /// Device instance (key `instance`, default 1).
    pub instance: u16,
    /// Reduction ratio (key `reduction_ratio`, default 1): a power of two, 1 to 512.
    pub reduction_ratio: u16,
    /// Watchdog factor (key `watchdog_factor`, default 3): 3 to 255.
    pub watchdog_factor: u16,
    /// Behaviour of the simulated device with `network = "sim"` (key `sim`).
    pub sim: SimBehaviour,
    /// Its submodules (array of tables `[[device.submodule]]`), in configuration order.
    pub submodules: Vec<SubmoduleConfig>,
    /// The neighbours its ports are to have (array of tables `[[device.topology]]`), which
    /// the controller writes as the ports' topology checks (PDPortDataCheck) at connect.
    pub topology: Vec<PortPeer>,
    /// Whether the device is optional (key `optional`, default `false`): a machine may be
    /// built without it. An optional device stays deactivated until a program tailors the
    /// IO system (IO-Base's `PNIO_iosystem_reconfig`, `procimg device tailor`) and names it
    /// among those present.
    pub optional: bool,
}

/// The neighbour a port of a device is to have (an element of `[[device.topology]]`).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PortPeer {
    /// The device's port submodule (key `subslot`, default its first port, 0x8001 on most
    /// devices), in slot 0.
    pub subslot: u16,
    /// Who the neighbour is.
    pub peer: Peer,
}

/// The neighbour of a [`PortPeer`].
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Peer {
    /// A fixed neighbour (keys `station` and `port`).
    Fixed {
        /// The neighbour's NameOfStation (key `station`).
        station: String,
        /// The neighbour's port (key `port`, e.g. `port-001`).
        port: String,
    },
    /// A programmable peer (key `programmable = true`): the neighbour depends on how the
    /// machine is built, and tailoring the IO system names it.
    Programmable,
}

/// Where a device's description came from (keys `gsdml` and `dap` of a device).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GsdmlSource {
    /// The GSDML file as opened: the `gsdml` path, joined to the configuration file's
    /// directory if relative.
    pub path: PathBuf,
    /// The ID of the device access point (`DeviceAccessPointItem/@ID`).
    pub dap: String,
}

/// How a simulated device behaves (key `sim` of a device).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimBehaviour {
    /// `"none"` (default): inputs stay as they are.
    None,
    /// `"echo"`: outputs come back as inputs.
    Echo,
    /// `"counter"`: inputs count up every cycle.
    Counter,
    /// `"digital-io"`: inputs follow outputs bit by bit.
    DigitalIo,
    /// `"absent"`: the device is not on the simulated network; nothing answers for it, as
    /// when a configured device is missing or switched off.
    Absent,
}

impl SimBehaviour {
    /// The spelling in the configuration file.
    pub const fn as_str(self) -> &'static str {
        match self {
            SimBehaviour::None => "none",
            SimBehaviour::Echo => "echo",
            SimBehaviour::Counter => "counter",
            SimBehaviour::DigitalIo => "digital-io",
            SimBehaviour::Absent => "absent",
        }
    }
}

/// One submodule of a device (an entry of `[[device.submodule]]`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SubmoduleConfig {
    /// Application process identifier (key `api`, or the GSDML submodule's, default 0).
    pub api: u32,
    /// Slot (key `slot`).
    pub slot: u16,
    /// Subslot (key `subslot`, or the GSDML submodule's own), at least 1.
    pub subslot: u16,
    /// Module ident number (key `module_ident`, or from the GSDML `module`).
    pub module_ident: u32,
    /// Submodule ident number (key `submodule_ident`, or from the GSDML `module`).
    pub submodule_ident: u32,
    /// Bytes of input data (key `input_length`, or from the GSDML `module`, default 0), at
    /// most [`procimg_shm_layout::MAX_SUBMODULE_DATA_LEN`].
    pub input_length: u16,
    /// Bytes of output data (key `output_length`, or from the GSDML `module`, default 0), at
    /// most [`procimg_shm_layout::MAX_SUBMODULE_DATA_LEN`].
    pub output_length: u16,
    /// First logical address in the I space (key `input_address`, or assigned); for a
    /// submodule without any IO data its diagnostic address (key `diagnostic_address`, or
    /// assigned after all inputs), the address of length 0 that record jobs and alarms name
    /// it by; else [`procimg_shm_layout::NO_ADDRESS`].
    pub input_address: u32,
    /// First logical address in the Q space (key `output_address`, or assigned), or
    /// [`procimg_shm_layout::NO_ADDRESS`] if `output_length` is 0.
    pub output_address: u32,
    /// RT class, 1 (default) or 3 (key `rt_class`).
    pub rt_class: u8,
    /// Parameter records written at connect (key `records`, or the GSDML module's defaults),
    /// in configuration order.
    pub records: Vec<ParameterRecord>,
}

impl SubmoduleConfig {
    /// Whether the submodule has neither inputs nor outputs (and so a diagnostic address).
    pub fn has_no_data(&self) -> bool {
        self.input_length == 0 && self.output_length == 0
    }

    /// Its diagnostic address, if it has no IO data.
    pub fn diagnostic_address(&self) -> Option<u32> {
        (self.has_no_data() && self.input_address != procimg_shm_layout::NO_ADDRESS)
            .then_some(self.input_address)
    }
}

/// A parameter record (an element of a submodule's `records`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParameterRecord {
    /// Record index (key `index`).
    pub index: u16,
    /// Record data (key `data`, an array of bytes).
    pub data: Vec<u8>,
}
