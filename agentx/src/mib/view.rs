// SPDX-License-Identifier: MIT OR Apache-2.0
//! A snapshot's MIB as one sorted list of instances, and the three ways AgentX reads it
//! (RFC 2741 §7.2.3): Get, GetNext and GetBulk.

use super::builder::Builder;
use super::{Snapshot, lldp, pno, system};
use crate::pdu::{GetBulk, Oid, SearchRange, Value, VarBind};

/// The instances of the system group, the LLDP-MIB and the LLDP-EXT-PNO-MIB that one
/// [`Snapshot`] holds, in OID order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MibView {
    /// Every instance, sorted by name, each name once.
    instances: Vec<VarBind>,
    /// The object types served (scalars and columns), sorted.
    objects: Vec<Oid>,
}

impl MibView {
    /// The view of a snapshot. Two rows with the same index (two ports with one number)
    /// cannot both be served: the first one given stays.
    pub fn new(snapshot: &Snapshot) -> MibView {
        let mut b = Builder::default();
        system::build(snapshot, &mut b);
        lldp::build(snapshot, &mut b);
        pno::build(snapshot, &mut b);
        let Builder {
            mut instances,
            mut objects,
        } = b;
        // A stable sort keeps the first of equal names first, and dedup keeps it.
        instances.sort_by(|a, b| a.name.cmp(&b.name));
        instances.dedup_by(|later, earlier| later.name == earlier.name);
        objects.sort();
        objects.dedup();
        MibView { instances, objects }
    }

    /// Every instance in OID order: what a walk of the whole view returns.
    pub fn instances(&self) -> &[VarBind] {
        &self.instances
    }

    /// Get (RFC 2741 §7.2.3.1): the value of the instance `oid`, noSuchInstance when its
    /// object type is served but that instance does not exist, noSuchObject otherwise.
    pub fn get(&self, oid: &Oid) -> Value {
        match self.instances.binary_search_by(|v| v.name.cmp(oid)) {
            Ok(at) => self
                .instances
                .get(at)
                .map_or(Value::NoSuchObject, |v| v.value.clone()),
            Err(_) if self.objects.iter().any(|o| oid.starts_with(o.as_slice())) => {
                Value::NoSuchInstance
            }
            Err(_) => Value::NoSuchObject,
        }
    }

    /// GetNext (RFC 2741 §7.2.3.2): the first instance in the range (from its start, which
    /// itself counts when `include` is set, to before its end), or endOfMibView named by
    /// the range's start.
    pub fn get_next(&self, range: &SearchRange) -> VarBind {
        let at = if range.include {
            self.instances.partition_point(|v| v.name < range.start)
        } else {
            self.instances.partition_point(|v| v.name <= range.start)
        };
        match self.instances.get(at) {
            Some(v) if range.end.is_null() || v.name < range.end => v.clone(),
            _ => VarBind::new(range.start.clone(), Value::EndOfMibView),
        }
    }

    /// GetBulk (RFC 2741 §7.2.3.3): the first `non_repeaters` ranges once, as GetNext;
    /// then up to `max_repetitions` rounds over the others, each round going on from the
    /// previous round's names (excluding them) within the same ends. Stops after a round
    /// in which every repeater reached endOfMibView, which ends a walk as well.
    pub fn get_bulk(&self, bulk: &GetBulk) -> Vec<VarBind> {
        let split = usize::from(bulk.non_repeaters).min(bulk.ranges.len());
        let (non_repeaters, repeaters) = bulk.ranges.split_at(split);
        let mut out: Vec<VarBind> = non_repeaters.iter().map(|r| self.get_next(r)).collect();
        let mut ranges = repeaters.to_vec();
        for _ in 0..bulk.max_repetitions {
            if ranges.is_empty() {
                break;
            }
            let round: Vec<VarBind> = ranges.iter().map(|r| self.get_next(r)).collect();
            let all_ended = round.iter().all(|v| v.value == Value::EndOfMibView);
            for (range, found) in ranges.iter_mut().zip(&round) {
                range.start = found.name.clone();
                range.include = false;
            }
            out.extend(round);
            if all_ended {
                break;
            }
        }
        out
    }
}
