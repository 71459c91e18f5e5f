// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PN Driver configuration's generic object tree: `<Object>` elements, each with its
//! class (`<ClassRID>`), an optional key (`<Key AID="…">`) and object ID (`<RID>`), its
//! `<Variable>`s (an attribute ID `<AID>` and a `<Value>`), `<Link>`s and child objects.
//! Only the numbers mean something; `Name` attributes are what TIA Portal shows, kept for
//! messages.

use roxmltree::{Document, Node};

/// Something in the XML that is not the tree this reader knows, at a line.
#[derive(Debug)]
pub(super) struct TreeError {
    pub line: usize,
    pub element: String,
    pub message: String,
}

type Result<T> = core::result::Result<T, TreeError>;

/// One `<Object>`.
#[derive(Debug, Default)]
pub(super) struct Object {
    pub class: u32,
    pub name: String,
    pub line: usize,
    /// `<Key AID="a">v</Key>`: (a, v).
    pub key: Option<(u32, u64)>,
    pub rid: Option<u64>,
    pub variables: Vec<Variable>,
    /// Target RIDs of its `<Link>`s.
    pub links: Vec<u64>,
    pub children: Vec<Object>,
}

/// One `<Variable>`.
#[derive(Debug)]
pub(super) struct Variable {
    pub aid: u32,
    pub name: String,
    pub value: Value,
}

/// A variable's `<Value>`.
#[derive(Debug)]
pub(super) enum Value {
    /// `Datatype="Scalar"` with a text value (UINT16, UINT32, BOOL).
    Scalar(String),
    /// `Datatype="SparseArray" Valuetype="BLOB"`: records by key.
    Fields(Vec<Field>),
    /// `Valuetype="STRUCT"`: elements by attribute ID.
    Struct(Vec<(u32, String)>),
    /// `Datatype="Scalar" Valuetype="BLOB"`: one hex blob.
    Blob(Vec<u8>),
}

/// One `<Field Key="k" Length="n">HEX</Field>` of a sparse array.
#[derive(Debug)]
pub(super) struct Field {
    pub key: u64,
    pub data: Vec<u8>,
    pub line: usize,
}

impl Object {
    /// The variable with attribute ID `aid`.
    pub fn variable(&self, aid: u32) -> Option<&Variable> {
        self.variables.iter().find(|v| v.aid == aid)
    }

    /// Its children of class `class`.
    pub fn children_of(&self, class: u32) -> impl Iterator<Item = &Object> {
        self.children.iter().filter(move |c| c.class == class)
    }

    /// This object and every object below it, depth first.
    pub fn walk(&self) -> Vec<&Object> {
        let mut out = vec![self];
        for child in &self.children {
            out.extend(child.walk());
        }
        out
    }

    /// How messages name it: `Object "IO-Device_1" (line 52)`.
    pub fn describe(&self) -> String {
        format!("Object \"{}\" (class {})", self.name, self.class)
    }

    /// The key's value if its attribute ID is `aid`.
    pub fn key_of(&self, aid: u32) -> Option<u64> {
        self.key.filter(|(a, _)| *a == aid).map(|(_, v)| v)
    }
}

/// Parses the document and returns its configuration object (class 1): the root element,
/// or the class-1 object below another root element (PN Driver also accepts such a wrapper).
pub(super) fn parse(text: &str) -> Result<Object> {
    let doc = Document::parse(text).map_err(|e| TreeError {
        line: e.pos().row as usize,
        element: "the XML".to_owned(),
        message: format!("not well-formed XML: {e}"),
    })?;
    let line = |n: Node<'_, '_>| doc.text_pos_at(n.range().start).row as usize;
    let root = doc.root_element();
    let top = if is_object(root) {
        root
    } else {
        root.children()
            .find(|n| is_object(*n))
            .ok_or_else(|| TreeError {
                line: line(root),
                element: format!("<{}>", root.tag_name().name()),
                message: "no <Object> here: this is not a PN Driver configuration, whose root \
                          is <Object Name=\"HWConfiguration\"> with ClassRID 1 (TIA Portal \
                          exports it as …PNDriverConfiguration.xml)"
                    .to_owned(),
            })?
    };
    let object = read_object(top, &line)?;
    if object.class != 1 {
        return Err(TreeError {
            line: object.line,
            element: object.describe(),
            message: "the configuration's root object has ClassRID 1 (HWConfiguration): this \
                      is not a PN Driver configuration"
                .to_owned(),
        });
    }
    Ok(object)
}

fn is_object(n: Node<'_, '_>) -> bool {
    n.is_element() && n.tag_name().name() == "Object"
}

fn elements<'a, 'i>(n: Node<'a, 'i>) -> impl Iterator<Item = Node<'a, 'i>> {
    n.children().filter(|c| c.is_element())
}

fn text_of<'a>(n: Node<'a, '_>) -> &'a str {
    n.text().unwrap_or("").trim()
}

fn read_object(n: Node<'_, '_>, line: &dyn Fn(Node<'_, '_>) -> usize) -> Result<Object> {
    let mut o = Object {
        name: n.attribute("Name").unwrap_or("").to_owned(),
        line: line(n),
        ..Object::default()
    };
    let mut class = None;
    let err = |at: Node<'_, '_>, o: &Object, message: String| TreeError {
        line: line(at),
        element: format!("Object \"{}\"", o.name),
        message,
    };
    for c in elements(n) {
        match c.tag_name().name() {
            "ClassRID" => class = Some(number(text_of(c)).map_err(|m| err(c, &o, m))? as u32),
            "RID" => o.rid = Some(number(text_of(c)).map_err(|m| err(c, &o, m))?),
            "Key" => {
                let aid = c.attribute("AID").unwrap_or("");
                let aid = number(aid).map_err(|m| err(c, &o, format!("Key AID: {m}")))? as u32;
                let value = number(text_of(c)).map_err(|m| err(c, &o, format!("Key: {m}")))?;
                o.key = Some((aid, value));
            }
            "Variable" => {
                let v = read_variable(c, line).map_err(|m| err(c, &o, m))?;
                o.variables.push(v);
            }
            "Link" => {
                if let Some(t) = elements(c).find(|e| e.tag_name().name() == "TargetRID") {
                    o.links.push(number(text_of(t)).map_err(|m| err(t, &o, m))?);
                }
            }
            "Object" => o.children.push(read_object(c, line)?),
            // Anything else (comments, elements a newer version adds) is not needed.
            _ => {}
        }
    }
    o.class = class.ok_or_else(|| err(n, &o, "the object has no <ClassRID>".to_owned()))?;
    Ok(o)
}

fn read_variable(
    n: Node<'_, '_>,
    line: &dyn Fn(Node<'_, '_>) -> usize,
) -> core::result::Result<Variable, String> {
    let name = n.attribute("Name").unwrap_or("").to_owned();
    let aid = elements(n)
        .find(|e| e.tag_name().name() == "AID")
        .ok_or_else(|| format!("Variable \"{name}\" has no <AID>"))?;
    let aid = number(text_of(aid)).map_err(|m| format!("Variable \"{name}\" AID: {m}"))? as u32;
    let value = elements(n)
        .find(|e| e.tag_name().name() == "Value")
        .ok_or_else(|| format!("Variable \"{name}\" has no <Value>"))?;
    let value = match (value.attribute("Datatype"), value.attribute("Valuetype")) {
        (Some("SparseArray"), _) => {
            let mut fields = Vec::new();
            for f in elements(value).filter(|e| e.tag_name().name() == "Field") {
                let key = number(f.attribute("Key").unwrap_or(""))
                    .map_err(|m| format!("Variable \"{name}\", a Field's Key: {m}"))?;
                let data = hex(f, &name)?;
                fields.push(Field {
                    key,
                    data,
                    line: line(f),
                });
            }
            Value::Fields(fields)
        }
        (_, Some("STRUCT")) => {
            let mut elements_read = Vec::new();
            for e in elements(value).filter(|e| e.tag_name().name() == "Element") {
                let aid = number(e.attribute("AID").unwrap_or(""))
                    .map_err(|m| format!("Variable \"{name}\", an Element's AID: {m}"))?;
                elements_read.push((aid as u32, text_of(e).to_owned()));
            }
            Value::Struct(elements_read)
        }
        (_, Some("BLOB")) => Value::Blob(hex(value, &name)?),
        _ => Value::Scalar(text_of(value).to_owned()),
    };
    Ok(Variable { aid, name, value })
}

/// The bytes of an element's hex text, whose `Length` attribute (if any) gives their count.
fn hex(n: Node<'_, '_>, variable: &str) -> core::result::Result<Vec<u8>, String> {
    let text = text_of(n);
    let digits: Vec<u8> = text.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    if !digits.len().is_multiple_of(2) {
        return Err(format!(
            "Variable \"{variable}\": {} hex digits are not whole bytes",
            digits.len()
        ));
    }
    let mut bytes = Vec::with_capacity(digits.len() / 2);
    for pair in digits.chunks_exact(2) {
        let hi = (pair[0] as char).to_digit(16);
        let lo = (pair[1] as char).to_digit(16);
        match (hi, lo) {
            (Some(h), Some(l)) => bytes.push((h * 16 + l) as u8),
            _ => {
                return Err(format!(
                    "Variable \"{variable}\": \"{}\" is not hex",
                    String::from_utf8_lossy(pair)
                ));
            }
        }
    }
    if let Some(len) = n.attribute("Length") {
        let len = number(len).map_err(|m| format!("Variable \"{variable}\", Length: {m}"))?;
        if len != bytes.len() as u64 {
            return Err(format!(
                "Variable \"{variable}\": Length says {len} bytes, the hex holds {}",
                bytes.len()
            ));
        }
    }
    Ok(bytes)
}

/// A decimal number (the tree's keys, IDs and scalars).
pub(super) fn number(text: &str) -> core::result::Result<u64, String> {
    text.trim()
        .parse::<u64>()
        .map_err(|_| format!("\"{text}\" is not a decimal number"))
}
