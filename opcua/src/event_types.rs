// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimg's event types: subtypes of BaseEventType whose fields carry what a notification
//! says (a device's name and failure reason, an alarm's type, place, text and data, an AR's
//! state and PLC, the PLC's RUN/STOP), so that a client selects and filters on them instead
//! of reading the message. They live in namespace [`TYPES_NAMESPACE`], as ObjectType nodes
//! with their properties, known to the server's type tree (which event filters are checked
//! against).

use opcua::nodes::DefaultTypeTree;
use opcua::server::address_space::{AddressSpace, ObjectTypeBuilder, VariableBuilder};
use opcua::types::{
    DataTypeId, NodeClass, NodeId, ObjectId, ObjectTypeId, QualifiedName, VariableTypeId,
};

/// The namespace URI of procimg's event types.
pub const TYPES_NAMESPACE: &str = "urn:procimg:types";

pub use defs::{AlarmEvent, ArEvent, DeviceEvent, PlcStateEvent};

// The derive writes constructors (`new_event`, `event_type_id`, …) without documentation.
#[allow(missing_docs)]
mod defs {
    use opcua::Event;
    use opcua::nodes::BaseEventType;
    use opcua::types::{ByteString, UAString};

    /// A device (controller role) failed or returned to data exchange.
    #[derive(Event)]
    #[opcua(identifier = "s=DeviceEventType", namespace = "urn:procimg:types")]
    pub struct DeviceEvent {
        /// The base event.
        pub base: BaseEventType,
        /// The types' namespace index.
        pub own_namespace_index: u16,
        /// The device's NameOfStation.
        pub device: UAString,
        /// In data exchange now (its return) or not (its failure).
        pub in_data_exchange: bool,
        /// Why it failed (empty on its return).
        pub reason: UAString,
    }

    /// An alarm of a device (controller role).
    #[derive(Event)]
    #[opcua(identifier = "s=AlarmEventType", namespace = "urn:procimg:types")]
    pub struct AlarmEvent {
        /// The base event.
        pub base: BaseEventType,
        /// The types' namespace index.
        pub own_namespace_index: u16,
        /// The device's NameOfStation.
        pub device: UAString,
        /// The AlarmType (0x0001 diagnosis, 0x0002 process, 0x0003 pull, …).
        pub alarm_type: u16,
        /// Its slot.
        pub slot: u16,
        /// Its subslot.
        pub subslot: u16,
        /// Sent as a high-priority alarm.
        pub high_priority: bool,
        /// What it means, in words.
        pub text: UAString,
        /// Its AlarmItem's data.
        pub data: ByteString,
    }

    /// The life of a PLC's AR with the station (device role).
    #[derive(Event)]
    #[opcua(identifier = "s=ArEventType", namespace = "urn:procimg:types")]
    pub struct ArEvent {
        /// The base event.
        pub base: BaseEventType,
        /// The types' namespace index.
        pub own_namespace_index: u16,
        /// The station's NameOfStation.
        pub station: UAString,
        /// The PLC's NameOfStation (empty when it gave none).
        pub plc: UAString,
        /// The PLC's MAC address.
        pub plc_mac: UAString,
        /// The AR's state (`connected` … `data`), `ended` when it ended.
        pub ar_state: UAString,
        /// Why it ended (empty while it lives).
        pub reason: UAString,
        /// It was aborted, not released by the PLC.
        pub aborted: bool,
    }

    /// The PLC's RUN or STOP (device role).
    #[derive(Event)]
    #[opcua(identifier = "s=PlcStateEventType", namespace = "urn:procimg:types")]
    pub struct PlcStateEvent {
        /// The base event.
        pub base: BaseEventType,
        /// The types' namespace index.
        pub own_namespace_index: u16,
        /// The station's NameOfStation.
        pub station: UAString,
        /// The PLC is in RUN.
        pub running: bool,
        /// The PLC reports a station problem.
        pub station_problem: bool,
    }
}

/// Each type: its name and its fields' names and DataTypes.
const TYPES: [(&str, &[(&str, DataTypeId)]); 4] = [
    (
        "DeviceEventType",
        &[
            ("Device", DataTypeId::String),
            ("InDataExchange", DataTypeId::Boolean),
            ("Reason", DataTypeId::String),
        ],
    ),
    (
        "AlarmEventType",
        &[
            ("Device", DataTypeId::String),
            ("AlarmType", DataTypeId::UInt16),
            ("Slot", DataTypeId::UInt16),
            ("Subslot", DataTypeId::UInt16),
            ("HighPriority", DataTypeId::Boolean),
            ("Text", DataTypeId::String),
            ("Data", DataTypeId::ByteString),
        ],
    ),
    (
        "ArEventType",
        &[
            ("Station", DataTypeId::String),
            ("Plc", DataTypeId::String),
            ("PlcMac", DataTypeId::String),
            ("ArState", DataTypeId::String),
            ("Reason", DataTypeId::String),
            ("Aborted", DataTypeId::Boolean),
        ],
    ),
    (
        "PlcStateEventType",
        &[
            ("Station", DataTypeId::String),
            ("Running", DataTypeId::Boolean),
            ("StationProblem", DataTypeId::Boolean),
        ],
    ),
];

/// Adds the types, with their properties, to `space` (namespace `ns`) and to `type_tree`.
pub fn add(space: &mut AddressSpace, type_tree: &mut DefaultTypeTree, ns: u16) {
    let base: NodeId = ObjectTypeId::BaseEventType.into();
    for (name, fields) in TYPES {
        let id = NodeId::new(ns, name);
        ObjectTypeBuilder::new(&id, QualifiedName::new(ns, name), name)
            .is_abstract(false)
            .subtype_of(base.clone())
            .insert(space);
        type_tree.add_type_node(&id, &base, NodeClass::ObjectType);
        for (field, data_type) in fields {
            let field_id = NodeId::new(ns, format!("{name}/{field}"));
            let browse = QualifiedName::new(ns, *field);
            VariableBuilder::new(&field_id, browse.clone(), *field)
                .data_type(*data_type)
                .property_of(id.clone())
                .has_type_definition(VariableTypeId::PropertyType)
                .has_modelling_rule(ObjectId::ModellingRule_Mandatory)
                .insert(space);
            type_tree.add_type_property(&field_id, &id, &[&browse], NodeClass::Variable);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use opcua::nodes::{Event, NamespaceMap};
    use opcua::types::{AttributeId, ByteString, NumericRange, Variant};

    #[test]
    fn an_alarm_s_fields_are_read_by_their_names() {
        let mut namespaces = NamespaceMap::new();
        let ns = namespaces.add_namespace(TYPES_NAMESPACE);
        let mut alarm = AlarmEvent::new_event_now(
            AlarmEvent::event_type_id(&namespaces),
            ByteString::from(vec![1; 16]),
            "an alarm",
            &namespaces,
        );
        alarm.alarm_type = 1;
        alarm.slot = 2;
        alarm.data = ByteString::from(vec![0xAB]);
        let ty = NodeId::new(ns, "AlarmEventType");
        let get = |field: &str| {
            alarm.get_field(
                &ty,
                AttributeId::Value,
                &NumericRange::None,
                &[QualifiedName::new(ns, field)],
            )
        };
        assert_eq!(get("AlarmType"), Variant::from(1u16));
        assert_eq!(get("Slot"), Variant::from(2u16));
        assert_eq!(get("Data"), Variant::from(ByteString::from(vec![0xAB])));
        // The base type's fields keep their names in namespace 0.
        let message = alarm.get_field(
            &ty,
            AttributeId::Value,
            &NumericRange::None,
            &[QualifiedName::new(0, "Message")],
        );
        assert_eq!(
            message,
            Variant::from(opcua::types::LocalizedText::from("an alarm"))
        );
        // Every field the type declares is one the event has.
        for (name, fields) in TYPES {
            if name == "AlarmEventType" {
                for (field, _) in fields {
                    assert_ne!(get(field), Variant::Empty, "{field}");
                }
            }
        }
    }
}
