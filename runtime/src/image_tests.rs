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
        let (mut a, mut b) = (sample(&image), sample(&image));
        let mut expected: Vec<Vec<u8>> = (0..tables.submodules.len())
            .map(|s| vec![0; len(&tables, s)])
            .collect();
        // Round 1 into sample a (all of them arrive), round 2 into b (the subset), round 3
        // into the own payload (nothing arrives), round 4 into a again (the complement).
        for round in 1..=4u8 {
            let arriving: Vec<usize> = with_inputs
                .iter()
                .enumerate()
                .filter(|&(i, _)| match round {
                    1 => true,
                    2 => subset & (1 << i) != 0,
                    3 => false,
                    _ => subset & (1 << i) == 0,
                })
                .map(|(_, &s)| s)
                .collect();
            match round {
                1 | 4 => {
                    a.fill(0xEE);
                    bind(&mut image, Some(&mut a))
                }
                2 => bind(&mut image, Some(&mut b)),
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
                let published = if round == 2 { &b } else { &a };
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
