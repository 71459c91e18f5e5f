// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg gsdml`'s writer: the GSDML file of a station, read back by procimg's own GSDML
//! import as a controller configuration names it, gives the station's identity and every
//! submodule (DAP's included) as configured; the file is well-formed XML with what an
//! engineering tool reads; what one GSDML file cannot describe is refused with a message.

use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

use procimg_config::gsdml::export::{
    ExportError, GsdmlDate, StationGsdml, module_item_id, station_gsdml, submodule_item_id,
};
use procimg_config::{Config, DeviceConfig, StationConfig, parse, parse_in_dir};

fn date() -> GsdmlDate {
    GsdmlDate::new(2025, 1, 31).unwrap()
}

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "procimg-gsdml-export-{}-{}-{name}",
        std::process::id(),
        NEXT.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A device configuration: `[station]` keys, then `[[station.submodule]]` tables.
fn device_config(station: &str, submodules: &str) -> Config {
    let text = format!(
        "role = \"device\"\n[station]\nname = \"pc-device\"\nvendor_id = 0x0493\n\
         device_id = 0x0100\n{station}\n{submodules}"
    );
    match parse(&text, "device.toml") {
        Ok(c) => c,
        Err(e) => panic!("refused: {e}\n{text}"),
    }
}

fn export(config: &Config) -> Result<StationGsdml, ExportError> {
    station_gsdml(config.station.as_ref().unwrap(), config.cycle_ns, date())
}

/// What the file says about a submodule: (api, slot, subslot, module ident, submodule
/// ident, input, output, records as (index, data) by index).
type Described = (u32, u16, u16, u32, u32, u16, u16, Vec<(u16, Vec<u8>)>);

fn of_station(station: &StationConfig) -> Vec<Described> {
    let mut out: Vec<Described> = station
        .submodules
        .iter()
        .map(|s| {
            let m = &s.submodule;
            let mut records: Vec<(u16, Vec<u8>)> = s
                .accepts
                .iter()
                .map(|r| (r.index, r.initial.clone()))
                .collect();
            records.sort();
            (
                m.api,
                m.slot,
                m.subslot,
                m.module_ident,
                m.submodule_ident,
                m.input_length,
                m.output_length,
                records,
            )
        })
        .collect();
    out.sort();
    out
}

fn of_device(device: &DeviceConfig) -> Vec<Described> {
    let mut out: Vec<Described> = device
        .submodules
        .iter()
        .map(|m| {
            let mut records: Vec<(u16, Vec<u8>)> = m
                .records
                .iter()
                .map(|r| (r.index, r.data.clone()))
                .collect();
            records.sort();
            (
                m.api,
                m.slot,
                m.subslot,
                m.module_ident,
                m.submodule_ident,
                m.input_length,
                m.output_length,
                records,
            )
        })
        .collect();
    out.sort();
    out
}

/// The controller configuration of the station's GSDML file in `dir`: every submodule of
/// slots 1 and up by its module (and submodule, where the module has several); slot 0 left
/// to the import.
fn controller_config(station: &StationConfig, file_name: &str) -> String {
    let mut text = format!(
        "[[device]]\nname = \"{}\"\ngsdml = \"{file_name}\"\n",
        station.name
    );
    for s in station.submodules.iter().filter(|s| s.submodule.slot != 0) {
        let m = &s.submodule;
        let siblings = station
            .submodules
            .iter()
            .filter(|o| o.submodule.slot == m.slot)
            .count();
        text.push_str(&format!(
            "[[device.submodule]]\nslot = {}\nmodule = \"{}\"\n",
            m.slot,
            module_item_id(m.module_ident)
        ));
        if siblings > 1 {
            text.push_str(&format!(
                "submodule = \"{}\"\n",
                submodule_item_id(m.module_ident, m.subslot)
            ));
        }
    }
    text
}

/// Writes the station's file, imports it as a controller would, and compares.
#[track_caller]
fn round_trip(config: &Config, name: &str) -> StationGsdml {
    let station = config.station.as_ref().unwrap();
    let gsdml = match export(config) {
        Ok(g) => g,
        Err(e) => panic!("not exported: {e}"),
    };
    let dir = scratch(name);
    std::fs::write(dir.join(&gsdml.file_name), &gsdml.xml).unwrap();
    let text = controller_config(station, &gsdml.file_name);
    let imported = match parse_in_dir(&text, "plant.toml", &dir) {
        Ok(c) => c,
        Err(e) => panic!("the import refused: {e}\n{text}\n{}", gsdml.xml),
    };
    let device = &imported.devices[0];
    assert_eq!(
        (device.vendor_id, device.device_id),
        (station.vendor_id, station.device_id)
    );
    assert_eq!(device.instance, 1, "the controller's default");
    assert_eq!(
        of_device(device),
        of_station(station),
        "imported (left) and configured (right) differ; the file:\n{}",
        gsdml.xml
    );
    let _ = std::fs::remove_dir_all(&dir);
    gsdml
}

#[test]
fn the_device_demo_comes_back_as_configured() {
    let demo = Config::demo_device();
    let gsdml = round_trip(&demo, "demo");
    assert_eq!(
        gsdml.file_name,
        "GSDML-V2.4-procimg-procimg_device-20250131.xml"
    );
}

/// Three modules, one of them in two slots with three submodules each (one without data,
/// one with I&M, records), one in API 0x3A00; I&M0 text that XML has to escape.
fn several() -> Config {
    device_config(
        "dcp_hello = true\ninstance = 7\norder_number = \"A&B <1>\"\n\
         device_type = \"a \\\"quoted\\\" <type> & more\"",
        r#"
[[station.submodule]]
slot = 1
module_ident = 0x10
submodule_ident = 0x100
input_length = 1
output_length = 2
records = [{ index = 1, length = 4, data = [0, 0, 0, 10] }, { index = 0x7FFF, length = 1, data = [0xFF] }]
[[station.submodule]]
slot = 1
subslot = 2
module_ident = 0x10
submodule_ident = 0x101
im = true
[[station.submodule]]
slot = 1
subslot = 7
module_ident = 0x10
submodule_ident = 0x102
output_length = 16
[[station.submodule]]
slot = 3
module_ident = 0x20
submodule_ident = 0x1
input_length = 4
records = [{ index = 2, length = 3 }]
[[station.submodule]]
slot = 5
module_ident = 0x10
submodule_ident = 0x100
input_length = 1
output_length = 2
records = [{ index = 0x7FFF, length = 1, data = [0xFF] }, { index = 1, length = 4, data = [0, 0, 0, 10] }]
[[station.submodule]]
slot = 5
subslot = 2
module_ident = 0x10
submodule_ident = 0x101
im = true
[[station.submodule]]
slot = 5
subslot = 7
module_ident = 0x10
submodule_ident = 0x102
output_length = 16
[[station.submodule]]
api = 0x3A00
slot = 6
module_ident = 0xFFFFFFFF
submodule_ident = 0xFFFFFFFF
input_length = 2
"#,
    )
}

#[test]
fn slots_subslots_apis_and_records_come_back() {
    let several = several();
    let gsdml = round_trip(&several, "several");
    // Slots 1 and 5 hold one module.
    assert_eq!(
        gsdml.xml.matches("<ModuleItem ").count(),
        3,
        "{}",
        gsdml.xml
    );
    assert!(gsdml.xml.contains("FixedInSlots=\"1 5\""), "{}", gsdml.xml);

    assert_eq!(
        gsdml.file_name,
        "GSDML-V2.4-procimg-a_quoted_type_more-20250131.xml"
    );
}

#[test]
fn full_frames_and_the_longest_record_come_back() {
    let data: Vec<String> = (0..4068u32).map(|i| (i % 251).to_string()).collect();
    let data = data.join(", ");
    // The DAP's three submodules and this one fill the frame: 3 + 1436 + 1 IOPS = 1440.
    let full_input = device_config(
        "",
        &format!(
            "[[station.submodule]]\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
             input_length = 1436\nrecords = [{{ index = 100, length = 4068, data = [{data}] }}]\n"
        ),
    );
    let gsdml = round_trip(&full_input, "full-input");
    assert!(
        gsdml.xml.contains("MaxInputLength=\"1440\""),
        "{}",
        gsdml.xml
    );
    let full_output = device_config(
        "",
        "[[station.submodule]]\nslot = 32767\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         output_length = 1436\n",
    );
    let gsdml = round_trip(&full_output, "full-output");
    assert!(
        gsdml.xml.contains("MaxOutputLength=\"1440\""),
        "{}",
        gsdml.xml
    );
    assert!(
        gsdml.xml.contains("PhysicalSlots=\"0..32767\""),
        "{}",
        gsdml.xml
    );
}

#[test]
fn a_station_of_the_access_point_alone_comes_back() {
    let alone = device_config("", "");
    let gsdml = round_trip(&alone, "alone");
    assert!(!gsdml.xml.contains("<ModuleList"), "{}", gsdml.xml);
}

/// The element's attribute, or a panic naming it.
fn attr<'a>(node: roxmltree::Node<'a, '_>, name: &str) -> &'a str {
    node.attribute(name)
        .unwrap_or_else(|| panic!("<{}> has no {name}", node.tag_name().name()))
}

#[test]
fn the_file_is_well_formed_xml_with_what_a_tool_reads() {
    let gsdml = export(&several()).unwrap();
    let doc = match roxmltree::Document::parse(&gsdml.xml) {
        Ok(d) => d,
        Err(e) => panic!("not well-formed: {e}\n{}", gsdml.xml),
    };
    let root = doc.root_element();
    assert_eq!(
        (root.tag_name().namespace(), root.tag_name().name()),
        (
            Some("http://www.profibus.com/GSDML/2003/11/DeviceProfile"),
            "ISO15745Profile"
        )
    );
    let find = |name: &str| {
        doc.descendants()
            .find(|n| n.tag_name().name() == name)
            .unwrap_or_else(|| panic!("no <{name}>"))
    };
    let dap = find("DeviceAccessPointItem");
    assert_eq!(attr(dap, "PNIO_Version"), "V2.4");
    assert_eq!(attr(dap, "DNS_CompatibleName"), "pc-device");
    assert_eq!(attr(dap, "ObjectUUID_LocalIndex"), "7");
    assert_eq!(attr(dap, "PhysicalSlots"), "0..6");
    assert_eq!(attr(dap, "LLDP_NoD_Supported"), "true");
    assert_eq!(attr(find("OrderNumber"), "Value"), "A&B <1>");
    assert_eq!(attr(find("SoftwareRelease"), "Value"), "V0.1.0");
    assert_eq!(attr(find("CertificationInfo"), "ConformanceClass"), "A");
    assert_eq!(
        attr(find("InterfaceSubmoduleItem"), "DCP_HelloSupported"),
        "true"
    );
    // The frames: inputs 3 (the DAP's IOPS) + 2 x 5 (slots 1 and 5: 1 + IOPS, IOCS; IOPS;
    // IOCS) + 5 (slot 3: 4 + IOPS) + 3 (slot 6: 2 + IOPS); outputs 3 + 2 x 22 (IOCS, 2 +
    // IOPS; IOCS; 16 + IOPS) + 1 + 1 (IOCS of slots 3 and 6).
    let io = find("IOConfigData");
    assert_eq!(
        (attr(io, "MaxInputLength"), attr(io, "MaxOutputLength")),
        ("21", "49")
    );
    let family = find("Family");
    assert_eq!(attr(family, "ProductFamily"), "a \"quoted\" <type> & more");

    let items = |name: &'static str| {
        doc.descendants()
            .filter(move |n| n.tag_name().name() == name)
    };
    let im: Vec<&str> = items("VirtualSubmoduleItem")
        .filter(|n| n.attribute("Writeable_IM_Records") == Some("1 2 3 4"))
        .map(|n| attr(n, "ID"))
        .collect();
    assert_eq!(im, ["DAP_SM", "M_0x00000010_SS2"]);
    let one_byte = items("DataItem").find(|n| n.attribute("DataType") == Some("Unsigned8"));
    assert!(one_byte.is_some_and(|n| n.attribute("Length").is_none()));

    // Every ID is unique, and every TextId has its text.
    let mut ids: Vec<&str> = doc
        .descendants()
        .filter_map(|n| n.attribute("ID"))
        .collect();
    let count = ids.len();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), count, "IDs repeat");
    let texts: Vec<&str> = items("Text").map(|n| attr(n, "TextId")).collect();
    for n in doc.descendants().filter(|n| n.tag_name().name() != "Text") {
        if let Some(id) = n.attribute("TextId") {
            assert!(texts.contains(&id), "no text {id}");
        }
    }
    let mut unique = texts.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), texts.len(), "texts repeat");
}

#[test]
fn the_cycle_limits_the_reduction_ratios() {
    let slow = device_config("", "").clone();
    let station = slow.station.as_ref().unwrap();
    let gsdml = station_gsdml(station, 8_000_000, date()).unwrap();
    assert!(
        gsdml
            .xml
            .contains("ReductionRatio=\"8 16 32 64 128 256 512\""),
        "{}",
        gsdml.xml
    );
    assert!(gsdml.xml.contains("MinDeviceInterval=\"256\""));
    let e = station_gsdml(station, 3_000_000, date()).unwrap_err();
    assert_eq!(
        e,
        ExportError::Cycle {
            cycle_ns: 3_000_000
        }
    );
    assert!(e.to_string().contains("choose a cycle_time"), "{e}");
}

#[track_caller]
fn refused(config: &Config, phrases: &[&str]) -> ExportError {
    let e = match export(config) {
        Ok(g) => panic!("exported:\n{}", g.xml),
        Err(e) => e,
    };
    let shown = e.to_string();
    for phrase in phrases {
        assert!(shown.contains(phrase), "{phrase:?} not in: {shown}");
    }
    e
}

#[test]
fn what_one_gsdml_file_cannot_describe_is_refused() {
    let differ = device_config(
        "",
        "[[station.submodule]]\nslot = 2\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         input_length = 4\n\
         [[station.submodule]]\nslot = 4\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         input_length = 2\n",
    );
    refused(
        &differ,
        &[
            "slots 2 and 4 both hold module_ident 0x00000010",
            "slot 2 has subslot 1 (API 0, submodule_ident 0x00000001, 4 bytes in, 0 out, \
             records none), slot 4 subslot 1 (API 0, submodule_ident 0x00000001, 2 bytes in",
            "give one of the slots another module_ident",
        ],
    );
    let data_differs = device_config(
        "",
        "[[station.submodule]]\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         records = [{ index = 3, length = 1, data = [1] }]\n\
         [[station.submodule]]\nslot = 2\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         records = [{ index = 3, length = 1, data = [2] }]\n",
    );
    refused(&data_differs, &["the records' data differ"]);
    let fewer = device_config(
        "",
        "[[station.submodule]]\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         [[station.submodule]]\nslot = 1\nsubslot = 2\nmodule_ident = 0x10\nsubmodule_ident = 2\n\
         [[station.submodule]]\nslot = 2\nmodule_ident = 0x10\nsubmodule_ident = 1\n",
    );
    refused(&fewer, &["slot 1 has 2 submodule(s), slot 2 1"]);
    let two_apis = device_config(
        "",
        "[[station.submodule]]\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         [[station.submodule]]\napi = 1\nslot = 1\nsubslot = 2\nmodule_ident = 0x20\n\
         submodule_ident = 1\n",
    );
    refused(
        &two_apis,
        &["slot 1 holds module_ident 0x00000010 in one API"],
    );
    let same_subslot = device_config(
        "",
        "[[station.submodule]]\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 1\n\
         [[station.submodule]]\napi = 1\nslot = 1\nmodule_ident = 0x10\nsubmodule_ident = 2\n",
    );
    refused(
        &same_subslot,
        &["slot 1 subslot 1 is used in API 0 and in API 1"],
    );
    let dap_ident = device_config(
        "",
        "[[station.submodule]]\nslot = 1\nmodule_ident = 0x1\nsubmodule_ident = 1\n",
    );
    refused(
        &dap_ident,
        &["the device access point's", "give it another"],
    );

    // Stations built by hand, not from a configuration.
    let mut odd = Config::demo_device();
    let station = odd.station.as_mut().unwrap();
    station.submodules[1].submodule.input_length = 2;
    refused(&odd, &["slot 0 subslot 0x8000"]);
    let mut short = Config::demo_device();
    short.station.as_mut().unwrap().submodules[3].accepts[0]
        .initial
        .pop();
    refused(&short, &["record 1 of slot 1 subslot 1"]);
}
