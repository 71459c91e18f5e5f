// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device that `pnio-interop-device` runs: an IO device of the independent `pnio` stack
//! (crates.io, 0.1.0), declared once here so the running device, its GSDML and the procimgd
//! configuration a controller needs to reach it all come from the same object.
//!
//! # The device
//!
//! | slot | subslot | module ident | submodule ident | in | out | what |
//! |------|---------|--------------|-----------------|----|-----|------|
//! | 0 | 1 | 0x00000001 | 0x00000001 | 0 | 0 | DAP |
//! | 0 | 0x8000 | 0x00000001 | 0x00008000 | 0 | 0 | interface |
//! | 0 | 0x8001 | 0x00000001 | 0x00008001 | 0 | 0 | port 1 |
//! | 1 | 1 | 0x00000101 | 0x00000001 | 8 | 0 | inputs (device → controller) |
//! | 2 | 1 | 0x00000102 | 0x00000001 | 0 | 8 | outputs (controller → device) |
//!
//! The idents are pnio's own: its DAP is fixed (module 1 with submodules 1, 0x8000 and 0x8001)
//! and every declared slot `n` gets module ident `0x100 + n` with one submodule of ident 1 in
//! subslot 1 (`pnio::config::DeviceConfig::model`). Identity: vendor 0xFFFF, device 0x0001
//! (pnio's development identity, not a PI-assigned one), instance 1. I&M0 answers order id
//! [`ORDER_ID`] and the serial number given at start ([`DEFAULT_SERIAL`] by default).
//!
//! [`procimgd_device_toml`] walks the model pnio validates a Connect against, so the block it
//! prints is exactly what the device accepts in the ExpectedSubmoduleBlockReq.

use pnio::cm::DeviceModel;
use pnio::config::{ConfigError, DeviceConfig, Slot};
use pnio::data::FieldType;
use pnio::eth::MacAddr;
use pnio::gsdml::GsdmlMeta;
use pnio::im::{Im0, SwRevision};
use std::fmt::Write as _;
use std::net::Ipv4Addr;

/// The slot of the input submodule (device → controller).
pub const INPUT_SLOT: Slot = Slot(1);
/// The slot of the output submodule (controller → device).
pub const OUTPUT_SLOT: Slot = Slot(2);
/// Subslot of both IO submodules.
pub const IO_SUBSLOT: u16 = 1;
/// Bytes of input data and of output data.
pub const IO_LEN: usize = 8;
/// Fields of each IO submodule: four 16-bit words, 8 bytes.
const IO_FIELDS: [FieldType; IO_LEN / 2] = [FieldType::Word; IO_LEN / 2];

/// PROFINET vendor ID (pnio's development value).
pub const VENDOR_ID: u16 = 0xFFFF;
/// PROFINET device ID (pnio's development value).
pub const DEVICE_ID: u16 = 0x0001;
/// DCP TypeOfStation, also the product name in the GSDML.
pub const STATION_TYPE: &str = "procimg interop pnio device";
/// I&M0 order ID (also the GSDML's OrderNumber).
pub const ORDER_ID: &str = "PROCIMG-IOP-PNIO-1";
/// I&M0 serial number unless one is given.
pub const DEFAULT_SERIAL: &str = "IOP-000000000001";
/// I&M0 hardware revision.
pub const HARDWARE_REVISION: u16 = 1;

/// The device declaration for NameOfStation `station` with I&M0 serial number `serial`.
///
/// Fails for a name pnio does not accept as a NameOfStation, or a serial number that is not
/// ASCII or longer than 16 bytes.
pub fn declaration(station: &str, serial: &str) -> Result<DeviceConfig, ConfigError> {
    DeviceConfig::builder(station)
        .station_type(STATION_TYPE)
        .identity(VENDOR_ID, DEVICE_ID)
        .im0(Im0 {
            order_id: ORDER_ID.to_string(),
            serial_number: serial.to_string(),
            hardware_revision: HARDWARE_REVISION,
            software_revision: SwRevision {
                prefix: 'V',
                functional: 0,
                bug_fix: 1,
                internal: 0,
            },
            revision_counter: 0,
            profile_id: 0,
            profile_specific_type: 0,
        })
        .input(INPUT_SLOT, &IO_FIELDS)
        .output(OUTPUT_SLOT, &IO_FIELDS)
        .build()
}

/// The slot/submodule model the device checks a Connect request against. The MAC does not
/// enter the slot structure, so any MAC gives the same model apart from that field.
pub fn model(cfg: &DeviceConfig) -> DeviceModel {
    cfg.model(MacAddr([0; 6]))
}

/// Vendor texts and date of the rendered GSDML file.
pub fn gsdml_meta() -> GsdmlMeta {
    GsdmlMeta {
        vendor_name: "procimg".to_string(),
        product_family: "interop".to_string(),
        info_text: "An IO device of the pnio crate, used to test procimgd as IO controller \
                    against an independent PROFINET stack."
            .to_string(),
        date: (2025, 11, 21),
    }
}

/// The GSDML file of the declaration (pnio's renderer).
pub fn gsdml(cfg: &DeviceConfig) -> String {
    pnio::gsdml::render(cfg, &gsdml_meta())
}

/// The procimgd `[[device]]` table (with one `[[device.submodule]]` per submodule of the
/// model, slot 0 first) that a controller needs to connect to this device at `ip`.
pub fn procimgd_device_toml(cfg: &DeviceConfig, ip: Ipv4Addr) -> String {
    let m = model(cfg);
    let mut slots: Vec<_> = m.slots.iter().collect();
    slots.sort_by_key(|s| s.slot);
    let mut t = String::new();
    // Writing to a String cannot fail.
    let _ = writeln!(
        t,
        "# {STATION_TYPE} (pnio {}): the model the device checks the Connect against.",
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(t, "[[device]]");
    let _ = writeln!(t, "name = \"{}\"", m.station_name);
    let _ = writeln!(t, "ip = \"{ip}\"");
    let _ = writeln!(t, "vendor_id = 0x{:04X}", m.vendor_id);
    let _ = writeln!(t, "device_id = 0x{:04X}", m.device_id);
    let _ = writeln!(t, "instance = {}", m.instance);
    for slot in slots {
        let mut subs: Vec<_> = slot.submodules.iter().collect();
        subs.sort_by_key(|s| s.subslot);
        for sub in subs {
            let _ = writeln!(t);
            let _ = writeln!(t, "[[device.submodule]]");
            let _ = writeln!(t, "slot = {}", slot.slot);
            if sub.subslot >= 0x8000 {
                let _ = writeln!(t, "subslot = 0x{:04X}", sub.subslot);
            } else {
                let _ = writeln!(t, "subslot = {}", sub.subslot);
            }
            let _ = writeln!(t, "module_ident = 0x{:08X}", slot.module_ident);
            let _ = writeln!(t, "submodule_ident = 0x{:08X}", sub.submodule_ident);
            if sub.input_len > 0 {
                let _ = writeln!(t, "input_length = {}", sub.input_len);
            }
            if sub.output_len > 0 {
                let _ = writeln!(t, "output_length = {}", sub.output_len);
            }
        }
    }
    t
}

/// The inputs the device answers outputs `out` with: every byte plus one, wrapping.
pub fn answer(out: &[u8; IO_LEN]) -> [u8; IO_LEN] {
    out.map(|b| b.wrapping_add(1))
}

/// Bytes as lower-case hex without separators, e.g. `00ff10`.
pub fn hex(bytes: &[u8]) -> String {
    let mut s = String::with_capacity(bytes.len() * 2);
    for b in bytes {
        let _ = write!(s, "{b:02x}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_is_the_documented_one() {
        let cfg = declaration("pnio-iop", DEFAULT_SERIAL).unwrap();
        let m = model(&cfg);
        let mut rows = Vec::new();
        for s in &m.slots {
            for sm in &s.submodules {
                rows.push((
                    s.slot,
                    sm.subslot,
                    s.module_ident,
                    sm.submodule_ident,
                    sm.input_len,
                    sm.output_len,
                ));
            }
        }
        rows.sort();
        assert_eq!(
            rows,
            [
                (0, 1, 1, 1, 0, 0),
                (0, 0x8000, 1, 0x8000, 0, 0),
                (0, 0x8001, 1, 0x8001, 0, 0),
                (1, 1, 0x101, 1, 8, 0),
                (2, 1, 0x102, 1, 0, 8),
            ]
        );
        assert_eq!((m.vendor_id, m.device_id, m.instance), (0xFFFF, 1, 1));
        assert_eq!(cfg.im0().order_id, ORDER_ID);
    }

    #[test]
    fn answers_each_byte_plus_one() {
        assert_eq!(
            answer(&[0, 1, 0xfe, 0xff, 7, 8, 9, 10]),
            [1, 2, 0xff, 0, 8, 9, 10, 11]
        );
        assert_eq!(hex(&[0, 0xab, 0x10]), "00ab10");
    }

    #[test]
    fn bad_names_and_serials_are_refused() {
        assert!(declaration("Not_A_Name", DEFAULT_SERIAL).is_err());
        assert!(declaration("ok", "a serial number far too long").is_err());
    }
}
