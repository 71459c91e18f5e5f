// SPDX-License-Identifier: MIT OR Apache-2.0
//! GSDML import: what a device's GSDML file fills into the configuration (ident numbers, IO
//! lengths, the DAP submodules, parameter records), the refusals with both files' lines, the
//! demo's GSDML files against demo.toml, and no panics on any XML.

use std::path::{Path, PathBuf};
use tempfile::TempDir;

use procimg_config::gsdml::{Gsdml, GsdmlError, SubmoduleKind};
use procimg_config::{
    self as config, Config, ConfigError, DeviceConfig, GsdmlSource, ParameterRecord,
    SubmoduleConfig,
};
use procimg_shm_layout::NO_ADDRESS;
use proptest::prelude::*;

const SAMPLE: &str = "tests/fixtures/gsdml/sample-16real-32bool.xml";
const DEMO_ECHO: &str = "gsdml/GSDML-V2.4-procimg-SimEcho-20261121.xml";
const DEMO_COUNTER: &str = "gsdml/GSDML-V2.4-procimg-SimCounter-20261121.xml";
const DEMO_DIO: &str = "gsdml/GSDML-V2.4-procimg-SimDIO-20261121.xml";

/// A file of this package, by its path relative to the package.
fn package_file(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn sample_text() -> String {
    std::fs::read_to_string(package_file(SAMPLE)).unwrap()
}

/// A fresh directory for one test, removed when the guard drops.
fn scratch(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("procimg-gsdml-{name}-"))
        .tempdir()
        .unwrap_or_else(|e| panic!("cannot create a directory for test {name}: {e}"))
}

/// `e` and its sources, joined as procimgd prints an error (`{:#}` of anyhow).
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut shown = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        shown.push_str(&format!(": {s}"));
        source = s.source();
    }
    shown
}

/// The 1-based line of the only line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    let hits: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.contains(needle))
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(hits.len(), 1, "{needle:?} should be on one line of\n{text}");
    hits[0]
}

/// Parses `text` with relative GSDML paths starting at the runtime package.
fn parse(text: &str) -> Result<Config, ConfigError> {
    config::parse_in_dir(text, "plant.toml", Path::new(env!("CARGO_MANIFEST_DIR")))
}

#[track_caller]
fn accepted(text: &str) -> Config {
    match parse(text) {
        Ok(c) => c,
        Err(e) => panic!("refused: {e}\n{text}"),
    }
}

/// Asserts that `text` is refused on the line holding `needle`, for `key`, with every phrase
/// in the message; returns the error.
#[track_caller]
fn refused_at(text: &str, needle: &str, key: &str, phrases: &[&str]) -> ConfigError {
    let e = match parse(text) {
        Ok(c) => panic!("accepted:\n{text}\n{c:#?}"),
        Err(e) => e,
    };
    let shown = e.to_string();
    assert_eq!(e.line(), Some(line_of(text, needle)), "line of: {shown}");
    assert_eq!(e.key(), Some(key), "key of: {shown}");
    let prefix = format!("plant.toml:{}: {key}: ", line_of(text, needle));
    assert!(
        shown.starts_with(&prefix),
        "{prefix:?} does not start: {shown}"
    );
    for phrase in phrases {
        assert!(shown.contains(phrase), "{phrase:?} not in: {shown}");
    }
    e
}

/// A device of the sample GSDML with `submodules` (TOML text).
fn sample_device(submodules: &str) -> String {
    format!("[[device]]\nname = \"pnio\"\ngsdml = \"{SAMPLE}\"\n{submodules}")
}

/// One `[[device.submodule]]` table.
fn sub(slot: u16, extra: &str) -> String {
    format!("[[device.submodule]]\nslot = {slot}\n{extra}\n")
}

/// The submodules as (slot, subslot, module ident, submodule ident, input, output).
fn idents(d: &DeviceConfig) -> Vec<(u16, u16, u32, u32, u16, u16)> {
    d.submodules
        .iter()
        .map(|s| {
            (
                s.slot,
                s.subslot,
                s.module_ident,
                s.submodule_ident,
                s.input_length,
                s.output_length,
            )
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// The pnio sample file.

#[test]
fn sample_file_reads_as_written() {
    let g = Gsdml::load(&package_file(SAMPLE)).unwrap();
    assert_eq!((g.vendor_id, g.device_id), (0xFFFF, 0x0001));
    assert_eq!(g.vendor_name.as_deref(), Some("Core Engineering"));
    assert_eq!(g.identity_line, 16);

    assert_eq!(g.daps.len(), 1);
    let dap = &g.daps[0];
    assert_eq!(
        (dap.id.as_str(), dap.name.as_deref()),
        ("DAP1", Some("pnio DAP"))
    );
    assert_eq!((dap.line, dap.module_ident), (25, 1));
    assert_eq!(dap.fixed_in_slots.to_string(), "0");
    assert_eq!(dap.physical_slots.as_ref().unwrap().to_string(), "0..4");
    let subs: Vec<(&str, SubmoduleKind, String, u32, usize)> = dap
        .submodules
        .iter()
        .map(|s| {
            (
                s.id.as_str(),
                s.kind,
                s.subslots.as_ref().unwrap().to_string(),
                s.submodule_ident,
                s.line,
            )
        })
        .collect();
    assert_eq!(
        subs,
        [
            ("DAP1_SM", SubmoduleKind::Virtual, "1".into(), 0x1, 42),
            (
                "DAP1_IF",
                SubmoduleKind::Interface,
                "32768".into(),
                0x8000,
                51
            ),
            ("DAP1_P1", SubmoduleKind::Port, "32769".into(), 0x8001, 56),
        ]
    );
    assert_eq!(
        dap.submodules[1].name.as_deref(),
        Some("PROFINET interface")
    );
    assert_eq!(dap.submodules[2].name.as_deref(), Some("Port 1"));
    let useable: Vec<(&str, String)> = dap
        .useable_modules
        .iter()
        .map(|r| (r.target.as_str(), r.positions()))
        .collect();
    assert_eq!(
        useable,
        [
            ("M1", "1".into()),
            ("M2", "2".into()),
            ("M3", "3".into()),
            ("M4", "4".into())
        ]
    );

    // (ID, name, module ident, line, submodule ident, input bytes, output bytes)
    let modules: Vec<_> = g
        .modules
        .iter()
        .map(|m| {
            assert_eq!(m.submodules.len(), 1);
            let s = &m.submodules[0];
            let io = g.io_lengths(s).unwrap();
            assert!(g.records(s).unwrap().is_empty());
            (
                m.id.as_str(),
                m.name.as_deref().unwrap(),
                m.module_ident,
                m.line,
                s.submodule_ident,
                io.input,
                io.output,
            )
        })
        .collect();
    assert_eq!(
        modules,
        [
            ("M1", "in1", 0x101, 65, 1, 64, 0),
            ("M2", "in2", 0x102, 102, 1, 4, 0),
            ("M3", "out3", 0x103, 163, 1, 0, 64),
            ("M4", "out4", 0x104, 200, 1, 0, 4),
        ]
    );
    for s in &dap.submodules {
        assert_eq!(g.io_lengths(s).unwrap(), Default::default());
        assert!(g.records(s).unwrap().is_empty());
    }
    assert!(g.submodules.is_empty());
}

#[test]
fn sample_device_by_module_names() {
    let text = sample_device(&format!(
        "{}{}{}{}",
        sub(1, "module = \"in1\""),
        sub(2, "module = \"in2\""),
        sub(3, "module = \"out3\""),
        sub(4, "module = \"out4\""),
    ));
    let c = accepted(&text);
    let d = &c.devices[0];
    assert_eq!((d.vendor_id, d.device_id), (0xFFFF, 0x0001));
    assert_eq!(
        d.gsdml,
        Some(GsdmlSource {
            path: package_file(SAMPLE),
            dap: "DAP1".into()
        })
    );
    // The DAP's submodule, interface and port come first, in slot 0.
    assert_eq!(
        idents(d),
        [
            (0, 1, 0x1, 0x1, 0, 0),
            (0, 0x8000, 0x1, 0x8000, 0, 0),
            (0, 0x8001, 0x1, 0x8001, 0, 0),
            (1, 1, 0x101, 0x1, 64, 0),
            (2, 1, 0x102, 0x1, 4, 0),
            (3, 1, 0x103, 0x1, 0, 64),
            (4, 1, 0x104, 0x1, 0, 4),
        ]
    );
    let addresses: Vec<(u32, u32)> = d
        .submodules
        .iter()
        .map(|s| (s.input_address, s.output_address))
        .collect();
    // The DAP, interface and port have no IO data: diagnostic addresses after the inputs.
    let diagnostic = |a: u32| (a, NO_ADDRESS);
    assert_eq!(
        addresses,
        [
            diagnostic(68),
            diagnostic(69),
            diagnostic(70),
            (0, NO_ADDRESS),
            (64, NO_ADDRESS),
            (NO_ADDRESS, 0),
            (NO_ADDRESS, 64)
        ]
    );
    for s in &d.submodules {
        assert_eq!((s.api, s.rt_class), (0, 1));
        assert!(s.records.is_empty());
    }

    // The same by IDs, with the subslot and agreeing keys spelt out.
    let by_id = sample_device(&format!(
        "{}{}{}{}",
        sub(
            1,
            "module = \"M1\"\nsubmodule = \"M1_SM\"\nsubslot = 1\nmodule_ident = 0x101\n\
             submodule_ident = 1\ninput_length = 64\noutput_length = 0\napi = 0"
        ),
        sub(2, "module = \"M2\""),
        sub(3, "module = \"M3\""),
        sub(4, "module = \"M4\""),
    ));
    let again = accepted(&by_id);
    assert_eq!(again.devices, c.devices);
    // vendor_id and device_id may be given if they match.
    let with_ids = text.replace("gsdml =", "vendor_id = 0xFFFF\ndevice_id = 1\ngsdml =");
    assert_eq!(accepted(&with_ids).devices, c.devices);
}

#[test]
fn slot_zero_listed_replaces_the_automatic_dap() {
    let text = sample_device(&format!(
        "{}{}",
        sub(0, "module = \"DAP1\""),
        sub(0, "module = \"pnio DAP\"\nsubslot = 0x8000"),
    ));
    let c = accepted(&text);
    assert_eq!(
        idents(&c.devices[0]),
        [(0, 1, 0x1, 0x1, 0, 0), (0, 0x8000, 0x1, 0x8000, 0, 0)]
    );
    let text = sample_device(&sub(0, "module = \"DAP1\"\nsubmodule = \"DAP1_P1\""));
    assert_eq!(
        idents(&accepted(&text).devices[0]),
        [(0, 0x8001, 0x1, 0x8001, 0, 0)]
    );
    // Slot 0 by hand, without the GSDML, also switches the automatic DAP off.
    let text = sample_device(&format!(
        "{}{}",
        sub(0, "subslot = 1\nmodule_ident = 1\nsubmodule_ident = 1"),
        sub(1, "module = \"in1\""),
    ));
    assert_eq!(
        idents(&accepted(&text).devices[0]),
        [(0, 1, 0x1, 0x1, 0, 0), (1, 1, 0x101, 0x1, 64, 0)]
    );
}

#[test]
fn relative_paths_start_at_the_configuration_file() {
    let scratch = scratch("relative");
    let dir = scratch.path();
    std::fs::create_dir_all(dir.join("gsdml")).unwrap();
    std::fs::write(dir.join("gsdml/device.xml"), sample_text()).unwrap();
    let text = "[[device]]\nname = \"pnio\"\ngsdml = \"gsdml/device.xml\"\n\
                [[device.submodule]]\nslot = 1\nmodule = \"in1\"\n";
    let file = dir.join("plant.toml");
    std::fs::write(&file, text).unwrap();
    let c = config::load(&file, &|_: &str| Ok(())).unwrap();
    assert_eq!(
        c.devices[0].gsdml.as_ref().unwrap().path,
        dir.join("gsdml/device.xml")
    );
    assert_eq!(c.devices[0].submodules[3].input_length, 64);

    // parse() starts at the current directory: the package directory under `cargo test`.
    let text = format!(
        "[[device]]\nname = \"pnio\"\ngsdml = \"{SAMPLE}\"\n[[device.submodule]]\nslot = 1\n\
         module = \"in1\"\n"
    );
    let c = config::parse(&text, "plant.toml").unwrap();
    assert_eq!(c.devices[0].gsdml.as_ref().unwrap().path, Path::new(SAMPLE));
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn one_file_serves_several_devices() {
    let mut text = String::new();
    for name in ["a", "b", "c"] {
        text.push_str(
            &sample_device(&sub(2, "module = \"in2\"")).replace("\"pnio\"", &format!("{name:?}")),
        );
    }
    let c = accepted(&text);
    let inputs: Vec<u32> = c
        .devices
        .iter()
        .map(|d| d.submodules[3].input_address)
        .collect();
    assert_eq!(inputs, [0, 4, 8]);
    assert_eq!(c.submodule_count(), 12);
}

// ---------------------------------------------------------------------------------------------
// Parameter records.

#[test]
fn records_come_with_their_default_values() {
    let text = format!(
        "[[device]]\nname = \"dio\"\ngsdml = \"{DEMO_DIO}\"\n{}",
        sub(3, "module = \"AI 2\"")
    );
    let c = accepted(&text);
    let ai = c.devices[0].submodules.last().unwrap();
    assert_eq!(
        (ai.module_ident, ai.input_length, ai.output_length),
        (0x42, 4, 0)
    );
    // TransferSequence puts the limits (257) first: -27648 and 27648 as Integer16; then the
    // channel record (256): version 1, range 2, wire break on (bit 0), smoothing 5 in bits 4..6.
    assert_eq!(
        ai.records,
        [
            ParameterRecord {
                index: 257,
                data: vec![0x94, 0x00, 0x6C, 0x00]
            },
            ParameterRecord {
                index: 256,
                data: vec![0x01, 0x02, 0x01, 0x50]
            },
        ]
    );
    // Records given in the configuration replace them, `records = []` by none.
    let own = text.replace(
        "module = \"AI 2\"",
        "module = \"AI 2\"\nrecords = [{ index = 256, data = [1, 0, 0, 0] }]",
    );
    let c = accepted(&own);
    assert_eq!(
        c.devices[0].submodules.last().unwrap().records,
        [ParameterRecord {
            index: 256,
            data: vec![1, 0, 0, 0]
        }]
    );
    let none = text.replace("module = \"AI 2\"", "module = \"AI 2\"\nrecords = []");
    assert!(
        accepted(&none).devices[0]
            .submodules
            .last()
            .unwrap()
            .records
            .is_empty()
    );
}

/// A GSDML file with one DAP (`dap_extra` inside its element) and the module `M` whose
/// virtual submodule holds `sub_body`.
fn small_gsdml(dap_extra: &str, sub_body: &str) -> String {
    format!(
        r#"<?xml version="1.0" encoding="utf-8"?>
<ISO15745Profile xmlns="http://www.profibus.com/GSDML/2003/11/DeviceProfile">
  <ProfileBody>
    <DeviceIdentity VendorID="0x0493" DeviceID="0x0042"/>
    <ApplicationProcess>
      <DeviceAccessPointList>
        <DeviceAccessPointItem ID="DAP" ModuleIdentNumber="0x1">
          <UseableModules><ModuleItemRef ModuleItemTarget="M" AllowedInSlots="1..8"/></UseableModules>
          <VirtualSubmoduleList>
            <VirtualSubmoduleItem ID="DAP_SM" SubmoduleIdentNumber="0x1"/>
          </VirtualSubmoduleList>
          {dap_extra}
        </DeviceAccessPointItem>
      </DeviceAccessPointList>
      <ModuleList>
        <ModuleItem ID="M" ModuleIdentNumber="0x77">
          <VirtualSubmoduleList>
            <VirtualSubmoduleItem ID="M_SM" SubmoduleIdentNumber="0x7">
{sub_body}
            </VirtualSubmoduleItem>
          </VirtualSubmoduleList>
        </ModuleItem>
      </ModuleList>
    </ApplicationProcess>
  </ProfileBody>
</ISO15745Profile>
"#
    )
}

/// Writes `xml` as `dev.xml` into a fresh directory and returns a configuration using its
/// module `M` in slot 1 (with `extra` keys), the file's path, and the directory's guard.
fn with_file(name: &str, xml: &str, extra: &str) -> (String, PathBuf, TempDir) {
    let dir = scratch(name);
    let path = dir.path().join("dev.xml");
    std::fs::write(&path, xml).unwrap();
    let text = format!(
        "[[device]]\nname = \"x\"\ngsdml = {:?}\n[[device.submodule]]\nslot = 1\n\
         module = \"M\"\n{extra}\n",
        path.display().to_string()
    );
    (text, path, dir)
}

#[test]
fn record_encoding() {
    let xml = small_gsdml(
        "",
        r#"<IOData><Input><DataItem DataType="Unsigned8"/></Input></IOData>
              <RecordDataList>
                <ParameterRecordDataItem Index="0x10" Length="12">
                  <Const Data="0xAA 0xBB"/>
                  <Const ByteOffset="10" Data="0x01,0x02"/>
                  <Ref DataType="Unsigned16" ByteOffset="2" DefaultValue="0x1234"/>
                  <Ref DataType="Float32" ByteOffset="4" DefaultValue="-2.5"/>
                  <Ref DataType="Bit" ByteOffset="8" BitOffset="7" DefaultValue="1"/>
                  <Ref DataType="VisibleString" ByteOffset="9" Length="1" DefaultValue="Z"/>
                  <Ref DataType="Unsigned8" ByteOffset="11" DefaultValue="9"/>
                </ParameterRecordDataItem>
                <ParameterRecordDataItem Index="0x20" Length="2" Access="read;write">
                  <Ref Data="0x00"/>
                </ParameterRecordDataItem>
                <ParameterRecordDataItem Index="0x30" Length="1" Access="prm;read"/>
              </RecordDataList>"#,
    );
    let (text, path, _dir) = with_file("encoding", &xml, "");
    let c = accepted(&text);
    let m = c.devices[0].submodules.last().unwrap();
    assert_eq!(
        (m.module_ident, m.submodule_ident, m.input_length),
        (0x77, 7, 1)
    );
    // Read/write-only records (Access without prm) are not written at connect.
    assert_eq!(
        m.records,
        [
            ParameterRecord {
                index: 0x10,
                data: vec![
                    0xAA, 0xBB, 0x12, 0x34, 0xC0, 0x20, 0, 0, 0x80, b'Z', 0x01, 9
                ]
            },
            ParameterRecord {
                index: 0x30,
                data: vec![0]
            },
        ]
    );
    std::fs::remove_dir_all(path.parent().unwrap()).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Refusals.

#[test]
fn unknown_modules_are_listed() {
    let text = sample_device(&sub(1, "module = \"in9\""));
    refused_at(
        &text,
        "in9",
        "device[0].submodule[0].module",
        &[
            "has no module \"in9\"",
            "\"in1\" (ID \"M1\") in slot(s) 1",
            "\"out4\" (ID \"M4\") in slot(s) 4",
            "give one of these names or IDs",
        ],
    );
}

#[test]
fn modules_in_the_wrong_slot() {
    let text = sample_device(&sub(2, "module = \"in1\""));
    refused_at(
        &text,
        "slot = 2",
        "device[0].submodule[0].slot",
        &["module \"in1\" (ID \"M1\"", "goes in slot(s) 1", "move it"],
    );
    let text = sample_device(&sub(1, "module = \"DAP1\""));
    refused_at(
        &text,
        "slot = 1",
        "device[0].submodule[0].slot",
        &["sits in slot 0, not 1"],
    );
    let text = sample_device(&sub(1, "module = \"in1\"\nsubslot = 2"));
    refused_at(
        &text,
        "subslot = 2",
        "device[0].submodule[0].subslot",
        &["no submodule for subslot 2", "\"M1_SM\""],
    );
    let text = sample_device(&sub(1, "module = \"in1\"\nsubmodule = \"M2_SM\""));
    refused_at(
        &text,
        "M2_SM",
        "device[0].submodule[0].submodule",
        &[
            "has no submodule \"M2_SM\"",
            "\"in1\" (ID \"M1_SM\") in subslot(s) 1",
        ],
    );
}

#[test]
fn explicit_keys_must_agree() {
    let cases = [
        (
            "module_ident = 0x102",
            "module_ident",
            "0x00000102 differs from 0x00000101, the ModuleIdentNumber of module \"in1\" (ID \"M1\")",
        ),
        (
            "submodule_ident = 2",
            "submodule_ident",
            "0x00000002 differs from 0x00000001, the SubmoduleIdentNumber of submodule \"in1\" (ID \"M1_SM\")",
        ),
        (
            "input_length = 63",
            "input_length",
            "63 differs from 64, the input length of",
        ),
        (
            "output_length = 1",
            "output_length",
            "1 differs from 0, the output length of",
        ),
        ("api = 1", "api", "1 differs from 0, the API of"),
    ];
    for (extra, key, phrase) in cases {
        let text = sample_device(&sub(1, &format!("module = \"in1\"\n{extra}")));
        refused_at(
            &text,
            extra,
            &format!("device[0].submodule[0].{key}"),
            &[phrase, &format!("leave {key} out")],
        );
    }
    let text = sample_device("").replace("gsdml =", "vendor_id = 0x0493\ngsdml =");
    refused_at(
        &text,
        "vendor_id",
        "device[0].vendor_id",
        &["0x0493 differs from the VendorID 0xffff", "(line 16)"],
    );
    let text = sample_device("").replace("gsdml =", "device_id = 2\ngsdml =");
    refused_at(
        &text,
        "device_id",
        "device[0].device_id",
        &["DeviceID 0x0001"],
    );
}

#[test]
fn gsdml_keys_need_their_partners() {
    let text = "[[device]]\nname = \"x\"\nvendor_id = 1\ndevice_id = 1\n\
                [[device.submodule]]\nslot = 1\nmodule = \"in1\"\n";
    refused_at(
        text,
        "module =",
        "device[0].submodule[0].module",
        &["this device has none", "add `gsdml ="],
    );
    let text = "[[device]]\nname = \"x\"\nvendor_id = 1\ndevice_id = 1\ndap = \"DAP1\"\n";
    refused_at(text, "dap =", "device[0].dap", &["add `gsdml ="]);
    let text = "[[device]]\nname = \"x\"\nvendor_id = 1\ndevice_id = 1\n\
                [[device.submodule]]\nslot = 1\nsubslot = 1\nsubmodule = \"S\"\n\
                module_ident = 1\nsubmodule_ident = 1\n";
    refused_at(
        text,
        "submodule = ",
        "device[0].submodule[0].submodule",
        &["add `module`"],
    );
    let text = "[[device]]\nname = \"x\"\ndevice_id = 1\n";
    refused_at(
        text,
        "[[device]]",
        "device[0]",
        &["missing field `vendor_id`; add it, or give the device's GSDML file with `gsdml`"],
    );
    let text = "[[device]]\nname = \"x\"\nvendor_id = 1\ndevice_id = 1\n\
                [[device.submodule]]\nslot = 1\nmodule_ident = 1\nsubmodule_ident = 1\n";
    refused_at(
        text,
        "[[device.submodule]]",
        "device[0].submodule[0]",
        &["missing field `subslot`"],
    );
    let text = "[[device]]\nname = \"x\"\ngsdml = \" \"\n";
    refused_at(text, "gsdml", "device[0].gsdml", &["the path is empty"]);
}

#[test]
fn unreadable_and_broken_files_name_both_lines() {
    let text = "[[device]]\nname = \"x\"\ngsdml = \"no/such/GSDML.xml\"\n";
    let e = refused_at(
        text,
        "gsdml",
        "device[0].gsdml",
        &[
            "no/such/GSDML.xml: cannot read the GSDML file",
            "check the path",
        ],
    );
    let ConfigError::Gsdml { error, .. } = &e else {
        panic!("{e:?}")
    };
    assert!(matches!(**error, GsdmlError::Read { .. }), "{error:?}");
    let chain = error_chain(&e);
    assert_eq!(chain.matches("os error").count(), 1, "{chain}");

    // Not XML: the GSDML line of the damage.
    let broken = sample_text().replacen("</ModuleItem>", "</ModuleItm>", 2);
    let (text, path, _dir) = with_file("broken", &broken, "");
    let e = refused_at(&text, "gsdml", "device[0].gsdml", &["not well-formed XML"]);
    let ConfigError::Gsdml { error, .. } = &e else {
        panic!("{e:?}")
    };
    assert_eq!(error.line(), Some(101), "{error}");
    assert!(
        e.to_string().contains(&format!("{}:101: ", path.display())),
        "{e}"
    );

    // An IO data type the import does not know: the DataItem's line, reported at `module`.
    let xml = small_gsdml(
        "",
        "<IOData>\n<Input>\n<DataItem DataType=\"Real\"/>\n</Input>\n</IOData>",
    );
    let data_line = line_of(&xml, "\"Real\"");
    let (text, path, _dir) = with_file("datatype", &xml, "");
    let e = refused_at(
        &text,
        "module =",
        "device[0].submodule[0].module",
        &[
            &format!(
                "{}:{data_line}: <DataItem> DataType: \"Real\" is not an IO data type",
                path.display()
            ),
            "give input_length and output_length",
        ],
    );
    let ConfigError::Gsdml { error, .. } = &e else {
        panic!("{e:?}")
    };
    // The GSDML file's message is in the configuration's, once: no `source` repeats it when
    // procimgd prints the whole chain.
    let message = error.to_string();
    let chain = error_chain(&e);
    assert_eq!(chain.matches(message.as_str()).count(), 1, "{chain}");
    // ... unless the configuration gives both lengths itself.
    let (text, _, _dir) = with_file("datatype-own", &xml, "input_length = 4\noutput_length = 0");
    let m = accepted(&text).devices[0].submodules[1].clone();
    assert_eq!((m.input_length, m.output_length), (4, 0));

    // A record that does not fit its Length: the Ref's line.
    let xml = small_gsdml(
        "",
        "<RecordDataList>\n<ParameterRecordDataItem Index=\"1\" Length=\"1\">\n\
         <Ref DataType=\"Unsigned16\" ByteOffset=\"0\" DefaultValue=\"1\"/>\n\
         </ParameterRecordDataItem>\n</RecordDataList>",
    );
    let ref_line = line_of(&xml, "<Ref ");
    let (text, path, _dir) = with_file("record", &xml, "");
    refused_at(
        &text,
        "module =",
        "device[0].submodule[0].module",
        &[
            &format!(
                "{}:{ref_line}: <Ref> ByteOffset: 2 byte(s) at offset 0 do not fit",
                path.display()
            ),
            "give the submodule's records in the configuration instead",
        ],
    );
    let (text, _, _dir) = with_file("record-own", &xml, "records = []");
    assert!(accepted(&text).devices[0].submodules[1].records.is_empty());

    // PROFIsafe records are not built.
    let xml = small_gsdml(
        "",
        "<RecordDataList><F_ParameterRecordDataItem F_ParamDescCRC=\"1\"/></RecordDataList>",
    );
    let (text, _, _dir) = with_file("safety", &xml, "");
    refused_at(
        &text,
        "module =",
        "device[0].submodule[0].module",
        &["PROFIsafe"],
    );

    // A document that is not a GSDML file.
    let (text, _, _dir) = with_file("other", "<?xml version=\"1.0\"?>\n<html/>", "");
    refused_at(
        &text,
        "gsdml",
        "device[0].gsdml",
        &[":2: <html>: the document is a <html>"],
    );
}

#[test]
fn pluggable_submodules_go_where_their_module_allows() {
    // Module M has a built-in submodule in subslot 1 and takes the pluggable P in 2..4.
    let xml = small_gsdml("", "").replace(
        "</VirtualSubmoduleList>\n        </ModuleItem>",
        "</VirtualSubmoduleList>\n          <UseableSubmodules>\
         <SubmoduleItemRef SubmoduleItemTarget=\"P\" AllowedInSubslots=\"2..4\"/>\
         </UseableSubmodules>\n        </ModuleItem>",
    );
    let xml = xml.replace(
        "</ModuleList>",
        "</ModuleList>\n      <SubmoduleList>\n        <SubmoduleItem ID=\"P\" \
         SubmoduleIdentNumber=\"0x55\" API=\"0x3A00\"><IOData><Output>\
         <DataItem DataType=\"Unsigned16\"/></Output></IOData></SubmoduleItem>\n\
         </SubmoduleList>",
    );
    let (text, _, _dir) = with_file("pluggable", &xml, "");
    let plugged = format!("{text}[[device.submodule]]\nslot = 1\nmodule = \"M\"\nsubslot = 3\n");
    let c = accepted(&plugged);
    let subs = &c.devices[0].submodules;
    let last: Vec<(u32, u16, u32, u32, u16)> = subs[1..]
        .iter()
        .map(|s| {
            (
                s.api,
                s.subslot,
                s.module_ident,
                s.submodule_ident,
                s.output_length,
            )
        })
        .collect();
    assert_eq!(last, [(0, 1, 0x77, 0x7, 0), (0x3A00, 3, 0x77, 0x55, 2)]);
    // By ID alone it takes the lowest subslot its module allows; only 2..4 will do.
    let by_id =
        format!("{text}[[device.submodule]]\nslot = 1\nmodule = \"M\"\nsubmodule = \"P\"\n");
    assert_eq!(accepted(&by_id).devices[0].submodules[2].subslot, 2);
    let wrong = format!(
        "{text}[[device.submodule]]\nslot = 1\nmodule = \"M\"\nsubmodule = \"P\"\nsubslot = 5\n"
    );
    refused_at(
        &wrong,
        "subslot = 5",
        "device[0].submodule[1].subslot",
        &["cannot go in subslot 5", "in subslot(s) 2..4"],
    );
}

#[test]
fn dap_submodules_sharing_a_subslot_are_refused() {
    let xml = small_gsdml(
        "<SystemDefinedSubmoduleList>\n<InterfaceSubmoduleItem ID=\"IF\" SubslotNumber=\"1\" \
         SubmoduleIdentNumber=\"0x8000\"/>\n</SystemDefinedSubmoduleList>",
        "",
    );
    let (text, _, _dir) = with_file("shared-subslot", &xml, "");
    refused_at(
        &text,
        "gsdml",
        "device[0].gsdml",
        &[
            "two submodules in subslot 1, ID \"DAP_SM\"",
            "and ID \"IF\"",
            "list slot 0 in the configuration yourself",
        ],
    );
    // Listing slot 0 is the way out.
    let own = text.replace(
        "[[device.submodule]]",
        "[[device.submodule]]\nslot = 0\nmodule = \"DAP\"\nsubmodule = \"DAP_SM\"\n\
         [[device.submodule]]",
    );
    assert_eq!(accepted(&own).devices[0].submodules.len(), 2);
}

#[test]
fn records_are_bounded() {
    let one = "<ParameterRecordDataItem Index=\"1\" Length=\"65535\"/>\n";
    let xml = small_gsdml(
        "",
        &format!("<RecordDataList>\n{}</RecordDataList>", one.repeat(17)),
    );
    let (text, _, _dir) = with_file("many-records", &xml, "");
    refused_at(
        &text,
        "module =",
        "device[0].submodule[0].module",
        &["records add up to more than 1048576 bytes"],
    );
    let xml = small_gsdml(
        "",
        "<RecordDataList><ParameterRecordDataItem Index=\"1\" Length=\"65536\"/></RecordDataList>",
    );
    let (text, _, _dir) = with_file("long-record", &xml, "");
    refused_at(
        &text,
        "module =",
        "device[0].submodule[0].module",
        &["<ParameterRecordDataItem> Length: \"65536\" is not a number from 0 to 65535"],
    );
}

#[test]
fn several_daps_need_a_choice() {
    let second = r#"</DeviceAccessPointItem>
        <DeviceAccessPointItem ID="DAP_B" ModuleIdentNumber="0x2" PhysicalSlots="0..1">
          <ModuleInfo><Name TextId="T_B"/></ModuleInfo>
          <UseableModules><ModuleItemRef ModuleItemTarget="M" FixedInSlots="1"/></UseableModules>
          <VirtualSubmoduleList>
            <VirtualSubmoduleItem ID="DAP_B_SM" SubmoduleIdentNumber="0x2"/>
          </VirtualSubmoduleList>
          <SystemDefinedSubmoduleList>
            <InterfaceSubmoduleItem ID="DAP_B_IF" SubmoduleIdentNumber="0x8000"/>
            <PortSubmoduleItem ID="DAP_B_P1" SubslotNumber="0x8001" SubmoduleIdentNumber="0x8001"/>
            <PortSubmoduleItem ID="DAP_B_P2" SubslotNumber="32770" SubmoduleIdentNumber="0x8001"/>
          </SystemDefinedSubmoduleList>"#;
    let xml = small_gsdml(second, "").replace(
        "</ApplicationProcess>",
        "<ExternalTextList><PrimaryLanguage><Text TextId=\"T_B\" Value=\"Second DAP\"/>\
         </PrimaryLanguage></ExternalTextList></ApplicationProcess>",
    );
    let (text, _, _dir) = with_file("daps", &xml, "");
    refused_at(
        &text,
        "gsdml",
        "device[0].gsdml",
        &[
            "describes 2 device access points",
            "ID \"DAP\"; \"Second DAP\" (ID \"DAP_B\")",
            "`dap = \"<ID>\"`",
        ],
    );
    let chosen = text.replace(
        "\n[[device.submodule]]",
        "\ndap = \"Second DAP\"\n[[device.submodule]]",
    );
    let c = accepted(&chosen);
    let d = &c.devices[0];
    assert_eq!(d.gsdml.as_ref().unwrap().dap, "DAP_B");
    assert_eq!(
        idents(d),
        [
            (0, 1, 0x2, 0x2, 0, 0),
            (0, 0x8000, 0x2, 0x8000, 0, 0),
            (0, 0x8001, 0x2, 0x8001, 0, 0),
            (0, 0x8002, 0x2, 0x8001, 0, 0),
            (1, 1, 0x77, 0x7, 0, 0),
        ]
    );
    // The second DAP has slots 0..1 only.
    let far = chosen.replace("slot = 1", "slot = 2");
    refused_at(
        &far,
        "slot = 2",
        "device[0].submodule[0].slot",
        &["goes in slot(s) 1"],
    );
    let wrong = text.replace(
        "\n[[device.submodule]]",
        "\ndap = \"C\"\n[[device.submodule]]",
    );
    refused_at(
        &wrong,
        "dap =",
        "device[0].dap",
        &["no device access point \"C\"", "DAP_B"],
    );
}

// ---------------------------------------------------------------------------------------------
// The demo's GSDML files.

/// A demo device as it would be written with its GSDML file.
struct DemoDevice {
    name: &'static str,
    file: &'static str,
    /// The name of its DAP.
    dap: &'static str,
    /// (slot, module name, RT class) of its IO modules.
    modules: &'static [(u16, &'static str, u8)],
}

const DEMO_DEVICES: [DemoDevice; 3] = [
    DemoDevice {
        name: "echo",
        file: DEMO_ECHO,
        dap: "Sim echo",
        // Marked IRT in demo.toml (rt_class is the configuration's, not the GSDML's).
        modules: &[(1, "Echo 16 bytes", 3)],
    },
    DemoDevice {
        name: "counter",
        file: DEMO_COUNTER,
        dap: "Sim counter",
        modules: &[(1, "Counter 32 bit", 1)],
    },
    DemoDevice {
        name: "dio",
        file: DEMO_DIO,
        dap: "Sim DIO",
        modules: &[(1, "DI 16", 1), (2, "DO 16", 1)],
    },
];

/// The demo's devices written with their GSDML files (the rest of each device as in
/// demo.toml); with `list_slot_zero`, slot 0 is the DAP's subslot 1 as in demo.toml.
fn demo_from_gsdml(list_slot_zero: bool) -> Config {
    let demo = Config::demo();
    let mut text = String::new();
    for (dev, device) in DEMO_DEVICES.iter().zip(&demo.devices) {
        assert_eq!(dev.name, device.name);
        text.push_str(&format!(
            "[[device]]\nname = {:?}\nip = \"{}\"\ngsdml = {:?}\nsim = {:?}\n\
             instance = {}\nreduction_ratio = {}\nwatchdog_factor = {}\n",
            dev.name,
            device.ip.unwrap(),
            dev.file,
            device.sim.as_str(),
            device.instance,
            device.reduction_ratio,
            device.watchdog_factor,
        ));
        if list_slot_zero {
            text.push_str(&format!(
                "[[device.submodule]]\nslot = 0\nmodule = {:?}\n",
                dev.dap
            ));
        }
        for (slot, module, rt_class) in dev.modules {
            text.push_str(&format!(
                "[[device.submodule]]\nslot = {slot}\nmodule = {module:?}\nrt_class = {rt_class}\n"
            ));
        }
    }
    accepted(&text)
}

/// The demo's devices without the GSDML origin, for comparing with an import.
fn without_source(devices: &[DeviceConfig]) -> Vec<DeviceConfig> {
    devices
        .iter()
        .map(|d| DeviceConfig {
            gsdml: None,
            ..d.clone()
        })
        .collect()
}

#[test]
fn demo_toml_spells_out_what_its_gsdml_files_say() {
    let demo = Config::demo();
    // With slot 0 listed (subslot 1 only, as demo.toml has it), the import is demo.toml.
    let imported = demo_from_gsdml(true);
    assert_eq!(without_source(&imported.devices), demo.devices);
    for (d, dev) in imported.devices.iter().zip(&DEMO_DEVICES) {
        assert_eq!(d.gsdml.as_ref().unwrap().path, package_file(dev.file));
    }

    // Left to the GSDML files, slot 0 also gets the interface and the port.
    let full = demo_from_gsdml(false);
    for (d, demo_d) in full.devices.iter().zip(&demo.devices) {
        let dap: Vec<(u16, u32, u32)> = d.submodules[..3]
            .iter()
            .map(|s| (s.subslot, s.module_ident, s.submodule_ident))
            .collect();
        assert_eq!(dap, [(1, 1, 1), (0x8000, 1, 0x8000), (0x8001, 1, 0x8001)]);
        // Diagnostic addresses differ: the interfaces and ports take some too.
        let io_only = |s: &SubmoduleConfig| SubmoduleConfig {
            input_address: if s.has_no_data() {
                NO_ADDRESS
            } else {
                s.input_address
            },
            ..s.clone()
        };
        let rest: Vec<SubmoduleConfig> = d
            .submodules
            .iter()
            .filter(|s| s.subslot < 0x8000)
            .map(io_only)
            .collect();
        let want: Vec<SubmoduleConfig> = demo_d.submodules.iter().map(io_only).collect();
        assert_eq!(rest, want);
    }
}

#[test]
fn demo_gsdml_files_describe_their_devices() {
    for (i, dev) in DEMO_DEVICES.iter().enumerate() {
        let name = Path::new(dev.file).file_name().unwrap().to_str().unwrap();
        // GSDML-<version>-<vendor>-<family>-<yyyymmdd>.xml
        let parts: Vec<&str> = name.trim_end_matches(".xml").split('-').collect();
        assert_eq!(parts.len(), 5, "{name}");
        assert_eq!((parts[0], parts[1], parts[2]), ("GSDML", "V2.4", "procimg"));
        assert!(parts[4].len() == 8 && parts[4].bytes().all(|b| b.is_ascii_digit()));

        let g = Gsdml::load(&package_file(dev.file)).unwrap();
        assert_eq!((g.vendor_id, g.device_id), (0x0493, i as u16 + 1));
        assert_eq!(g.daps.len(), 1);
        let kinds: Vec<SubmoduleKind> = g.daps[0].submodules.iter().map(|s| s.kind).collect();
        assert_eq!(
            kinds,
            [
                SubmoduleKind::Virtual,
                SubmoduleKind::Interface,
                SubmoduleKind::Port
            ]
        );
        // Every module the DAP takes exists and sizes its data; every record builds.
        for r in &g.daps[0].useable_modules {
            let m = g.module(&r.target).unwrap();
            assert!(m.name.is_some());
            for s in &m.submodules {
                g.io_lengths(s).unwrap();
                g.records(s).unwrap();
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// No panics.

/// Runs everything the import does on `text`.
fn exercise(text: &str) {
    if let Ok(g) = Gsdml::parse(text, "fuzz.xml") {
        let subs = g
            .daps
            .iter()
            .flat_map(|d| &d.submodules)
            .chain(g.modules.iter().flat_map(|m| &m.submodules))
            .chain(&g.submodules);
        for s in subs {
            let _ = g.io_lengths(s);
            let _ = g.records(s);
            if let Some(list) = &s.subslots {
                let _ = list.values(256);
            }
        }
        for r in g.daps.iter().flat_map(|d| &d.useable_modules) {
            let _ = (r.allows(1), r.positions());
        }
    }
}

/// GSDML-like XML from a small grammar: the elements and attributes the import reads, with
/// values from plausible to absurd.
fn element() -> impl Strategy<Value = String> {
    let value = prop_oneof![
        "[0-9]{1,3}",
        "0x[0-9A-Fa-f]{1,9}",
        "-?[0-9]{1,20}",
        "[0-9]{1,5}\\.\\.[0-9]{1,10}( [0-9]{1,3})?",
        "(Unsigned8|Unsigned16|Integer32|Float32|Float64|OctetString|VisibleString|Bit|BitArea|Real|Boolean)",
        "(0x01,0x02|0x1FF|x|1\\.5|true|)",
        "[ -~]{0,8}",
    ];
    let attr = (
        prop_oneof![
            Just("ID"),
            Just("ModuleIdentNumber"),
            Just("SubmoduleIdentNumber"),
            Just("FixedInSlots"),
            Just("FixedInSubslots"),
            Just("AllowedInSlots"),
            Just("PhysicalSlots"),
            Just("SubslotNumber"),
            Just("DataType"),
            Just("Length"),
            Just("Index"),
            Just("ByteOffset"),
            Just("BitOffset"),
            Just("BitLength"),
            Just("DefaultValue"),
            Just("Data"),
            Just("TransferSequence"),
            Just("Access"),
            Just("API"),
            Just("ModuleItemTarget"),
            Just("TextId"),
            Just("Value"),
        ],
        value,
    )
        .prop_map(|(name, value)| format!(" {name}=\"{}\"", value.replace(['"', '<', '&'], "")));
    let name = prop_oneof![
        Just("DeviceAccessPointItem"),
        Just("ModuleItem"),
        Just("VirtualSubmoduleList"),
        Just("VirtualSubmoduleItem"),
        Just("SystemDefinedSubmoduleList"),
        Just("InterfaceSubmoduleItem"),
        Just("PortSubmoduleItem"),
        Just("UseableModules"),
        Just("ModuleItemRef"),
        Just("IOData"),
        Just("Input"),
        Just("Output"),
        Just("DataItem"),
        Just("RecordDataList"),
        Just("ParameterRecordDataItem"),
        Just("F_ParameterRecordDataItem"),
        Just("Const"),
        Just("Ref"),
        Just("ModuleInfo"),
        Just("Name"),
    ];
    let leaf = (name.clone(), prop::collection::vec(attr.clone(), 0..5))
        .prop_map(|(n, a)| format!("<{n}{}/>", a.concat()));
    leaf.prop_recursive(5, 64, 6, move |inner| {
        (
            name.clone(),
            prop::collection::vec(attr.clone(), 0..5),
            prop::collection::vec(inner, 0..6),
        )
            .prop_map(|(n, a, kids)| format!("<{n}{}>{}</{n}>", a.concat(), kids.concat()))
    })
}

proptest! {
    #[test]
    fn parse_never_panics(text in any::<String>()) {
        exercise(&text);
    }

    #[test]
    fn garbled_sample_never_panics(
        edits in prop::collection::vec((any::<prop::sample::Index>(), 0usize..4, "[<>/=\"a-z0-9 ]{0,3}"), 1..8),
        cut in any::<prop::sample::Index>(),
        truncate in any::<bool>(),
    ) {
        let mut text = sample_text().into_bytes();
        for (at, remove, insert) in edits {
            let i = at.index(text.len());
            let end = (i + remove).min(text.len());
            text.splice(i..end, insert.bytes());
        }
        if truncate {
            let n = cut.index(text.len());
            text.truncate(n);
        }
        exercise(&String::from_utf8_lossy(&text));
    }

    #[test]
    fn gsdml_shaped_xml_never_panics(
        daps in prop::collection::vec(element(), 0..3),
        modules in prop::collection::vec(element(), 0..4),
    ) {
        let text = format!(
            "<ISO15745Profile><ProfileBody><DeviceIdentity VendorID=\"1\" DeviceID=\"2\"/>\
             <ApplicationProcess><DeviceAccessPointList>{}</DeviceAccessPointList>\
             <ModuleList>{}</ModuleList></ApplicationProcess></ProfileBody></ISO15745Profile>",
            daps.concat(),
            modules.concat()
        );
        exercise(&text);
    }
}
