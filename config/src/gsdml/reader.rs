// SPDX-License-Identifier: MIT OR Apache-2.0
//! Reading a GSDML file's XML: its text encoding, line numbers for messages, and the walk
//! from the device access points down to the modules, submodules, IO data and records.

use super::*;

/// The text of a GSDML file: UTF-8 (with or without BOM), or ISO-8859-1 where the XML
/// declaration says so.
pub(super) fn decode(bytes: &[u8], origin: &str) -> Result<String, GsdmlError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(text) => Ok(text.to_owned()),
        Err(e) => {
            let head = String::from_utf8_lossy(&bytes[..bytes.len().min(200)]).to_lowercase();
            let latin1 = head.starts_with("<?xml")
                && (head.contains("iso-8859-1") || head.contains("iso8859-1"));
            if latin1 {
                // ISO-8859-1 bytes are the first 256 code points.
                return Ok(bytes.iter().map(|&b| char::from(b)).collect());
            }
            let line = bytes[..e.valid_up_to()]
                .iter()
                .filter(|&&b| b == b'\n')
                .count()
                + 1;
            Err(GsdmlError::Xml {
                origin: origin.to_owned(),
                line: Some(line),
                message: "the file is not UTF-8 text; GSDML files are UTF-8 XML, convert it \
                          (e.g. with iconv) or use the file as the vendor ships it"
                    .to_owned(),
            })
        }
    }
}

/// Byte offsets of line starts, for lines of nodes in large files without rescanning.
pub(super) struct Lines(Vec<usize>);

impl Lines {
    pub(super) fn new(text: &str) -> Lines {
        let starts = core::iter::once(0)
            .chain(
                text.bytes()
                    .enumerate()
                    .filter(|&(_, b)| b == b'\n')
                    .map(|(i, _)| i + 1),
            )
            .collect();
        Lines(starts)
    }

    pub(super) fn line(&self, offset: usize) -> usize {
        self.0.partition_point(|&start| start <= offset).max(1)
    }
}

/// Walks the document once into a [`Gsdml`].
pub(super) struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    lines: Lines,
    origin: &'a str,
    texts: HashMap<&'a str, &'a str>,
}

fn local<'a, 'input>(node: Node<'a, 'input>) -> &'a str {
    node.tag_name().name()
}

fn children<'a, 'input>(
    node: Node<'a, 'input>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    node.children()
        .filter(move |c| c.is_element() && local(*c) == name)
}

fn child<'a, 'input>(node: Node<'a, 'input>, name: &'static str) -> Option<Node<'a, 'input>> {
    children(node, name).next()
}

/// The element at `path` below `node`, each step the first child of that name.
fn descend<'a, 'input>(node: Node<'a, 'input>, path: &[&'static str]) -> Option<Node<'a, 'input>> {
    path.iter().try_fold(node, |n, name| child(n, name))
}

impl<'a, 'input> Reader<'a, 'input> {
    pub(super) fn new(doc: &'a Document<'input>, text: &str, origin: &'a str) -> Self {
        Reader {
            doc,
            lines: Lines::new(text),
            origin,
            texts: HashMap::new(),
        }
    }

    fn line(&self, node: Node<'_, '_>) -> usize {
        self.lines.line(node.range().start)
    }

    fn attr_line(&self, node: Node<'_, '_>, name: &str) -> usize {
        match node.attribute_node(name) {
            Some(a) => self.lines.line(a.range().start),
            None => self.line(node),
        }
    }

    fn attr(&self, node: Node<'_, '_>, name: &str) -> Attr {
        Attr {
            value: node.attribute(name).map(str::to_owned),
            line: self.attr_line(node, name),
        }
    }

    fn invalid(&self, node: Node<'_, '_>, attribute: Option<&str>, message: String) -> GsdmlError {
        let line = match attribute {
            Some(a) => self.attr_line(node, a),
            None => self.line(node),
        };
        GsdmlError::Invalid {
            origin: self.origin.to_owned(),
            line,
            element: local(node).to_owned(),
            attribute: attribute.map(str::to_owned),
            message,
        }
    }

    fn required_child(
        &self,
        node: Node<'a, 'input>,
        name: &'static str,
    ) -> Result<Node<'a, 'input>, GsdmlError> {
        child(node, name).ok_or_else(|| {
            self.invalid(
                node,
                None,
                format!(
                    "has no <{name}>, which every GSDML file has; check that this is a \
                     device's GSDML file"
                ),
            )
        })
    }

    fn required(&self, node: Node<'a, 'input>, name: &str) -> Result<&'a str, GsdmlError> {
        node.attribute(name).ok_or_else(|| {
            self.invalid(
                node,
                Some(name),
                "missing; every GSDML file has it here".to_owned(),
            )
        })
    }

    /// A required numeric attribute of at most `max`.
    fn number(&self, node: Node<'a, 'input>, name: &str, max: u64) -> Result<u64, GsdmlError> {
        let text = self.required(node, name)?;
        match data::number(text) {
            Some(n) if n <= max => Ok(n),
            _ => Err(self.invalid(
                node,
                Some(name),
                format!("{text:?} is not a number from 0 to {max:#x}"),
            )),
        }
    }

    fn value_list(
        &self,
        node: Node<'a, 'input>,
        name: &str,
    ) -> Result<Option<ValueList>, GsdmlError> {
        match node.attribute(name) {
            None => Ok(None),
            Some(text) => ValueList::parse(text).map(Some).ok_or_else(|| {
                self.invalid(
                    node,
                    Some(name),
                    format!("{text:?} is not a value list such as \"1..4 7\""),
                )
            }),
        }
    }

    /// The primary-language text of `text_id`.
    fn text(&self, text_id: Option<&str>) -> Option<String> {
        text_id
            .and_then(|id| self.texts.get(id))
            .map(|t| (*t).to_owned())
    }

    /// The name of an item: the text of `ModuleInfo/Name/@TextId`.
    fn name(&self, item: Node<'a, 'input>) -> Option<String> {
        let name = descend(item, &["ModuleInfo", "Name"])?;
        self.text(name.attribute("TextId"))
    }

    pub(super) fn gsdml(mut self) -> Result<Gsdml, GsdmlError> {
        let root = self.doc.root_element();
        if local(root) != "ISO15745Profile" {
            return Err(self.invalid(
                root,
                None,
                format!(
                    "the document is a <{}>, not a GSDML file (<ISO15745Profile>); give the \
                     device's GSDML file",
                    local(root)
                ),
            ));
        }
        let body = self.required_child(root, "ProfileBody")?;
        let identity = self.required_child(body, "DeviceIdentity")?;
        let vendor_id = self.number(identity, "VendorID", 0xFFFF)? as u16;
        let device_id = self.number(identity, "DeviceID", 0xFFFF)? as u16;
        let vendor_name = child(identity, "VendorName")
            .and_then(|n| n.attribute("Value"))
            .map(str::to_owned);
        let process = self.required_child(body, "ApplicationProcess")?;
        if let Some(primary) = descend(process, &["ExternalTextList", "PrimaryLanguage"]) {
            for text in children(primary, "Text") {
                if let (Some(id), Some(value)) = (text.attribute("TextId"), text.attribute("Value"))
                {
                    self.texts.entry(id).or_insert(value);
                }
            }
        }

        let mut ids: HashMap<String, usize> = HashMap::new();
        let mut unique = |reader: &Self, node: Node<'a, 'input>, id: &str| {
            let line = reader.line(node);
            match ids.insert(id.to_owned(), line) {
                Some(first) => Err(reader.invalid(
                    node,
                    Some("ID"),
                    format!(
                        "{id:?} is already the ID of the item on line {first}; IDs are unique \
                         in a GSDML file"
                    ),
                )),
                None => Ok(()),
            }
        };

        let list = self.required_child(process, "DeviceAccessPointList")?;
        let mut daps = Vec::new();
        for item in children(list, "DeviceAccessPointItem") {
            let id = self.required(item, "ID")?;
            unique(&self, item, id)?;
            let mut submodules = Vec::new();
            if let Some(list) = child(item, "VirtualSubmoduleList") {
                for sub in children(list, "VirtualSubmoduleItem") {
                    submodules.push(self.submodule(sub, SubmoduleKind::Virtual)?);
                }
            }
            if let Some(list) = child(item, "SystemDefinedSubmoduleList") {
                for sub in list.children().filter(Node::is_element) {
                    let kind = match local(sub) {
                        "InterfaceSubmoduleItem" => SubmoduleKind::Interface,
                        "PortSubmoduleItem" => SubmoduleKind::Port,
                        _ => continue,
                    };
                    submodules.push(self.submodule(sub, kind)?);
                }
            }
            let useable_modules = match child(item, "UseableModules") {
                Some(list) => children(list, "ModuleItemRef")
                    .map(|r| self.plug_ref(r, "ModuleItemTarget", "Slots"))
                    .collect::<Result<_, _>>()?,
                None => Vec::new(),
            };
            daps.push(Dap {
                id: id.to_owned(),
                name: self.name(item),
                line: self.line(item),
                module_ident: self.number(item, "ModuleIdentNumber", 0xFFFF_FFFF)? as u32,
                fixed_in_slots: self
                    .value_list(item, "FixedInSlots")?
                    .unwrap_or_else(|| ValueList::single(0)),
                physical_slots: self.value_list(item, "PhysicalSlots")?,
                useable_modules,
                submodules,
            });
        }
        if daps.is_empty() {
            return Err(self.invalid(
                list,
                None,
                "has no <DeviceAccessPointItem>; a GSDML file describes at least one device \
                 access point"
                    .to_owned(),
            ));
        }

        let mut modules = Vec::new();
        if let Some(list) = child(process, "ModuleList") {
            for item in children(list, "ModuleItem") {
                let id = self.required(item, "ID")?;
                unique(&self, item, id)?;
                let mut submodules = Vec::new();
                if let Some(list) = child(item, "VirtualSubmoduleList") {
                    for sub in children(list, "VirtualSubmoduleItem") {
                        submodules.push(self.submodule(sub, SubmoduleKind::Virtual)?);
                    }
                }
                let useable_submodules = match child(item, "UseableSubmodules") {
                    Some(list) => children(list, "SubmoduleItemRef")
                        .map(|r| self.plug_ref(r, "SubmoduleItemTarget", "Subslots"))
                        .collect::<Result<_, _>>()?,
                    None => Vec::new(),
                };
                modules.push(Module {
                    id: id.to_owned(),
                    name: self.name(item),
                    line: self.line(item),
                    module_ident: self.number(item, "ModuleIdentNumber", 0xFFFF_FFFF)? as u32,
                    submodules,
                    useable_submodules,
                });
            }
        }

        let mut submodules = Vec::new();
        if let Some(list) = child(process, "SubmoduleList") {
            for item in children(list, "SubmoduleItem") {
                submodules.push(self.submodule(item, SubmoduleKind::Pluggable)?);
            }
        }

        Ok(Gsdml {
            origin: self.origin.to_owned(),
            vendor_id,
            device_id,
            vendor_name,
            identity_line: self.line(identity),
            daps,
            modules,
            submodules,
        })
    }

    fn plug_ref(
        &self,
        node: Node<'a, 'input>,
        target: &str,
        positions: &str,
    ) -> Result<PlugRef, GsdmlError> {
        Ok(PlugRef {
            target: self.required(node, target)?.to_owned(),
            line: self.line(node),
            allowed: self.value_list(node, &format!("AllowedIn{positions}"))?,
            fixed: self.value_list(node, &format!("FixedIn{positions}"))?,
            used: self.value_list(node, &format!("UsedIn{positions}"))?,
        })
    }

    fn submodule(
        &self,
        node: Node<'a, 'input>,
        kind: SubmoduleKind,
    ) -> Result<Submodule, GsdmlError> {
        let subslots = match kind {
            SubmoduleKind::Virtual => Some(
                self.value_list(node, "FixedInSubslots")?
                    .unwrap_or_else(|| ValueList::single(1)),
            ),
            SubmoduleKind::Pluggable => None,
            SubmoduleKind::Interface => Some(match node.attribute("SubslotNumber") {
                Some(_) => ValueList::single(self.number(node, "SubslotNumber", 0xFFFF)? as u32),
                None => ValueList::single(0x8000),
            }),
            SubmoduleKind::Port => {
                Some(ValueList::single(
                    self.number(node, "SubslotNumber", 0xFFFF)? as u32,
                ))
            }
        };
        let name = match kind {
            SubmoduleKind::Interface | SubmoduleKind::Port => self.text(node.attribute("TextId")),
            _ => self.name(node),
        };
        let api = match node.attribute("API") {
            Some(_) => self.number(node, "API", 0xFFFF_FFFF)? as u32,
            None => 0,
        };
        let mut io = Vec::new();
        if let Some(data) = child(node, "IOData") {
            for (direction, output) in [("Input", false), ("Output", true)] {
                for list in children(data, direction) {
                    for item in children(list, "DataItem") {
                        let bits = children(item, "BitDataItem")
                            .filter_map(|b| {
                                let offset = b.attribute("BitOffset")?.trim().parse().ok()?;
                                Some((offset, self.text(b.attribute("TextId"))))
                            })
                            .collect();
                        io.push(IoItem {
                            output,
                            data_type: item.attribute("DataType").map(str::to_owned),
                            length: item.attribute("Length").map(str::to_owned),
                            name: self.text(item.attribute("TextId")),
                            bits,
                            line: self.attr_line(item, "DataType"),
                            length_line: self.attr_line(item, "Length"),
                        });
                    }
                }
            }
        }
        let mut records = Vec::new();
        if let Some(list) = child(node, "RecordDataList") {
            for item in list.children().filter(Node::is_element) {
                match local(item) {
                    "ParameterRecordDataItem" => {
                        let parts = item
                            .children()
                            .filter(|c| c.is_element() && matches!(local(*c), "Const" | "Ref"))
                            .map(|c| Part {
                                is_ref: local(c) == "Ref",
                                line: self.line(c),
                                attrs: REF_ATTRS
                                    .iter()
                                    .filter(|a| c.has_attribute(**a))
                                    .map(|&a| (a, self.attr(c, a)))
                                    .collect(),
                            })
                            .collect();
                        records.push(RecordItem::Parameter(ParameterItem {
                            line: self.line(item),
                            access: item.attribute("Access").map(str::to_owned),
                            index: self.attr(item, "Index"),
                            length: self.attr(item, "Length"),
                            transfer_sequence: self.attr(item, "TransferSequence"),
                            parts,
                        }));
                    }
                    "F_ParameterRecordDataItem" => {
                        records.push(RecordItem::Safety(self.line(item)))
                    }
                    _ => {}
                }
            }
        }
        Ok(Submodule {
            id: self.required(node, "ID")?.to_owned(),
            name,
            kind,
            line: self.line(node),
            submodule_ident: self.number(node, "SubmoduleIdentNumber", 0xFFFF_FFFF)? as u32,
            api,
            subslots,
            // Empty says none, as the attribute left out does.
            writeable_im: match node.attribute("Writeable_IM_Records") {
                Some(t) if t.trim().is_empty() => None,
                _ => self.value_list(node, "Writeable_IM_Records")?,
            },
            io,
            records,
        })
    }
}
