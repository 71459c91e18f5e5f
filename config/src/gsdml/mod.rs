// SPDX-License-Identifier: MIT OR Apache-2.0
//! GSDML device descriptions (PROFINET GSDML V2.x, the XML file a device vendor ships):
//! what a controller needs from them to configure a device.
//!
//! [`Gsdml::load`] and [`Gsdml::parse`] read the device identity, the device access points
//! ([`Dap`]: the module in slot 0 with its own submodules, among them the interface and port
//! submodules), the modules ([`Module`]) and the submodules ([`Submodule`]) with their ident
//! numbers and where they may be plugged. [`Gsdml::io_lengths`] sums a submodule's IO data
//! items; [`Gsdml::records`] builds its parameter records with their default values, the
//! records a controller writes at connect.
//!
//! Elements are matched by local name, whatever the namespace prefix, and anything else
//! (graphics, diagnosis, value lists, languages other than the primary one, elements of newer
//! schema versions) is skipped. IO lengths and records are worked out when asked for, so a
//! module this import cannot handle only matters when it is used. Any input gives a result or
//! a [`GsdmlError`] naming the file, the line, the element and the attribute; nothing panics.
//!
//! The other way round, [`export`] writes the GSDML file of procimgd's own station (the
//! device role), which this import reads back as it was configured.
//!
//! ```
//! use procimg_config::gsdml::Gsdml;
//!
//! let text = r#"<ISO15745Profile><ProfileBody>
//!   <DeviceIdentity VendorID="0x0493" DeviceID="0x0001"/>
//!   <ApplicationProcess>
//!     <DeviceAccessPointList>
//!       <DeviceAccessPointItem ID="DAP" ModuleIdentNumber="0x1">
//!         <VirtualSubmoduleList>
//!           <VirtualSubmoduleItem ID="DAP_SM" SubmoduleIdentNumber="0x1"/>
//!         </VirtualSubmoduleList>
//!       </DeviceAccessPointItem>
//!     </DeviceAccessPointList>
//!     <ModuleList>
//!       <ModuleItem ID="M" ModuleIdentNumber="0x20">
//!         <VirtualSubmoduleList>
//!           <VirtualSubmoduleItem ID="M_SM" SubmoduleIdentNumber="0x1">
//!             <IOData><Input><DataItem DataType="Unsigned32"/></Input></IOData>
//!           </VirtualSubmoduleItem>
//!         </VirtualSubmoduleList>
//!       </ModuleItem>
//!     </ModuleList>
//!   </ApplicationProcess>
//! </ProfileBody></ISO15745Profile>"#;
//! let gsdml = Gsdml::parse(text, "GSDML-V2.4-example-20250101.xml")?;
//! assert_eq!((gsdml.vendor_id, gsdml.device_id), (0x0493, 0x0001));
//! let lengths = gsdml.io_lengths(&gsdml.modules[0].submodules[0])?;
//! assert_eq!((lengths.input, lengths.output), (4, 0));
//! # Ok::<(), procimg_config::gsdml::GsdmlError>(())
//! ```

mod data;
pub mod export;
mod reader;

use core::fmt;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use roxmltree::{Document, Node, ParsingOptions};

pub use data::ValueList;
use data::{IO_TYPES, MAX_RECORD_LEN, MAX_RECORDS_LEN, RefValue, SizeError};

use super::ParameterRecord;
use reader::{Reader, decode};

/// The largest GSDML file read (real ones, with many languages, reach a few MB).
pub const MAX_FILE_LEN: u64 = 64 << 20;

/// Most XML nodes parsed, which bounds the memory a broken or hostile file can take.
const NODES_LIMIT: u32 = 4_000_000;

/// Most values one value list may stand for where they are listed one by one (the subslots
/// of a DAP submodule added automatically).
pub(super) const MAX_LISTED_VALUES: usize = 256;

/// Why a GSDML file could not be read or used.
///
/// Messages name the file (as given), the 1-based line, the element and the attribute, and
/// say what to do.
#[derive(Debug)]
pub enum GsdmlError {
    /// The file could not be read.
    Read {
        /// The path as given.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The file is not what a GSDML file has to be at the byte level: larger than
    /// [`MAX_FILE_LEN`], not UTF-8 (or a declared ISO-8859-1), or not well-formed XML.
    Xml {
        /// The file name as shown.
        origin: String,
        /// 1-based line of the problem, where known.
        line: Option<usize>,
        /// What is wrong and what to do.
        message: String,
    },
    /// An element or attribute the import needs is missing or has a value it cannot use.
    Invalid {
        /// The file name as shown.
        origin: String,
        /// 1-based line of the element or attribute.
        line: usize,
        /// Local name of the element, e.g. `DataItem`.
        element: String,
        /// Name of the attribute, if the problem is one.
        attribute: Option<String>,
        /// What is wrong and what to do.
        message: String,
    },
}

impl GsdmlError {
    /// The 1-based line in the GSDML file, if the error refers to one.
    pub fn line(&self) -> Option<usize> {
        match self {
            GsdmlError::Read { .. } => None,
            GsdmlError::Xml { line, .. } => *line,
            GsdmlError::Invalid { line, .. } => Some(*line),
        }
    }
}

impl fmt::Display for GsdmlError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GsdmlError::Read { path, source } => write!(
                f,
                "{}: cannot read the GSDML file: {source}; check the path (relative paths \
                 start at the configuration file's directory) and its permissions",
                path.display()
            ),
            GsdmlError::Xml {
                origin,
                line,
                message,
            } => {
                f.write_str(origin)?;
                if let Some(line) = line {
                    write!(f, ":{line}")?;
                }
                write!(f, ": {message}")
            }
            GsdmlError::Invalid {
                origin,
                line,
                element,
                attribute,
                message,
            } => {
                write!(f, "{origin}:{line}: <{element}>")?;
                if let Some(attribute) = attribute {
                    write!(f, " {attribute}")?;
                }
                write!(f, ": {message}")
            }
        }
    }
}

// No `source`: the message holds what the operating system said, and error chains would
// print it twice.
impl core::error::Error for GsdmlError {}

/// A GSDML file, as far as a controller needs it.
#[derive(Clone, Debug)]
pub struct Gsdml {
    /// The file name as shown in messages.
    pub origin: String,
    /// `DeviceIdentity/@VendorID`.
    pub vendor_id: u16,
    /// `DeviceIdentity/@DeviceID`.
    pub device_id: u16,
    /// `DeviceIdentity/VendorName/@Value`, if given.
    pub vendor_name: Option<String>,
    /// Line of `<DeviceIdentity>`.
    pub identity_line: usize,
    /// The device access points (`DeviceAccessPointItem`), in file order; at least one.
    pub daps: Vec<Dap>,
    /// The modules (`ModuleList/ModuleItem`), in file order.
    pub modules: Vec<Module>,
    /// The pluggable submodules (`SubmoduleList/SubmoduleItem`), in file order.
    pub submodules: Vec<Submodule>,
}

/// A device access point (`DeviceAccessPointItem`): the module in slot 0 that makes the
/// device reachable, with the modules it takes.
#[derive(Clone, Debug)]
pub struct Dap {
    /// `@ID`, unique in the file.
    pub id: String,
    /// Its name (`ModuleInfo/Name`, from the primary language's texts).
    pub name: Option<String>,
    /// Line of the element.
    pub line: usize,
    /// `@ModuleIdentNumber`.
    pub module_ident: u32,
    /// `@FixedInSlots` (default 0): the slot the DAP is in.
    pub fixed_in_slots: ValueList,
    /// `@PhysicalSlots`: the slots the device has, if given.
    pub physical_slots: Option<ValueList>,
    /// `UseableModules/ModuleItemRef`: the modules this DAP takes and where.
    pub useable_modules: Vec<PlugRef>,
    /// Its submodules: the `VirtualSubmoduleList` items, then the
    /// `SystemDefinedSubmoduleList` interface and port submodules.
    pub submodules: Vec<Submodule>,
}

/// A module (`ModuleItem`).
#[derive(Clone, Debug)]
pub struct Module {
    /// `@ID`, unique in the file.
    pub id: String,
    /// Its name (`ModuleInfo/Name`, from the primary language's texts).
    pub name: Option<String>,
    /// Line of the element.
    pub line: usize,
    /// `@ModuleIdentNumber`.
    pub module_ident: u32,
    /// Its built-in submodules (`VirtualSubmoduleList`), in file order.
    pub submodules: Vec<Submodule>,
    /// `UseableSubmodules/SubmoduleItemRef`: pluggable submodules it takes, and where.
    pub useable_submodules: Vec<PlugRef>,
}

/// Where a module (`ModuleItemRef`) or pluggable submodule (`SubmoduleItemRef`) may be
/// plugged.
#[derive(Clone, Debug)]
pub struct PlugRef {
    /// `@ModuleItemTarget` or `@SubmoduleItemTarget`: the ID of the module or submodule.
    pub target: String,
    /// Line of the element.
    pub line: usize,
    /// `@AllowedInSlots` / `@AllowedInSubslots`.
    pub allowed: Option<ValueList>,
    /// `@FixedInSlots` / `@FixedInSubslots`.
    pub fixed: Option<ValueList>,
    /// `@UsedInSlots` / `@UsedInSubslots`.
    pub used: Option<ValueList>,
}

impl PlugRef {
    /// Whether it may go in `position` (slot or subslot); `None` if no position is listed.
    pub fn allows(&self, position: u32) -> Option<bool> {
        let lists = [&self.allowed, &self.fixed, &self.used];
        if lists.iter().all(|l| l.is_none()) {
            return None;
        }
        Some(
            lists
                .iter()
                .flat_map(|l| l.iter())
                .any(|l| l.contains(position)),
        )
    }

    /// The positions it may go in, for messages ("1..4 7").
    pub fn positions(&self) -> String {
        let lists: Vec<String> = [&self.fixed, &self.used, &self.allowed]
            .iter()
            .flat_map(|l| l.iter())
            .map(ValueList::to_string)
            .collect();
        if lists.is_empty() {
            "any".to_owned()
        } else {
            lists.join(" ")
        }
    }
}

/// What kind of submodule a [`Submodule`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SubmoduleKind {
    /// A built-in submodule of a module or DAP (`VirtualSubmoduleItem`).
    Virtual,
    /// A pluggable submodule (`SubmoduleList/SubmoduleItem`).
    Pluggable,
    /// The PROFINET interface of a DAP (`InterfaceSubmoduleItem`).
    Interface,
    /// A port of a DAP (`PortSubmoduleItem`).
    Port,
}

impl SubmoduleKind {
    /// The element name.
    pub const fn element(self) -> &'static str {
        match self {
            SubmoduleKind::Virtual => "VirtualSubmoduleItem",
            SubmoduleKind::Pluggable => "SubmoduleItem",
            SubmoduleKind::Interface => "InterfaceSubmoduleItem",
            SubmoduleKind::Port => "PortSubmoduleItem",
        }
    }
}

/// A submodule, with its IO data and parameter records (read with [`Gsdml::io_lengths`] and
/// [`Gsdml::records`]).
#[derive(Clone, Debug)]
pub struct Submodule {
    /// `@ID`.
    pub id: String,
    /// Its name (`ModuleInfo/Name` or `@TextId`, from the primary language's texts).
    pub name: Option<String>,
    /// What kind it is.
    pub kind: SubmoduleKind,
    /// Line of the element.
    pub line: usize,
    /// `@SubmoduleIdentNumber`.
    pub submodule_ident: u32,
    /// `@API` (default 0).
    pub api: u32,
    /// The subslots it is fixed in: `@FixedInSubslots` of a virtual submodule (default 1),
    /// `@SubslotNumber` of an interface (default 32768, 0x8000) or port; `None` for a
    /// pluggable submodule, whose subslots its module's [`PlugRef`] gives.
    pub subslots: Option<ValueList>,
    /// `@Writeable_IM_Records`: the I&M records 1–4 the PLC may write. A submodule that has
    /// them has I&M data of its own (I&M0 included), rather than its module's or the
    /// device's.
    pub writeable_im: Option<ValueList>,
    io: Vec<IoItem>,
    records: Vec<RecordItem>,
}

/// Bytes of IO data of a submodule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct IoLengths {
    /// Bytes of input data (`IOData/Input`).
    pub input: u16,
    /// Bytes of output data (`IOData/Output`).
    pub output: u16,
}

/// A `DataItem` of `IOData/Input` or `IOData/Output`.
#[derive(Clone, Debug)]
struct IoItem {
    output: bool,
    data_type: Option<String>,
    length: Option<String>,
    /// The text of `@TextId`.
    name: Option<String>,
    /// Its `BitDataItem`s: bit offset and the text of their `@TextId`.
    bits: Vec<(u16, Option<String>)>,
    line: usize,
    length_line: usize,
}

/// A `DataItem` of a submodule's IO data, where it lies: what a program (or an OPC UA
/// server) reads its bytes as.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DataItem {
    /// Of `IOData/Output` (the controller's outputs); else of `IOData/Input`.
    pub output: bool,
    /// Its first byte within its direction's data.
    pub offset: u16,
    /// Its bytes.
    pub length: u16,
    /// `@DataType` (`Unsigned16`, `Float32`, `OctetString`, …), big-endian on the wire.
    pub data_type: String,
    /// Its name: the primary-language text of `@TextId`.
    pub name: Option<String>,
    /// Its `BitDataItem`s (`@UseAsBits`): bit offset within the item (0 the lowest bit of
    /// its last byte) and name.
    pub bits: Vec<(u16, Option<String>)>,
}

/// An entry of a `RecordDataList`.
#[derive(Clone, Debug)]
enum RecordItem {
    Parameter(ParameterItem),
    /// An `F_ParameterRecordDataItem` (PROFIsafe), at this line.
    Safety(usize),
}

/// A `ParameterRecordDataItem`, attributes as text; checked by [`Gsdml::records`].
#[derive(Clone, Debug)]
struct ParameterItem {
    line: usize,
    /// `@Access`, if given: written at connect only if it includes `prm`.
    access: Option<String>,
    index: Attr,
    length: Attr,
    transfer_sequence: Attr,
    parts: Vec<Part>,
}

/// A `Const` or `Ref` of a parameter record.
#[derive(Clone, Debug)]
struct Part {
    is_ref: bool,
    line: usize,
    attrs: HashMap<&'static str, Attr>,
}

/// An attribute's value and line, if present.
#[derive(Clone, Debug, Default)]
struct Attr {
    value: Option<String>,
    line: usize,
}

const REF_ATTRS: [&str; 7] = [
    "DataType",
    "ByteOffset",
    "BitOffset",
    "BitLength",
    "Length",
    "DefaultValue",
    "Data",
];

impl Gsdml {
    /// Reads and parses the GSDML file at `path`; messages name it as `path` is written.
    pub fn load(path: &Path) -> Result<Gsdml, GsdmlError> {
        let origin = path.display().to_string();
        let read = |source| GsdmlError::Read {
            path: path.to_path_buf(),
            source,
        };
        let len = std::fs::metadata(path).map_err(read)?.len();
        if len > MAX_FILE_LEN {
            return Err(GsdmlError::Xml {
                origin,
                line: None,
                message: format!(
                    "the file has {len} bytes, more than the {MAX_FILE_LEN} a GSDML file may \
                     have here; check that this is the device's GSDML file"
                ),
            });
        }
        let bytes = std::fs::read(path).map_err(read)?;
        let text = decode(&bytes, &origin)?;
        Gsdml::parse(&text, &origin)
    }

    /// Parses GSDML `text`; `origin` names it in messages (a file name).
    pub fn parse(text: &str, origin: &str) -> Result<Gsdml, GsdmlError> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let options = ParsingOptions {
            allow_dtd: false,
            nodes_limit: NODES_LIMIT,
            ..ParsingOptions::default()
        };
        let doc = Document::parse_with_options(text, options).map_err(|e| GsdmlError::Xml {
            origin: origin.to_owned(),
            line: Some(e.pos().row as usize),
            message: format!(
                "not well-formed XML: {e}; a GSDML file is XML as the vendor ships it, check \
                 that the file is complete and unedited"
            ),
        })?;
        Reader::new(&doc, text, origin).gsdml()
    }

    /// The DAP with ID (or else name) `id_or_name`.
    pub fn dap(&self, id_or_name: &str) -> Option<&Dap> {
        self.daps.iter().find(|d| d.id == id_or_name).or_else(|| {
            self.daps
                .iter()
                .find(|d| d.name.as_deref() == Some(id_or_name))
        })
    }

    /// The module with ID `id`.
    pub fn module(&self, id: &str) -> Option<&Module> {
        self.modules.iter().find(|m| m.id == id)
    }

    /// The pluggable submodule with ID `id`.
    pub fn pluggable(&self, id: &str) -> Option<&Submodule> {
        self.submodules.iter().find(|s| s.id == id)
    }

    fn invalid(
        &self,
        line: usize,
        element: &str,
        attribute: Option<&str>,
        message: String,
    ) -> GsdmlError {
        GsdmlError::Invalid {
            origin: self.origin.clone(),
            line,
            element: element.to_owned(),
            attribute: attribute.map(str::to_owned),
            message,
        }
    }

    /// The `DataItem`s of `submodule`'s `IOData/Input` and `IOData/Output`, each with its
    /// place in its direction's data.
    pub fn data_items(&self, submodule: &Submodule) -> Result<Vec<DataItem>, GsdmlError> {
        let mut items = Vec::with_capacity(submodule.io.len());
        let mut sums = [0u64; 2];
        for item in &submodule.io {
            let size = self.item_size(item)?;
            let sum = &mut sums[usize::from(item.output)];
            let too_long = || {
                self.invalid(
                    submodule.line,
                    submodule.kind.element(),
                    None,
                    "its IO data add up to more bytes than a frame can carry".to_owned(),
                )
            };
            items.push(DataItem {
                output: item.output,
                offset: u16::try_from(*sum).map_err(|_| too_long())?,
                length: u16::try_from(size).map_err(|_| too_long())?,
                data_type: item.data_type.clone().unwrap_or_default(),
                name: item.name.clone(),
                bits: item.bits.clone(),
            });
            *sum = sum.saturating_add(size);
        }
        Ok(items)
    }

    /// The bytes of one `DataItem`.
    fn item_size(&self, item: &IoItem) -> Result<u64, GsdmlError> {
        let Some(data_type) = item.data_type.as_deref() else {
            return Err(self.invalid(
                item.line,
                "DataItem",
                Some("DataType"),
                "missing; every data item has a data type".to_owned(),
            ));
        };
        let length = match &item.length {
            Some(text) => Some(data::number(text).ok_or_else(|| {
                self.invalid(
                    item.length_line,
                    "DataItem",
                    Some("Length"),
                    format!("{text:?} is not a number of bytes"),
                )
            })?),
            None => None,
        };
        data::io_size(data_type, length).map_err(|e| match e {
            SizeError::NeedsLength => self.invalid(
                item.line,
                "DataItem",
                Some("Length"),
                format!("missing; a {data_type} data item needs its Length in bytes"),
            ),
            SizeError::Unknown => self.invalid(
                item.line,
                "DataItem",
                Some("DataType"),
                format!(
                    "{data_type:?} is not an IO data type this import knows ({IO_TYPES}); \
                     give input_length and output_length in the configuration instead"
                ),
            ),
        })
    }

    /// The submodule with `submodule_ident` (in `api`) of the DAP or module with
    /// `module_ident`, one of its own or a pluggable one it takes: what a device reporting
    /// those ident numbers has plugged, as far as the file tells.
    pub fn find_submodule(
        &self,
        module_ident: u32,
        submodule_ident: u32,
        api: u32,
    ) -> Option<&Submodule> {
        let fits = |s: &&Submodule| s.submodule_ident == submodule_ident && s.api == api;
        let daps = self
            .daps
            .iter()
            .filter(|d| d.module_ident == module_ident)
            .flat_map(|d| d.submodules.iter());
        let modules = self
            .modules
            .iter()
            .filter(|m| m.module_ident == module_ident);
        let own = modules.clone().flat_map(|m| m.submodules.iter());
        let pluggable = modules
            .flat_map(|m| m.useable_submodules.iter())
            .filter_map(|r| self.pluggable(&r.target));
        daps.chain(own).chain(pluggable).find(|s| fits(s))
    }

    /// The IO data lengths of `submodule`: the sizes of the `DataItem`s of its
    /// `IOData/Input` and `IOData/Output`, added up.
    pub fn io_lengths(&self, submodule: &Submodule) -> Result<IoLengths, GsdmlError> {
        let mut sums = [0u64; 2];
        for item in &submodule.io {
            let size = self.item_size(item)?;
            let sum = &mut sums[usize::from(item.output)];
            *sum = sum.saturating_add(size);
        }
        let fit = |sum: u64, what: &str| {
            u16::try_from(sum).map_err(|_| {
                self.invalid(
                    submodule.line,
                    submodule.kind.element(),
                    None,
                    format!("its {what} data add up to {sum} bytes, more than a frame can carry"),
                )
            })
        };
        Ok(IoLengths {
            input: fit(sums[0], "input")?,
            output: fit(sums[1], "output")?,
        })
    }

    /// The parameter records of `submodule` with their default values, as a controller
    /// writes them at connect: each `ParameterRecordDataItem` as `@Length` zero bytes,
    /// overwritten by its `Const` and `Ref` elements in file order, values big-endian. Records
    /// with a non-zero `@TransferSequence` come first, in that order; the others follow in
    /// file order. Records with an `@Access` that does not include `prm` (read or write only,
    /// such as data objects) are left out.
    pub fn records(&self, submodule: &Submodule) -> Result<Vec<ParameterRecord>, GsdmlError> {
        let mut records = Vec::new();
        let mut total = 0u64;
        for item in &submodule.records {
            let item = match item {
                RecordItem::Parameter(p) => p,
                RecordItem::Safety(line) => {
                    return Err(self.invalid(
                        *line,
                        "F_ParameterRecordDataItem",
                        None,
                        "this is a PROFIsafe submodule, whose F-parameter record carries a \
                         CRC this import does not compute; give the submodule's records in \
                         the configuration instead"
                            .to_owned(),
                    ));
                }
            };
            // Records only to be read or written later (data objects) are not part of the
            // start-up parameterization.
            if let Some(access) = &item.access
                && !access.split(';').any(|a| a.trim() == "prm")
            {
                continue;
            }
            let el = "ParameterRecordDataItem";
            let index = self.number_attr(&item.index, el, "Index", item.line, 0xFFFF)?;
            let length = self.number_attr(&item.length, el, "Length", item.line, MAX_RECORD_LEN)?;
            let sequence = match item.transfer_sequence.value {
                Some(_) => self.number_attr(
                    &item.transfer_sequence,
                    el,
                    "TransferSequence",
                    item.line,
                    0xFFFF,
                )?,
                None => 0,
            };
            total += length;
            if total > MAX_RECORDS_LEN {
                return Err(self.invalid(
                    item.line,
                    el,
                    Some("Length"),
                    format!(
                        "the submodule's records add up to more than {MAX_RECORDS_LEN} bytes; \
                         check the GSDML file, or give the records in the configuration instead"
                    ),
                ));
            }
            // `length` is at most MAX_RECORD_LEN, so this allocation is bounded.
            let mut data = vec![0u8; length as usize];
            for part in &item.parts {
                self.apply(&mut data, part)?;
            }
            records.push((
                sequence,
                ParameterRecord {
                    index: index as u16,
                    data,
                },
            ));
        }
        // Stable: equal keys keep file order.
        records.sort_by_key(|&(sequence, _)| (sequence == 0, sequence));
        Ok(records.into_iter().map(|(_, r)| r).collect())
    }

    fn number_attr(
        &self,
        attr: &Attr,
        element: &str,
        name: &str,
        element_line: usize,
        max: u64,
    ) -> Result<u64, GsdmlError> {
        let Some(text) = &attr.value else {
            return Err(self.invalid(
                element_line,
                element,
                Some(name),
                "missing; the import needs it".to_owned(),
            ));
        };
        match data::number(text) {
            Some(n) if n <= max => Ok(n),
            _ => Err(self.invalid(
                attr.line,
                element,
                Some(name),
                format!("{text:?} is not a number from 0 to {max}"),
            )),
        }
    }

    fn apply(&self, record: &mut [u8], part: &Part) -> Result<(), GsdmlError> {
        let element = if part.is_ref { "Ref" } else { "Const" };
        let get = |name: &str| part.attrs.get(name).and_then(|a| a.value.as_deref());
        let line_of = |name: &str| part.attrs.get(name).map_or(part.line, |a| a.line);
        let opt_number = |name: &'static str| -> Result<Option<u64>, GsdmlError> {
            match get(name) {
                None => Ok(None),
                Some(text) => data::number(text).map(Some).ok_or_else(|| {
                    self.invalid(
                        line_of(name),
                        element,
                        Some(name),
                        format!("{text:?} is not a number"),
                    )
                }),
            }
        };
        let byte_offset = opt_number("ByteOffset")?.unwrap_or(0);
        let result = if part.is_ref {
            let Some(data_type) = get("DataType") else {
                return Err(self.invalid(
                    part.line,
                    element,
                    Some("DataType"),
                    "missing; every Ref has a data type".to_owned(),
                ));
            };
            let Some(default) = get("DefaultValue") else {
                return Err(self.invalid(
                    part.line,
                    element,
                    Some("DefaultValue"),
                    "missing; the import writes each parameter's default value".to_owned(),
                ));
            };
            let value = RefValue {
                data_type,
                byte_offset,
                bit_offset: opt_number("BitOffset")?,
                bit_length: opt_number("BitLength")?,
                length: opt_number("Length")?,
                default,
            };
            data::write_ref(record, &value)
        } else {
            let text = get("Data").unwrap_or("");
            let bytes = data::const_bytes(text)
                .map_err(|m| self.invalid(line_of("Data"), element, Some("Data"), m))?;
            data::write_const(record, byte_offset, &bytes)
        };
        result.map_err(|e| {
            self.invalid(
                line_of(e.attribute),
                element,
                Some(e.attribute),
                format!(
                    "{}; correct the GSDML file or give the submodule's records in the \
                     configuration instead",
                    e.message
                ),
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::reader::Lines;
    use super::*;

    #[test]
    fn lines() {
        let l = Lines::new("a\nbc\n\nd");
        assert_eq!(l.line(0), 1);
        assert_eq!(l.line(1), 1);
        assert_eq!(l.line(2), 2);
        assert_eq!(l.line(5), 3);
        assert_eq!(l.line(6), 4);
        assert_eq!(l.line(999), 4);
    }

    #[test]
    fn latin1_is_decoded_where_declared() {
        let bytes = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a b=\"\xE4\"/>";
        assert_eq!(
            decode(bytes, "x").unwrap(),
            "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<a b=\"\u{e4}\"/>"
        );
        let e = decode(b"<?xml version=\"1.0\"?>\n\n<a b=\"\xE4\"/>", "x").unwrap_err();
        assert_eq!(e.line(), Some(3));
        assert_eq!(decode(b"\xEF\xBB\xBF<a/>", "x").unwrap(), "<a/>");
    }
}
