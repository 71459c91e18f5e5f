// SPDX-License-Identifier: MIT OR Apache-2.0
//! VarBinds (RFC 2741 §5.4): a value with its name.
//!
//! ```text
//! v.type (2)  reserved (2)  v.name (OID)  v.data (by type)
//! ```
//!
//! Integer, Counter32, Gauge32 and TimeTicks are 4 bytes; Counter64 8; OctetString,
//! IpAddress (4 octets) and Opaque an octet string; ObjectIdentifier an OID; Null,
//! noSuchObject, noSuchInstance and endOfMibView nothing. A VarBindList is VarBinds up to
//! the end of the payload.

use super::codec::{Reader, Writer, octets_len};
use super::{EmitError, Oid, ParseError};

/// An SNMP value as AgentX carries it.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Value {
    /// INTEGER / Integer32 (type 2).
    Integer(i32),
    /// OCTET STRING (type 4).
    OctetString(Vec<u8>),
    /// NULL (type 5).
    Null,
    /// OBJECT IDENTIFIER (type 6).
    ObjectIdentifier(Oid),
    /// IpAddress (type 64).
    IpAddress([u8; 4]),
    /// Counter32 (type 65).
    Counter32(u32),
    /// Gauge32 / Unsigned32 (type 66).
    Gauge32(u32),
    /// TimeTicks, hundredths of a second (type 67).
    TimeTicks(u32),
    /// Opaque (type 68).
    Opaque(Vec<u8>),
    /// Counter64 (type 70).
    Counter64(u64),
    /// noSuchObject (type 128): no such object type here.
    NoSuchObject,
    /// noSuchInstance (type 129): the object type exists, the instance does not.
    NoSuchInstance,
    /// endOfMibView (type 130): nothing further in the search range.
    EndOfMibView,
}

impl Value {
    /// v.type.
    pub const fn type_code(&self) -> u16 {
        match self {
            Value::Integer(_) => 2,
            Value::OctetString(_) => 4,
            Value::Null => 5,
            Value::ObjectIdentifier(_) => 6,
            Value::IpAddress(_) => 64,
            Value::Counter32(_) => 65,
            Value::Gauge32(_) => 66,
            Value::TimeTicks(_) => 67,
            Value::Opaque(_) => 68,
            Value::Counter64(_) => 70,
            Value::NoSuchObject => 128,
            Value::NoSuchInstance => 129,
            Value::EndOfMibView => 130,
        }
    }

    /// Whether this is one of the exceptions (noSuchObject, noSuchInstance,
    /// endOfMibView) rather than a value.
    pub const fn is_exception(&self) -> bool {
        matches!(
            self,
            Value::NoSuchObject | Value::NoSuchInstance | Value::EndOfMibView
        )
    }

    /// An OCTET STRING of a text's UTF-8 bytes.
    pub fn string(text: &str) -> Value {
        Value::OctetString(text.as_bytes().to_vec())
    }

    fn data_len(&self) -> usize {
        match self {
            Value::Integer(_) | Value::Counter32(_) | Value::Gauge32(_) | Value::TimeTicks(_) => 4,
            Value::Counter64(_) => 8,
            Value::OctetString(o) | Value::Opaque(o) => octets_len(o.len()),
            Value::IpAddress(_) => octets_len(4),
            Value::ObjectIdentifier(oid) => oid.wire_len(),
            Value::Null | Value::NoSuchObject | Value::NoSuchInstance | Value::EndOfMibView => 0,
        }
    }

    fn read(type_code: u16, r: &mut Reader<'_>) -> Result<Value, ParseError> {
        const FIELD: &str = "VarBind data";
        Ok(match type_code {
            2 => Value::Integer(r.u32(FIELD)?.cast_signed()),
            4 => Value::OctetString(r.octets(FIELD)?.to_vec()),
            5 => Value::Null,
            6 => Value::ObjectIdentifier(Oid::read(r)?.0),
            64 => {
                let octets = r.octets(FIELD)?;
                let len = octets.len();
                Value::IpAddress(octets.try_into().map_err(|_| {
                    ParseError::IpAddressLength(u32::try_from(len).unwrap_or(u32::MAX))
                })?)
            }
            65 => Value::Counter32(r.u32(FIELD)?),
            66 => Value::Gauge32(r.u32(FIELD)?),
            67 => Value::TimeTicks(r.u32(FIELD)?),
            68 => Value::Opaque(r.octets(FIELD)?.to_vec()),
            70 => Value::Counter64(r.u64(FIELD)?),
            128 => Value::NoSuchObject,
            129 => Value::NoSuchInstance,
            130 => Value::EndOfMibView,
            other => return Err(ParseError::ValueType(other)),
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<(), EmitError> {
        match self {
            Value::Integer(v) => w.u32(v.cast_unsigned()),
            Value::Counter32(v) | Value::Gauge32(v) | Value::TimeTicks(v) => w.u32(*v),
            Value::Counter64(v) => w.u64(*v),
            Value::OctetString(o) | Value::Opaque(o) => w.octets(o),
            Value::IpAddress(a) => w.octets(a),
            Value::ObjectIdentifier(oid) => oid.write(false, w),
            Value::Null | Value::NoSuchObject | Value::NoSuchInstance | Value::EndOfMibView => {
                Ok(())
            }
        }
    }
}

/// A value and the name of the object instance it belongs to.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct VarBind {
    /// v.name.
    pub name: Oid,
    /// v.type and v.data.
    pub value: Value,
}

impl VarBind {
    /// A VarBind of a name and a value.
    pub fn new(name: impl Into<Oid>, value: Value) -> VarBind {
        VarBind {
            name: name.into(),
            value,
        }
    }

    pub(crate) fn wire_len(&self) -> usize {
        4 + self.name.wire_len() + self.value.data_len()
    }

    pub(crate) fn read(r: &mut Reader<'_>) -> Result<VarBind, ParseError> {
        let type_code = r.u16("VarBind type")?;
        r.u16("VarBind type")?;
        let (name, _include) = Oid::read(r)?;
        let value = Value::read(type_code, r)?;
        Ok(VarBind { name, value })
    }

    pub(crate) fn write(&self, w: &mut Writer<'_>) -> Result<(), EmitError> {
        w.u16(self.value.type_code())?;
        w.u16(0)?;
        self.name.write(false, w)?;
        self.value.write(w)
    }

    /// Reads VarBinds up to the end of the reader.
    pub(crate) fn read_list(r: &mut Reader<'_>) -> Result<Vec<VarBind>, ParseError> {
        let mut list = Vec::new();
        while !r.is_empty() {
            list.push(VarBind::read(r)?);
        }
        Ok(list)
    }

    pub(crate) fn list_len(list: &[VarBind]) -> usize {
        list.iter().map(VarBind::wire_len).sum()
    }

    pub(crate) fn write_list(list: &[VarBind], w: &mut Writer<'_>) -> Result<(), EmitError> {
        list.iter().try_for_each(|v| v.write(w))
    }
}
