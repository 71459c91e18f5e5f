// SPDX-License-Identifier: MIT OR Apache-2.0
//! A frame whose data are already in place, completed around them, against the frame
//! written whole: the same bytes.

use super::ProducedData;
use crate::cyclic::{CrMap, CrTiming, CyclicAr, DataMap, IocsMap, PRODUCED_C_SDU_OFFSET};
use crate::wire::MacAddress;
use proptest::prelude::*;

/// A producer's table: per submodule its data, IOPS and IOCS.
struct Table {
    data: Vec<Vec<u8>>,
    seed: u8,
}

impl ProducedData for Table {
    fn data(&self, submodule: usize) -> &[u8] {
        self.data.get(submodule).map_or(&[], Vec::as_slice)
    }
    fn iops(&self, submodule: usize) -> u8 {
        0x80 | submodule as u8 ^ self.seed
    }
    fn iocs(&self, submodule: usize) -> u8 {
        0x60 | submodule as u8 ^ self.seed
    }
}

fn exchange(output: CrMap) -> CyclicAr {
    let timing = CrTiming {
        send_clock_factor: 32,
        reduction_ratio: 1,
        every_cycles: 1,
        data_hold_factor: 3,
    };
    let input = CrMap {
        frame_id: 0x8000,
        data_length: 40,
        objects: vec![],
        iocs: vec![],
    };
    let peers = (
        MacAddress([2, 0, 0, 0, 0, 1]),
        MacAddress([2, 0, 0, 0, 0, 2]),
    );
    CyclicAr::from_maps(0, 1, peers, input, output, timing, 0..8)
}

/// Objects of the given (data length, gap before) one after another, each with its IOPS
/// behind it, then `iocs` consumer statuses.
fn in_frame_order(objects: &[(usize, usize)], iocs: usize) -> CrMap {
    let mut at = 0;
    let mut placed = Vec::new();
    for (s, &(len, gap)) in objects.iter().enumerate() {
        at += gap;
        placed.push(DataMap {
            submodule: s,
            data: at,
            len,
            iops: at + len,
        });
        at += len + 1;
    }
    CrMap {
        frame_id: 0x8001,
        data_length: (at + iocs).max(40),
        objects: placed,
        iocs: (0..iocs)
            .map(|k| IocsMap {
                submodule: k,
                offset: at + k,
            })
            .collect(),
    }
}

proptest! {
    /// Data put in place first (as the image holds them), the rest written around them: the
    /// frame `fill` and `seal` write whole, round after round.
    #[test]
    fn a_frame_completed_around_its_data_is_the_frame_written_whole(
        objects in proptest::collection::vec((0usize..6, 0usize..3), 0..10),
        iocs in 0usize..4,
        rounds in 1u8..3,
    ) {
        let map = in_frame_order(&objects, iocs);
        let (mut whole, mut around) = (exchange(map.clone()), exchange(map.clone()));
        prop_assert!(around.data_in_frame_order());
        let mut image = vec![0xee; around.frame.len()];
        for seed in 0..rounds {
            let from = Table {
                data: objects
                    .iter()
                    .enumerate()
                    .map(|(s, &(n, _))| vec![seed ^ s as u8; n])
                    .collect(),
                seed,
            };
            whole.fill(&from);
            let expected = whole.seal(u16::from(seed) * 32, 0x35).to_vec();
            for o in &map.objects {
                image[PRODUCED_C_SDU_OFFSET + o.data..][..o.len].copy_from_slice(&from.data[o.submodule]);
            }
            around.fill_status(&from);
            around.seal(u16::from(seed) * 32, 0x35);
            prop_assert!(around.write_around_data(&mut image));
            prop_assert_eq!(&image, &expected);
        }
    }
}

#[test]
fn data_out_of_frame_order_or_over_another_are_seen() {
    let mut map = in_frame_order(&[(4, 0), (2, 0), (0, 0)], 1);
    assert!(exchange(map.clone()).data_in_frame_order());
    map.objects.swap(0, 1);
    assert!(!exchange(map.clone()).data_in_frame_order(), "out of order");
    map.objects.swap(0, 1);
    map.objects[1].data = 3;
    assert!(!exchange(map.clone()).data_in_frame_order(), "overlapping");
    map.objects[1].data = 39;
    assert!(!exchange(map).data_in_frame_order(), "past the C_SDU");
}

#[test]
fn a_buffer_of_another_length_is_not_written() {
    let ar = exchange(in_frame_order(&[(4, 0)], 0));
    let mut short = vec![7; ar.frame.len() - 1];
    assert!(!ar.write_around_data(&mut short));
    assert!(short.iter().all(|&b| b == 7));
}
