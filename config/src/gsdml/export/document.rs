// SPDX-License-Identifier: MIT OR Apache-2.0
//! The GSDML document of a planned station: the structure of the GSDML V2.4 schema, in its
//! element order, as the hand-written files in `config/gsdml/` have it.

use super::catalogue::Catalogue;
use super::plan::Plan;
use super::planned::{FileSubmodule, PlannedModule, Slots};
use super::xml::El;
use super::{Timing, VENDOR_NAME};
use crate::station::{AcceptedRecord, DAP_SUBSLOT, INTERFACE_SUBSLOT, PORT_SUBSLOT, StationConfig};

const NAMESPACE: &str = "http://www.profibus.com/GSDML/2003/11/DeviceProfile";
const DAP_ID: &str = "DAP";

/// What the I&M submodules let the PLC write (I&M0 is read-only).
const WRITEABLE_IM: &str = "1 2 3 4";

/// The `ExternalTextList` as it is filled, in order of first use.
#[derive(Default)]
struct Texts(Vec<(String, String)>);

impl Texts {
    /// The text ID `id` for `value`, added once.
    fn add(&mut self, id: impl Into<String>, value: impl Into<String>) -> String {
        let id = id.into();
        if !self.0.iter().any(|(i, _)| *i == id) {
            self.0.push((id.clone(), value.into()));
        }
        id
    }
}

/// The `ID` of the module with `module_ident`: what a controller configuration names it by
/// (`module = "M_0x00000010"`).
pub(super) fn module_id(module_ident: u32) -> String {
    format!("M_0x{module_ident:08X}")
}

/// The `ID` of the module's submodule in `subslot` (`submodule = "M_0x00000010_SS1"`).
pub(super) fn submodule_id(module_ident: u32, subslot: u16) -> String {
    format!("{}_SS{subslot}", module_id(module_ident))
}

fn hex32(v: u32) -> String {
    format!("0x{v:08X}")
}

/// "1 3..5": ascending `values` as a GSDML value list, runs as ranges.
fn value_list(values: &[u16]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < values.len() {
        let mut j = i;
        while j + 1 < values.len() && values[j + 1] == values[j] + 1 {
            j += 1;
        }
        parts.push(if j > i + 1 {
            format!("{}..{}", values[i], values[j])
        } else if j == i + 1 {
            format!("{} {}", values[i], values[j])
        } else {
            values[i].to_string()
        });
        i = j + 1;
    }
    parts.join(" ")
}

/// "1..64", or "3" for one slot.
fn range(slots: &core::ops::RangeInclusive<u16>) -> String {
    if slots.start() == slots.end() {
        slots.start().to_string()
    } else {
        format!("{}..{}", slots.start(), slots.end())
    }
}

/// Slots 0 to `max_slot`: "0..4", or "0" for the DAP alone.
fn physical_slots(max_slot: u16) -> String {
    match max_slot {
        0 => "0".to_owned(),
        n => format!("0..{n}"),
    }
}

fn bytes(n: u16) -> String {
    if n == 1 {
        "1 byte".to_owned()
    } else {
        format!("{n} bytes")
    }
}

/// "8 bytes in, 8 bytes out", "4 bytes in", "no IO data".
fn io_text(s: &FileSubmodule<'_>) -> String {
    match (s.input_length, s.output_length) {
        (0, 0) => "no IO data".to_owned(),
        (i, 0) => format!("{} in", bytes(i)),
        (0, o) => format!("{} out", bytes(o)),
        (i, o) => format!("{} in, {} out", bytes(i), bytes(o)),
    }
}

/// The head comment of a station's own file.
const STATION_COMMENT: &str = "Written by `procimg gsdml` from a procimgd configuration (role = \
     \"device\").\n     Not certified by PI; change the configuration and write the file again \
     rather than editing it.";

/// The comment at the file's head: who wrote it, and not to edit it. The writer's name
/// comes from the caller, so any "--" in it is broken up: it would end the comment.
fn head_comment(catalogue: Option<&Catalogue>) -> String {
    let mut text = match catalogue {
        None => STATION_COMMENT.to_owned(),
        Some(c) => format!(
            "Written by `{}`: a procimgd station and the modules its program may plug.\n     \
             Not certified by PI; write the file again rather than editing it.",
            c.writer
        ),
    };
    while text.contains("--") {
        text = text.replace("--", "- -");
    }
    format!("<!-- {text} -->\n")
}

/// The whole document, with the XML declaration and a closing line end.
pub(super) fn document(
    station: &StationConfig,
    catalogue: Option<&Catalogue>,
    plan: &Plan<'_>,
    timing: &Timing,
) -> String {
    let mut texts = Texts::default();
    let info = match catalogue {
        None => format!(
            "{}: procimgd as a PROFINET IO device, described by `procimg gsdml` from its \
             configuration",
            station.device_type
        ),
        Some(c) => c.info.clone(),
    };
    let identity = El::new("DeviceIdentity")
        .attr("VendorID", format!("0x{:04X}", station.vendor_id))
        .attr("DeviceID", format!("0x{:04X}", station.device_id))
        .child(El::new("InfoText").attr("TextId", texts.add("T_DeviceInfo", info)))
        .child(El::new("VendorName").attr("Value", VENDOR_NAME));
    let function = El::new("DeviceFunction").child(
        El::new("Family")
            .attr("MainFamily", "I/O")
            .attr("ProductFamily", &station.device_type),
    );
    let dap = dap(station, plan, timing, &mut texts);
    let modules: Vec<El> = plan.modules.iter().map(|m| module(m, &mut texts)).collect();

    let mut process =
        El::new("ApplicationProcess").child(El::new("DeviceAccessPointList").child(dap));
    if !modules.is_empty() {
        process = process.child(El::new("ModuleList").children(modules));
    }
    let text_list = El::new("PrimaryLanguage").children(
        texts
            .0
            .into_iter()
            .map(|(id, value)| El::new("Text").attr("TextId", id).attr("Value", value)),
    );
    process = process.child(El::new("ExternalTextList").child(text_list));

    let root = El::new("ISO15745Profile")
        .attr("xmlns", NAMESPACE)
        .attr("xmlns:xsi", "http://www.w3.org/2001/XMLSchema-instance")
        .attr(
            "xsi:schemaLocation",
            format!("{NAMESPACE} ..\\xsd\\GSDML-DeviceProfile-V2.4.xsd"),
        )
        .child(profile_header())
        .child(
            El::new("ProfileBody")
                .child(identity)
                .child(function)
                .child(process),
        );
    let mut out = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    out.push_str(&head_comment(catalogue));
    root.write(&mut out, 0);
    out
}

/// The ISO 15745 header every PROFINET GSDML file carries unchanged.
fn profile_header() -> El {
    let text = |name, value| El::new(name).text(value);
    El::new("ProfileHeader")
        .child(text("ProfileIdentification", "PROFINET Device Profile"))
        .child(text("ProfileRevision", "1.00"))
        .child(text("ProfileName", "Device Profile for PROFINET Devices"))
        .child(text(
            "ProfileSource",
            "PROFIBUS Nutzerorganisation e. V. (PNO)",
        ))
        .child(text("ProfileClassID", "Device"))
        .child(
            El::new("ISO15745Reference")
                .child(text("ISO15745Part", "4"))
                .child(text("ISO15745Edition", "1"))
                .child(text("ProfileTechnology", "GSDML")),
        )
}

fn dap(station: &StationConfig, plan: &Plan<'_>, timing: &Timing, texts: &mut Texts) -> El {
    let d = &station.dap;
    let name = texts.add("T_DAP_Name", station.device_type.clone());
    let info = texts.add(
        "T_DAP_Info",
        "Device access point: PROFINET interface X1 with one port",
    );
    let order = station.order_number.trim();
    let module_info = El::new("ModuleInfo")
        .child(El::new("Name").attr("TextId", &name))
        .child(El::new("InfoText").attr("TextId", &info))
        .child(El::new("VendorName").attr("Value", VENDOR_NAME))
        .children((!order.is_empty()).then(|| El::new("OrderNumber").attr("Value", order)))
        .child(El::new("HardwareRelease").attr("Value", station.hardware_revision))
        .child(El::new("SoftwareRelease").attr("Value", station.software_revision));
    let useable: Vec<El> = plan
        .modules
        .iter()
        .map(|m| {
            let item = El::new("ModuleItemRef").attr("ModuleItemTarget", module_id(m.module_ident));
            match &m.slots {
                Slots::Fixed(slots) => item.attr("FixedInSlots", value_list(slots)),
                Slots::Allowed(slots) => item.attr("AllowedInSlots", range(slots)),
            }
        })
        .collect();
    let own = El::new("VirtualSubmoduleItem")
        .attr("ID", "DAP_SM")
        .attr("SubmoduleIdentNumber", hex32(d.submodule_ident))
        .attr("FixedInSubslots", DAP_SUBSLOT)
        .attr("MayIssueProcessAlarm", "false")
        .attr_opt("Writeable_IM_Records", plan.dap_im.then_some(WRITEABLE_IM))
        .child(El::new("IOData"))
        .child(
            El::new("ModuleInfo")
                .child(El::new("Name").attr("TextId", &name))
                .child(El::new("InfoText").attr("TextId", &info)),
        );
    let ratios: Vec<String> = timing.reduction_ratios.iter().map(u16::to_string).collect();
    let interface = El::new("InterfaceSubmoduleItem")
        .attr("ID", "DAP_IF")
        .attr("SubslotNumber", INTERFACE_SUBSLOT)
        .attr("TextId", texts.add("T_Interface", "X1"))
        .attr("SubmoduleIdentNumber", hex32(d.interface_ident))
        .attr("SupportedRT_Classes", "RT_CLASS_1")
        .attr("SupportedProtocols", "LLDP")
        .attr("DCP_HelloSupported", station.dcp_hello)
        .attr("PTP_BoundarySupported", "false")
        .attr("DCP_BoundarySupported", "false")
        .attr("DelayMeasurementSupported", "false")
        .child(
            El::new("ApplicationRelations")
                .attr("StartupMode", "Advanced")
                .child(
                    El::new("TimingProperties")
                        .attr("SendClock", timing.send_clock)
                        .attr("ReductionRatio", ratios.join(" ")),
                ),
        );
    let port = El::new("PortSubmoduleItem")
        .attr("ID", "DAP_P1")
        .attr("SubslotNumber", PORT_SUBSLOT)
        .attr("TextId", texts.add("T_Port1", "X1 P1"))
        .attr("SubmoduleIdentNumber", hex32(d.port_ident))
        .attr("MaxPortRxDelay", 350)
        .attr("MaxPortTxDelay", 160)
        // 100BASE-TX full duplex.
        .child(El::new("MAUTypeList").child(El::new("MAUTypeItem").attr("Value", 16)));

    let mut item = El::new("DeviceAccessPointItem")
        .attr("ID", DAP_ID)
        .attr("PNIO_Version", "V2.4")
        .attr("PhysicalSlots", physical_slots(plan.max_slot))
        .attr("ModuleIdentNumber", hex32(d.module_ident))
        .attr("MinDeviceInterval", timing.min_device_interval)
        .attr("DNS_CompatibleName", &station.name)
        .attr("FixedInSlots", 0)
        .attr("ObjectUUID_LocalIndex", station.instance)
        .attr("DeviceAccessSupported", "false")
        .attr("MultipleWriteSupported", "true")
        .attr("CheckDeviceID_Allowed", "true")
        .attr("NameOfStationNotTransferable", "false")
        .attr("LLDP_NoD_Supported", "true")
        .attr("ResetToFactoryModes", 2)
        .child(module_info)
        .child(
            El::new("CertificationInfo")
                .attr("ConformanceClass", "A")
                .attr("NetloadClass", "I"),
        )
        .child(
            El::new("IOConfigData")
                .attr("MaxInputLength", plan.input_bytes)
                .attr("MaxOutputLength", plan.output_bytes),
        );
    if !useable.is_empty() {
        item = item.child(El::new("UseableModules").children(useable));
    }
    item.child(El::new("VirtualSubmoduleList").child(own))
        .child(
            El::new("SystemDefinedSubmoduleList")
                .child(interface)
                .child(port),
        )
}

fn module(m: &PlannedModule<'_>, texts: &mut Texts) -> El {
    let id = module_id(m.module_ident);
    let name = texts.add(
        format!("T_{id}"),
        match m.name {
            Some(name) => name.to_owned(),
            None => format!("Module 0x{:08X}", m.module_ident),
        },
    );
    let contents: Vec<String> = m
        .submodules
        .iter()
        .map(|s| format!("subslot {}: {}", s.subslot, io_text(s)))
        .collect();
    let slots = match &m.slots {
        Slots::Fixed(slots) => format!("In slot(s) {}", value_list(slots)),
        Slots::Allowed(slots) => format!("Allowed in slots {}", range(slots)),
    };
    let info = texts.add(
        format!("T_{id}_Info"),
        format!("{slots}; {}", contents.join("; ")),
    );
    let submodules: Vec<El> = m
        .submodules
        .iter()
        .map(|s| submodule(m.module_ident, s, texts))
        .collect();
    El::new("ModuleItem")
        .attr("ID", &id)
        .attr("ModuleIdentNumber", hex32(m.module_ident))
        .child(
            El::new("ModuleInfo")
                .child(El::new("Name").attr("TextId", name))
                .child(El::new("InfoText").attr("TextId", info)),
        )
        .child(El::new("VirtualSubmoduleList").children(submodules))
}

fn submodule(module_ident: u32, s: &FileSubmodule<'_>, texts: &mut Texts) -> El {
    let id = submodule_id(module_ident, s.subslot);
    let name = texts.add(
        format!("T_{id}"),
        format!("Subslot {}: {}", s.subslot, io_text(s)),
    );
    let mut io = El::new("IOData");
    if s.input_length > 0 {
        let text = texts.add("T_Input", "Input data (the device provides, the PLC reads)");
        io = io.child(
            El::new("Input")
                .attr("Consistency", "All items consistency")
                .child(data_item(s.input_length, text)),
        );
    }
    if s.output_length > 0 {
        let text = texts.add("T_Output", "Output data (the PLC writes, the device reads)");
        io = io.child(
            El::new("Output")
                .attr("Consistency", "All items consistency")
                .child(data_item(s.output_length, text)),
        );
    }
    let records: Vec<El> = s.accepts.iter().map(|r| record(r, texts)).collect();
    let mut item = El::new("VirtualSubmoduleItem")
        .attr("ID", &id)
        .attr("SubmoduleIdentNumber", hex32(s.submodule_ident))
        .attr_opt("API", (s.api != 0).then_some(s.api))
        .attr("FixedInSubslots", s.subslot)
        .attr("MayIssueProcessAlarm", "true")
        .attr_opt("Writeable_IM_Records", s.im.then_some(WRITEABLE_IM))
        .child(io);
    if !records.is_empty() {
        item = item.child(El::new("RecordDataList").children(records));
    }
    item.child(El::new("ModuleInfo").child(El::new("Name").attr("TextId", name)))
}

/// The IO data of one direction as one item: a byte as `Unsigned8`, more as an `OctetString`
/// of that length, which engineering tools show as bytes for the user to interpret.
fn data_item(length: u16, text_id: String) -> El {
    let item = El::new("DataItem");
    let item = if length == 1 {
        item.attr("DataType", "Unsigned8")
    } else {
        item.attr("DataType", "OctetString").attr("Length", length)
    };
    item.attr("TextId", text_id)
}

/// A parameter record the submodule accepts, whose default (what the PLC writes at connect)
/// is what the station returns before any write.
fn record(r: &AcceptedRecord, texts: &mut Texts) -> El {
    let name = texts.add(
        format!("T_Record_{}_{}", r.index, r.length),
        format!("Parameter record {} ({})", r.index, bytes(r.length)),
    );
    let data: Vec<String> = r.initial.iter().map(|b| format!("0x{b:02X}")).collect();
    El::new("ParameterRecordDataItem")
        .attr("Index", r.index)
        .attr("Length", r.length)
        .child(El::new("Name").attr("TextId", name))
        .child(
            El::new("Const")
                .attr("ByteOffset", 0)
                .attr("Data", data.join(",")),
        )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_lists() {
        assert_eq!(value_list(&[1]), "1");
        assert_eq!(value_list(&[1, 2]), "1 2");
        assert_eq!(value_list(&[1, 2, 3, 5, 7, 8, 9, 10]), "1..3 5 7..10");
        assert_eq!(value_list(&[]), "");
    }
}
