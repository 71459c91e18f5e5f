// SPDX-License-Identifier: MIT OR Apache-2.0
//! The checks of `[[device]]` and `[[device.submodule]]`: station names, addresses, timing,
//! the GSDML import and its agreement with what the file says, IO lengths and addresses.

use super::*;

/// Checks a PROFINET NameOfStation.
pub(super) fn station_name(name: &str) -> Result<(), String> {
    const HOW: &str = "a station name is 1 to 240 characters: labels of a-z, 0-9 and '-' (1 to \
                       63 each, not starting or ending with '-') separated by '.', e.g. \
                       \"io-device-1\"";
    if name.is_empty() {
        return Err(format!("the name is empty; {HOW}"));
    }
    if let Some(c) = name
        .chars()
        .find(|&c| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '.'))
    {
        let hint = if name.chars().any(|c| c.is_ascii_uppercase()) {
            format!("; write it in lower case, {:?}", name.to_lowercase())
        } else {
            String::new()
        };
        return Err(format!("{name:?} contains {c:?}; {HOW}{hint}"));
    }
    if name.len() > 240 {
        return Err(format!("{name:?} is {} characters long; {HOW}", name.len()));
    }
    let labels: Vec<&str> = name.split('.').collect();
    for label in &labels {
        if label.is_empty() {
            return Err(format!(
                "{name:?} has an empty label (a '.' at the start or end, or two in a row); {HOW}"
            ));
        }
        if label.len() > 63 {
            return Err(format!(
                "{name:?} has a label longer than 63 characters; {HOW}"
            ));
        }
        if label.starts_with('-') || label.ends_with('-') {
            return Err(format!(
                "{name:?} has a label {label:?} starting or ending with '-'; {HOW}"
            ));
        }
    }
    if labels.first().is_some_and(|first| is_port_name(first)) {
        return Err(format!(
            "{name:?} has the form \"port-xyz\" or \"port-xyz-abcde\" reserved for port names; \
             choose another name"
        ));
    }
    let numeric = |l: &&str| (1..=3).contains(&l.len()) && l.bytes().all(|b| b.is_ascii_digit());
    if labels.len() == 4 && labels.iter().all(numeric) {
        return Err(format!(
            "{name:?} looks like an IPv4 address, which a station name may not; give the \
             address as `ip` and choose a name such as \"io-device-1\""
        ));
    }
    Ok(())
}

/// `port-xyz` or `port-xyz-abcde` with digits x..e: reserved for port names (IEC 61158-6-10).
fn is_port_name(label: &str) -> bool {
    let Some(rest) = label.strip_prefix("port-") else {
        return false;
    };
    let digits = |s: &str, n: usize| s.len() == n && s.bytes().all(|b| b.is_ascii_digit());
    match rest.split_once('-') {
        None => digits(rest, 3),
        Some((xyz, abcde)) => digits(xyz, 3) && digits(abcde, 5),
    }
}

pub(super) fn device_ip(text: &str) -> Result<Ipv4Addr, String> {
    let ip: Ipv4Addr = text.parse().map_err(|_| {
        format!("{text:?} is not an IPv4 address; write it like \"192.168.0.10\", or leave ip out")
    })?;
    if ip.is_unspecified() || ip.is_broadcast() || ip.is_multicast() || ip.is_loopback() {
        return Err(format!(
            "{text:?} is not an address a device can have; give a unicast address such as \
             \"192.168.0.10\", or leave ip out"
        ));
    }
    Ok(ip)
}

fn reduction_ratio(value: i64) -> Result<u16, String> {
    match u16::try_from(value) {
        Ok(ratio) if ratio.is_power_of_two() && ratio <= 512 => Ok(ratio),
        _ => Err(format!(
            "{value} is not a reduction ratio; use a power of two from 1 to 512 (1, 2, 4, ..., 512)"
        )),
    }
}

/// The range of `watchdog_factor`, as the README documents it: PROFINET allows a
/// DataHoldFactor of 1 to 0x1E00, but fewer than 3 frame periods fail a device on one late
/// frame, and 3 to 255 is what engineering tools offer ("accepted update cycles without IO
/// data").
const WATCHDOG_FACTORS: core::ops::RangeInclusive<i64> = 3..=255;

fn watchdog_factor(value: i64) -> Result<u16, String> {
    match u16::try_from(value) {
        Ok(factor) if WATCHDOG_FACTORS.contains(&value) => Ok(factor),
        _ => Err(format!(
            "{value} is not a watchdog factor (the frame periods without data before the device \
             counts as failed); use {} to {} (default 3)",
            WATCHDOG_FACTORS.start(),
            WATCHDOG_FACTORS.end()
        )),
    }
}

pub(super) fn data_length(value: u16, noun: &str) -> Result<u16, String> {
    if value > MAX_SUBMODULE_DATA_LEN {
        return Err(format!(
            "{value} bytes of {noun} data are more than the {MAX_SUBMODULE_DATA_LEN} one \
             submodule can have (a frame carries at most 1440 bytes of data and status); split \
             the data over several submodules"
        ));
    }
    Ok(value)
}

/// The logical addresses of `named` submodules (with their device's name and their draft),
/// in the I space and in the Q space, in their order.
pub(super) fn addresses(
    cx: &Cx<'_>,
    named: &[(&str, &Draft, &SubmoduleConfig)],
) -> Result<[Vec<u32>; 2], ConfigError> {
    let place = |space: Space| {
        let items: Vec<Item<'_>> = named
            .iter()
            .map(|&(device_name, draft, sub)| {
                let diagnostic = space == Space::Input && sub.has_no_data();
                let (length, explicit) = match space {
                    Space::Input if diagnostic => (0, draft.diagnostic_address.clone()),
                    Space::Input => (sub.input_length, draft.input_address.clone()),
                    Space::Output => (sub.output_length, draft.output_address.clone()),
                };
                Item {
                    key: &draft.key,
                    device_name,
                    slot: sub.slot,
                    subslot: sub.subslot,
                    length,
                    span: draft.span.clone(),
                    explicit,
                    diagnostic,
                }
            })
            .collect();
        address::assign(cx, space, &items)
    };
    Ok([place(Space::Input)?, place(Space::Output)?])
}

/// A submodule checked on its own, with what address assignment needs.
pub(super) struct Draft {
    pub key: String,
    pub span: Range<usize>,
    pub input_address: Option<(u32, Range<usize>)>,
    pub output_address: Option<(u32, Range<usize>)>,
    pub diagnostic_address: Option<(u32, Range<usize>)>,
}

pub(super) fn devices(
    raw: Vec<Spanned<RawDevice>>,
    cx: &Cx<'_>,
) -> Result<Vec<DeviceConfig>, ConfigError> {
    if let Some(extra) = raw.get(MAX_DEVICES) {
        return Err(cx.invalid(
            extra.span(),
            format!("device[{MAX_DEVICES}]"),
            format!(
                "the IO system has {} devices, more than the {MAX_DEVICES} one server supports; \
                 split it over several server instances",
                raw.len()
            ),
        ));
    }
    let mut total = 0usize;
    for (d, device) in raw.iter().enumerate() {
        for (s, submodule) in device.get_ref().submodule.iter().enumerate() {
            total += 1;
            if total > MAX_SUBMODULES {
                return Err(cx.invalid(
                    submodule.span(),
                    format!("device[{d}].submodule[{s}]"),
                    format!(
                        "this is submodule number {total}, over the limit of {MAX_SUBMODULES} \
                         per server; split the IO system over several server instances"
                    ),
                ));
            }
        }
    }

    let mut names: HashMap<String, (usize, usize)> = HashMap::new();
    let mut files = Files::new(cx.dir);
    let mut devices = Vec::with_capacity(raw.len());
    let mut drafts: Vec<Vec<Draft>> = Vec::with_capacity(raw.len());
    let mut total = 0usize;
    for (d, device) in raw.into_iter().enumerate() {
        let span = device.span();
        let (config, device_drafts) =
            device_config(d, span, device.into_inner(), cx, &mut names, &mut files)?;
        // The DAP submodules a GSDML file adds count too.
        total += config.submodules.len();
        if total > MAX_SUBMODULES {
            let at = device_drafts.first().map_or(0..0, |dr| dr.span.clone());
            return Err(cx.invalid(
                at,
                format!("device[{d}].gsdml"),
                format!(
                    "with the device access point submodules its GSDML file adds, the IO \
                     system has {total} submodules, over the limit of {MAX_SUBMODULES} per \
                     server; split it over several server instances"
                ),
            ));
        }
        devices.push(config);
        drafts.push(device_drafts);
    }

    let named: Vec<(&str, &Draft, &SubmoduleConfig)> = devices
        .iter()
        .zip(&drafts)
        .flat_map(|(device, device_drafts)| {
            device_drafts
                .iter()
                .zip(&device.submodules)
                .map(|(draft, sub)| (device.name.as_str(), draft, sub))
        })
        .collect();
    let [inputs, outputs] = addresses(cx, &named)?;
    let targets = devices.iter_mut().flat_map(|d| d.submodules.iter_mut());
    for ((sub, input), output) in targets.zip(inputs).zip(outputs) {
        sub.input_address = input;
        sub.output_address = output;
    }
    Ok(devices)
}

fn device_config(
    d: usize,
    span: Range<usize>,
    raw: RawDevice,
    cx: &Cx<'_>,
    names: &mut HashMap<String, (usize, usize)>,
    files: &mut Files,
) -> Result<(DeviceConfig, Vec<Draft>), ConfigError> {
    let key = |k: &str| format!("device[{d}].{k}");
    cx.check(&raw.name, key("name"), station_name(raw.name.get_ref()))?;
    let line = cx.line(raw.name.span().start);
    if let Some((other, other_line)) = names.get(raw.name.get_ref()) {
        return Err(cx.invalid(
            raw.name.span(),
            key("name"),
            format!(
                "{:?} is already the name of device[{other}] (line {other_line}); give every \
                 device its own name",
                raw.name.get_ref()
            ),
        ));
    }
    names.insert(raw.name.get_ref().clone(), (d, line));

    let import = match &raw.gsdml {
        Some(gsdml) => Some(import::device(d, gsdml, raw.dap.as_ref(), files, cx)?),
        None => {
            if let Some(dap) = &raw.dap {
                return Err(cx.invalid(
                    dap.span(),
                    key("dap"),
                    "`dap` picks a device access point of the device's GSDML file, and this \
                     device has none; add `gsdml = \"path/to/GSDML-....xml\"`, or leave dap out",
                ));
            }
            None
        }
    };
    let identity =
        |value: &Option<Spanned<u16>>, name: &str, attribute: &str| match (value, &import) {
            (Some(v), None) => Ok(*v.get_ref()),
            (Some(v), Some(imp)) => {
                let theirs = match attribute {
                    "VendorID" => imp.gsdml.vendor_id,
                    _ => imp.gsdml.device_id,
                };
                if *v.get_ref() == theirs {
                    Ok(theirs)
                } else {
                    Err(cx.invalid(
                        v.span(),
                        key(name),
                        format!(
                            "{:#06x} differs from the {attribute} {theirs:#06x} of {} (line {}); \
                         correct it, or leave {name} out to take the GSDML file's",
                            v.get_ref(),
                            imp.path.display(),
                            imp.gsdml.identity_line
                        ),
                    ))
                }
            }
            (None, Some(imp)) => Ok(match attribute {
                "VendorID" => imp.gsdml.vendor_id,
                _ => imp.gsdml.device_id,
            }),
            (None, None) => Err(cx.missing(
                span.clone(),
                &format!("device[{d}]"),
                name,
                "add it, or give the device's GSDML file with `gsdml`",
            )),
        };
    let vendor_id = identity(&raw.vendor_id, "vendor_id", "VendorID")?;
    let device_id = identity(&raw.device_id, "device_id", "DeviceID")?;

    let ip = match &raw.ip {
        Some(v) => Some(cx.check(v, key("ip"), device_ip(v.get_ref()))?),
        None => None,
    };
    let reduction_ratio = match &raw.reduction_ratio {
        Some(v) => cx.check(v, key("reduction_ratio"), reduction_ratio(*v.get_ref()))?,
        None => 1,
    };
    let watchdog_factor = match &raw.watchdog_factor {
        Some(v) => cx.check(v, key("watchdog_factor"), watchdog_factor(*v.get_ref()))?,
        None => 3,
    };
    let sim = match &raw.sim {
        Some(v) => cx.check(
            v,
            key("sim"),
            choose(
                v.get_ref(),
                "a simulated behaviour",
                &[
                    ("echo", SimBehaviour::Echo),
                    ("counter", SimBehaviour::Counter),
                    ("digital-io", SimBehaviour::DigitalIo),
                    ("none", SimBehaviour::None),
                    ("absent", SimBehaviour::Absent),
                ],
            ),
        )?,
        None => SimBehaviour::None,
    };

    let mut seen: HashMap<(u32, u16, u16), (usize, usize)> = HashMap::new();
    let mut submodules = Vec::with_capacity(raw.submodule.len());
    let mut drafts = Vec::with_capacity(raw.submodule.len());

    // A device described by a GSDML file gets its DAP's submodules in slot 0, unless the
    // configuration says itself what is in slot 0.
    if let Some(imp) = &import
        && !raw
            .submodule
            .iter()
            .any(|s| *s.get_ref().slot.get_ref() == 0)
    {
        for (subslot, sub) in import::dap_submodules(imp, cx)? {
            let lengths = imp
                .gsdml
                .io_lengths(sub)
                .map_err(|e| imp.error_here(cx, e))?;
            let records = imp.gsdml.records(sub).map_err(|e| imp.error_here(cx, e))?;
            for (length, noun) in [(lengths.input, "input"), (lengths.output, "output")] {
                data_length(length, noun).map_err(|m| {
                    cx.invalid(imp.span.clone(), &imp.key, dap_message(imp, sub, m))
                })?;
            }
            submodules.push(SubmoduleConfig {
                api: sub.api,
                slot: 0,
                subslot,
                module_ident: imp.dap().module_ident,
                submodule_ident: sub.submodule_ident,
                input_length: lengths.input,
                output_length: lengths.output,
                input_address: NO_ADDRESS,
                output_address: NO_ADDRESS,
                rt_class: 1,
                records,
            });
            drafts.push(Draft {
                key: imp.key.clone(),
                span: imp.span.clone(),
                input_address: None,
                output_address: None,
                diagnostic_address: None,
            });
        }
    }

    for (s, sub) in raw.submodule.into_iter().enumerate() {
        let span = sub.span();
        let base = format!("device[{d}].submodule[{s}]");
        let (config, draft) = submodule_config(
            &base,
            span,
            sub.into_inner(),
            cx,
            &mut seen,
            s,
            import.as_ref(),
        )?;
        submodules.push(config);
        drafts.push(draft);
    }

    let topology = raw
        .topology
        .into_iter()
        .enumerate()
        .map(|(t, peer)| port_peer(&key(&format!("topology[{t}]")), peer, &submodules, cx))
        .collect::<Result<Vec<_>, _>>()?;
    let config = DeviceConfig {
        topology,
        optional: raw.optional.unwrap_or(false),
        name: raw.name.into_inner(),
        ip,
        vendor_id,
        device_id,
        gsdml: import.as_ref().map(|imp| GsdmlSource {
            path: imp.path.clone(),
            dap: imp.dap().id.clone(),
        }),
        instance: raw.instance.unwrap_or(1),
        reduction_ratio,
        watchdog_factor,
        sim,
        submodules,
    };
    Ok((config, drafts))
}

/// Whether `subslot` is a port's: 0x8X01 to 0x8XFF.
fn is_port(subslot: u16) -> bool {
    subslot & 0xf000 == 0x8000 && subslot & 0x00ff != 0
}

/// Checks an element of a device's `topology`: a port of the device (its first one if
/// `subslot` is left out), a station name, a port name.
fn port_peer(
    base: &str,
    raw: Spanned<RawTopology>,
    submodules: &[SubmoduleConfig],
    cx: &Cx<'_>,
) -> Result<PortPeer, ConfigError> {
    let span = raw.span();
    let raw = raw.into_inner();
    let key = |k: &str| format!("{base}.{k}");
    let ports: Vec<u16> = submodules
        .iter()
        .filter(|s| s.slot == 0 && is_port(s.subslot))
        .map(|s| s.subslot)
        .collect();
    let list = || {
        ports
            .iter()
            .map(|p| format!("{p:#06x}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let subslot = match &raw.subslot {
        Some(v) if ports.contains(v.get_ref()) => *v.get_ref(),
        Some(v) => {
            return Err(cx.invalid(
                v.span(),
                key("subslot"),
                format!(
                    "{:#06x} is not a port of the device: its ports are the subslots 0x8X01 to \
                     0x8XFF of slot 0 among its submodules ({}); name one of them",
                    v.get_ref(),
                    if ports.is_empty() { "none".to_owned() } else { list() }
                ),
            ));
        }
        None => *ports.first().ok_or_else(|| {
            cx.invalid(
                span.clone(),
                base,
                "the device has no port submodule (subslot 0x8001 … of slot 0) to check; add                  its ports to its submodules, or name them with a GSDML file",
            )
        })?,
    };
    let programmable = raw.programmable.as_ref().is_some_and(|p| *p.get_ref());
    let (station, port) = match (raw.station, raw.port, programmable) {
        (None, None, true) => {
            return Ok(PortPeer {
                subslot,
                peer: Peer::Programmable,
            });
        }
        (Some(station), Some(port), false) => (station, port),
        (_, _, true) => {
            return Err(cx.invalid(
                span,
                base,
                "a programmable peer has no fixed neighbour: leave out station and port (the \
                 IO system's tailoring names the neighbour), or programmable",
            ));
        }
        _ => {
            return Err(cx.invalid(
                span,
                base,
                "give the neighbour as station and port (its NameOfStation and its port, e.g. \
                 \"port-001\"), or programmable = true for a neighbour tailoring names",
            ));
        }
    };
    cx.check(&station, key("station"), station_name(station.get_ref()))?;
    let port_name = port.get_ref();
    if port_name.is_empty()
        || port_name.len() > 240
        || !port_name.bytes().all(|b| b.is_ascii_graphic())
    {
        return Err(cx.invalid(
            port.span(),
            key("port"),
            format!(
                "{port_name:?} is not a port name: the neighbour's port as its LLDP names it, 1 to                  240 visible characters, e.g. \"port-001\""
            ),
        ));
    }
    Ok(PortPeer {
        subslot,
        peer: Peer::Fixed {
            station: station.into_inner(),
            port: port.into_inner(),
        },
    })
}

fn dap_message(imp: &DeviceImport, sub: &Submodule, message: String) -> String {
    format!(
        "the device access point's submodule {:?} ({}:{}): {message}",
        sub.id,
        imp.path.display(),
        sub.line
    )
}

/// `imported` unless the configuration gives the value too, in which case the two agree.
fn agree<T: PartialEq + Copy + core::fmt::Display>(
    cx: &Cx<'_>,
    explicit: Option<&Spanned<T>>,
    key: String,
    imported: T,
    what: &str,
) -> Result<T, ConfigError> {
    match explicit {
        Some(v) if *v.get_ref() != imported => {
            let name = key.rsplit('.').next().unwrap_or(&key).to_owned();
            Err(cx.invalid(
                v.span(),
                key,
                format!(
                    "{} differs from {imported}, {what}; correct it, or leave {name} out to \
                     take the GSDML file's",
                    v.get_ref()
                ),
            ))
        }
        _ => Ok(imported),
    }
}

/// A number shown as hex with at least `width` digits, for ident numbers.
#[derive(Clone, Copy, PartialEq)]
struct Hex(u32, usize);

impl core::fmt::Display for Hex {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "{:#0width$x}", self.0, width = self.1 + 2)
    }
}

fn hex_spanned(v: &Option<Spanned<u32>>) -> Option<Spanned<Hex>> {
    v.as_ref()
        .map(|v| Spanned::new(v.span(), Hex(*v.get_ref(), 8)))
}

fn submodule_config(
    base: &str,
    span: Range<usize>,
    raw: RawSubmodule,
    cx: &Cx<'_>,
    seen: &mut HashMap<(u32, u16, u16), (usize, usize)>,
    s: usize,
    import: Option<&DeviceImport>,
) -> Result<(SubmoduleConfig, Draft), ConfigError> {
    let key = |k: &str| format!("{base}.{k}");
    let found: Option<(Found<'_>, &DeviceImport)> = match (&raw.module, import) {
        (Some(module), Some(imp)) => {
            let lookup = Lookup {
                base,
                module,
                submodule: raw.submodule.as_ref(),
                slot: &raw.slot,
                subslot: raw.subslot.as_ref(),
            };
            Some((import::find(imp, &lookup, cx)?, imp))
        }
        (Some(module), None) => {
            return Err(cx.invalid(
                module.span(),
                key("module"),
                "`module` names a module of the device's GSDML file, and this device has none; \
                 add `gsdml = \"path/to/GSDML-....xml\"` to the device, or give module_ident, \
                 submodule_ident and the lengths instead",
            ));
        }
        (None, _) => {
            if let Some(submodule) = &raw.submodule {
                return Err(cx.invalid(
                    submodule.span(),
                    key("submodule"),
                    "`submodule` picks a submodule of the GSDML module given with `module`; add \
                     `module`, or leave submodule out",
                ));
            }
            None
        }
    };

    let slot = *raw.slot.get_ref();
    let (subslot, subslot_span, subslot_key) = match (&raw.subslot, &found) {
        (Some(v), _) => (*v.get_ref(), v.span(), key("subslot")),
        (None, Some((f, _))) => (
            f.subslot,
            raw.module.as_ref().map_or(span.clone(), Spanned::span),
            key("module"),
        ),
        (None, None) => {
            return Err(cx.missing(span, base, "subslot", "add it"));
        }
    };
    if subslot == 0 {
        return Err(cx.invalid(
            subslot_span,
            subslot_key,
            "subslot 0 does not exist; subslots count from 1 (a module's first submodule is \
             subslot 1)",
        ));
    }

    let api = match &found {
        Some((f, _)) => agree(
            cx,
            raw.api.as_ref(),
            key("api"),
            f.sub.api,
            &format!("the API of {}", f.submodule),
        )?,
        None => raw.api.as_ref().map_or(0, |v| *v.get_ref()),
    };
    if let Some((other, other_line)) = seen.get(&(api, slot, subslot)) {
        return Err(cx.invalid(
            raw.slot.span(),
            key("slot"),
            format!(
                "slot {slot} subslot {subslot} (api {api}) is already used by submodule[{other}] \
                 of this device (line {other_line}); give each submodule its own slot and subslot"
            ),
        ));
    }
    seen.insert((api, slot, subslot), (s, cx.line(raw.slot.span().start)));

    let (module_ident, submodule_ident) = match &found {
        Some((f, _)) => (
            agree(
                cx,
                hex_spanned(&raw.module_ident).as_ref(),
                key("module_ident"),
                Hex(f.module_ident, 8),
                &format!("the ModuleIdentNumber of {}", f.module),
            )?
            .0,
            agree(
                cx,
                hex_spanned(&raw.submodule_ident).as_ref(),
                key("submodule_ident"),
                Hex(f.sub.submodule_ident, 8),
                &format!("the SubmoduleIdentNumber of {}", f.submodule),
            )?
            .0,
        ),
        None => {
            let Some(module_ident) = &raw.module_ident else {
                return Err(cx.missing(
                    span,
                    base,
                    "module_ident",
                    "add it, or name the GSDML module with `module`",
                ));
            };
            let Some(submodule_ident) = &raw.submodule_ident else {
                return Err(cx.missing(
                    span,
                    base,
                    "submodule_ident",
                    "add it, or name the GSDML module with `module`",
                ));
            };
            (*module_ident.get_ref(), *submodule_ident.get_ref())
        }
    };

    let explicit_input = match &raw.input_length {
        Some(v) => Some(cx.check(v, key("input_length"), data_length(*v.get_ref(), "input"))?),
        None => None,
    };
    let explicit_output = match &raw.output_length {
        Some(v) => Some(cx.check(v, key("output_length"), data_length(*v.get_ref(), "output"))?),
        None => None,
    };
    let (input_length, output_length) = match &found {
        None => (explicit_input.unwrap_or(0), explicit_output.unwrap_or(0)),
        Some((f, imp)) => {
            let module_span = raw.module.as_ref().map_or(span.clone(), Spanned::span);
            match imp.gsdml.io_lengths(f.sub) {
                Ok(lengths) => {
                    for (length, noun) in [(lengths.input, "input"), (lengths.output, "output")] {
                        data_length(length, noun).map_err(|m| {
                            cx.invalid(
                                module_span.clone(),
                                key("module"),
                                format!("{}: {m}", f.submodule),
                            )
                        })?;
                    }
                    (
                        agree(
                            cx,
                            raw.input_length.as_ref(),
                            key("input_length"),
                            lengths.input,
                            &format!("the input length of {}", f.submodule),
                        )?,
                        agree(
                            cx,
                            raw.output_length.as_ref(),
                            key("output_length"),
                            lengths.output,
                            &format!("the output length of {}", f.submodule),
                        )?,
                    )
                }
                // The configuration's own lengths stand in for data items this import
                // cannot size.
                Err(_) if explicit_input.is_some() && explicit_output.is_some() => {
                    (explicit_input.unwrap_or(0), explicit_output.unwrap_or(0))
                }
                Err(e) => return Err(cx.gsdml_error(module_span, &key("module"), e)),
            }
        }
    };

    let rt_class = match &raw.rt_class {
        Some(v) if matches!(v.get_ref(), 1 | 3) => *v.get_ref(),
        Some(v) => {
            return Err(cx.invalid(
                v.span(),
                key("rt_class"),
                format!(
                    "{} is not an RT class; use 1 (default) or 3 (IRT)",
                    v.get_ref()
                ),
            ));
        }
        None => 1,
    };
    let records = match (raw.records, &found) {
        (Some(records), _) => records
            .into_iter()
            .map(|r| ParameterRecord {
                index: r.index,
                data: r.data,
            })
            .collect(),
        (None, Some((f, imp))) => imp.gsdml.records(f.sub).map_err(|e| {
            let module_span = raw.module.as_ref().map_or(span.clone(), Spanned::span);
            cx.gsdml_error(module_span, &key("module"), e)
        })?,
        (None, None) => Vec::new(),
    };
    let explicit = |a: &Option<Spanned<u32>>| a.as_ref().map(|v| (*v.get_ref(), v.span()));
    let draft = Draft {
        key: base.to_owned(),
        span,
        input_address: explicit(&raw.input_address),
        output_address: explicit(&raw.output_address),
        diagnostic_address: explicit(&raw.diagnostic_address),
    };
    diagnostic_address_fits(&draft, input_length, output_length, cx)?;
    let config = SubmoduleConfig {
        api,
        slot,
        subslot,
        module_ident,
        submodule_ident,
        input_length,
        output_length,
        input_address: NO_ADDRESS,
        output_address: NO_ADDRESS,
        rt_class,
        records,
    };
    Ok((config, draft))
}

/// A diagnostic address only for a submodule without IO data, and no input address for one.
pub(super) fn diagnostic_address_fits(
    draft: &Draft,
    input_length: u16,
    output_length: u16,
    cx: &Cx<'_>,
) -> Result<(), ConfigError> {
    let dataless = input_length == 0 && output_length == 0;
    match (&draft.diagnostic_address, &draft.input_address) {
        (Some((_, span)), _) if !dataless => Err(cx.invalid(
            span.clone(),
            format!("{}.{DIAGNOSTIC_ADDRESS_KEY}", draft.key),
            "a diagnostic address is for a submodule without IO data; this one is addressed \
             by its input_address or output_address: remove diagnostic_address"
                .to_string(),
        )),
        (_, Some((_, span))) if dataless => Err(cx.invalid(
            span.clone(),
            format!("{}.input_address", draft.key),
            "a submodule without IO data has a diagnostic address, not an input address: write \
             diagnostic_address instead"
                .to_string(),
        )),
        _ => Ok(()),
    }
}
