// SPDX-License-Identifier: MIT OR Apache-2.0
//! From the object tree to what the project says: the controller's interface and the IO
//! system's devices with their submodules, records and addresses.

use std::net::Ipv4Addr;

use super::blocks::{
    BlockError, DeviceProperties, Expected, ExpectedSubmodules, IocrData, IocrType, IpSuite,
    NameOfStation, SetAtDevice, index_list,
};
use super::tree::{Field, Object, TreeError, Value, number};

// Object classes (ClassRID).
const CLASS_INTERFACE: u32 = 3;
const CLASS_PORT: u32 = 4;
const CLASS_IO_SYSTEM: u32 = 5;
const CLASS_DEVICE: u32 = 6;
const CLASS_MODULE: u32 = 7;
/// A module's proxy (head) submodule: no submodule of the device's, a placeholder.
const CLASS_MODULE_PROXY: u32 = 8;
const CLASS_SUBMODULE: u32 = 9;
const CLASS_IO_SUBMODULE: u32 = 10;
const CLASS_NETWORK: u32 = 11;

// Attribute IDs (AID).
const AID_SLOT: u32 = 1;
const AID_SUBSLOT: u32 = 2;
const AID_DEVICE_NUMBER: u32 = 3;
const AID_DEACTIVATED: u32 = 4;
const AID_IO_MAPPING: u32 = 5;
const AID_LADDR: u32 = 10;
const AID_RECORDS: u32 = 11;
const AID_NETWORK: u32 = 12;
const AID_DEVICE_PARAMS: u32 = 13;
const AID_TRANSFER_SEQUENCE: u32 = 14;

// IOmapping elements.
const MAP_INPUT_ADDRESS: u32 = 6;
const MAP_INPUT_LENGTH: u32 = 7;
const MAP_OUTPUT_ADDRESS: u32 = 8;
const MAP_OUTPUT_LENGTH: u32 = 9;

// Record keys of the network parameters and of the device's blocks.
const KEY_IP_SUITE: u64 = 0x1000;
const KEY_IP_AT_DEVICE: u64 = 0x1001;
const KEY_NAME: u64 = 0x1003;
const KEY_NAME_AT_DEVICE: u64 = 0x1004;
const KEY_REMOTE_IP_AT_DEVICE: u64 = 0x1007;
const KEY_DEVICE_PROPERTIES: u64 = 0x3060;
const KEY_EXPECTED: u64 = 0x3101;
const KEY_IOCRS: u64 = 0x3102;
const KEY_AR_RECORDS: u64 = 0x3105;
const KEY_IR_INFO: u64 = 0x3106;

/// What the project says.
#[derive(Debug)]
pub(super) struct Project {
    pub controller: Controller,
    pub devices: Vec<Device>,
}

/// The PN Driver's own interface.
#[derive(Debug, Default)]
pub(super) struct Controller {
    pub station_name: Option<String>,
    pub ip: Option<IpSuite>,
    pub name_by_program: bool,
    pub address_by_program: bool,
    pub laddr: Option<u32>,
    pub port_laddr: Option<u32>,
}

/// One IO device.
#[derive(Debug)]
pub(super) struct Device {
    pub number: u64,
    pub object: String,
    pub line: usize,
    pub name: String,
    /// The address the controller gives it: none where the project leaves it at 0.0.0.0 or
    /// to the device ([`Device::ip_at_device`]).
    pub ip: Option<Ipv4Addr>,
    /// The project's "IP address is set directly at the device" for this device.
    pub ip_at_device: bool,
    pub identity: DeviceProperties,
    pub deactivated: bool,
    pub send_clock_factor: u16,
    pub reduction_ratio: u16,
    pub watchdog_factor: u16,
    /// AR record data (fast start-up) the project has, which procimg does not send.
    pub ar_records: usize,
    pub submodules: Vec<Submodule>,
}

/// One submodule of a device.
#[derive(Debug)]
pub(super) struct Submodule {
    pub expected: Expected,
    pub object: Option<String>,
    pub line: Option<usize>,
    pub input_address: Option<u32>,
    pub output_address: Option<u32>,
    pub laddr: Option<u32>,
    pub records: Vec<(u16, Vec<u8>)>,
}

/// Where a problem is, and what it is.
#[derive(Debug)]
pub(super) struct Problem {
    pub line: usize,
    pub element: String,
    pub message: String,
}

impl From<TreeError> for Problem {
    fn from(e: TreeError) -> Problem {
        Problem {
            line: e.line,
            element: e.element,
            message: e.message,
        }
    }
}

type Result<T> = core::result::Result<T, Problem>;

fn problem(o: &Object, message: impl Into<String>) -> Problem {
    Problem {
        line: o.line,
        element: o.describe(),
        message: message.into(),
    }
}

fn field_problem(o: &Object, f: &Field, what: &str, e: BlockError) -> Problem {
    Problem {
        line: f.line,
        element: format!("{}, Field {} ({what})", o.describe(), f.key),
        message: e.0,
    }
}

/// The fields of `o`'s sparse-array variable `aid` (none if it has none).
fn fields(o: &Object, aid: u32) -> &[Field] {
    match o.variable(aid).map(|v| &v.value) {
        Some(Value::Fields(f)) => f,
        _ => &[],
    }
}

fn field(o: &Object, aid: u32, key: u64) -> Option<&Field> {
    fields(o, aid).iter().find(|f| f.key == key)
}

fn scalar(o: &Object, aid: u32) -> Option<&str> {
    match o.variable(aid).map(|v| &v.value) {
        Some(Value::Scalar(s)) => Some(s),
        _ => None,
    }
}

fn laddr(o: &Object) -> Result<Option<u32>> {
    scalar(o, AID_LADDR)
        .map(|s| {
            number(s)
                .map(|n| n as u32)
                .map_err(|m| problem(o, format!("LADDR: {m}")))
        })
        .transpose()
}

/// Reads the project from its root object.
pub(super) fn read(root: &Object) -> Result<Project> {
    let all = root.walk();
    let interfaces: Vec<&Object> = all
        .iter()
        .copied()
        .filter(|o| o.class == CLASS_INTERFACE)
        .collect();
    let interface = match interfaces.as_slice() {
        [one] => *one,
        [] => {
            return Err(problem(
                root,
                "the project has no PROFINET interface (class 3)",
            ));
        }
        [_, second, ..] => {
            return Err(problem(
                second,
                "the project has a second PROFINET interface: procimgd drives one interface; \
                 give each interface a procimgd of its own",
            ));
        }
    };
    let controller = read_controller(interface, &all)?;
    let systems: Vec<&Object> = all
        .iter()
        .copied()
        .filter(|o| o.class == CLASS_IO_SYSTEM)
        .collect();
    let system = systems
        .iter()
        .find(|s| s.rid.is_some_and(|r| interface.links.contains(&r)))
        .or_else(|| (systems.len() == 1).then(|| &systems[0]));
    let devices = match system {
        Some(system) => system
            .children_of(CLASS_DEVICE)
            .map(read_device)
            .collect::<Result<Vec<_>>>()?,
        None if systems.is_empty() => Vec::new(),
        None => {
            return Err(problem(
                interface,
                "the project has several IO systems and the interface links none of them",
            ));
        }
    };
    Ok(Project {
        controller,
        devices,
    })
}

fn read_controller(interface: &Object, all: &[&Object]) -> Result<Controller> {
    let mut c = Controller {
        laddr: laddr(interface)?,
        ..Controller::default()
    };
    for f in fields(interface, AID_RECORDS) {
        let e = |what, e| field_problem(interface, f, what, e);
        match f.key {
            KEY_IP_SUITE | 0x3000 => {
                c.ip = Some(IpSuite::parse(&f.data).map_err(|x| e("IP suite", x))?)
            }
            KEY_NAME | 0x3003 => {
                c.station_name = Some(NameOfStation::parse(&f.data).map_err(|x| e("name", x))?)
            }
            KEY_IP_AT_DEVICE => {
                c.address_by_program = SetAtDevice::parse(&f.data, SetAtDevice::IP_BLOCK_TYPE)
                    .map_err(|x| e("IP address validation", x))?
            }
            KEY_NAME_AT_DEVICE => {
                c.name_by_program = SetAtDevice::parse(&f.data, SetAtDevice::NAME_BLOCK_TYPE)
                    .map_err(|x| e("NameOfStation validation", x))?
            }
            0x230FF => {
                return Err(problem(
                    interface,
                    "the interface is isochronous (its isochronous-mode data, record 0x230FF): \
                     procimgd exchanges RT data on a standard adapter, as PN Driver does on \
                     one; switch isochronous mode off in the project",
                ));
            }
            // The PDEV send clock (0x10000: SCF 1024 in standard-Ethernet projects, PN
            // Driver's own base, adapted per IOCR), identification and the PDEV's own
            // records: procimgd's interface has its own, and its cycle comes from the
            // devices' IOCRs, which carry the wire's values.
            _ => {}
        }
    }
    c.port_laddr = match all.iter().find(|o| o.class == CLASS_PORT) {
        Some(port) => laddr(port)?,
        None => None,
    };
    Ok(c)
}

fn read_device(d: &Object) -> Result<Device> {
    let number = d.key_of(AID_DEVICE_NUMBER).unwrap_or(0);
    let deactivated = match scalar(d, AID_DEACTIVATED) {
        None => false,
        Some(s) if s.eq_ignore_ascii_case("true") || s == "1" => true,
        Some(s) if s.eq_ignore_ascii_case("false") || s == "0" => false,
        Some(s) => {
            return Err(problem(
                d,
                format!("DeactivatedConfig \"{s}\" is not a BOOL"),
            ));
        }
    };
    let need = |key: u64, what: &str| {
        field(d, AID_DEVICE_PARAMS, key).ok_or_else(|| {
            problem(
                d,
                format!(
                    "the device has no {what} (IODevParamConfig field {key}): export the \
                     configuration again from TIA Portal"
                ),
            )
        })
    };
    let f = need(KEY_DEVICE_PROPERTIES, "PNIOD_PROPERTIES")?;
    let identity =
        DeviceProperties::parse(&f.data).map_err(|e| field_problem(d, f, "PNIOD_PROPERTIES", e))?;
    if let Some(f) = field(d, AID_DEVICE_PARAMS, KEY_IR_INFO) {
        return Err(Problem {
            line: f.line,
            element: d.describe(),
            message: "the device is planned for IRT (its IRInfoData): procimgd exchanges RT \
                      data on a standard adapter, as PN Driver does on one; plan the device \
                      with RT in the project"
                .to_owned(),
        });
    }
    let f = need(KEY_IOCRS, "IOCR_DATA")?;
    let iocrs = IocrData::parse(&f.data).map_err(|e| field_problem(d, f, "IOCR_DATA", e))?;
    let mut timing: Option<(u16, u16, u16)> = None;
    for iocr in &iocrs {
        if let IocrType::Other(t) = iocr.kind {
            return Err(problem(
                d,
                format!(
                    "the device has an IOCR of type {t} (multicast): procimgd exchanges data \
                     with a device in one input and one output IOCR"
                ),
            ));
        }
        match iocr.rt_class {
            1 | 2 => {}
            3 => {
                return Err(problem(
                    d,
                    "the device's IOCRs are RT class 3 (IRT): procimgd exchanges RT data on a \
                     standard adapter, as PN Driver does on one; plan the device with RT",
                ));
            }
            other => {
                return Err(problem(
                    d,
                    format!("the device's IOCRs are RT class {other}: procimgd exchanges RT data"),
                ));
            }
        }
        let this = (
            iocr.send_clock_factor,
            iocr.reduction_ratio,
            iocr.watchdog_factor,
        );
        match timing {
            None => timing = Some(this),
            Some((scf, rr, wdf)) => {
                if u32::from(scf) * u32::from(rr) != u32::from(this.0) * u32::from(this.1) {
                    return Err(problem(
                        d,
                        "the device's input and output IOCRs have different update times: \
                         procimgd exchanges both directions of a device at one rate",
                    ));
                }
                let (scf, rr) = if this.0 < scf {
                    (this.0, this.1)
                } else {
                    (scf, rr)
                };
                timing = Some((scf, rr, wdf.max(this.2)));
            }
        }
    }
    let (send_clock_factor, reduction_ratio, watchdog_factor) =
        timing.ok_or_else(|| problem(d, "the device has no IOCR"))?;
    if send_clock_factor == 0 || reduction_ratio == 0 {
        return Err(problem(
            d,
            format!(
                "send clock factor {send_clock_factor} × reduction ratio {reduction_ratio}: neither may be 0"
            ),
        ));
    }
    let f = need(KEY_EXPECTED, "EXPECTED_SUBMODULE_DATA")?;
    let expected = ExpectedSubmodules::parse(&f.data)
        .map_err(|e| field_problem(d, f, "EXPECTED_SUBMODULE_DATA", e))?;
    let ar_records = match field(d, AID_DEVICE_PARAMS, KEY_AR_RECORDS) {
        Some(f) if f.data.len() >= 10 => usize::from(u16::from_be_bytes([f.data[8], f.data[9]])),
        _ => 0,
    };
    let (name, ip, ip_at_device) = read_network(d)?;
    let mut submodules = Vec::with_capacity(expected.len());
    for e in expected {
        submodules.push(read_submodule(d, e)?);
    }
    for module in d.children_of(CLASS_MODULE) {
        for proxy in module.children_of(CLASS_MODULE_PROXY) {
            if !fields(proxy, AID_RECORDS).is_empty() {
                return Err(problem(
                    proxy,
                    "records on a module's proxy submodule: procimgd writes records to a \
                     device's submodules only",
                ));
            }
        }
    }
    Ok(Device {
        number,
        object: d.name.clone(),
        line: d.line,
        name,
        ip,
        ip_at_device,
        identity,
        deactivated,
        send_clock_factor,
        reduction_ratio,
        watchdog_factor,
        ar_records,
        submodules,
    })
}

/// The device's NameOfStation, the IP address the controller gives it (none for 0.0.0.0,
/// and none where the project leaves it to the device), and whether it does so.
fn read_network(d: &Object) -> Result<(String, Option<Ipv4Addr>, bool)> {
    let network = d
        .children_of(CLASS_NETWORK)
        .next()
        .ok_or_else(|| problem(d, "the device has no network parameters (class 11)"))?;
    let name = match field(network, AID_NETWORK, KEY_NAME) {
        Some(f) => {
            NameOfStation::parse(&f.data).map_err(|e| field_problem(network, f, "name", e))?
        }
        None => {
            return Err(problem(
                network,
                "the device has no NameOfStation (field 4099): give it a PROFINET device name \
                 in the project",
            ));
        }
    };
    let ip = match field(network, AID_NETWORK, KEY_IP_SUITE) {
        Some(f) => Some(
            IpSuite::parse(&f.data)
                .map_err(|e| field_problem(network, f, "IP suite", e))?
                .ip,
        ),
        None => None,
    };
    let at_device = match field(network, AID_NETWORK, KEY_REMOTE_IP_AT_DEVICE) {
        Some(f) => SetAtDevice::parse(&f.data, SetAtDevice::REMOTE_IP_BLOCK_TYPE)
            .map_err(|e| field_problem(network, f, "IP address validation", e))?,
        None => false,
    };
    let ip = ip.filter(|ip| !ip.is_unspecified() && !at_device);
    Ok((name, ip, at_device))
}

/// The submodule the expected configuration lists, with what its object in the tree adds:
/// records in their order, logical addresses, hardware identifier.
fn read_submodule(d: &Object, expected: Expected) -> Result<Submodule> {
    let object = d
        .children_of(CLASS_MODULE)
        .filter(|m| m.key_of(AID_SLOT) == Some(u64::from(expected.slot)))
        .flat_map(|m| m.children.iter())
        .find(|s| {
            matches!(s.class, CLASS_SUBMODULE | CLASS_IO_SUBMODULE)
                && s.key_of(AID_SUBSLOT) == Some(u64::from(expected.subslot))
        });
    let mut sub = Submodule {
        expected,
        object: object.map(|o| o.name.clone()),
        line: object.map(|o| o.line),
        input_address: None,
        output_address: None,
        laddr: None,
        records: Vec::new(),
    };
    let at = |message: String| Problem {
        line: object.map_or(d.line, |o| o.line),
        element: object.map_or_else(|| d.describe(), |o| o.describe()),
        message: format!(
            "slot {} subslot 0x{:04X}: {message}",
            expected.slot, expected.subslot
        ),
    };
    if expected.status_lengths != [1, 1] {
        return Err(at(format!(
            "IOPS and IOCS of {} and {} bytes: PROFINET's are one byte each",
            expected.status_lengths[0], expected.status_lengths[1]
        )));
    }
    // SharedInput, ReduceInputSubmoduleDataLength, ReduceOutputSubmoduleDataLength,
    // DiscardIOXS: for a device shared with another controller.
    if expected.properties & 0x3C != 0 {
        return Err(at(format!(
            "SubmoduleProperties 0x{:04X} (shared input, reduced data length or discarded \
             IOXS: a shared device): procimgd owns its devices' submodules",
            expected.properties
        )));
    }
    let Some(o) = object else {
        return Ok(sub);
    };
    sub.laddr = laddr(o)?;
    sub.records = records(o)?;
    if let Some(v) = o.variable(AID_IO_MAPPING) {
        let Value::Struct(elements) = &v.value else {
            return Err(problem(o, "IOmapping is not a STRUCT"));
        };
        let get = |aid: u32| -> Result<Option<u32>> {
            elements
                .iter()
                .find(|(a, _)| *a == aid)
                .map(|(_, s)| {
                    number(s)
                        .map(|n| n as u32)
                        .map_err(|m| problem(o, format!("IOmapping element {aid}: {m}")))
                })
                .transpose()
        };
        for (length_aid, length, what) in [
            (MAP_INPUT_LENGTH, expected.input_length, "input"),
            (MAP_OUTPUT_LENGTH, expected.output_length, "output"),
        ] {
            if let Some(mapped) = get(length_aid)?
                && mapped != u32::from(length)
            {
                return Err(problem(
                    o,
                    format!(
                        "IOmapping gives {mapped} {what} bytes, the expected configuration \
                         {length}: export the configuration again from TIA Portal"
                    ),
                ));
            }
        }
        if expected.input_length > 0 {
            sub.input_address = get(MAP_INPUT_ADDRESS)?;
        }
        if expected.output_length > 0 {
            sub.output_address = get(MAP_OUTPUT_ADDRESS)?;
        }
    }
    Ok(sub)
}

/// A submodule's parameter records, in the order of its transfer sequence where it has
/// one, the rest in file order.
fn records(o: &Object) -> Result<Vec<(u16, Vec<u8>)>> {
    let all = fields(o, AID_RECORDS);
    let mut order: Vec<&Field> = Vec::with_capacity(all.len());
    if let Some(v) = o.variable(AID_TRANSFER_SEQUENCE)
        && let Value::Blob(bytes) = &v.value
    {
        let sequence = index_list(bytes).map_err(|e| problem(o, format!("{}: {}", v.name, e.0)))?;
        for index in sequence {
            let f = all
                .iter()
                .find(|f| f.key == u64::from(index))
                .ok_or_else(|| {
                    problem(
                        o,
                        format!("the transfer sequence names record {index}, which it lacks"),
                    )
                })?;
            if !order.iter().any(|g| g.key == f.key) {
                order.push(f);
            }
        }
    }
    for f in all {
        if !order.iter().any(|g| g.key == f.key) {
            order.push(f);
        }
    }
    order
        .into_iter()
        .map(|f| {
            let index = u16::try_from(f.key).map_err(|_| Problem {
                line: f.line,
                element: o.describe(),
                message: format!("record index {} is beyond 0xFFFF", f.key),
            })?;
            Ok((index, f.data.clone()))
        })
        .collect()
}
