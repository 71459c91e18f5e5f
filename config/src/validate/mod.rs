// SPDX-License-Identifier: MIT OR Apache-2.0
//! From the file as written ([`RawConfig`]) to a checked [`Config`].

use std::collections::HashMap;
use std::net::Ipv4Addr;
use std::ops::Range;

use procimg_shm_layout::{MAX_SUBMODULE_DATA_LEN, Mode, NO_ADDRESS};
use toml::Spanned;

use super::address::{self, DIAGNOSTIC_ADDRESS_KEY, Item, Space};
use super::context::Cx;
use super::duration::{format_duration, parse_duration};
use super::error::ConfigError;
use super::gsdml::Submodule;
use super::import::{self, DeviceImport, Files, Found, Lookup};
use super::raw::{
    RawAccess, RawConfig, RawCycleThread, RawDevice, RawInterface, RawSubmodule, RawTopology,
};
use super::{
    AccessConfig, CYCLE_UNIT_NS, Config, CycleThreadConfig, DEFAULT_CYCLE_NS, DEFAULT_INSTANCE,
    DeviceConfig, GsdmlSource, InterfaceConfig, LatePolicy, MAX_CYCLE_NS, MAX_DEVICES,
    MAX_INTERFACE_ADDRESS, MAX_SUBMODULES, Network, OpdoneWait, OutputTiming, ParameterRecord,
    Peer, PortPeer, Role, SimBehaviour, SubmoduleConfig,
};

mod devices;
pub(crate) mod station;
pub(crate) mod station_tree;
use devices::devices;

/// Checks `raw` and resolves defaults and addresses.
pub(super) fn build(raw: RawConfig, cx: &Cx<'_>) -> Result<Config, ConfigError> {
    let role = match &raw.role {
        Some(v) => cx.check(
            v,
            "role",
            choose(
                v.get_ref(),
                "a role",
                &[("controller", Role::Controller), ("device", Role::Device)],
            ),
        )?,
        None => Role::Controller,
    };
    let instance = match raw.instance {
        Some(v) => {
            cx.check(&v, "instance", instance_name(v.get_ref()))?;
            v.into_inner()
        }
        None => DEFAULT_INSTANCE.to_owned(),
    };
    let cycle_ns = match &raw.cycle_time {
        Some(v) => cx.check(v, "cycle_time", cycle_time(v.get_ref()))?,
        None => DEFAULT_CYCLE_NS,
    };
    let opdone_deadline_ns = match &raw.opdone_deadline {
        Some(v) => cx.check(v, "opdone_deadline", deadline(v.get_ref(), cycle_ns))?,
        None => cycle_ns / 2,
    };
    let late_policy = match &raw.late_client_policy {
        Some(v) => cx.check(
            v,
            "late_client_policy",
            choose(
                v.get_ref(),
                "a late-client policy",
                &[
                    ("hold-last-outputs", LatePolicy::HoldLastOutputs),
                    ("iops-bad", LatePolicy::IopsBad),
                ],
            ),
        )?,
        None => LatePolicy::HoldLastOutputs,
    };
    let output_timing = match &raw.send_outputs {
        Some(v) => cx.check(
            v,
            "send_outputs",
            choose(
                v.get_ref(),
                "an output timing",
                &[
                    ("immediately", OutputTiming::Immediately),
                    ("at-next-cycle-start", OutputTiming::AtNextCycleStart),
                ],
            ),
        )?,
        None => OutputTiming::Immediately,
    };
    let start_mode = match &raw.start_mode {
        Some(v) => cx.check(
            v,
            "start_mode",
            choose(
                v.get_ref(),
                "a mode",
                &[
                    ("offline", Mode::Offline),
                    ("clear", Mode::Clear),
                    ("operate", Mode::Operate),
                ],
            ),
        )?,
        None => Mode::Operate,
    };
    let network = match raw.network {
        Some(v) if v.get_ref() == "sim" => Network::Sim,
        Some(v) => {
            cx.check(&v, "network", interface_name(v.get_ref()))?;
            if let Some(check) = cx.interface {
                cx.check(&v, "network", interface_exists(check, v.get_ref()))?;
            }
            Network::Interface(v.into_inner())
        }
        None => Network::Sim,
    };
    let cycle_thread = match raw.cycle_thread {
        Some(t) => cycle_thread(t, cx)?,
        None => CycleThreadConfig::default(),
    };
    let access = match raw.access {
        Some(a) => access(a, cx)?,
        None => AccessConfig::default(),
    };
    if let (Role::Device, Some(i)) = (role, &raw.interface) {
        return Err(cx.invalid(
            i.span(),
            "interface",
            "[interface] describes the controller's own interface, and the role is \
             \"device\"; the station's name and address are in [station]",
        ));
    }
    let (devices, station) = match (role, raw.station) {
        (Role::Controller, Some(station)) => {
            return Err(cx.invalid(
                station.span(),
                "station",
                "[station] describes this server as an IO device, and the role is \
                 \"controller\"; add `role = \"device\"` at the top, or remove [station]",
            ));
        }
        (Role::Controller, None) => (devices(raw.device, cx)?, None),
        (Role::Device, station) => {
            if let Some(device) = raw.device.first() {
                return Err(cx.invalid(
                    device.span(),
                    "device[0]",
                    "[[device]] describes an IO device this server controls, and the role is \
                     \"device\"; describe this server's own modules in [[station.submodule]], \
                     or set `role = \"controller\"`",
                ));
            }
            let Some(station) = station else {
                let at = raw.role.as_ref().map_or(0..0, Spanned::span);
                return Err(cx.missing(
                    at,
                    "station",
                    "station",
                    "with `role = \"device\"` add a [station] table with the device's name, \
                     vendor_id and device_id (`procimgd --print-demo-device-config` shows one)",
                ));
            };
            (Vec::new(), Some(station::station(station, cx)?))
        }
    };
    let interface = match raw.interface {
        Some(i) => interface(i.into_inner(), &devices, cx)?,
        None if role == Role::Controller => interface(RawInterface::default(), &devices, cx)?,
        None => InterfaceConfig::default(),
    };
    Ok(Config {
        origin: cx.origin.to_owned(),
        role,
        instance,
        cycle_ns,
        opdone_deadline_ns,
        late_policy,
        output_timing,
        start_mode,
        network,
        cycle_thread,
        access,
        devices,
        station,
        interface,
    })
}

/// `[interface]`: the controller's own interface, its diagnostic addresses clear of every
/// device's inputs.
fn interface(
    raw: RawInterface,
    devices: &[DeviceConfig],
    cx: &Cx<'_>,
) -> Result<InterfaceConfig, ConfigError> {
    let mut config = InterfaceConfig {
        name_by_program: raw.name_by_program.unwrap_or(false),
        address_by_program: raw.address_by_program.unwrap_or(false),
        check_link: raw.check_link.unwrap_or(false),
        ..InterfaceConfig::default()
    };
    if let Some(t) = raw.type_of_station {
        cx.check(&t, "interface.type_of_station", {
            let n = t.get_ref().len();
            if n == 0 || n > 255 {
                Err(format!(
                    "a type of station of {n} bytes: give 1 to 255 (engineering tools show 19 \
                     characters)"
                ))
            } else {
                Ok(())
            }
        })?;
        config.type_of_station = t.into_inner();
    }
    if let Some(name) = raw.station_name {
        cx.check(
            &name,
            "interface.station_name",
            devices::station_name(name.get_ref()),
        )?;
        config.station_name = Some(name.into_inner());
    }
    let taken = |address: u32| {
        devices.iter().find_map(|d| {
            d.submodules.iter().find_map(|s| {
                let extent = u32::from(s.input_length.max(u16::from(s.has_no_data())));
                (s.input_address != NO_ADDRESS
                    && (s.input_address..s.input_address + extent).contains(&address))
                .then(|| format!("{} slot {} subslot {:#06x}", d.name, s.slot, s.subslot))
            })
        })
    };
    // What the devices' inputs and diagnostic addresses take of the I space, for a default
    // that has to move.
    let used: Vec<(u32, u32)> = devices
        .iter()
        .flat_map(|d| &d.submodules)
        .filter(|s| s.input_address != NO_ADDRESS)
        .map(|s| {
            let extent = u32::from(s.input_length.max(u16::from(s.has_no_data())));
            (s.input_address, s.input_address.saturating_add(extent))
        })
        .collect();
    let check = |value: Option<&Spanned<u32>>, default: u32, avoid: Option<u32>, key: &str| {
        let Some(v) = value else {
            // A default that a device's inputs have taken moves to the highest free address
            // below it (above all inputs if there is none: the I space is theirs).
            return Ok(free_address(&used, default, avoid));
        };
        let a = *v.get_ref();
        let problem = match taken(a) {
            _ if a > MAX_INTERFACE_ADDRESS => Some(format!(
                "{a} is not a diagnostic address of the controller's interface; use 0 to \
                 {MAX_INTERFACE_ADDRESS}"
            )),
            Some(owner) => Some(format!(
                "I address {a} is {owner}'s; give the controller's interface another one"
            )),
            None => None,
        };
        match problem {
            Some(p) => Err(cx.invalid(v.span(), format!("interface.{key}"), p)),
            None => Ok(a),
        }
    };
    config.diagnostic_address = check(
        raw.diagnostic_address.as_ref(),
        config.diagnostic_address,
        raw.port_diagnostic_address.as_ref().map(|v| *v.get_ref()),
        "diagnostic_address",
    )?;
    config.port_diagnostic_address = check(
        raw.port_diagnostic_address.as_ref(),
        config.port_diagnostic_address,
        Some(config.diagnostic_address),
        "port_diagnostic_address",
    )?;
    if config.diagnostic_address == config.port_diagnostic_address {
        let at = raw
            .port_diagnostic_address
            .as_ref()
            .or(raw.diagnostic_address.as_ref())
            .map_or(0..0, Spanned::span);
        return Err(cx.invalid(
            at,
            "interface.port_diagnostic_address",
            "the interface and its port need diagnostic addresses of their own",
        ));
    }
    Ok(config)
}

/// `wanted` if no range of `used` (start, end) holds it and it is not `avoid`; else the
/// highest address below it that is free, or, with none free below, the first above every
/// range.
fn free_address(used: &[(u32, u32)], wanted: u32, avoid: Option<u32>) -> u32 {
    let is_free = |a: u32| Some(a) != avoid && !used.iter().any(|(s, e)| (*s..*e).contains(&a));
    let mut a = wanted;
    loop {
        if is_free(a) {
            return a;
        }
        // Below the range that holds it (or below `avoid`).
        let below = used
            .iter()
            .find(|(s, e)| (*s..*e).contains(&a))
            .map_or(a.checked_sub(1), |(s, _)| s.checked_sub(1));
        match below {
            Some(b) => a = b,
            None => break,
        }
    }
    let mut a = used.iter().map(|(_, e)| *e).max().unwrap_or(0);
    while !is_free(a) {
        a += 1;
    }
    a
}

fn instance_name(name: &str) -> Result<(), String> {
    let fine = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    if name.is_empty() || name.len() > 32 || !name.chars().all(fine) {
        return Err(format!(
            "{name:?} is not an instance name; use 1 to 32 characters of A-Z, a-z, 0-9, '_' \
             and '-', e.g. \"procimg\" or \"line-1\""
        ));
    }
    Ok(())
}

/// Valid cycle times next to `ns`, as suggestions: the neighbouring multiples of 125 µs (round
/// numbers), or of 31.25 µs below 125 µs.
fn cycle_suggestions(ns: u64) -> String {
    let step = if ns >= 4 * CYCLE_UNIT_NS {
        4 * CYCLE_UNIT_NS
    } else {
        CYCLE_UNIT_NS
    };
    let lower = ns / step * step;
    let upper = lower + step;
    let mut options = Vec::new();
    if lower > 0 {
        options.push(format!("{:?}", format_duration(lower)));
    }
    if upper <= MAX_CYCLE_NS {
        options.push(format!("{:?}", format_duration(upper)));
    }
    options.join(" or ")
}

fn cycle_time(text: &str) -> Result<u64, String> {
    let ns = parse_duration(text).map_err(|e| format!("{text:?} {e}"))?;
    if ns == 0 {
        return Err(format!(
            "{text:?} is zero; the cycle time is a positive multiple of 31.25 µs, e.g. \"1ms\""
        ));
    }
    if ns > MAX_CYCLE_NS {
        return Err(format!(
            "{text:?} is longer than the longest cycle time, 512 ms; use at most \"512ms\""
        ));
    }
    if !ns.is_multiple_of(CYCLE_UNIT_NS) {
        return Err(format!(
            "{text:?} is not a multiple of 31.25 µs; use e.g. {}",
            cycle_suggestions(ns)
        ));
    }
    Ok(ns)
}

fn deadline(text: &str, cycle_ns: u64) -> Result<u64, String> {
    let ns = parse_duration(text).map_err(|e| format!("{text:?} {e}"))?;
    let example = format_duration(cycle_ns / 2);
    if ns == 0 {
        return Err(format!(
            "{text:?} is zero; give the time clients have after the cycle start, e.g. \
             {example:?} (half the cycle), or leave it out for that default"
        ));
    }
    if ns >= cycle_ns {
        return Err(format!(
            "{text:?} is not shorter than the cycle time ({}); give a shorter deadline, e.g. \
             {example:?} (half the cycle), or leave it out for that default",
            format_duration(cycle_ns)
        ));
    }
    Ok(ns)
}

fn choose<T: Copy>(text: &str, what: &str, choices: &[(&str, T)]) -> Result<T, String> {
    if let Some((_, value)) = choices.iter().find(|(name, _)| *name == text) {
        return Ok(*value);
    }
    let names: Vec<String> = choices.iter().map(|(n, _)| format!("{n:?}")).collect();
    let list = match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        Some((last, _)) => last.clone(),
        None => String::new(),
    };
    Err(format!("{text:?} is not {what}; use {list}"))
}

fn interface_name(name: &str) -> Result<(), String> {
    let bad = |c: char| c == '/' || c == ':' || c.is_whitespace() || c.is_control();
    if name.is_empty() || name.len() > 15 || name == "." || name == ".." || name.contains(bad) {
        return Err(format!(
            "{name:?} is neither \"sim\" nor a network interface name (1 to 15 bytes without \
             '/', ':' or blanks); give the interface as `ip link` lists it, e.g. \"enp1s0\", or \
             \"sim\" for the simulated network"
        ));
    }
    Ok(())
}

fn interface_exists(check: crate::InterfaceCheck<'_>, name: &str) -> Result<(), String> {
    check(name).map_err(|missing| {
        if name == crate::pn_driver::ADAPTER_PLACEHOLDER {
            return "the PN Driver configuration names no network interface (PN Driver's \
                    program chooses its adapter): start procimgd with --adapter IFACE, as \
                    SERV_CP_startup does, or import it with `procimg config import FILE \
                    --network IFACE`"
                .to_owned();
        }
        format!(
            "{missing}; give one of them (as `ip link` lists it), or \"sim\" for the simulated \
             devices"
        )
    })
}

fn cycle_thread(raw: RawCycleThread, cx: &Cx<'_>) -> Result<CycleThreadConfig, ConfigError> {
    let mut config = CycleThreadConfig::default();
    if let Some(cpu) = raw.cpu {
        if let Ok(count) = std::thread::available_parallelism() {
            let count = count.get();
            if *cpu.get_ref() >= count {
                return Err(cx.invalid(
                    cpu.span(),
                    "cycle_thread.cpu",
                    format!(
                        "CPU {} does not exist: this machine has {count} CPUs, 0 to {}; choose \
                         one of them (best one isolated with isolcpus=) or leave cpu out",
                        cpu.get_ref(),
                        count - 1
                    ),
                ));
            }
        }
        config.cpu = Some(cpu.into_inner());
    }
    if let Some(priority) = raw.priority {
        if !(1..=99).contains(priority.get_ref()) {
            return Err(cx.invalid(
                priority.span(),
                "cycle_thread.priority",
                format!(
                    "{} is not a SCHED_FIFO priority; use 1 to 99 (default 80)",
                    priority.get_ref()
                ),
            ));
        }
        config.priority = priority.into_inner();
    }
    if let Some(priority) = raw.status_priority {
        if *priority.get_ref() > 99 {
            return Err(cx.invalid(
                priority.span(),
                "cycle_thread.status_priority",
                format!(
                    "{} is not a SCHED_FIFO priority; use 1 to 99, or 0 for normal priority \
                     (default 40)",
                    priority.get_ref()
                ),
            ));
        }
        config.status_priority = priority.into_inner();
    }
    if let Some(lock) = raw.lock_memory {
        config.lock_memory = lock;
    }
    if let Some(all) = raw.prefault_all {
        config.prefault_all = all;
    }
    if let Some(v) = &raw.opdone_wait {
        config.opdone_wait = cx.check(
            v,
            "cycle_thread.opdone_wait",
            choose(
                v.get_ref(),
                "a way to wait for OPDONE",
                &[
                    ("event", OpdoneWait::Event),
                    ("busy-poll", OpdoneWait::BusyPoll),
                ],
            ),
        )?;
    }
    if let Some(v) = &raw.opdone_spin {
        config.opdone_spin_ns = cx.check(
            v,
            "cycle_thread.opdone_spin",
            parse_duration(v.get_ref()).map_err(|e| {
                format!(
                    "{:?} {e}; give how long to poll before sleeping, e.g. \"20us\", or \"0\" \
                     to sleep at once",
                    v.get_ref()
                )
            }),
        )?;
    }
    Ok(config)
}

fn octal_mode(text: &str) -> Result<u32, String> {
    let digits = text.strip_prefix("0o").unwrap_or(text);
    if digits.is_empty() || !digits.bytes().all(|b| (b'0'..=b'7').contains(&b)) {
        return Err(format!(
            "{text:?} is not an octal mode; write it like \"0660\" or \"0640\""
        ));
    }
    let significant = digits.trim_start_matches('0');
    let mode = match u32::from_str_radix(significant, 8) {
        _ if significant.is_empty() => 0,
        Ok(mode) if mode <= 0o777 => mode,
        _ => {
            return Err(format!(
                "{text:?} has bits other than the permission bits (0777); give only those, \
                 e.g. \"0660\""
            ));
        }
    };
    Ok(mode)
}

fn group_name(name: &str) -> Result<(), String> {
    let bad = |c: char| c == ':' || c == '/' || c == ',' || c.is_whitespace() || c.is_control();
    if name.is_empty() || name.len() > 256 || name.contains(bad) {
        return Err(format!(
            "{name:?} is not a group name; give one `getent group` lists, or leave group out"
        ));
    }
    Ok(())
}

fn access(raw: RawAccess, cx: &Cx<'_>) -> Result<AccessConfig, ConfigError> {
    let mut config = AccessConfig::default();
    if let Some(group) = raw.group {
        cx.check(&group, "access.group", group_name(group.get_ref()))?;
        config.group = Some(group.into_inner());
        // A group is named to be given access: read and write, as the owner has.
        config.mode = 0o660;
    }
    if let Some(mode) = raw.mode {
        config.mode = cx.check(&mode, "access.mode", octal_mode(mode.get_ref()))?;
    }
    Ok(config)
}

#[cfg(test)]
mod tests {
    use super::devices::station_name;
    use super::*;

    #[test]
    fn station_names() {
        for good in [
            "echo",
            "io-device-1",
            "plc.line-1",
            "a",
            "port-01",
            "port-0011",
            "xport-001",
            "1.2.3",
            "1.2.3.4.5",
            "1234.1.1.1",
            "dev.port-001",
        ] {
            assert_eq!(station_name(good), Ok(()), "{good}");
        }
        let long_label = "a".repeat(64);
        let long_name = [
            "a".repeat(63),
            "a".repeat(63),
            "a".repeat(63),
            "a".repeat(50),
        ]
        .join(".");
        for bad in [
            "",
            "Echo",
            "echo_1",
            "-echo",
            "echo-",
            "a..b",
            ".a",
            "a.",
            "port-001",
            "port-001-00000",
            "port-001.plc",
            "192.168.0.1",
            "ä",
            long_label.as_str(),
            long_name.as_str(),
        ] {
            assert!(station_name(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn modes() {
        assert_eq!(octal_mode("0660"), Ok(0o660));
        assert_eq!(octal_mode("640"), Ok(0o640));
        assert_eq!(octal_mode("0o600"), Ok(0o600));
        assert_eq!(octal_mode("0"), Ok(0));
        assert_eq!(octal_mode("0000000000000777"), Ok(0o777));
        for bad in [
            "",
            "0o",
            "0668",
            "04770",
            "rw-rw----",
            "0x1ff",
            "-660",
            "7777777777777",
        ] {
            assert!(octal_mode(bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn interfaces() {
        assert_eq!(interface_name("enp1s0"), Ok(()));
        assert_eq!(interface_name("eth0.100"), Ok(()));
        for bad in ["", "a/b", "a b", "eth0:1", "abcdefghijklmnop", ".", ".."] {
            assert!(interface_name(bad).is_err(), "{bad:?}");
        }
    }
}
