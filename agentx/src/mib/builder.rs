// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the group builders fill: the instances with their values, and the object types
//! (scalars and table columns) the MIB serves whether or not an instance exists, which tell
//! noSuchInstance from noSuchObject.

use crate::pdu::{Oid, Value, VarBind};

/// The instances and object types of a MIB view under construction.
#[derive(Default)]
pub(crate) struct Builder {
    pub(crate) instances: Vec<VarBind>,
    pub(crate) objects: Vec<Oid>,
}

impl Builder {
    /// A scalar object: the object type `object` and its one instance `object.0`.
    pub(crate) fn scalar(&mut self, object: Oid, value: Value) {
        self.instances.push(VarBind::new(object.child(&[0]), value));
        self.objects.push(object);
    }

    /// The columns of a table: object types, each with or without rows.
    pub(crate) fn columns(&mut self, entry: &Oid, columns: impl IntoIterator<Item = u32>) {
        self.objects
            .extend(columns.into_iter().map(|column| entry.child(&[column])));
    }

    /// One cell of a table: `entry.column.index`.
    pub(crate) fn cell(&mut self, entry: &Oid, column: u32, index: &[u32], value: Value) {
        let name = entry.child(&[column]).child(index);
        self.instances.push(VarBind::new(name, value));
    }
}

/// An OCTET STRING of bytes.
pub(crate) fn octets(bytes: &[u8]) -> Value {
    Value::OctetString(bytes.to_vec())
}

/// An INTEGER of an unsigned value, clamped to INTEGER's range.
pub(crate) fn integer(v: u32) -> Value {
    Value::Integer(i32::try_from(v).unwrap_or(i32::MAX))
}
