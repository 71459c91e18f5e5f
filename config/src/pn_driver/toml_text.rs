// SPDX-License-Identifier: MIT OR Apache-2.0
//! The project written as procimgd's own configuration: TOML text, commented with the
//! objects and lines of the XML each table comes from, so that procimgd's checks (and a
//! reader) can be followed back to the project.

use std::fmt::Write;
use std::ops::Range;

use super::project::{Device, Problem, Project, Submodule};
use crate::address::LAST_ADDRESS;
use crate::{CYCLE_UNIT_NS, MAX_INTERFACE_ADDRESS, format_duration};

/// Writes `project` (from `origin`) as TOML, on interface `network`.
pub(super) fn write(project: &Project, origin: &str, network: &str) -> Result<String, Problem> {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "# procimgd's configuration, imported (`procimg config import`) from TIA Portal's PN\n\
         # Driver configuration {origin}\n\
         # Like PN Driver's, its controller starts OFFLINE: the program (or `procimg mode\n\
         # operate`) sets the mode. procimgd plans the wire itself (frame IDs, phases, AR and\n\
         # alarm parameters): the project's plan is PN Driver's."
    );
    let _ = writeln!(t, "network = {}", quoted(network));
    let _ = writeln!(t, "start_mode = \"offline\"");
    let base = project.devices.iter().map(|d| d.send_clock_factor).min();
    if let Some(scf) = base {
        let _ = writeln!(
            t,
            "# The devices' shortest send clock: send clock factor {scf} × 31.25 µs."
        );
        let _ = writeln!(
            t,
            "cycle_time = {}",
            quoted(&format_duration(u64::from(scf) * CYCLE_UNIT_NS))
        );
    }
    let mut book = AddressBook::new(project);
    interface(&mut t, project, &mut book);
    for d in &project.devices {
        device(&mut t, d, base.unwrap_or(d.send_clock_factor), &mut book)?;
    }
    Ok(t)
}

/// The I space's inputs and the diagnostic addresses given so far, so that a hardware
/// identifier becomes a diagnostic address only where it collides with nothing.
struct AddressBook {
    inputs: Vec<Range<u32>>,
    diagnostic: Vec<u32>,
}

impl AddressBook {
    fn new(project: &Project) -> AddressBook {
        let inputs = project
            .devices
            .iter()
            .flat_map(|d| &d.submodules)
            .filter_map(|s| {
                let a = s.input_address?;
                Some(a..a.saturating_add(u32::from(s.expected.input_length)))
            })
            .collect();
        AddressBook {
            inputs,
            diagnostic: Vec::new(),
        }
    }

    /// Takes `address` as a diagnostic address if it is free and at most `last`.
    fn take(&mut self, address: Option<u32>, last: u32) -> Option<u32> {
        let a = address?;
        let free = a <= last
            && !self.inputs.iter().any(|r| r.contains(&a))
            && !self.diagnostic.contains(&a);
        free.then(|| {
            self.diagnostic.push(a);
            a
        })
    }
}

fn interface(t: &mut String, project: &Project, book: &mut AddressBook) {
    let c = &project.controller;
    let _ = writeln!(t, "\n# The PN Driver's PROFINET interface.\n[interface]");
    if let Some(name) = &c.station_name {
        let _ = writeln!(t, "station_name = {}", quoted(name));
    }
    let _ = writeln!(t, "name_by_program = {}", c.name_by_program);
    let _ = writeln!(t, "address_by_program = {}", c.address_by_program);
    // The interface's and port's hardware identifiers name them, as in PN Driver, where
    // they are free in the I space (and differ).
    if let Some(a) = book.take(c.laddr, MAX_INTERFACE_ADDRESS) {
        let _ = writeln!(t, "diagnostic_address = {a}");
    }
    if let Some(a) = book.take(c.port_laddr, MAX_INTERFACE_ADDRESS) {
        let _ = writeln!(t, "port_diagnostic_address = {a}");
    }
    if let Some(ip) = c.ip.filter(|s| !s.ip.is_unspecified()) {
        let _ = writeln!(
            t,
            "# The project gives the interface {} netmask {}{}: procimgd speaks with the\n\
             # address its network interface has; give the interface this one (`ip addr add`).",
            ip.ip,
            ip.mask,
            if ip.gateway.is_unspecified() || ip.gateway == ip.ip {
                String::new()
            } else {
                format!(" router {}", ip.gateway)
            }
        );
    }
}

fn device(t: &mut String, d: &Device, base: u16, book: &mut AddressBook) -> Result<(), Problem> {
    let whole = u32::from(d.send_clock_factor) * u32::from(d.reduction_ratio);
    let base = u32::from(base.max(1));
    if !whole.is_multiple_of(base) {
        return Err(Problem {
            line: d.line,
            element: format!("Object \"{}\" (class 6)", d.object),
            message: format!(
                "its update time (send clock factor {} × reduction ratio {}) is no whole \
                 multiple of the shortest send clock factor {base}: procimgd runs one cycle",
                d.send_clock_factor, d.reduction_ratio
            ),
        });
    }
    let _ = writeln!(
        t,
        "\n# \"{}\": device number {}, line {} of the project.\n[[device]]",
        d.object, d.number, d.line
    );
    let _ = writeln!(t, "name = {}", quoted(&d.name));
    if let Some(ip) = d.ip {
        let _ = writeln!(t, "ip = {}", quoted(&ip.to_string()));
    } else if d.ip_at_device {
        let _ = writeln!(
            t,
            "# Its IP address is set directly at the device: the controller keeps the device's own."
        );
    }
    let _ = writeln!(t, "vendor_id = 0x{:04X}", d.identity.vendor_id);
    let _ = writeln!(t, "device_id = 0x{:04X}", d.identity.device_id);
    let _ = writeln!(t, "instance = {}", d.identity.instance);
    let _ = writeln!(t, "reduction_ratio = {}", whole / base);
    let _ = writeln!(t, "watchdog_factor = {}", d.watchdog_factor);
    if d.deactivated {
        let _ = writeln!(
            t,
            "# Deactivated in the project: it waits to be activated, or tailored in.\n\
             optional = true"
        );
    }
    if d.ar_records > 0 {
        let _ = writeln!(
            t,
            "# The project's {} AR record(s) (fast start-up) are not sent: the device starts \
             up as usual.",
            d.ar_records
        );
    }
    for s in &d.submodules {
        submodule(t, s, book);
    }
    Ok(())
}

fn submodule(t: &mut String, s: &Submodule, book: &mut AddressBook) {
    let e = &s.expected;
    match (&s.object, s.line) {
        (Some(name), Some(line)) => {
            let _ = writeln!(t, "\n# \"{name}\", line {line}.");
        }
        _ => {
            let _ = writeln!(t);
        }
    }
    let _ = writeln!(t, "[[device.submodule]]");
    if e.api != 0 {
        let _ = writeln!(t, "api = 0x{:X}", e.api);
    }
    let _ = writeln!(t, "slot = {}", e.slot);
    let _ = writeln!(t, "subslot = 0x{:X}", e.subslot);
    let _ = writeln!(t, "module_ident = 0x{:08X}", e.module_ident);
    let _ = writeln!(t, "submodule_ident = 0x{:08X}", e.submodule_ident);
    if e.input_length > 0 {
        let _ = writeln!(t, "input_length = {}", e.input_length);
        if let Some(a) = s.input_address {
            let _ = writeln!(t, "input_address = {a}");
        }
    }
    if e.output_length > 0 {
        let _ = writeln!(t, "output_length = {}", e.output_length);
        if let Some(a) = s.output_address {
            let _ = writeln!(t, "output_address = {a}");
        }
    }
    if e.input_length == 0
        && e.output_length == 0
        && let Some(a) = book.take(s.laddr, LAST_ADDRESS)
    {
        let _ = writeln!(t, "diagnostic_address = {a}");
    }
    if !s.records.is_empty() {
        let _ = writeln!(t, "records = [");
        for (index, data) in &s.records {
            let bytes: Vec<String> = data.iter().map(|b| format!("0x{b:02X}")).collect();
            let _ = writeln!(
                t,
                "  {{ index = 0x{index:04X}, data = [{}] }},",
                bytes.join(", ")
            );
        }
        let _ = writeln!(t, "]");
    }
}

/// `s` as a TOML basic string.
fn quoted(s: &str) -> String {
    toml::Value::String(s.to_owned()).to_string()
}
