// SPDX-License-Identifier: MIT OR Apache-2.0

use super::blocks::{ExpectedSubmodules, IocrData, IocrType};
use super::{ADAPTER_PLACEHOLDER, import, is_xml};
use crate::{ConfigError, Network, parse};
use proptest::prelude::*;

/// The station of the veth tests (pc-device) behind a PN Driver, in the manual's format.
const PC_DEVICE: &str = include_str!("../../tests/data/pn-driver/pc-device.xml");

fn imported(text: &str) -> crate::Config {
    let toml = import(text, "pc-device.xml", Some("veth0")).unwrap();
    parse(&toml, "imported").unwrap_or_else(|e| panic!("{e}\n{toml}"))
}

fn refusal(text: &str) -> (usize, String, String) {
    match import(text, "plant.xml", None) {
        Err(ConfigError::PnDriver {
            line,
            element,
            message,
            ..
        }) => (line, element, message),
        other => panic!("expected a refusal, got {other:?}"),
    }
}

#[test]
fn the_project_becomes_procimgs_configuration() {
    let c = imported(PC_DEVICE);
    assert_eq!(c.network, Network::Interface("veth0".into()));
    assert_eq!(c.start_mode, procimg_shm_layout::Mode::Offline);
    assert_eq!(c.cycle_ns, 1_000_000, "send clock factor 32");
    assert_eq!(c.interface.station_name.as_deref(), Some("plc-pn-driver"));
    assert!(c.interface.name_by_program, "0x3009 says 0xFFFF");
    assert!(!c.interface.address_by_program);
    assert_eq!(c.interface.diagnostic_address, 64);
    assert_eq!(c.interface.port_diagnostic_address, 65);
    let [d] = c.devices.as_slice() else {
        panic!("one device: {:?}", c.devices)
    };
    assert_eq!(d.name, "pc-device");
    assert_eq!(d.ip, Some("10.47.0.50".parse().unwrap()));
    assert_eq!((d.vendor_id, d.device_id, d.instance), (0x0493, 0x0100, 1));
    assert_eq!((d.reduction_ratio, d.watchdog_factor), (1, 100));
    assert!(!d.optional);
    let subs: Vec<_> = d
        .submodules
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
        .collect();
    assert_eq!(
        subs,
        [
            (0, 1, 1, 1, 0, 0),
            (0, 0x8000, 1, 0x8000, 0, 0),
            (0, 0x8001, 1, 0x8001, 0, 0),
            (1, 1, 0x10, 1, 8, 8),
            (2, 1, 0x20, 1, 4, 0),
        ]
    );
    let io = &d.submodules[3];
    assert_eq!((io.input_address, io.output_address), (0, 0));
    assert_eq!(io.records.len(), 1);
    assert_eq!(
        (io.records[0].index, io.records[0].data.as_slice()),
        (1, &[0u8, 0, 0, 7][..])
    );
    assert_eq!(d.submodules[4].input_address, 8);
    // The hardware identifiers of the submodules without IO data name them.
    let diagnostic: Vec<_> = d.submodules[..3]
        .iter()
        .map(|s| s.diagnostic_address())
        .collect();
    assert_eq!(diagnostic, [Some(258), Some(259), Some(260)]);
}

#[test]
fn parse_takes_the_xml_itself_and_an_adapter_is_asked_for() {
    let c = parse(PC_DEVICE, "pc-device.xml").unwrap();
    assert_eq!(c.network, Network::Interface(ADAPTER_PLACEHOLDER.into()));
    assert_eq!(c.devices[0].name, "pc-device");
    // On a machine, the placeholder is refused with what to do; with an adapter chosen
    // (procimgd --adapter: any interface passes), it is replaced.
    let dir = std::path::Path::new("");
    assert!(crate::parse_for_machine(PC_DEVICE, "pc-device.xml", dir, &|_| Ok(())).is_ok());
    let absent = |n: &str| Err(format!("there is no interface {n:?}"));
    let e = crate::parse_for_machine(PC_DEVICE, "pc-device.xml", dir, &absent).unwrap_err();
    assert!(e.to_string().contains("--adapter"), "{e}");
    assert!(e.to_string().starts_with("pc-device.xml (imported)"), "{e}");
}

#[test]
fn xml_is_told_from_toml() {
    assert!(is_xml("\u{feff}  <?xml version=\"1.0\"?>"));
    assert!(is_xml("\n<Object>"));
    assert!(!is_xml("# <comment>\ncycle_time = \"1ms\""));
}

#[test]
fn a_deactivated_device_is_optional_and_a_lost_ip_is_none() {
    let text = PC_DEVICE
        .replace(
            "<Value Datatype=\"Scalar\" Valuetype=\"BOOL\">false</Value>",
            "<Value Datatype=\"Scalar\" Valuetype=\"BOOL\">true</Value>",
        )
        .replace("0A2F0032FFFFFF000A2F0032", "00000000FFFFFF0000000000");
    let c = imported(&text);
    assert!(c.devices[0].optional);
    assert_eq!(c.devices[0].ip, None);
}

#[test]
fn an_address_set_at_the_device_is_the_devices() {
    let text = PC_DEVICE.replace("301100080101000000000000", "3011000801010000FFFF0000");
    let toml = import(&text, "pc-device.xml", Some("veth0")).unwrap();
    assert!(toml.contains("set directly at the device"), "{toml}");
    assert_eq!(parse(&toml, "imported").unwrap().devices[0].ip, None);
}

#[test]
fn an_irt_device_is_refused_at_its_line() {
    // IOCRProperties 2 (RT) → 3 (IRT), in the input IOCR.
    let text = PC_DEVICE.replace("88920000000000020012", "88920000000000030012");
    let (line, element, message) = refusal(&text);
    assert!(message.contains("IRT"), "{message}");
    assert!(element.contains("pc-device"), "{element}");
    let want = PC_DEVICE
        .lines()
        .position(|l| l.contains("<Object Name=\"pc-device\">"))
        .unwrap()
        + 1;
    assert_eq!(line, want);
}

#[test]
fn a_cut_block_and_bad_hex_are_refused_with_their_field() {
    let cut = PC_DEVICE.replace(
        "<Field Key=\"12384\" Length=\"32\">3060001C01000000049301000001300000000001000010000000000000000000",
        "<Field Key=\"12384\" Length=\"10\">3060001C010000000493",
    );
    let (_, element, message) = refusal(&cut);
    assert!(element.contains("Field 12384"), "{element}");
    assert!(message.contains("cut short"), "{message}");
    let bad = PC_DEVICE.replace("Length=\"4\">00000007", "Length=\"4\">0000000G");
    let (_, _, message) = refusal(&bad);
    assert!(message.contains("not hex"), "{message}");
    let short = PC_DEVICE.replace("Length=\"4\">00000007", "Length=\"5\">00000007");
    let (_, _, message) = refusal(&short);
    assert!(message.contains("Length says 5"), "{message}");
}

#[test]
fn other_xml_is_not_a_pn_driver_configuration() {
    let (_, _, message) = refusal("<?xml version=\"1.0\"?><HWConfiguration/>");
    assert!(
        message.contains("not a PN Driver configuration"),
        "{message}"
    );
    let (line, _, message) =
        refusal("<Object>\n<ClassRID>1</ClassRID>\n<Object>\n</Object>\n</Object>");
    assert_eq!(line, 3);
    assert!(message.contains("ClassRID"), "{message}");
    let (_, _, message) = refusal("<Object><ClassRID>1");
    assert!(message.contains("not well-formed"), "{message}");
}

#[test]
fn the_blocks_read_as_the_manual_lays_them_out() {
    let iocrs = IocrData::parse(&hex(
        "3102010C01000000000200800100000100018892000000000002000F80000080000800010000FFFFFFFF00030003",
    ));
    // Cut after the first entry's header: the count says two.
    assert!(iocrs.is_err());
    let expected = ExpectedSubmodules::parse(&hex(concat!(
        "3101002C01000000000100000000000000010020010000020000000000200000000100000001000100000000",
        "000100010000000100040001000100000000"
    )))
    .unwrap();
    assert_eq!(expected.len(), 1);
    assert_eq!(
        (
            expected[0].slot,
            expected[0].module_ident,
            expected[0].submodule_ident,
            expected[0].input_length
        ),
        (2, 0x20, 1, 4)
    );
    let _ = IocrType::Input;
}

fn hex(s: &str) -> Vec<u8> {
    (0..s.len() / 2)
        .map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).unwrap())
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    /// No block content panics the import: every field of the device's blocks replaced by
    /// arbitrary bytes gives a configuration or a refusal.
    #[test]
    fn no_block_content_panics_the_import(
        key in prop::sample::select(vec![12384u32, 12545, 12546, 4096, 4099]),
        bytes in prop::collection::vec(any::<u8>(), 0..300),
    ) {
        let start = PC_DEVICE.find(&format!("<Field Key=\"{key}\"")).unwrap();
        let end = start + PC_DEVICE[start..].find("</Field>").unwrap();
        let hex: String = bytes.iter().map(|b| format!("{b:02X}")).collect();
        let text = format!(
            "{}<Field Key=\"{key}\" Length=\"{}\">{hex}{}",
            &PC_DEVICE[..start],
            bytes.len(),
            &PC_DEVICE[end..]
        );
        let _ = import(&text, "fuzz.xml", None).map(|toml| parse(&toml, "fuzz"));
    }

    /// Nor does any text.
    #[test]
    fn no_text_panics_the_import(text in "<Object>[<>/a-zA-Z0-9=\" ]{0,200}") {
        let _ = import(&text, "fuzz.xml", None);
    }
}
