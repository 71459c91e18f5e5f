// SPDX-License-Identifier: MIT OR Apache-2.0
//! The checks of `[station]`, `[station.dap]` and `[[station.submodule]]`: the identity a
//! PLC and an engineering tool see (name, address, ident numbers, I&M0), what is plugged and
//! whether its cyclic data fits a frame, the parameter records, the logical addresses.

use std::collections::HashMap;
use std::net::Ipv4Addr;
use std::ops::Range;
use std::path::PathBuf;

use procimg_shm_layout::NO_ADDRESS;
use toml::Spanned;

use super::devices::{
    Draft, addresses, data_length, device_ip, diagnostic_address_fits, station_name,
};
use crate::context::Cx;
use crate::error::ConfigError;
use crate::gsdml::{Dap, Gsdml, SubmoduleKind};
use crate::raw::{RawAcceptedRecord, RawDap, RawStation, RawStationSubmodule};
use crate::station::{
    AcceptedRecord, DAP_SUBSLOT, DapConfig, INTERFACE_SUBSLOT, MAX_CR_DATA, MAX_RECORD_LENGTH,
    MAX_STATION_SLOT, PORT_SUBSLOT, ProgramStation, SoftwareVersion, StationConfig,
    StationSubmodule,
};
use crate::{SnmpMaster, SubmoduleConfig};

/// Checks `[station]`.
pub(super) fn station(raw: Spanned<RawStation>, cx: &Cx<'_>) -> Result<StationConfig, ConfigError> {
    let span = raw.span();
    let raw = raw.into_inner();
    cx.check(&raw.name, "station.name", station_name(raw.name.get_ref()))?;
    let ip = match &raw.ip {
        Some(v) => Some(cx.check(v, "station.ip", device_ip(v.get_ref()))?),
        None => None,
    };
    let netmask = match (&raw.netmask, ip) {
        (Some(v), Some(_)) => cx.check(v, "station.netmask", netmask(v.get_ref()))?,
        (Some(v), None) => {
            return Err(cx.invalid(
                v.span(),
                "station.netmask",
                "a netmask without an ip; give `ip` too, or leave netmask out",
            ));
        }
        (None, Some(_)) => Ipv4Addr::new(255, 255, 255, 0),
        (None, None) => Ipv4Addr::UNSPECIFIED,
    };
    let gateway = match (&raw.gateway, ip) {
        (Some(v), Some(ip)) => cx.check(v, "station.gateway", gateway(v.get_ref(), ip, netmask))?,
        (Some(v), None) => {
            return Err(cx.invalid(
                v.span(),
                "station.gateway",
                "a gateway without an ip; give `ip` too, or leave gateway out",
            ));
        }
        (None, _) => Ipv4Addr::UNSPECIFIED,
    };
    let text = |v: &Option<Spanned<String>>, key: &str, max: usize, default: &str| match v {
        Some(v) => cx
            .check(v, format!("station.{key}"), visible_ascii(v.get_ref(), max))
            .map(|()| v.get_ref().clone()),
        None => Ok(default.to_owned()),
    };
    let device_type = text(&raw.device_type, "device_type", 240, "procimg")?;
    if device_type.is_empty() {
        let v = raw.device_type.as_ref().map_or(span.clone(), Spanned::span);
        return Err(cx.invalid(
            v,
            "station.device_type",
            "the type of station is empty; give 1 to 240 characters, e.g. \"procimg\"",
        ));
    }
    let order_number = text(&raw.order_number, "order_number", 20, "")?;
    let serial_number = text(&raw.serial_number, "serial_number", 16, "")?;
    let software_revision = match &raw.software_revision {
        Some(v) => cx.check(
            v,
            "station.software_revision",
            software_version(v.get_ref()),
        )?,
        None => SoftwareVersion {
            prefix: 'V',
            functional: 0,
            bug_fix: 1,
            internal: 0,
        },
    };
    let instance = match &raw.instance {
        Some(v) => *v.get_ref(),
        None => 1,
    };
    let state_file = match &raw.state_file {
        Some(v) if v.get_ref().is_empty() => {
            return Err(cx.invalid(
                v.span(),
                "station.state_file",
                "the path is empty; give a file such as \"/var/lib/procimg/station.toml\", or \
                 leave state_file out",
            ));
        }
        Some(v) => Some(PathBuf::from(v.get_ref())),
        None => None,
    };
    let program = program_station(&raw, cx)?;
    let dap = match (raw.dap, &program) {
        (Some(d), None) => dap(d.into_inner()),
        (Some(d), Some(_)) => {
            return Err(cx.invalid(
                d.span(),
                "station.dap",
                "with `gsdml` the file's device access point gives the ident numbers of slot \
                 0; remove [station.dap]",
            ));
        }
        (None, Some(p)) => dap_config(&p.file.daps[p.dap_index]),
        (None, None) => DapConfig::default(),
    };
    let identity =
        |v: &Option<Spanned<u16>>, key: &str, from_file: Option<u16>| match (v, from_file) {
            (Some(v), _) => Ok(*v.get_ref()),
            (None, Some(id)) => Ok(id),
            (None, None) => Err(cx.missing(
                span.clone(),
                "station",
                key,
                "give the station's PROFINET identity (vendor_id and device_id), or its GSDML \
             file with `gsdml`",
            )),
        };
    let vendor_id = identity(
        &raw.vendor_id,
        "vendor_id",
        program.as_ref().map(|p| p.file.vendor_id),
    )?;
    let device_id = identity(
        &raw.device_id,
        "device_id",
        program.as_ref().map(|p| p.file.device_id),
    )?;

    let mut submodules = dap_submodules(&dap);
    let mut drafts: Vec<Draft> = submodules
        .iter()
        .map(|s| Draft {
            key: format!("station.dap (slot 0 subslot 0x{:04X})", s.submodule.subslot),
            span: span.clone(),
            input_address: None,
            output_address: None,
            diagnostic_address: None,
        })
        .collect();
    let mut seen: HashMap<(u32, u16, u16), usize> = HashMap::new();
    let mut module_of_slot: HashMap<(u32, u16), (u32, usize, usize)> = HashMap::new();
    for (s, raw_sub) in raw.submodule.into_iter().enumerate() {
        let (sub, draft) = submodule(s, raw_sub, cx, &mut seen, &mut module_of_slot)?;
        submodules.push(sub);
        drafts.push(draft);
    }
    frame_fits(&submodules, span.clone(), cx)?;

    let name = raw.name.into_inner();
    let named: Vec<(&str, &Draft, &SubmoduleConfig)> = drafts
        .iter()
        .zip(&submodules)
        .map(|(d, s)| (name.as_str(), d, &s.submodule))
        .collect();
    let [inputs, outputs] = addresses(cx, &named)?;
    for ((s, input), output) in submodules.iter_mut().zip(inputs).zip(outputs) {
        s.submodule.input_address = input;
        s.submodule.output_address = output;
    }

    Ok(StationConfig {
        name,
        ip,
        netmask,
        gateway,
        vendor_id,
        device_id,
        instance,
        device_type,
        order_number,
        serial_number,
        hardware_revision: raw.hardware_revision.map_or(1, |v| *v.get_ref()),
        software_revision,
        state_file,
        dcp_hello: raw.dcp_hello.unwrap_or(false),
        snmp_agentx: match &raw.snmp_agentx {
            None => SnmpMaster::Standard,
            Some(v) if v.get_ref() == "off" => SnmpMaster::Off,
            Some(v) if v.get_ref().is_empty() => {
                return Err(cx.invalid(
                    v.span(),
                    "station.snmp_agentx",
                    "an empty master; give the AgentX socket of the SNMP agent (e.g. \
                     \"/var/agentx/master\", \"tcp:127.0.0.1:705\"), or \"off\" for no SNMP",
                ));
            }
            Some(v) => SnmpMaster::At(v.get_ref().clone()),
        },
        dap,
        submodules,
        program,
    })
}

/// `gsdml` and `gsdml_dap` of `[station]`: a station its program defines, its GSDML file
/// read and its device access point chosen (index in the file's DAPs); `None` without
/// `gsdml`.
fn program_station(raw: &RawStation, cx: &Cx<'_>) -> Result<Option<ProgramStation>, ConfigError> {
    let Some(written) = &raw.gsdml else {
        if let Some(d) = &raw.gsdml_dap {
            return Err(cx.invalid(
                d.span(),
                "station.gsdml_dap",
                "a device access point without a GSDML file; give the file with `gsdml`, or \
                 leave gsdml_dap out",
            ));
        }
        return Ok(None);
    };
    if let Some(first) = raw.submodule.first() {
        return Err(cx.invalid(
            first.span(),
            "station.submodule[0]",
            "with `gsdml` the station's program defines its submodules; remove the \
             [[station.submodule]] tables, or remove `gsdml` to give the tree here",
        ));
    }
    let path = cx.dir.join(written.get_ref());
    let gsdml =
        Gsdml::load(&path).map_err(|e| cx.gsdml_error(written.span(), "station.gsdml", e))?;
    let at = match &raw.gsdml_dap {
        Some(id) => gsdml
            .daps
            .iter()
            .position(|d| d.id == *id.get_ref() || d.name.as_deref() == Some(id.get_ref()))
            .ok_or_else(|| {
                let ids: Vec<&str> = gsdml.daps.iter().map(|d| d.id.as_str()).collect();
                cx.invalid(
                    id.span(),
                    "station.gsdml_dap",
                    format!(
                        "{} has no device access point {:?}; it has {}",
                        path.display(),
                        id.get_ref(),
                        ids.join(", ")
                    ),
                )
            })?,
        None => 0,
    };
    Ok(Some(ProgramStation {
        gsdml: path,
        dap: gsdml.daps[at].id.clone(),
        file: std::sync::Arc::new(gsdml),
        dap_index: at,
    }))
}

fn dap(raw: RawDap) -> DapConfig {
    let d = DapConfig::default();
    let or = |v: Option<Spanned<u32>>, default: u32| v.map_or(default, |v| *v.get_ref());
    DapConfig {
        module_ident: or(raw.module_ident, d.module_ident),
        submodule_ident: or(raw.submodule_ident, d.submodule_ident),
        interface_ident: or(raw.interface_ident, d.interface_ident),
        port_ident: or(raw.port_ident, d.port_ident),
    }
}

/// The DAP's submodule, interface and port: no IO data; the DAP's own speaks for the
/// device's I&M.
pub(crate) fn dap_submodules(dap: &DapConfig) -> Vec<StationSubmodule> {
    [
        (DAP_SUBSLOT, dap.submodule_ident),
        (INTERFACE_SUBSLOT, dap.interface_ident),
        (PORT_SUBSLOT, dap.port_ident),
    ]
    .into_iter()
    .map(|(subslot, submodule_ident)| StationSubmodule {
        submodule: SubmoduleConfig {
            api: 0,
            slot: 0,
            subslot,
            module_ident: dap.module_ident,
            submodule_ident,
            input_length: 0,
            output_length: 0,
            input_address: NO_ADDRESS,
            output_address: NO_ADDRESS,
            rt_class: 1,
            records: Vec::new(),
        },
        accepts: Vec::new(),
        im: subslot == DAP_SUBSLOT,
        plugged: true,
    })
    .collect()
}

fn submodule(
    s: usize,
    raw: Spanned<RawStationSubmodule>,
    cx: &Cx<'_>,
    seen: &mut HashMap<(u32, u16, u16), usize>,
    module_of_slot: &mut HashMap<(u32, u16), (u32, usize, usize)>,
) -> Result<(StationSubmodule, Draft), ConfigError> {
    let base = format!("station.submodule[{s}]");
    let key = |k: &str| format!("{base}.{k}");
    let span = raw.span();
    let raw = raw.into_inner();
    let slot = *raw.slot.get_ref();
    if slot == 0 || slot > MAX_STATION_SLOT {
        return Err(cx.invalid(
            raw.slot.span(),
            key("slot"),
            format!(
                "slot {slot} is not for a submodule of [[station.submodule]]; slot 0 is the \
                 device access point (its ident numbers are [station.dap]), use 1 to \
                 {MAX_STATION_SLOT}"
            ),
        ));
    }
    let subslot = raw.subslot.as_ref().map_or(1, |v| *v.get_ref());
    if subslot == 0 || subslot >= 0x8000 {
        let at = raw.subslot.as_ref().map_or(span.clone(), Spanned::span);
        return Err(cx.invalid(
            at,
            key("subslot"),
            format!(
                "subslot {subslot} is not for an IO submodule; use 1 to 32767 (0x8000 and up \
                 are interfaces and ports)"
            ),
        ));
    }
    let api = raw.api.as_ref().map_or(0, |v| *v.get_ref());
    if let Some(other) = seen.insert((api, slot, subslot), s) {
        return Err(cx.invalid(
            raw.slot.span(),
            key("slot"),
            format!(
                "slot {slot} subslot {subslot} (api {api}) is already station.submodule[{other}]; \
                 give each submodule its own slot and subslot"
            ),
        ));
    }
    let module_ident = *raw.module_ident.get_ref();
    match module_of_slot.get(&(api, slot)) {
        Some(&(other_ident, other, other_line)) if other_ident != module_ident => {
            return Err(cx.invalid(
                raw.module_ident.span(),
                key("module_ident"),
                format!(
                    "slot {slot} holds one module: station.submodule[{other}] (line \
                     {other_line}) gives it module_ident 0x{other_ident:08X}, this one \
                     0x{module_ident:08X}; give the submodules of a slot the same module_ident"
                ),
            ));
        }
        _ => {
            let line = cx.line(raw.module_ident.span().start);
            module_of_slot.insert((api, slot), (module_ident, s, line));
        }
    }
    let length = |v: &Option<Spanned<u16>>, k: &str, noun: &str| match v {
        Some(v) => cx.check(v, key(k), data_length(*v.get_ref(), noun)),
        None => Ok(0),
    };
    let input_length = length(&raw.input_length, "input_length", "input")?;
    let output_length = length(&raw.output_length, "output_length", "output")?;

    let mut accepts: Vec<AcceptedRecord> = Vec::with_capacity(raw.records.len());
    for (r, record) in raw.records.into_iter().enumerate() {
        let accepted = accepted_record(&key(&format!("records[{r}]")), record, cx)?;
        if accepts.iter().any(|a| a.index == accepted.index) {
            return Err(cx.invalid(
                span.clone(),
                key(&format!("records[{r}].index")),
                format!(
                    "record index {} is listed twice for this submodule; list each index once",
                    accepted.index
                ),
            ));
        }
        accepts.push(accepted);
    }

    let explicit = |a: &Option<Spanned<u32>>| a.as_ref().map(|v| (*v.get_ref(), v.span()));
    let draft = Draft {
        key: base.clone(),
        span,
        input_address: explicit(&raw.input_address),
        output_address: explicit(&raw.output_address),
        diagnostic_address: explicit(&raw.diagnostic_address),
    };
    diagnostic_address_fits(&draft, input_length, output_length, cx)?;
    let submodule = SubmoduleConfig {
        api,
        slot,
        subslot,
        module_ident,
        submodule_ident: *raw.submodule_ident.get_ref(),
        input_length,
        output_length,
        input_address: NO_ADDRESS,
        output_address: NO_ADDRESS,
        rt_class: 1,
        records: Vec::new(),
    };
    let station_submodule = StationSubmodule {
        submodule,
        accepts,
        im: raw.im.unwrap_or(false),
        plugged: raw.plugged.unwrap_or(true),
    };
    Ok((station_submodule, draft))
}

fn accepted_record(
    base: &str,
    raw: Spanned<RawAcceptedRecord>,
    cx: &Cx<'_>,
) -> Result<AcceptedRecord, ConfigError> {
    let raw = raw.into_inner();
    let index = *raw.index.get_ref();
    if index > 0x7FFF {
        return Err(cx.invalid(
            raw.index.span(),
            format!("{base}.index"),
            format!(
                "index 0x{index:04X} is not a parameter record of the device's own; use \
                 0x0000 to 0x7FFF (the indexes above belong to PROFINET and procimg answers \
                 them itself)"
            ),
        ));
    }
    let length = *raw.length.get_ref();
    if length == 0 || length > MAX_RECORD_LENGTH {
        return Err(cx.invalid(
            raw.length.span(),
            format!("{base}.length"),
            format!("a record of {length} bytes; give 1 to {MAX_RECORD_LENGTH}"),
        ));
    }
    let initial = match raw.data {
        Some(d) if d.get_ref().len() != usize::from(length) => {
            return Err(cx.invalid(
                d.span(),
                format!("{base}.data"),
                format!(
                    "{} bytes of data for a record of length {length}; give exactly {length} \
                     bytes, or leave data out for zeros",
                    d.get_ref().len()
                ),
            ));
        }
        Some(d) => d.into_inner(),
        None => vec![0; usize::from(length)],
    };
    Ok(AcceptedRecord {
        index,
        length,
        initial,
    })
}

/// Each direction's C_SDU must fit one frame: the input CR carries every submodule's input
/// data with its IOPS and an IOCS for every submodule with outputs (and for each dataless
/// one, an IOPS in the input CR and an IOCS in the output CR); the output CR the mirror.
fn frame_fits(
    submodules: &[StationSubmodule],
    span: Range<usize>,
    cx: &Cx<'_>,
) -> Result<(), ConfigError> {
    match frame_overflow(submodules) {
        Some(message) => Err(cx.invalid(span, "station.submodule", message)),
        None => Ok(()),
    }
}

/// Why the station's cyclic data does not fit its frames, if it does not: each direction's
/// C_SDU carries every submodule's data of that direction with its IOPS and an IOCS for
/// every submodule with data of the other (and for each dataless one, an IOPS in the input
/// CR and an IOCS in the output CR).
pub(crate) fn frame_overflow(submodules: &[StationSubmodule]) -> Option<String> {
    let (mut input_cr, mut output_cr) = (0usize, 0usize);
    for s in submodules.iter().map(|s| &s.submodule) {
        let (i, o) = (usize::from(s.input_length), usize::from(s.output_length));
        if s.has_no_data() {
            input_cr += 1;
            output_cr += 1;
            continue;
        }
        if i > 0 {
            input_cr += i + 1;
            output_cr += 1;
        }
        if o > 0 {
            output_cr += o + 1;
            input_cr += 1;
        }
    }
    [(input_cr, "input"), (output_cr, "output")]
        .into_iter()
        .find(|&(bytes, _)| bytes > MAX_CR_DATA)
        .map(|(bytes, what)| {
            format!(
                "the {what} frame would carry {bytes} bytes of data and status, more than the \
                 {MAX_CR_DATA} of one RT frame; plug fewer or shorter submodules"
            )
        })
}

/// `base` with the name, IP suite (address, netmask, gateway; address `0.0.0.0`: none, the
/// PLC assigns one by DCP) and serial number a station's program gives, each checked as
/// the configuration's keys are (the message names the part: `name`, `ip`, `netmask`,
/// `gateway`, `serial_number`).
pub fn with_identity(
    base: &StationConfig,
    name: Option<&str>,
    ip: Option<(Ipv4Addr, Ipv4Addr, Ipv4Addr)>,
    serial_number: Option<&str>,
) -> Result<StationConfig, String> {
    let mut s = base.clone();
    if let Some(name) = name {
        station_name(name).map_err(|e| format!("name: {e}"))?;
        s.name = name.to_owned();
    }
    if let Some((ip, mask, gw)) = ip {
        if ip.is_unspecified() {
            s.ip = None;
        } else {
            let ip = device_ip(&ip.to_string()).map_err(|e| format!("ip: {e}"))?;
            let mask = netmask(&mask.to_string()).map_err(|e| format!("netmask: {e}"))?;
            let gw = gateway(&gw.to_string(), ip, mask).map_err(|e| format!("gateway: {e}"))?;
            (s.ip, s.netmask, s.gateway) = (Some(ip), mask, gw);
        }
    }
    if let Some(serial) = serial_number {
        visible_ascii(serial, 16).map_err(|e| format!("serial_number: {e}"))?;
        s.serial_number = serial.to_owned();
    }
    Ok(s)
}

fn netmask(text: &str) -> Result<Ipv4Addr, String> {
    let mask: Ipv4Addr = text
        .parse()
        .map_err(|_| format!("{text:?} is not a netmask; write it like \"255.255.255.0\""))?;
    let bits = u32::from(mask);
    if bits == 0 || bits.leading_ones() + bits.trailing_zeros() != 32 {
        return Err(format!(
            "{text:?} is not a netmask (ones, then zeros); write it like \"255.255.255.0\""
        ));
    }
    Ok(mask)
}

fn gateway(text: &str, ip: Ipv4Addr, mask: Ipv4Addr) -> Result<Ipv4Addr, String> {
    let gw: Ipv4Addr = text.parse().map_err(|_| {
        format!(
            "{text:?} is not an IPv4 address; write it like \"192.168.0.1\", or leave gateway out"
        )
    })?;
    let net = |a: Ipv4Addr| u32::from(a) & u32::from(mask);
    if !gw.is_unspecified() && net(gw) != net(ip) {
        return Err(format!(
            "gateway {gw} is not in the station's subnet {ip}/{}; give a router of that \
             subnet, or leave gateway out",
            u32::from(mask).leading_ones()
        ));
    }
    Ok(gw)
}

fn visible_ascii(text: &str, max: usize) -> Result<(), String> {
    if let Some(c) = text.chars().find(|c| !(c.is_ascii_graphic() || *c == ' ')) {
        return Err(format!(
            "{text:?} contains {c:?}; use visible ASCII characters and blanks"
        ));
    }
    if text.len() > max {
        return Err(format!(
            "{text:?} is {} characters long; give at most {max}",
            text.len()
        ));
    }
    Ok(())
}

fn software_version(text: &str) -> Result<SoftwareVersion, String> {
    const HOW: &str = "write a letter V (release), R (revision), P (prototype), U (under test) \
                       or T (test device) and three numbers 0 to 255, e.g. \"V1.2.0\"";
    let mut chars = text.chars();
    let prefix = chars.next().filter(|c| "VRPUT".contains(*c));
    let numbers: Vec<Option<u8>> = chars.as_str().split('.').map(|n| n.parse().ok()).collect();
    match (prefix, numbers.as_slice()) {
        (Some(prefix), [Some(functional), Some(bug_fix), Some(internal)]) => Ok(SoftwareVersion {
            prefix,
            functional: *functional,
            bug_fix: *bug_fix,
            internal: *internal,
        }),
        _ => Err(format!("{text:?} is not a software revision; {HOW}")),
    }
}

/// The ident numbers of the DAP's own submodule, interface and port, from the GSDML.
pub fn dap_config(dap: &Dap) -> DapConfig {
    let d = DapConfig::default();
    let ident = |kind: SubmoduleKind, subslot: Option<u16>| {
        dap.submodules
            .iter()
            .find(|s| {
                s.kind == kind
                    && subslot.is_none_or(|n| {
                        s.subslots.as_ref().is_none_or(|l| l.contains(u32::from(n)))
                    })
            })
            .map(|s| s.submodule_ident)
    };
    DapConfig {
        module_ident: dap.module_ident,
        submodule_ident: ident(SubmoduleKind::Virtual, Some(DAP_SUBSLOT))
            .unwrap_or(d.submodule_ident),
        interface_ident: ident(SubmoduleKind::Interface, Some(INTERFACE_SUBSLOT))
            .unwrap_or(d.interface_ident),
        port_ident: ident(SubmoduleKind::Port, None).unwrap_or(d.port_ident),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn netmasks() {
        assert!(netmask("255.255.255.0").is_ok());
        assert!(netmask("255.0.255.0").is_err());
        assert!(netmask("0.0.0.0").is_err());
    }

    #[test]
    fn software_versions() {
        let v = software_version("V1.2.3").unwrap();
        assert_eq!(v.to_string(), "V1.2.3");
        for bad in ["1.2.3", "X1.2.3", "V1.2", "V1.2.300", ""] {
            assert!(software_version(bad).is_err(), "{bad}");
        }
    }
}
