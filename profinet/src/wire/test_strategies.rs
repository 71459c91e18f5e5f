// SPDX-License-Identifier: MIT OR Apache-2.0
//! Property-test strategies for the values several wire formats carry.

use crate::wire::diagnosis::{
    AlarmItem, ChannelDiagnosis, ChannelProperties, Diagnosis, DiagnosisFormat,
};
use proptest::prelude::*;
use std::ops::Range;

/// A channel diagnosis entry of `format`: the extended fields only where the format has them.
fn channel_diagnosis(format: DiagnosisFormat) -> impl Strategy<Value = ChannelDiagnosis> {
    any::<(u16, u16, u16, u16, u32, u32)>().prop_map(move |(ch, props, err, ext, add, q)| {
        let mut e = ChannelDiagnosis::new(ch, ChannelProperties(props), err);
        if format != DiagnosisFormat::Channel {
            e.ext_channel_error_type = ext;
            e.ext_channel_add_value = add;
        }
        if format == DiagnosisFormat::Qualified {
            e.qualifier = q;
        }
        e
    })
}

/// An alarm item (AlarmNotification, DiagnosisData): a diagnosis with `entries` channel
/// entries of one format, or a vendor item of up to 39 bytes.
pub(crate) fn alarm_item(entries: Range<usize>) -> impl Strategy<Value = AlarmItem> {
    let format = prop_oneof![
        Just(DiagnosisFormat::Channel),
        Just(DiagnosisFormat::Extended),
        Just(DiagnosisFormat::Qualified),
    ];
    prop_oneof![
        format.prop_flat_map(move |format| {
            proptest::collection::vec(channel_diagnosis(format), entries.clone())
                .prop_map(move |entries| AlarmItem::Diagnosis(Diagnosis { format, entries }))
        }),
        (0u16..0x8000, proptest::collection::vec(any::<u8>(), 0..40))
            .prop_map(|(usi, data)| AlarmItem::Other { usi, data }),
    ]
}
