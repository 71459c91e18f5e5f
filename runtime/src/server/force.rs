// SPDX-License-Identifier: MIT OR Apache-2.0
//! The force table, as a PLC keeps one: bytes of the image that the server holds at given
//! values every cycle, over what the devices deliver (inputs) or what the clients write
//! (outputs), until they are unforced or the server ends. It lives here, off the real-time
//! path; each change becomes a [`ForcePlan`] that the cycle thread takes whole.

use crate::cycle::ForcePlan;
use crate::image::Tables;
use procimg_control::{ForceReport, Refusal, Space};
use procimg_shm_layout::{NO_ADDRESS, SubmoduleEntry};
use std::collections::BTreeMap;

/// The most bytes forced at once.
pub const MAX_FORCED_BYTES: usize = 4096;

/// Forced values by (space, logical address): one entry per byte.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ForceTable {
    bytes: BTreeMap<(Space, u32), u8>,
}

/// The submodule holding `address` in `space`, with the address of its first byte and its
/// length there.
fn locate(tables: &Tables, space: Space, address: u32) -> Result<(usize, u32, u32), Refusal> {
    let range = |e: &SubmoduleEntry| match space {
        Space::Input => (e.input_address, e.input_length as u32),
        Space::Output => (e.output_address, e.output_length as u32),
    };
    tables
        .submodules
        .iter()
        .enumerate()
        .find_map(|(s, e)| {
            let (first, len) = range(e);
            (first != NO_ADDRESS && address >= first && address - first < len)
                .then_some((s, first, len))
        })
        .ok_or(Refusal::NoSuchAddress { space, address })
}

impl ForceTable {
    /// Whether nothing is forced.
    pub fn is_empty(&self) -> bool {
        self.bytes.is_empty()
    }

    /// Forces `data` at `address`; the bytes must lie in one submodule.
    pub fn force(
        &mut self,
        tables: &Tables,
        space: Space,
        address: u32,
        data: &[u8],
    ) -> Result<(), Refusal> {
        let (_, first, len) = locate(tables, space, address)?;
        let room = first + len - address;
        if data.is_empty() || data.len() as u64 > u64::from(room) {
            return Err(Refusal::PastSubmoduleEnd {
                space,
                address,
                length: data.len() as u32,
                room,
            });
        }
        let mut next = self.bytes.clone();
        for (a, &v) in (address..).zip(data) {
            next.insert((space, a), v);
        }
        if next.len() > MAX_FORCED_BYTES {
            return Err(Refusal::TooManyForces {
                max: MAX_FORCED_BYTES as u32,
            });
        }
        self.bytes = next;
        Ok(())
    }

    /// Unforces `length` bytes from `address` (to the end of its submodule when `None`).
    pub fn unforce(
        &mut self,
        tables: &Tables,
        space: Space,
        address: u32,
        length: Option<u32>,
    ) -> Result<(), Refusal> {
        let (_, first, len) = locate(tables, space, address)?;
        let room = first + len - address;
        let length = length.unwrap_or(room);
        if length == 0 || length > room {
            return Err(Refusal::PastSubmoduleEnd {
                space,
                address,
                length,
                room,
            });
        }
        for a in address..address + length {
            self.bytes.remove(&(space, a));
        }
        Ok(())
    }

    /// Unforces everything.
    pub fn clear(&mut self) {
        self.bytes.clear();
    }

    /// The runs of consecutive forced addresses inside one submodule: (space, submodule,
    /// first address, values).
    fn runs(&self, tables: &Tables) -> Vec<(Space, usize, u32, Vec<u8>)> {
        let mut runs: Vec<(Space, usize, u32, Vec<u8>)> = Vec::new();
        for (&(space, address), &v) in &self.bytes {
            let Ok((s, _, _)) = locate(tables, space, address) else {
                continue;
            };
            match runs.last_mut() {
                Some((sp, sm, first, values))
                    if *sp == space && *sm == s && *first + values.len() as u32 == address =>
                {
                    values.push(v)
                }
                _ => runs.push((space, s, address, vec![v])),
            }
        }
        runs
    }

    /// The plan the cycle thread applies.
    pub fn plan(&self, tables: &Tables) -> ForcePlan {
        let mut plan = ForcePlan::empty(tables.submodules.len());
        for (space, s, address, values) in self.runs(tables) {
            let e = &tables.submodules[s];
            let first = match space {
                Space::Input => e.input_address,
                Space::Output => e.output_address,
            };
            plan.push(space, s as u32, address - first, &values);
        }
        plan
    }

    /// What `procimg status` shows.
    pub fn reports(&self, tables: &Tables) -> Vec<ForceReport> {
        self.runs(tables)
            .into_iter()
            .map(|(space, s, address, data)| {
                let e = &tables.submodules[s];
                ForceReport {
                    space,
                    address,
                    data,
                    device: tables.device_name(e.device as usize).to_string(),
                    slot: e.slot,
                    subslot: e.subslot,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;

    fn demo() -> Tables {
        let config = Config::demo();
        Tables::from_config(&config).expect("the demo layout")
    }

    fn output_submodule(t: &Tables) -> (usize, u32, u32) {
        let (s, e) = t
            .submodules
            .iter()
            .enumerate()
            .find(|(_, e)| e.output_length >= 4)
            .expect("the demo has outputs");
        (s, e.output_address, e.output_length as u32)
    }

    #[test]
    fn forced_bytes_become_one_run_per_submodule() {
        let t = demo();
        let (s, q, _) = output_submodule(&t);
        let mut f = ForceTable::default();
        f.force(&t, Space::Output, q, &[1, 2]).unwrap();
        f.force(&t, Space::Output, q + 2, &[3]).unwrap();
        let plan = f.plan(&t);
        assert_eq!(plan.runs().len(), 1);
        let r = plan.runs()[0];
        assert_eq!((r.submodule as usize, r.offset, r.len), (s, 0, 3));
        assert!(plan.forces_outputs_of(s));
        let reports = f.reports(&t);
        assert_eq!(reports.len(), 1);
        assert_eq!(
            (reports[0].address, &reports[0].data[..]),
            (q, &[1, 2, 3][..])
        );
    }

    #[test]
    fn a_force_past_its_submodule_is_refused_and_changes_nothing() {
        let t = demo();
        let (_, q, len) = output_submodule(&t);
        let mut f = ForceTable::default();
        let err = f
            .force(&t, Space::Output, q + 1, &vec![0; len as usize])
            .unwrap_err();
        assert_eq!(
            err,
            Refusal::PastSubmoduleEnd {
                space: Space::Output,
                address: q + 1,
                length: len,
                room: len - 1
            }
        );
        assert!(f.is_empty());
        assert!(matches!(
            f.force(&t, Space::Output, 60000, &[1]),
            Err(Refusal::NoSuchAddress { .. })
        ));
    }

    #[test]
    fn unforce_takes_a_range_or_the_rest_of_the_submodule() {
        let t = demo();
        let (_, q, len) = output_submodule(&t);
        let mut f = ForceTable::default();
        f.force(&t, Space::Output, q, &vec![7; len as usize])
            .unwrap();
        f.unforce(&t, Space::Output, q + 1, Some(1)).unwrap();
        assert_eq!(f.reports(&t).len(), 2, "a hole splits the run");
        f.unforce(&t, Space::Output, q, None).unwrap();
        assert!(f.is_empty());
    }

    #[test]
    fn the_table_is_bounded() {
        let t = demo();
        let (_, q, _) = output_submodule(&t);
        let mut f = ForceTable::default();
        for i in 0..MAX_FORCED_BYTES as u32 {
            f.bytes.insert((Space::Input, 100_000 + i), 0);
        }
        assert_eq!(
            f.force(&t, Space::Output, q, &[1]),
            Err(Refusal::TooManyForces {
                max: MAX_FORCED_BYTES as u32
            })
        );
    }
}
