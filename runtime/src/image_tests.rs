// SPDX-License-Identifier: MIT OR Apache-2.0
//! The image built in place: whatever set of submodules gets new inputs (or outputs) in a
//! cycle, the image that results holds those and the last ones of all others, in every
//! combination of own payload and samples.

use super::*;

/// The demo's tables: submodules of several lengths, some without inputs.
fn tables() -> Tables {
    Tables::from_config(&Config::demo()).expect("the demo layout")
}

/// A sample as a loan hands it out: garbage everywhere.
fn sample(image: &Image) -> Vec<u8> {
    vec![0xEE; image.payload_len()]
}

fn bind(image: &mut Image, sample: Option<&mut Vec<u8>>) {
    #[allow(unsafe_code)]
    // SAFETY: each sample outlives the image's use of it in the test, is not resized, and is
    // only read through the image while bound.
    unsafe {
        image.bind_inputs(sample.map(|s| NonNull::new(s.as_mut_ptr()).unwrap()))
    };
}

#[test]
fn every_subset_of_fresh_submodules_carries_the_others_over() {
    let tables = tables();
    let with_inputs: Vec<usize> = (0..tables.submodules.len())
        .filter(|&s| tables.submodules[s].input_length > 0)
        .take(6)
        .collect();
    let value = |s: usize, round: u8| vec![round.wrapping_mul(31) ^ s as u8; len(&tables, s)];
    for subset in 0u32..1 << with_inputs.len() {
        let mut image = Image::new(&tables);
        let (mut a, mut b, mut c) = (sample(&image), sample(&image), sample(&image));
        let mut expected: Vec<Vec<u8>> = (0..tables.submodules.len())
            .map(|s| vec![0; len(&tables, s)])
            .collect();
        // Round 1 into sample a (all of them arrive), round 2 into b (the subset), round 3
        // into the own payload (nothing arrives), round 4 into a again, as it was published
        // in round 1 (the complement arrives), round 5 into a new sample c (nothing).
        for round in 1..=5u8 {
            let arriving: Vec<usize> = with_inputs
                .iter()
                .enumerate()
                .filter(|&(i, _)| match round {
                    1 => true,
                    2 => subset & (1 << i) != 0,
                    3 | 5 => false,
                    _ => subset & (1 << i) == 0,
                })
                .map(|(_, &s)| s)
                .collect();
            match round {
                1 | 4 => bind(&mut image, Some(&mut a)),
                2 => bind(&mut image, Some(&mut b)),
                5 => bind(&mut image, Some(&mut c)),
                _ => bind(&mut image, None),
            }
            for &s in &arriving {
                assert!(image.set_inputs(s, &value(s, round)));
                expected[s] = value(s, round);
            }
            image.carry_over_inputs();
            image.publish_into();
            for (s, want) in expected.iter().enumerate() {
                assert_eq!(
                    image.inputs(s),
                    &want[..],
                    "subset {subset:b}, round {round}"
                );
            }
            if round != 3 {
                let published = match round {
                    2 => &b,
                    5 => &c,
                    _ => &a,
                };
                assert!(
                    !published.contains(&0xEE),
                    "subset {subset:b}, round {round}"
                );
            }
        }
    }
}

#[test]
fn inputs_of_another_length_are_refused_and_not_fresh() {
    let tables = tables();
    let (s, mut image, mut a) = bound_to_a_sample(&tables, 1);
    bind(&mut image, Some(&mut a));
    assert!(!image.set_inputs(s, &[1]));
    image.carry_over_inputs();
    assert!(image.inputs(s).iter().all(|&b| b == 0));
}

#[test]
fn writing_inputs_after_publishing_leaves_the_published_sample_alone() {
    let tables = tables();
    let (s, mut image, mut a) = bound_to_a_sample(&tables, 0);
    bind(&mut image, Some(&mut a));
    assert!(image.set_inputs(s, &vec![7; len(&tables, s)]));
    image.carry_over_inputs();
    image.publish_into();
    assert!(image.set_inputs(s, &vec![9; len(&tables, s)]));
    assert_eq!(image.inputs(s), &vec![9; len(&tables, s)][..]);
    let at = tables.submodules[s].input_offset as usize;
    assert_eq!(a[at], 7);
}

/// The first submodule with more than `longer_than` bytes of inputs, a new image and a sample.
fn bound_to_a_sample(tables: &Tables, longer_than: u16) -> (usize, Image, Vec<u8>) {
    let s = (0..tables.submodules.len())
        .find(|&s| tables.submodules[s].input_length > longer_than)
        .unwrap();
    let image = Image::new(tables);
    let a = sample(&image);
    (s, image, a)
}

fn len(tables: &Tables, s: usize) -> usize {
    tables.submodules[s].input_length as usize
}

/// A partial write into outputs just moved to a new sample keeps the rest as last sent, and
/// a whole write does not need them; reads before the carry-over see the last outputs.
#[test]
fn outputs_moved_to_a_new_sample_keep_what_was_not_written() {
    let tables = tables();
    let partial = (0..tables.submodules.len())
        .find(|&s| tables.submodules[s].output_length > 1)
        .unwrap();
    let untouched = (0..tables.submodules.len())
        .find(|&s| s != partial && tables.submodules[s].output_length > 0)
        .unwrap();
    let olen = |s: usize| tables.submodules[s].output_length as usize;
    let first = |s: usize| vec![s as u8 + 1; olen(s)];
    let mut image = Image::new(&tables);
    assert!(image.set_outputs(partial, &first(partial)));
    assert!(image.set_outputs(untouched, &first(untouched)));
    let (mut a, mut b) = (sample(&image), sample(&image));
    let bind = |image: &mut Image, to: &mut Vec<u8>| {
        #[allow(unsafe_code)]
        // SAFETY: the sample outlives the image's use of it and is not resized.
        unsafe {
            image.bind_outputs(Some(NonNull::new(to.as_mut_ptr()).unwrap()))
        };
    };
    bind(&mut image, &mut a);
    assert_eq!(image.outputs(untouched), &first(untouched)[..]);
    image.outputs_mut(partial)[0] = 0x55;
    image.carry_over_outputs();
    let mut want = first(partial);
    want[0] = 0x55;
    assert_eq!(image.outputs(partial), &want[..]);
    assert_eq!(image.outputs(untouched), &first(untouched)[..]);
    let at = tables.submodules[untouched].output_mirror_offset as usize;
    assert_eq!(a[at], untouched as u8 + 1, "carried into the sample");

    bind(&mut image, &mut b);
    assert!(image.set_outputs(partial, &vec![0x66; olen(partial)]));
    image.carry_over_outputs();
    assert_eq!(image.outputs(partial), &vec![0x66; olen(partial)][..]);
    assert_eq!(image.outputs(untouched), &first(untouched)[..]);
    assert_eq!(b[at], untouched as u8 + 1, "carried into the next sample");
}

/// One step of the cycle as the engine takes it, for [`images_follow_their_model_through_any_cycles`].
#[derive(Clone, Debug)]
enum Step {
    /// New inputs of a submodule (a frame arrived): all of them, or the first byte.
    Inputs { s: usize, value: u8, whole: bool },
    /// A client's outputs of a submodule: all of them, or the first byte.
    Outputs { s: usize, value: u8, whole: bool },
    /// The cycle starts: the inputs join the sample the outputs are in, or, if there is
    /// none, a new loan (`Some(k)`: sample k, `None`: the loan fails).
    Begin { loan: Option<usize> },
    /// The image is completed and published (or not: `sent` false), then the next sample is
    /// loaned for the outputs (`None`: the loan fails); `late` writes inputs in between.
    Finish {
        sent: bool,
        next: Option<usize>,
        late: Option<(usize, u8)>,
    },
}

/// Samples of the publisher in the model test: fewer than the steps, so each comes back.
const POOL: usize = 4;

fn step() -> impl proptest::strategy::Strategy<Value = Step> {
    use proptest::prelude::*;
    let sample = proptest::option::weighted(0.9, 0..POOL);
    prop_oneof![
        3 => (0..16usize, any::<u8>(), any::<bool>())
            .prop_map(|(s, value, whole)| Step::Inputs { s, value, whole }),
        3 => (0..16usize, any::<u8>(), any::<bool>())
            .prop_map(|(s, value, whole)| Step::Outputs { s, value, whole }),
        2 => sample.clone().prop_map(|loan| Step::Begin { loan }),
        2 => (
            proptest::bool::weighted(0.9),
            sample,
            proptest::option::weighted(0.1, (0..16usize, any::<u8>())),
        )
            .prop_map(|(sent, next, late)| Step::Finish { sent, next, late }),
    ]
}

proptest::proptest! {
    /// Whatever the cycles do (submodules written or not, in any order, samples loaned
    /// in any order and coming back as they were published, loans and publications that
    /// fail), the image reads as its model and every sample is published holding exactly
    /// the model: carried over where needed, with no byte of an older image or of garbage.
    #[test]
    fn images_follow_their_model_through_any_cycles(
        steps in proptest::collection::vec(step(), 1..120),
    ) {
        let tables = tables();
        let n = tables.submodules.len();
        let ilen = |s: usize| tables.submodules[s].input_length as usize;
        let olen = |s: usize| tables.submodules[s].output_length as usize;
        let mut image = Image::new(&tables);
        let mut pool: Vec<Vec<u8>> = (0..POOL).map(|_| sample(&image)).collect();
        let ptr = |pool: &mut Vec<Vec<u8>>, k: usize| NonNull::new(pool[k].as_mut_ptr());
        let mut inputs: Vec<Vec<u8>> = (0..n).map(|s| vec![0; ilen(s)]).collect();
        let mut outputs: Vec<Vec<u8>> = (0..n).map(|s| vec![0; olen(s)]).collect();
        // The sample the outputs are bound to (loaned for the next image), the one the
        // image is built in, and the newest published (the history holds it: no loan).
        let (mut next, mut current, mut newest): (Option<usize>, Option<usize>, Option<usize>) =
            (None, None, None);
        let free = |k: Option<usize>, newest: Option<usize>| k.filter(|&k| Some(k) != newest);
        for step in steps {
            match step {
                Step::Inputs { s, value, whole } => {
                    let s = s % n;
                    if ilen(s) == 0 {
                        continue;
                    }
                    if whole {
                        proptest::prop_assert!(image.set_inputs(s, &vec![value; ilen(s)]));
                        inputs[s].fill(value);
                    } else {
                        image.inputs_mut(s)[0] = value;
                        inputs[s][0] = value;
                    }
                }
                Step::Outputs { s, value, whole } => {
                    let s = s % n;
                    if olen(s) == 0 {
                        continue;
                    }
                    if whole {
                        proptest::prop_assert!(image.set_outputs(s, &vec![value; olen(s)]));
                        outputs[s].fill(value);
                    } else {
                        image.outputs_mut(s)[0] = value;
                        outputs[s][0] = value;
                    }
                }
                Step::Begin { loan } => {
                    if current.is_some() {
                        continue;
                    }
                    let sample = match next.take() {
                        Some(k) => Some(k),
                        None => {
                            let k = free(loan, newest);
                            let p = k.and_then(|k| ptr(&mut pool, k));
                            #[allow(unsafe_code)]
                            // SAFETY: the pool outlives the image's use of it and is never
                            // resized; only the image writes it.
                            unsafe { image.bind_outputs(p) };
                            k
                        }
                    };
                    let p = sample.and_then(|k| ptr(&mut pool, k));
                    #[allow(unsafe_code)]
                    // SAFETY: as above.
                    unsafe { image.bind_inputs(p) };
                    current = sample;
                    // A cycle without a sample builds the image in its own payload.
                    if sample.is_none() {
                        current = Some(usize::MAX);
                    }
                }
                Step::Finish { sent, next: loan, late } => {
                    let Some(built) = current.take() else {
                        continue;
                    };
                    image.publish_into();
                    if built != usize::MAX {
                        let payload = &pool[built];
                        for s in 0..n {
                            let e = &tables.submodules[s];
                            let at = e.input_offset as usize;
                            proptest::prop_assert_eq!(&payload[at..at + ilen(s)], &inputs[s][..]);
                            let at = e.output_mirror_offset as usize;
                            proptest::prop_assert_eq!(&payload[at..at + olen(s)], &outputs[s][..]);
                        }
                    }
                    if built != usize::MAX && sent {
                        newest = Some(built);
                    } else {
                        image.keep_unpublished();
                    }
                    if let Some((s, value)) = late {
                        let s = s % n;
                        if ilen(s) > 0 {
                            proptest::prop_assert!(image.set_inputs(s, &vec![value; ilen(s)]));
                            inputs[s].fill(value);
                        }
                    }
                    let k = free(loan, newest);
                    let p = k.and_then(|k| ptr(&mut pool, k));
                    #[allow(unsafe_code)]
                    // SAFETY: as above.
                    unsafe { image.bind_outputs(p) };
                    next = k;
                }
            }
            for s in 0..n {
                proptest::prop_assert_eq!(image.inputs(s), &inputs[s][..]);
                proptest::prop_assert_eq!(image.outputs(s), &outputs[s][..]);
            }
        }
    }
}

/// The device role's image holds the station's frame to its PLC as the demo PLC (which plans
/// as an S7-1500 does) lays it out: each input the PLC consumes sits in the output mirror
/// where the frame carries it, so that the frame goes out from the image.
#[test]
fn the_station_frame_is_in_the_mirror_where_the_plcs_plan_puts_each_input() {
    use crate::roles::device::sim_plc::{SIM_PLC_MAC, SIM_STATION_MAC, plan};
    use procimg_profinet::cyclic::CyclicAr;
    let station = Config::demo_device().station.expect("the demo station");
    let tables = Tables::of_station(&station).expect("the station's layout");
    let frame = tables.output_frames[0]
        .clone()
        .expect("the station's frame");
    let plans = plan(&station, 1_000_000).expect("the demo PLC's plan");
    let plc = CyclicAr::new(
        &plans[0],
        1,
        SIM_PLC_MAC,
        SIM_STATION_MAC,
        plans[0].frame_ids,
    );
    assert_eq!(frame.range.len(), produced_frame_len(plc.input.data_length));
    let mut placed = 0;
    for o in plc.input.objects.iter().filter(|o| o.len > 0) {
        let e = &tables.submodules[o.submodule];
        assert_eq!(
            usize::from(e.output_length),
            o.len,
            "submodule {}",
            o.submodule
        );
        assert_eq!(
            e.output_mirror_offset as usize,
            frame.range.start + PRODUCED_C_SDU_OFFSET + o.data,
            "submodule {}",
            o.submodule
        );
        placed += 1;
    }
    assert!(placed > 0);
    assert_eq!(frame.outputs, placed);
}
