// SPDX-License-Identifier: MIT OR Apache-2.0
//! The configuration file: the demo, every refusal with its line and key, address assignment,
//! durations, and no panics on any input.

use std::net::Ipv4Addr;

use procimg_config::{
    self as config, Config, ConfigError, DEMO_ORIGIN, DEMO_TOML, DurationError, LatePolicy,
    Network, OpdoneWait, OutputTiming, Peer, PortPeer, SimBehaviour, format_duration,
    parse_duration,
};
use procimg_shm_layout::{MAX_SUBMODULE_DATA_LEN, Mode, NO_ADDRESS};
use proptest::prelude::*;

/// [`config::load`] on a machine without network interfaces (the files these tests load
/// name none; the check with the machine's own interfaces is the runtime's test).
fn load(path: &std::path::Path) -> Result<Config, ConfigError> {
    config::load(path, &|name: &str| {
        Err(format!("no interface {name:?} here"))
    })
}

/// The 1-based line of the only line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    let hits: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(
        hits.len(),
        1,
        "{needle:?} should be on exactly one line of\n{text}"
    );
    hits[0]
}

fn parse(text: &str) -> Result<Config, ConfigError> {
    config::parse(text, "plant.toml")
}

#[track_caller]
fn refused(text: &str) -> ConfigError {
    match parse(text) {
        Ok(c) => panic!("accepted:\n{text}\n{c:#?}"),
        Err(e) => e,
    }
}

/// Asserts that `text` is refused on the line holding `needle`, for `key`, with `phrase` in
/// the message; returns the error.
#[track_caller]
fn refused_at(text: &str, needle: &str, key: &str, phrase: &str) -> ConfigError {
    let e = refused(text);
    let shown = e.to_string();
    assert_eq!(e.line(), Some(line_of(text, needle)), "line of: {shown}");
    assert_eq!(e.key(), Some(key), "key of: {shown}");
    assert!(shown.contains(phrase), "{phrase:?} not in: {shown}");
    let prefix = format!("plant.toml:{}: {key}: ", line_of(text, needle));
    assert!(
        shown.starts_with(&prefix),
        "{prefix:?} does not start: {shown}"
    );
    e
}

/// A device table with one submodule, for building test files.
fn device(name: &str, submodules: &str) -> String {
    format!("[[device]]\nname = \"{name}\"\nvendor_id = 0x0493\ndevice_id = 0x0001\n{submodules}")
}

fn submodule(slot: u16, extra: &str) -> String {
    format!(
        "[[device.submodule]]\nslot = {slot}\nsubslot = 1\nmodule_ident = 0x20\n\
         submodule_ident = 0x1\n{extra}\n"
    )
}

// ---------------------------------------------------------------------------------------------
// The demo.

#[test]
fn demo_parses_with_the_documented_addresses() {
    let demo = Config::demo();
    assert_eq!(config::parse(DEMO_TOML, DEMO_ORIGIN).unwrap(), demo);
    assert_eq!(demo.origin, "<built-in demo>");
    assert_eq!(demo.instance, "procimg");
    assert_eq!(demo.cycle_ns, 1_000_000);
    assert_eq!(demo.opdone_deadline_ns, 500_000);
    assert_eq!(demo.late_policy, LatePolicy::HoldLastOutputs);
    assert_eq!(demo.output_timing, OutputTiming::Immediately);
    assert_eq!(demo.start_mode, Mode::Operate);
    assert_eq!(demo.network, Network::Sim);
    assert_eq!(demo.cycle_thread.cpu, None);
    assert_eq!(demo.cycle_thread.priority, 80);
    assert!(demo.cycle_thread.lock_memory);
    assert_eq!(demo.access.mode, 0o600);
    assert_eq!(demo.access.group, None);
    assert_eq!(demo.submodule_count(), 7);

    let names: Vec<&str> = demo.devices.iter().map(|d| d.name.as_str()).collect();
    assert_eq!(names, ["echo", "counter", "dio"]);
    let sims: Vec<SimBehaviour> = demo.devices.iter().map(|d| d.sim).collect();
    assert_eq!(
        sims,
        [
            SimBehaviour::Echo,
            SimBehaviour::Counter,
            SimBehaviour::DigitalIo
        ]
    );
    for (i, d) in demo.devices.iter().enumerate() {
        assert_eq!(d.vendor_id, 0x0493);
        assert_eq!(d.device_id, i as u16 + 1);
        assert_eq!(d.ip, Some(Ipv4Addr::new(192, 168, 0, 11 + i as u8)));
        // The simulated devices run at normal priority: a generous watchdog.
        assert_eq!(
            (d.instance, d.reduction_ratio, d.watchdog_factor),
            (1, 1, 100)
        );
        // Ident numbers spelt out; tests/gsdml.rs checks them against config/gsdml/.
        assert_eq!(d.gsdml, None);
        let dap = &d.submodules[0];
        assert_eq!((dap.slot, dap.subslot), (0, 1));
        assert_eq!((dap.module_ident, dap.submodule_ident), (1, 1));
        assert_eq!((dap.input_length, dap.output_length), (0, 0));
        // No IO data: a diagnostic address after all inputs (I 0..21), in device order.
        assert_eq!(
            (dap.input_address, dap.output_address),
            (22 + i as u32, NO_ADDRESS)
        );
        assert_eq!(dap.diagnostic_address(), Some(22 + i as u32));
    }

    // (device, submodule) -> (module ident, input length, I address, output length, Q address)
    let io = |d: usize, s: usize| {
        let m = &demo.devices[d].submodules[s];
        // The echo's data is IRT (RT class 3), for the isochronous examples; the rest RT.
        let rt_class = if d == 0 { 3 } else { 1 };
        assert_eq!(
            (m.api, m.subslot, m.submodule_ident, m.rt_class),
            (0, 1, 1, rt_class)
        );
        (
            m.module_ident,
            m.input_length,
            m.input_address,
            m.output_length,
            m.output_address,
        )
    };
    // echo I 0..15 / Q 0..15
    assert_eq!(io(0, 1), (0x20, 16, 0, 16, 0));
    // counter I 16..19
    assert_eq!(io(1, 1), (0x30, 4, 16, 0, NO_ADDRESS));
    // dio I 20..21, Q 16..17
    assert_eq!(io(2, 1), (0x40, 2, 20, 0, NO_ADDRESS));
    assert_eq!(io(2, 2), (0x41, 0, NO_ADDRESS, 2, 16));
    assert_eq!(demo.devices[2].submodules[2].slot, 2);
}

#[test]
fn empty_file_gives_the_defaults() {
    let c = parse("").unwrap();
    assert_eq!(c.origin, "plant.toml");
    assert_eq!(c.instance, "procimg");
    assert_eq!(c.cycle_ns, 1_000_000);
    assert_eq!(c.opdone_deadline_ns, 500_000);
    assert_eq!(c.late_policy, LatePolicy::HoldLastOutputs);
    assert_eq!(c.output_timing, OutputTiming::Immediately);
    assert_eq!(c.start_mode, Mode::Operate);
    assert_eq!(c.network, Network::Sim);
    assert_eq!(
        (
            c.cycle_thread.cpu,
            c.cycle_thread.priority,
            c.cycle_thread.lock_memory,
            c.cycle_thread.prefault_all,
            c.cycle_thread.opdone_wait,
            c.cycle_thread.opdone_spin_ns
        ),
        (None, 80, true, false, OpdoneWait::Event, 20_000)
    );
    assert_eq!((c.access.mode, c.access.group), (0o600, None));
    assert!(c.devices.is_empty());
}

#[test]
fn every_key_is_read() {
    let text = r#"
instance = "line_2-b"
cycle_time = "31.25us"
opdone_deadline = "20us"
late_client_policy = "iops-bad"
send_outputs = "at-next-cycle-start"
start_mode = "clear"
network = "enp1s0"

[cycle_thread]
cpu = 0
priority = 99
lock_memory = false
prefault_all = true
opdone_wait = "busy-poll"
opdone_spin = "5us"

[access]
mode = "0640"
group = "plc"

[[device]]
name = "io.line-2"
ip = "10.0.0.7"
vendor_id = 0xFFFF
device_id = 65535
instance = 7
reduction_ratio = 512
watchdog_factor = 255
sim = "none"

[[device.submodule]]
api = 0x3A00
slot = 3
subslot = 0x8001
module_ident = 0xFFFFFFFF
submodule_ident = 4294967295
input_length = 1439
output_length = 1439
input_address = 0x100
output_address = 200
rt_class = 3
records = [ { index = 0x100, data = [1, 2, 0xFF] }, { index = 2, data = [] } ]
"#;
    let c = parse(text).unwrap();
    assert_eq!(c.instance, "line_2-b");
    assert_eq!((c.cycle_ns, c.opdone_deadline_ns), (31_250, 20_000));
    assert_eq!(c.late_policy, LatePolicy::IopsBad);
    assert_eq!(c.output_timing, OutputTiming::AtNextCycleStart);
    assert_eq!(c.start_mode, Mode::Clear);
    assert_eq!(c.network, Network::Interface("enp1s0".into()));
    assert_eq!(
        (
            c.cycle_thread.cpu,
            c.cycle_thread.priority,
            c.cycle_thread.lock_memory,
            c.cycle_thread.prefault_all,
            c.cycle_thread.opdone_wait,
            c.cycle_thread.opdone_spin_ns
        ),
        (Some(0), 99, false, true, OpdoneWait::BusyPoll, 5_000)
    );
    assert_eq!(
        (c.access.mode, c.access.group.as_deref()),
        (0o640, Some("plc"))
    );
    let d = &c.devices[0];
    assert_eq!(d.name, "io.line-2");
    assert_eq!(d.ip, Some(Ipv4Addr::new(10, 0, 0, 7)));
    assert_eq!((d.vendor_id, d.device_id, d.instance), (0xFFFF, 0xFFFF, 7));
    assert_eq!((d.reduction_ratio, d.watchdog_factor), (512, 255));
    assert_eq!(d.sim, SimBehaviour::None);
    let s = &d.submodules[0];
    assert_eq!((s.api, s.slot, s.subslot), (0x3A00, 3, 0x8001));
    assert_eq!((s.module_ident, s.submodule_ident), (u32::MAX, u32::MAX));
    assert_eq!((s.input_length, s.output_length), (1439, 1439));
    assert_eq!((s.input_address, s.output_address), (0x100, 200));
    assert_eq!(s.rt_class, 3);
    assert_eq!(s.records.len(), 2);
    assert_eq!(
        (s.records[0].index, &s.records[0].data[..]),
        (0x100, &[1, 2, 0xFF][..])
    );
    assert_eq!((s.records[1].index, s.records[1].data.len()), (2, 0));
}

// ---------------------------------------------------------------------------------------------
// Refusals of top-level values.

#[test]
fn bad_cycle_times() {
    let text = "instance = \"x\"\n\ncycle_time = \"1.1ms\"\n";
    let e = refused_at(
        text,
        "cycle_time",
        "cycle_time",
        "\"1.1ms\" is not a multiple of 31.25 µs; use e.g. \"1ms\" or \"1.125ms\"",
    );
    assert_eq!(
        e.to_string(),
        "plant.toml:3: cycle_time: \"1.1ms\" is not a multiple of 31.25 µs; use e.g. \"1ms\" or \
         \"1.125ms\""
    );
    for (value, phrase) in [
        ("0ms", "is zero"),
        ("0", "has no unit"),
        ("", "is not a duration"),
        ("-1ms", "is not a duration"),
        ("1 parsec", "unknown unit"),
        ("10us", "use e.g. \"31.25us\""),
        ("600ms", "512 ms"),
        ("512.03125ms", "512 ms"),
        ("99999999999999999999999s", "too long"),
    ] {
        refused_at(
            &format!("cycle_time = \"{value}\""),
            "cycle_time",
            "cycle_time",
            phrase,
        );
    }
    for (value, ns) in [
        ("512ms", 512_000_000),
        ("31.25us", 31_250),
        ("31250ns", 31_250),
        ("0.5ms", 500_000),
        ("0.25 s", 250_000_000),
        ("250µs", 250_000),
    ] {
        assert_eq!(
            parse(&format!("cycle_time = \"{value}\""))
                .unwrap()
                .cycle_ns,
            ns
        );
    }
    refused_at(
        "cycle_time = 1000",
        "cycle_time",
        "cycle_time",
        "expected a string",
    );
}

#[test]
fn bad_deadlines() {
    let text = "cycle_time = \"2ms\"\nopdone_deadline = \"2ms\"\n";
    refused_at(
        text,
        "opdone_deadline",
        "opdone_deadline",
        "\"2ms\" is not shorter than the cycle time (2ms); give a shorter deadline, e.g. \"1ms\"",
    );
    refused_at(
        "opdone_deadline = \"1.5ms\"",
        "opdone_deadline",
        "opdone_deadline",
        "not shorter than the cycle time (1ms)",
    );
    refused_at(
        "opdone_deadline = \"0ns\"",
        "opdone_deadline",
        "opdone_deadline",
        "is zero",
    );
    refused_at(
        "opdone_deadline = \"soon\"",
        "opdone_deadline",
        "opdone_deadline",
        "is not a duration",
    );
    let c = parse("cycle_time = \"4ms\"\nopdone_deadline = \"3999999ns\"").unwrap();
    assert_eq!(c.opdone_deadline_ns, 3_999_999);
    assert_eq!(
        parse("cycle_time = \"4ms\"").unwrap().opdone_deadline_ns,
        2_000_000
    );
}

#[test]
fn bad_top_level_choices() {
    for (text, key, phrase) in [
        ("instance = \"\"", "instance", "not an instance name"),
        ("instance = \"a b\"", "instance", "not an instance name"),
        (
            "instance = \"abcdefghijklmnopqrstuvwxyz0123456\"",
            "instance",
            "1 to 32 characters",
        ),
        (
            "late_client_policy = \"drop\"",
            "late_client_policy",
            "use \"hold-last-outputs\" or \"iops-bad\"",
        ),
        (
            "send_outputs = \"later\"",
            "send_outputs",
            "use \"immediately\" or \"at-next-cycle-start\"",
        ),
        (
            "start_mode = \"OPERATE\"",
            "start_mode",
            "use \"offline\", \"clear\" or \"operate\"",
        ),
        ("network = \"\"", "network", "\"enp1s0\""),
        ("network = \"a/b\"", "network", "1 to 15 bytes"),
        ("network = \"eth 0\"", "network", "1 to 15 bytes"),
        ("network = \"abcdefghijklmnop\"", "network", "1 to 15 bytes"),
    ] {
        refused_at(text, key, key, phrase);
    }
    let max = "a".repeat(32);
    assert_eq!(
        parse(&format!("instance = \"{max}\"")).unwrap().instance,
        max
    );
    assert_eq!(
        parse("network = \"abcdefghijklmno\"").unwrap().network,
        Network::Interface("abcdefghijklmno".into())
    );
}

#[test]
fn bad_cycle_thread_and_access() {
    let cpus = std::thread::available_parallelism().unwrap().get();
    let text = format!("[cycle_thread]\npriority = 50\ncpu = {cpus}\n");
    refused_at(&text, "cpu", "cycle_thread.cpu", "does not exist");
    let ok = format!("[cycle_thread]\ncpu = {}\n", cpus - 1);
    assert_eq!(parse(&ok).unwrap().cycle_thread.cpu, Some(cpus - 1));
    refused_at(
        "[cycle_thread]\ncpu = -1",
        "cpu",
        "cycle_thread.cpu",
        "invalid value",
    );

    for p in [0, 100, 255] {
        refused_at(
            &format!("[cycle_thread]\npriority = {p}"),
            "priority",
            "cycle_thread.priority",
            "use 1 to 99",
        );
    }
    refused_at(
        "[cycle_thread]\nopdone_wait = \"spin\"",
        "opdone_wait",
        "cycle_thread.opdone_wait",
        "use \"event\" or \"busy-poll\"",
    );
    refused_at(
        "[cycle_thread]\nopdone_spin = \"a while\"",
        "opdone_spin",
        "cycle_thread.opdone_spin",
        "e.g. \"20us\"",
    );
    refused_at(
        "[cycle_thread]\nprefault_all = \"some\"",
        "prefault_all",
        "cycle_thread.prefault_all",
        "expected a boolean",
    );
    refused_at(
        "[cycle_thread]\nlock_memory = \"yes\"",
        "lock_memory",
        "cycle_thread.lock_memory",
        "expected a boolean",
    );

    for (mode, phrase) in [
        ("0668", "not an octal mode"),
        ("rw-rw----", "not an octal mode"),
        ("", "not an octal mode"),
        ("04770", "bits other than the permission bits"),
        ("1777", "bits other than the permission bits"),
    ] {
        refused_at(
            &format!("[access]\nmode = \"{mode}\""),
            "mode",
            "access.mode",
            phrase,
        );
    }
    refused_at(
        "[access]\nmode = 0o660",
        "mode",
        "access.mode",
        "expected a string",
    );
    refused_at(
        "[access]\ngroup = \"a b\"",
        "group",
        "access.group",
        "not a group name",
    );
    assert_eq!(
        parse("[access]\nmode = \"0o600\"").unwrap().access.mode,
        0o600
    );
    // A group gets the owner's access unless a mode says otherwise.
    let grouped = parse("[access]\ngroup = \"plc\"").unwrap().access;
    assert_eq!(
        (grouped.mode, grouped.group.as_deref()),
        (0o660, Some("plc"))
    );
    refused_at(
        "[cycle_thread]\nstatus_priority = 100",
        "status_priority",
        "cycle_thread.status_priority",
        "not a SCHED_FIFO priority",
    );
    assert_eq!(
        parse("[cycle_thread]\nstatus_priority = 0")
            .unwrap()
            .cycle_thread
            .status_priority,
        0
    );
}

// ---------------------------------------------------------------------------------------------
// Refusals of devices and submodules.

#[test]
fn bad_device_values() {
    let cases = [
        ("name = \"Echo\"", "device[0].name", "lower case, \"echo\""),
        ("name = \"\"", "device[0].name", "the name is empty"),
        (
            "name = \"-echo\"",
            "device[0].name",
            "starting or ending with '-'",
        ),
        ("name = \"a..b\"", "device[0].name", "empty label"),
        (
            "name = \"port-001\"",
            "device[0].name",
            "reserved for port names",
        ),
        (
            "name = \"port-001-12345\"",
            "device[0].name",
            "reserved for port names",
        ),
        (
            "name = \"192.168.0.1\"",
            "device[0].name",
            "looks like an IPv4 address",
        ),
        ("name = \"io_1\"", "device[0].name", "contains '_'"),
        ("ip = \"192.168.0\"", "device[0].ip", "not an IPv4 address"),
        (
            "ip = \"0.0.0.0\"",
            "device[0].ip",
            "not an address a device can have",
        ),
        (
            "ip = \"224.0.0.1\"",
            "device[0].ip",
            "not an address a device can have",
        ),
        (
            "reduction_ratio = 3",
            "device[0].reduction_ratio",
            "power of two",
        ),
        (
            "reduction_ratio = 0",
            "device[0].reduction_ratio",
            "power of two",
        ),
        (
            "reduction_ratio = 1024",
            "device[0].reduction_ratio",
            "power of two",
        ),
        (
            "watchdog_factor = 2",
            "device[0].watchdog_factor",
            "use 3 to 255",
        ),
        (
            "watchdog_factor = 256",
            "device[0].watchdog_factor",
            "use 3 to 255",
        ),
        (
            "reduction_ratio = 65536",
            "device[0].reduction_ratio",
            "power of two from 1 to 512",
        ),
        ("sim = \"random\"", "device[0].sim", "\"digital-io\""),
        (
            "vendor_id = 0x10000",
            "device[0].vendor_id",
            "from 0 to 65535",
        ),
        (
            "device_id = \"1\"",
            "device[0].device_id",
            "invalid type: string",
        ),
    ];
    for (line, key, phrase) in cases {
        let field = line.split(' ').next().unwrap();
        let mut text = String::from("[[device]]\n");
        for default in ["name = \"ok\"", "vendor_id = 1", "device_id = 1"] {
            if !default.starts_with(&format!("{field} ")) {
                text.push_str(default);
                text.push('\n');
            }
        }
        text.push_str(line);
        text.push('\n');
        refused_at(&text, line, key, phrase);
    }
}

#[test]
fn missing_required_keys_name_the_table() {
    let text = format!("{}{}", device("a", ""), device("b", &submodule(1, ""))).replace(
        "device_id = 0x0001\n[[device.submodule]]",
        "[[device.submodule]]",
    );
    let e = refused(&text);
    assert_eq!(e.key(), Some("device[1]"));
    assert_eq!(e.line(), Some(line_of(&text, "name = \"b\"") - 1));
    assert!(
        e.to_string().contains("missing field `device_id`; add it"),
        "{e}"
    );

    let text = "[[device]]\nname = \"a\"\nvendor_id = 1\ndevice_id = 1\n\
                [[device.submodule]]\nslot = 1\nsubslot = 1\nmodule_ident = 1\n";
    let e = refused(text);
    assert_eq!(e.key(), Some("device[0].submodule[0]"));
    assert_eq!(e.line(), Some(line_of(text, "[[device.submodule]]")));
    assert!(e.to_string().contains("`submodule_ident`"), "{e}");
}

#[test]
fn bad_submodule_values() {
    let max = MAX_SUBMODULE_DATA_LEN;
    let cases = [
        (
            format!("input_length = {}", max + 1),
            "input_length",
            "split the data",
        ),
        (
            format!("output_length = {}", max + 1),
            "output_length",
            "1439",
        ),
        ("rt_class = 2".into(), "rt_class", "use 1 (default) or 3"),
        ("input_length = -1".into(), "input_length", "invalid value"),
        (
            "records = [{ index = 1 }]".into(),
            "records[0]",
            "missing field `data`",
        ),
        (
            "records = [{ index = 1, data = [256] }]".into(),
            "records[0].data[0]",
            "from 0 to 255",
        ),
        (
            "records = [{ index = 1, data = [], size = 3 }]".into(),
            "records[0].size",
            "unknown field `size`",
        ),
    ];
    for (line, key, phrase) in cases {
        let text = device("a", &submodule(1, &line));
        refused_at(
            &text,
            &line,
            &format!("device[0].submodule[0].{key}"),
            phrase,
        );
    }
    let text = device("a", &submodule(1, "")).replace("subslot = 1", "subslot = 0");
    refused_at(
        &text,
        "subslot",
        "device[0].submodule[0].subslot",
        "subslots count from 1",
    );
    let ok = device("a", &submodule(1, &format!("input_length = {max}")));
    assert_eq!(
        parse(&ok).unwrap().devices[0].submodules[0].input_length,
        max
    );
}

#[test]
fn duplicate_device_names() {
    let text = format!(
        "{}\n{}\n{}",
        device("echo", ""),
        device("other", ""),
        device("echo", "")
    );
    let e = refused(&text);
    assert_eq!(e.key(), Some("device[2].name"));
    assert_eq!(e.line(), Some(12));
    assert!(
        e.to_string()
            .contains("\"echo\" is already the name of device[0] (line 2)"),
        "{e}"
    );
}

#[test]
fn duplicate_slots() {
    let subs = format!(
        "{}{}{}",
        submodule(1, ""),
        submodule(2, ""),
        submodule(1, "# again")
    );
    let text = device("a", &subs);
    let e = refused(&text);
    assert_eq!(e.key(), Some("device[0].submodule[2].slot"));
    // On the slot line: the one after the header, four above the marker.
    assert_eq!(e.line(), Some(line_of(&text, "# again") - 4));
    assert!(
        e.to_string().contains(&format!(
            "slot 1 subslot 1 (api 0) is already used by submodule[0] of this device (line {})",
            line_of(&text, "name = \"a\"") + 4
        )),
        "{e}"
    );

    // The same slot in another API, or in another device, is fine.
    let subs = format!("{}{}", submodule(1, ""), submodule(1, "api = 1"));
    let text = format!("{}{}", device("a", &subs), device("b", &submodule(1, "")));
    parse(&text).unwrap();
}

#[test]
fn address_without_data() {
    let text = device("a", &submodule(1, "input_length = 2\noutput_address = 5"));
    refused_at(
        &text,
        "output_address",
        "device[0].submodule[0].output_address",
        "an output address is given but output_length is 0",
    );
    let text = device("a", &submodule(1, "output_length = 1\ninput_address = 0"));
    refused_at(
        &text,
        "input_address",
        "device[0].submodule[0].input_address",
        "input_length is 0",
    );
    // A submodule without any IO data is named by a diagnostic address instead.
    let text = device("a", &submodule(1, "input_address = 0"));
    refused_at(
        &text,
        "input_address",
        "device[0].submodule[0].input_address",
        "write diagnostic_address instead",
    );
    let text = device(
        "a",
        &submodule(1, "input_length = 1\ndiagnostic_address = 7"),
    );
    refused_at(
        &text,
        "diagnostic_address",
        "device[0].submodule[0].diagnostic_address",
        "a diagnostic address is for a submodule without IO data",
    );
}

#[test]
fn dataless_submodules_get_diagnostic_addresses_after_the_inputs() {
    let subs = [
        submodule(1, ""),                       // diag auto -> 7
        submodule(2, "input_length = 4"),       // I auto -> 0..3
        submodule(3, "diagnostic_address = 4"), // diag 4, one byte
        submodule(4, "input_length = 2"),       // I auto -> 5..6
        submodule(5, "output_length = 2"),      // Q only: no diag
        submodule(6, ""),                       // diag auto -> 8
    ]
    .concat();
    let c = parse(&device("a", &subs)).unwrap();
    let got: Vec<(u32, u32, Option<u32>)> = c.devices[0]
        .submodules
        .iter()
        .map(|s| (s.input_address, s.output_address, s.diagnostic_address()))
        .collect();
    let n = NO_ADDRESS;
    assert_eq!(
        got,
        [
            (7, n, Some(7)),
            (0, n, None),
            (4, n, Some(4)),
            (5, n, None),
            (n, 0, None),
            (8, n, Some(8)),
        ]
    );

    // A diagnostic address takes its byte of the I space: an input range may not cover it.
    let subs = [
        submodule(1, "diagnostic_address = 2"),
        submodule(2, "input_length = 4\ninput_address = 0"),
    ]
    .concat();
    refused_at(
        &device("a", &subs),
        "input_address = 0",
        "device[0].submodule[1].input_address",
        "overlaps I 2..2",
    );
}

#[test]
fn address_past_the_end() {
    for (address, length) in [(0xFFFF_FFFFu32, 1u16), (0xFFFF_FFF0, 16), (0xFFFF_FFFE, 2)] {
        let line = format!("input_address = 0x{address:X}");
        let text = device(
            "a",
            &submodule(1, &format!("input_length = {length}\n{line}")),
        );
        refused_at(
            &text,
            &line,
            "device[0].submodule[0].input_address",
            "runs past the last logical address 4294967294 (0xFFFFFFFE)",
        );
    }
    let text = device(
        "a",
        &submodule(1, "output_length = 16\noutput_address = 0xFFFFFFEF"),
    );
    let c = parse(&text).unwrap();
    assert_eq!(c.devices[0].submodules[0].output_address, 0xFFFF_FFEF);
    refused_at(
        &device(
            "a",
            &submodule(1, "input_length = 1\ninput_address = 0x100000000"),
        ),
        "input_address",
        "device[0].submodule[0].input_address",
        "from 0 to 4294967295",
    );
}

#[test]
fn overlapping_addresses() {
    let text = format!(
        "{}{}",
        device("echo", &submodule(1, "input_length = 2\ninput_address = 4")),
        device("b", &submodule(1, "input_length = 8\ninput_address = 0")),
    );
    let e = refused(&text);
    assert_eq!(
        e.to_string(),
        format!(
            "plant.toml:{}: device[1].submodule[0].input_address: I 0..7 overlaps I 4..5 of \
             device \"echo\" slot 1 subslot 1 (line {}); give one of them another address or \
             leave it out to have one assigned",
            line_of(&text, "input_address = 0"),
            line_of(&text, "input_address = 4"),
        )
    );
    assert_eq!(e.key(), Some("device[1].submodule[0].input_address"));

    // Within one device, in the Q space, touching from below.
    let subs = format!(
        "{}{}",
        submodule(1, "output_length = 4\noutput_address = 10"),
        submodule(2, "output_length = 4\noutput_address = 7"),
    );
    refused_at(
        &device("a", &subs),
        "output_address = 7",
        "device[0].submodule[1].output_address",
        "Q 7..10 overlaps Q 10..13 of device \"a\" slot 1 subslot 1",
    );

    // Adjacent ranges do not overlap; I and Q are independent spaces.
    let subs = format!(
        "{}{}",
        submodule(
            1,
            "input_length = 4\ninput_address = 0\noutput_length = 4\noutput_address = 0"
        ),
        submodule(
            2,
            "input_length = 4\ninput_address = 4\noutput_length = 4\noutput_address = 4"
        ),
    );
    let c = parse(&device("a", &subs)).unwrap();
    let s = &c.devices[0].submodules;
    assert_eq!((s[0].input_address, s[1].input_address), (0, 4));
    assert_eq!((s[0].output_address, s[1].output_address), (0, 4));
}

#[test]
fn explicit_and_automatic_addresses_mix() {
    // I space: explicit 4..5 and 10..19; automatic ones fill 0..3, 6..9, then 20.. (first fit,
    // in configuration order); the 5-byte one does not fit below 10 any more.
    let subs = [
        submodule(1, "input_length = 4"),                      // auto -> 0
        submodule(2, "input_length = 2\ninput_address = 4"),   // 4..5
        submodule(3, "input_length = 5"),                      // auto -> 20 (6..9 too small)
        submodule(4, "input_length = 10\ninput_address = 10"), // 10..19
        submodule(5, "input_length = 4"),                      // auto -> 6
        submodule(6, "input_length = 1"),                      // auto -> 25
        submodule(7, "output_length = 3\noutput_address = 1"), // Q 1..3
        submodule(8, "output_length = 1"),                     // Q auto -> 0
        submodule(9, "output_length = 2\ninput_length = 1"),   // Q auto -> 4, I auto -> 26
    ]
    .concat();
    let c = parse(&device("a", &subs)).unwrap();
    let got: Vec<(u32, u32)> = c.devices[0]
        .submodules
        .iter()
        .map(|s| (s.input_address, s.output_address))
        .collect();
    let n = NO_ADDRESS;
    assert_eq!(
        got,
        [
            (0, n),
            (4, n),
            (20, n),
            (10, n),
            (6, n),
            (25, n),
            (n, 1),
            (n, 0),
            (26, 4)
        ]
    );

    // Automatic addresses also work around explicit ones of later devices.
    let text = format!(
        "{}{}",
        device("a", &submodule(1, "input_length = 8")),
        device("b", &submodule(1, "input_length = 4\ninput_address = 2")),
    );
    let c = parse(&text).unwrap();
    assert_eq!(c.devices[0].submodules[0].input_address, 6);
    assert_eq!(c.devices[1].submodules[0].input_address, 2);
}

#[test]
fn too_many_devices() {
    let mut text = String::new();
    for i in 0..257 {
        text.push_str(&device(&format!("d{i}"), ""));
    }
    let e = refused(&text);
    assert_eq!(e.key(), Some("device[256]"));
    assert_eq!(e.line(), Some(256 * 4 + 1));
    assert!(e.to_string().contains("more than the 256"), "{e}");

    let fits: String = (0..256).map(|i| device(&format!("d{i}"), "")).collect();
    assert_eq!(parse(&fits).unwrap().devices.len(), 256);
}

#[test]
fn too_many_submodules() {
    // 16 devices of 256 submodules fit; one more submodule does not.
    let mut text = String::new();
    for d in 0..16 {
        let subs: String = (0..256).map(|s| submodule(s, "")).collect();
        text.push_str(&device(&format!("d{d}"), &subs));
    }
    let c = parse(&text).unwrap();
    assert_eq!(c.submodule_count(), 4096);
    text.push_str(&device("last", &submodule(0, "# the 4097th")));
    let e = refused(&text);
    assert_eq!(e.key(), Some("device[16].submodule[0]"));
    assert_eq!(e.line(), Some(line_of(&text, "# the 4097th") - 5));
    assert!(e.to_string().contains("over the limit of 4096"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// TOML errors.

#[test]
fn syntax_errors_name_their_line() {
    let text = "cycle_time = \"1ms\"\n\n[cycle_thread\npriority = 80\n";
    let e = refused(text);
    assert!(matches!(e, ConfigError::Syntax { .. }), "{e:?}");
    assert_eq!(e.line(), Some(3));
    assert!(e.to_string().starts_with("plant.toml:3"), "{e}");

    let text = "cycle_time = \"1ms\"\nnetwork = sim\n";
    let e = refused(text);
    assert_eq!(e.line(), Some(2));
    assert!(e.to_string().contains("toml.io"), "{e}");

    let text = "cycle_time = \"1ms\"\ncycle_time = \"2ms\"\n";
    let e = refused(text);
    assert_eq!((e.line(), e.key()), (Some(2), Some("cycle_time")));
    assert!(
        e.to_string().contains("duplicate key; give each key once"),
        "{e}"
    );

    let text = "cycle_time = \"1ms\n";
    assert_eq!(refused(text).line(), Some(1));
}

#[test]
fn unknown_keys_name_their_line_and_key() {
    let cases = [
        ("cycletime = \"1ms\"", "cycletime"),
        ("[cycle_thread]\ncore = 1", "cycle_thread.core"),
        ("[access]\nuser = \"x\"", "access.user"),
        ("[nonsense]\na = 1", "nonsense"),
    ];
    for (text, key) in cases {
        let last = key.rsplit('.').next().unwrap();
        let needle = if key == "nonsense" {
            "[nonsense]"
        } else {
            last
        };
        refused_at(text, needle, key, &format!("unknown field `{last}`"));
    }
    let text = format!(
        "{}{}",
        device("a", ""),
        device("b", &submodule(1, "input_lenght = 2"))
    );
    refused_at(
        &text,
        "input_lenght",
        "device[1].submodule[0].input_lenght",
        "unknown field `input_lenght`, expected one of",
    );
    let text = format!("{}colour = \"red\"\n", device("a", ""));
    let e = refused_at(
        &text,
        "colour",
        "device[0].colour",
        "remove it or correct its spelling",
    );
    assert!(matches!(e, ConfigError::Syntax { .. }));
}

#[test]
fn single_bracket_device_is_explained() {
    let text = "[device]\nname = \"a\"\nvendor_id = 1\ndevice_id = 1\n";
    let e = refused(text);
    assert_eq!(e.key(), Some("device"));
    assert_eq!(e.line(), Some(1));
    assert!(e.to_string().contains("double brackets"), "{e}");
}

// ---------------------------------------------------------------------------------------------
// Files.

#[test]
fn load_reads_files_and_names_them() {
    let dir = std::env::temp_dir().join(format!("procimg-config-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("plant.toml");
    std::fs::write(&path, DEMO_TOML).unwrap();
    let c = load(&path).unwrap();
    assert_eq!(c.origin, path.display().to_string());
    assert_eq!(c.devices, Config::demo().devices);

    std::fs::write(&path, "cycle_time = \"0ms\"\n").unwrap();
    let e = load(&path).unwrap_err();
    assert!(
        e.to_string()
            .starts_with(&format!("{}:1: cycle_time: ", path.display())),
        "{e}"
    );

    let missing = dir.join("missing.toml");
    let e = load(&missing).unwrap_err();
    assert!(matches!(e, ConfigError::Read { .. }), "{e:?}");
    assert_eq!((e.line(), e.key()), (None, None));
    let shown = e.to_string();
    assert!(
        shown.starts_with(&format!("cannot read {}: ", missing.display())),
        "{shown}"
    );
    assert!(shown.contains("--print-demo-config"), "{shown}");
    // The OS error is in the message, once, also where procimgd prints the whole chain
    // (its error and every source).
    let mut chain = e.to_string();
    let mut source = std::error::Error::source(&e);
    while let Some(s) = source {
        chain.push_str(&format!(": {s}"));
        source = s.source();
    }
    assert_eq!(chain.matches("os error").count(), 1, "{chain}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn watchdog_factor_takes_the_documented_range() {
    let with = |value: &str| {
        format!(
            "[[device]]\nname = \"ok\"\nvendor_id = 1\ndevice_id = 1\nwatchdog_factor = {value}\n"
        )
    };
    assert_eq!(parse(&with("3")).unwrap().devices[0].watchdog_factor, 3);
    assert_eq!(parse(&with("255")).unwrap().devices[0].watchdog_factor, 255);
    // Values the key's type could hold and values it could not are refused alike, with the
    // range the README gives, not the one of a 16-bit integer.
    for value in [
        "0",
        "1",
        "2",
        "256",
        "7680",
        "65535",
        "65536",
        "-1",
        "99999999999",
    ] {
        let text = with(value);
        let e = refused_at(
            &text,
            "watchdog_factor",
            "device[0].watchdog_factor",
            "use 3 to 255 (default 3)",
        );
        assert!(!e.to_string().contains("0 to 65535"), "{e}");
    }
    refused_at(
        &with("\"3\""),
        "watchdog_factor",
        "device[0].watchdog_factor",
        "expected an integer",
    );
    // The README's configuration reference says the same.
    let readme = include_str!("../../README.md");
    let row = readme
        .lines()
        .find(|l| l.starts_with("| `watchdog_factor`"))
        .expect("the README documents watchdog_factor");
    assert!(row.contains("(3–255)"), "{row}");
}

// ---------------------------------------------------------------------------------------------
// Durations.

#[test]
fn durations() {
    for (text, ns) in [
        ("1ms", 1_000_000),
        ("250us", 250_000),
        ("250µs", 250_000),
        ("250μs", 250_000),
        ("31.25us", 31_250),
        ("0.5ms", 500_000),
        ("1s", 1_000_000_000),
        ("1.5s", 1_500_000_000),
        ("7ns", 7),
        ("0ns", 0),
        ("  2 ms ", 2_000_000),
        (
            "1.000000000000000000000000000000000000000000000000ms",
            1_000_000,
        ),
        (
            "000000000000000000000000000000000000000000000001ms",
            1_000_000,
        ),
        ("0.000000001s", 1),
        ("18446744073709551615ns", u64::MAX),
        ("18446744073.709551615s", u64::MAX),
    ] {
        assert_eq!(parse_duration(text), Ok(ns), "{text:?}");
    }
    for (text, error) in [
        ("", DurationError::BadNumber),
        ("ms", DurationError::BadNumber),
        (".5ms", DurationError::BadNumber),
        ("1.ms", DurationError::BadNumber),
        ("1..5ms", DurationError::BadNumber),
        ("1.2.3ms", DurationError::BadNumber),
        ("-1ms", DurationError::BadNumber),
        ("+1ms", DurationError::BadNumber),
        ("1e3us", DurationError::UnknownUnit),
        ("1", DurationError::MissingUnit),
        ("1 ", DurationError::MissingUnit),
        ("1 m s", DurationError::UnknownUnit),
        ("1MS", DurationError::UnknownUnit),
        ("1min", DurationError::UnknownUnit),
        ("1ms1", DurationError::UnknownUnit),
        ("0.1ns", DurationError::NotWholeNanoseconds),
        ("0.0000000001s", DurationError::NotWholeNanoseconds),
        ("1.0001us", DurationError::NotWholeNanoseconds),
        ("18446744073709551616ns", DurationError::TooLarge),
        ("18446744074s", DurationError::TooLarge),
        (
            "999999999999999999999999999999999999999999ms",
            DurationError::TooLarge,
        ),
    ] {
        assert_eq!(parse_duration(text), Err(error), "{text:?}");
    }
}

proptest! {
    #[test]
    fn parse_never_panics(text in any::<String>()) {
        let _ = parse(&text);
    }

    #[test]
    fn parse_never_panics_on_plausible_files(
        lines in prop::collection::vec(
            prop_oneof![
                Just("[[device]]".to_owned()),
                Just("[[device.submodule]]".to_owned()),
                Just("[cycle_thread]".to_owned()),
                Just("[access]".to_owned()),
                "(name|ip|sim|network|cycle_time|opdone_deadline|mode|group|start_mode) = \"[a-z0-9.:/ µ-]{0,12}\"",
                "(vendor_id|device_id|slot|subslot|module_ident|submodule_ident|input_length|output_length|input_address|output_address|rt_class|priority|cpu|api|reduction_ratio|watchdog_factor|instance) = -?[0-9]{1,11}",
                "(input_address|output_address) = 0xFFFFFF[0-9A-F]{2}",
                "records = \\[\\{ index = [0-9]{1,6}, data = \\[[0-9]{1,3}\\] \\}\\]",
                Just("gsdml = \"tests/fixtures/gsdml/sample-16real-32bool.xml\"".to_owned()),
                "(module|submodule|dap) = \"(in1|in2|out3|out4|M1|M1_SM|DAP1|DAP1_IF|pnio DAP|x)\"",
                "[a-z_\\[\\]={}\" .0-9]{0,20}",
            ],
            0..40,
        )
    ) {
        let _ = parse(&lines.join("\n"));
    }

    #[test]
    fn duration_parser_never_panics(text in any::<String>()) {
        let _ = parse_duration(&text);
    }

    #[test]
    fn duration_parser_never_panics_on_plausible_text(text in "[0-9.]{0,30} ?(ns|us|µs|ms|s|x|)") {
        let _ = parse_duration(&text);
    }

    #[test]
    fn durations_round_trip(ns in any::<u64>()) {
        prop_assert_eq!(parse_duration(&format_duration(ns)), Ok(ns));
    }

    #[test]
    fn every_error_has_a_line_and_key(
        field in "(cycle_time|opdone_deadline|network|instance|start_mode)",
        value in "[a-z0-9. ]{0,10}",
    ) {
        let text = format!("# comment\n{field} = \"{value}\"\n");
        if let Err(e) = parse(&text) {
            prop_assert_eq!(e.line(), Some(2));
            prop_assert_eq!(e.key(), Some(field.as_str()));
        }
    }
}

#[test]
fn every_simulated_behaviour_is_read_by_its_documented_name() {
    for behaviour in [
        SimBehaviour::None,
        SimBehaviour::Echo,
        SimBehaviour::Counter,
        SimBehaviour::DigitalIo,
        SimBehaviour::Absent,
    ] {
        let text = format!(
            "network = \"sim\"\n[[device]]\nname = \"ok\"\nvendor_id = 1\ndevice_id = 1\n\
             sim = \"{}\"\n",
            behaviour.as_str()
        );
        assert_eq!(parse(&text).unwrap().devices[0].sim, behaviour, "{text}");
    }
}

// ---------------------------------------------------------------------------------------------
// The topology a device's ports are to have.

/// A device with its access point's interface and two ports, and `topology`.
fn device_with_ports(topology: &str) -> String {
    let mut text = device("io-1", "");
    for subslot in [1, 0x8000, 0x8001, 0x8002] {
        text += &format!(
            "[[device.submodule]]\nslot = 0\nsubslot = {subslot:#06x}\nmodule_ident = 1\n\
             submodule_ident = {subslot:#06x}\n"
        );
    }
    text + topology
}

#[test]
fn a_ports_neighbour_defaults_to_the_first_port() {
    let c = parse(&device_with_ports(
        "[[device.topology]]\nstation = \"plc\"\nport = \"port-001\"\n\
         [[device.topology]]\nsubslot = 0x8002\nstation = \"switch-1\"\nport = \"port-007\"\n",
    ))
    .unwrap();
    let peers: Vec<(u16, &str, &str)> = c.devices[0]
        .topology
        .iter()
        .map(|p| match &p.peer {
            Peer::Fixed { station, port } => (p.subslot, station.as_str(), port.as_str()),
            Peer::Programmable => panic!("no programmable peer here"),
        })
        .collect();
    assert_eq!(
        peers,
        [
            (0x8001, "plc", "port-001"),
            (0x8002, "switch-1", "port-007")
        ]
    );
}

#[test]
fn optional_devices_and_programmable_peers_are_read() {
    let text = device_with_ports("[[device.topology]]\nsubslot = 0x8002\nprogrammable = true\n")
        .replacen(
            "[[device.submodule]]",
            "optional = true\n[[device.submodule]]",
            1,
        );
    let c = parse(&text).unwrap();
    assert!(c.devices[0].optional);
    assert_eq!(
        c.devices[0].topology,
        [PortPeer {
            subslot: 0x8002,
            peer: Peer::Programmable
        }]
    );
    assert!(!parse(&device_with_ports("")).unwrap().devices[0].optional);
    let both = device_with_ports(
        "[[device.topology]]\nprogrammable = true\nstation = \"plc\"\nport = \"port-001\"\n",
    );
    refused_at(
        &both,
        "[[device.topology]]",
        "device[0].topology[0]",
        "leave out station and port",
    );
    let neither = device_with_ports("[[device.topology]]\nsubslot = 0x8001\n");
    refused_at(
        &neither,
        "[[device.topology]]",
        "device[0].topology[0]",
        "programmable = true",
    );
}

#[test]
fn bad_topology() {
    let text = device_with_ports(
        "[[device.topology]]\nsubslot = 0x8005\nstation = \"plc\"\nport = \"port-001\"\n",
    );
    refused_at(
        &text,
        "subslot = 0x8005",
        "device[0].topology[0].subslot",
        "0x8001, 0x8002",
    );
    let text = device_with_ports("[[device.topology]]\nstation = \"PLC\"\nport = \"port-001\"\n");
    refused_at(
        &text,
        "station = \"PLC\"",
        "device[0].topology[0].station",
        "lower case",
    );
    let text = device_with_ports("[[device.topology]]\nstation = \"plc\"\nport = \"\"\n");
    refused_at(
        &text,
        "port = \"\"",
        "device[0].topology[0].port",
        "not a port name",
    );
    let text = device("io-1", &submodule(1, ""))
        + "[[device.topology]]\nstation = \"plc\"\nport = \"port-001\"\n";
    refused_at(
        &text,
        "[[device.topology]]",
        "device[0].topology[0]",
        "no port submodule",
    );
}

// ---------------------------------------------------------------------------------------------
// The controller's own interface.

#[test]
fn the_controllers_interface() {
    let c = parse("instance = \"Line_1\"").unwrap();
    assert_eq!(c.controller_station_name(), "procimgd-line-1");
    assert_eq!(
        (
            c.interface.diagnostic_address,
            c.interface.port_diagnostic_address
        ),
        (16382, 16381)
    );
    assert!(!c.interface.name_by_program && !c.interface.address_by_program);

    let text = "[interface]\nstation_name = \"plc-1\"\nname_by_program = true\n\
                address_by_program = true\ncheck_link = true\ndiagnostic_address = 100\n\
                port_diagnostic_address = 101\n"
        .to_owned()
        + &device("io-1", &submodule(1, "input_length = 4"))
        + "[[device.submodule]]\nslot = 0\nsubslot = 0x8002\nmodule_ident = 1\n\
           submodule_ident = 2\n"
        + "[[device.topology]]\nsubslot = 0x8002\nstation = \"plc-1\"\nport = \"port-001\"\n";
    let c = parse(&text).unwrap();
    assert_eq!(c.controller_station_name(), "plc-1");
    assert!(c.interface.name_by_program && c.interface.address_by_program);
    assert!(c.interface.check_link);
    assert_eq!(c.controller_port_peer(), Some(("io-1", 0x8002)));

    // Its addresses are clear of the devices' inputs and of each other.
    let taken = "[interface]\ndiagnostic_address = 2\n".to_owned()
        + &device("io-1", &submodule(1, "input_length = 4"));
    refused_at(
        &taken,
        "diagnostic_address = 2",
        "interface.diagnostic_address",
        "io-1 slot 1",
    );
    // A default that inputs have taken moves below them; with the I space up to 32767
    // theirs, above them.
    let default_taken = device(
        "io-1",
        &submodule(1, "input_length = 4\ninput_address = 16380"),
    );
    let c = parse(&default_taken).unwrap();
    assert_eq!(
        (
            c.interface.diagnostic_address,
            c.interface.port_diagnostic_address
        ),
        (16379, 16378)
    );
    let full: String = (0..23)
        .map(|k| {
            device(
                &format!("io-{k}"),
                &submodule(
                    1,
                    &format!("input_length = 1439\ninput_address = {}", k * 1439),
                ),
            )
        })
        .collect();
    let c = parse(&full).unwrap();
    assert_eq!(
        (
            c.interface.diagnostic_address,
            c.interface.port_diagnostic_address
        ),
        (23 * 1439, 23 * 1439 + 1)
    );
    refused_at(
        "[interface]\ndiagnostic_address = 40000\n",
        "40000",
        "interface.diagnostic_address",
        "0 to 32767",
    );
    refused_at(
        "[interface]\ndiagnostic_address = 7\nport_diagnostic_address = 7\n",
        "port_diagnostic_address = 7",
        "interface.port_diagnostic_address",
        "of their own",
    );
    refused_at(
        "[interface]\nstation_name = \"Bad Name\"\n",
        "Bad Name",
        "interface.station_name",
        "Bad Name",
    );
    // The device role's station is [station].
    refused_at(
        "role = \"device\"\n[interface]\nname_by_program = true\n",
        "[interface]",
        "interface",
        "[station]",
    );
}
