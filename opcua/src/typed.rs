// SPDX-License-Identifier: MIT OR Apache-2.0
//! Typed variables from the devices' GSDML files: where a submodule's `DataItem`s say what
//! its bytes are (`Unsigned16`, `Float32`, bits with names …), the tree shows them as
//! variables of those types beside the raw bytes. The files are a catalogue (`--gsdml`):
//! a device's is found by its VendorID and DeviceID, a submodule by the ident numbers in
//! procimgd's layout, as an engineering tool finds them.

use crate::items::{Area, Format};
use opcua::types::{ByteString, DataTypeId, Variant};
use procimg_client::Layout;
use procimg_config::gsdml::{DataItem, Gsdml};
use std::path::{Path, PathBuf};

/// Why the GSDML catalogue could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CatalogError {
    /// A folder or file could not be read.
    #[error(
        "cannot read the GSDML files at {path}: {why}; give --gsdml a GSDML file or a folder of them"
    )]
    Read {
        /// The path.
        path: PathBuf,
        /// What the system said.
        why: String,
    },
    /// A file is no GSDML file procimg reads.
    #[error("{0}")]
    Gsdml(String),
}

/// The GSDML files the typed variables come from.
#[derive(Debug, Default)]
pub struct Catalog {
    files: Vec<Gsdml>,
}

impl Catalog {
    /// Reads `paths`: GSDML files, and folders whose `GSDML-*.xml` files are read.
    pub fn load(paths: &[PathBuf]) -> Result<Catalog, CatalogError> {
        let mut files = Vec::new();
        for path in paths {
            let read = |why: std::io::Error| CatalogError::Read {
                path: path.clone(),
                why: why.to_string(),
            };
            if path.is_dir() {
                let mut names: Vec<PathBuf> = std::fs::read_dir(path)
                    .map_err(read)?
                    .filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| is_gsdml(p))
                    .collect();
                names.sort();
                for p in names {
                    files.push(Gsdml::load(&p).map_err(|e| CatalogError::Gsdml(e.to_string()))?);
                }
            } else {
                files.push(Gsdml::load(path).map_err(|e| CatalogError::Gsdml(e.to_string()))?);
            }
        }
        Ok(Catalog { files })
    }

    /// How many files it holds.
    pub fn len(&self) -> usize {
        self.files.len()
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.files.is_empty()
    }

    /// The data items of submodule `s` of `layout`, with the layout's area each lies in;
    /// none where no file describes the submodule.
    pub fn items(&self, layout: &Layout, s: usize) -> Vec<(Area, DataItem)> {
        let Some(e) = layout.submodules.get(s) else {
            return Vec::new();
        };
        let Some(device) = layout.devices.get(usize::from(e.device)) else {
            return Vec::new();
        };
        let items = self.describe(
            (device.vendor_id, device.device_id),
            (e.module_ident, e.submodule_ident, e.api),
        );
        // The file's Input is what the device sends: the controller's inputs, a station's
        // I data (the layout's outputs in the device role).
        let area = |output: bool| match (layout.is_device(), output) {
            (false, false) | (true, true) => Area::Input,
            (false, true) | (true, false) => Area::Output,
        };
        let length = |a: Area| match a {
            Area::Input => e.input_length,
            Area::Output => e.output_length,
        };
        items
            .into_iter()
            .map(|i| (area(i.output), i))
            // Only what lies within the bytes procimgd exchanges.
            .filter(|(a, i)| u32::from(i.offset) + u32::from(i.length) <= u32::from(length(*a)))
            .collect()
    }
}

impl Catalog {
    /// The data items of the submodule with `(module_ident, submodule_ident, api)` of the
    /// device with `(vendor_id, device_id)`, as its file describes them (none without one).
    pub fn describe(
        &self,
        (vendor_id, device_id): (u16, u16),
        (module_ident, submodule_ident, api): (u32, u32, u32),
    ) -> Vec<DataItem> {
        self.files
            .iter()
            .filter(|f| f.vendor_id == vendor_id && f.device_id == device_id)
            .find_map(|f| {
                let sub = f.find_submodule(module_ident, submodule_ident, api)?;
                f.data_items(sub).ok()
            })
            .unwrap_or_default()
    }
}

fn is_gsdml(p: &Path) -> bool {
    let name = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    name.to_ascii_uppercase().starts_with("GSDML-") && name.to_ascii_lowercase().ends_with(".xml")
}

/// How a data item's bytes read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// `Boolean`: a byte, not zero is true.
    Boolean,
    /// `Integer8`.
    SByte,
    /// `Unsigned8`.
    Byte,
    /// `Integer16`.
    Int16,
    /// `Unsigned16`.
    UInt16,
    /// `Integer32`.
    Int32,
    /// `Unsigned32`.
    UInt32,
    /// `Integer64`.
    Int64,
    /// `Unsigned64`.
    UInt64,
    /// `Float32`.
    Float,
    /// `Float64`.
    Double,
    /// `VisibleString`: text up to its first NUL.
    Text,
    /// Anything else (`OctetString`, the PROFIsafe and time types): its bytes.
    Bytes,
}

impl Kind {
    /// The kind of a GSDML data type.
    pub fn of(data_type: &str) -> Kind {
        match data_type {
            "Boolean" => Kind::Boolean,
            "Integer8" => Kind::SByte,
            "Unsigned8" => Kind::Byte,
            "Integer16" => Kind::Int16,
            "Unsigned16" => Kind::UInt16,
            "Integer32" => Kind::Int32,
            "Unsigned32" => Kind::UInt32,
            "Integer64" => Kind::Int64,
            "Unsigned64" => Kind::UInt64,
            "Float32" => Kind::Float,
            "Float64" => Kind::Double,
            "VisibleString" => Kind::Text,
            _ => Kind::Bytes,
        }
    }

    /// Its OPC UA DataType.
    pub fn data_type(self) -> DataTypeId {
        match self {
            Kind::Boolean => DataTypeId::Boolean,
            Kind::SByte => DataTypeId::SByte,
            Kind::Byte => DataTypeId::Byte,
            Kind::Int16 => DataTypeId::Int16,
            Kind::UInt16 => DataTypeId::UInt16,
            Kind::Int32 => DataTypeId::Int32,
            Kind::UInt32 => DataTypeId::UInt32,
            Kind::Int64 => DataTypeId::Int64,
            Kind::UInt64 => DataTypeId::UInt64,
            Kind::Float => DataTypeId::Float,
            Kind::Double => DataTypeId::Double,
            Kind::Text => DataTypeId::String,
            Kind::Bytes => DataTypeId::ByteString,
        }
    }

    /// The PNIO item format that reads the same bytes, where there is one.
    pub fn format(self) -> Option<Format> {
        Some(match self {
            Kind::Byte => Format::Byte,
            Kind::UInt16 => Format::Word,
            Kind::Int16 => Format::Int,
            Kind::UInt32 => Format::DWord,
            Kind::Int32 => Format::DInt,
            Kind::Float => Format::Real,
            _ => return None,
        })
    }

    /// `bytes` (the item's, big-endian) as a value of this kind; `None` when they are too
    /// few.
    pub fn decode(self, bytes: &[u8]) -> Option<Variant> {
        fn be<const N: usize>(b: &[u8]) -> Option<[u8; N]> {
            b.get(..N)?.try_into().ok()
        }
        Some(match self {
            Kind::Boolean => Variant::from(*bytes.first()? != 0),
            Kind::SByte => Variant::from(i8::from_be_bytes(be(bytes)?)),
            Kind::Byte => Variant::from(*bytes.first()?),
            Kind::Int16 => Variant::from(i16::from_be_bytes(be(bytes)?)),
            Kind::UInt16 => Variant::from(u16::from_be_bytes(be(bytes)?)),
            Kind::Int32 => Variant::from(i32::from_be_bytes(be(bytes)?)),
            Kind::UInt32 => Variant::from(u32::from_be_bytes(be(bytes)?)),
            Kind::Int64 => Variant::from(i64::from_be_bytes(be(bytes)?)),
            Kind::UInt64 => Variant::from(u64::from_be_bytes(be(bytes)?)),
            Kind::Float => Variant::from(f32::from_be_bytes(be(bytes)?)),
            Kind::Double => Variant::from(f64::from_be_bytes(be(bytes)?)),
            Kind::Text => {
                let end = bytes.iter().position(|&b| b == 0).unwrap_or(bytes.len());
                Variant::from(String::from_utf8_lossy(&bytes[..end]).into_owned())
            }
            Kind::Bytes => Variant::from(ByteString::from(bytes.to_vec())),
        })
    }
}

/// Bit `bit` of an item's `bytes`, read as a big-endian number (bit 0 the lowest bit of
/// the last byte), as GSDML's `BitDataItem/@BitOffset` counts.
pub fn bit(bytes: &[u8], bit: u16) -> Option<bool> {
    let from_end = usize::from(bit / 8);
    let byte = bytes.len().checked_sub(1 + from_end).map(|i| bytes[i])?;
    Some(byte >> (bit % 8) & 1 == 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_read_big_endian_as_their_gsdml_types() {
        assert_eq!(
            Kind::of("Unsigned16").decode(&[0x12, 0x34]),
            Some(Variant::from(0x1234u16))
        );
        assert_eq!(
            Kind::of("Integer16").decode(&[0xFF, 0xFE]),
            Some(Variant::from(-2i16))
        );
        assert_eq!(
            Kind::of("Float32").decode(&1.5f32.to_be_bytes()),
            Some(Variant::from(1.5f32))
        );
        assert_eq!(
            Kind::of("VisibleString").decode(b"ab\0c"),
            Some(Variant::from("ab"))
        );
        assert_eq!(Kind::of("Unsigned32").decode(&[1, 2]), None);
        assert_eq!(Kind::of("OctetString"), Kind::Bytes);
    }

    #[test]
    fn bits_count_from_the_lowest_bit_of_the_last_byte() {
        let bytes = [0b0000_0001, 0b1000_0000];
        assert_eq!(bit(&bytes, 7), Some(true));
        assert_eq!(bit(&bytes, 8), Some(true));
        assert_eq!(bit(&bytes, 0), Some(false));
        assert_eq!(bit(&bytes, 16), None);
    }

    #[test]
    fn the_demo_devices_files_type_the_counter_and_the_digital_io() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../config/gsdml");
        let catalog = Catalog::load(&[dir]).unwrap();
        assert_eq!(catalog.len(), 3);
        let demo = procimg_config::Config::demo();
        let items = |name: &str| {
            let d = demo.devices.iter().find(|d| d.name == name).unwrap();
            let s = d.submodules.iter().find(|s| s.slot == 1).unwrap();
            catalog.describe(
                (d.vendor_id, d.device_id),
                (s.module_ident, s.submodule_ident, s.api),
            )
        };
        let counter = items("counter");
        assert_eq!(counter.len(), 1, "{counter:?}");
        assert_eq!(
            (counter[0].output, counter[0].data_type.as_str()),
            (false, "Unsigned32")
        );
        let dio = items("dio");
        let bits: Vec<u16> = dio[0].bits.iter().map(|b| b.0).collect();
        assert_eq!(bits, (0..8).collect::<Vec<u16>>(), "{dio:?}");
        assert!(dio[0].bits[0].1.is_some(), "bits have names: {dio:?}");
    }
}
