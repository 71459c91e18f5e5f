// SPDX-License-Identifier: MIT OR Apache-2.0
//! The input samples are faulted in as they come into use, a few ahead of the cycle
//! (`shm::reserve`), not all of them at the start: procimgd's locked memory grows with the
//! readers that actually hold an image, not with the readers that may. This relies on
//! iceoryx2 loaning the free sample at the lowest address, which is checked here against the
//! iceoryx2 procimg is built with.

use iceoryx2::prelude::*;
use procimg_control as control;
use procimg_runtime::config::{Config, SubmoduleConfig};
use procimg_runtime::cycle::ClientLink;
use procimg_runtime::image::Tables;
use procimg_runtime::shm::reserve::{AHEAD, InputReserve};
use procimg_runtime::shm::{CyclePorts, server_node};
use procimg_runtime::sys::clock::now_ns;
use procimg_runtime::sys::populate;
use procimg_shm_layout::ImageHeader;
use std::sync::Arc;

/// The demo's first device with `n` submodules of `len` bytes each way: an image of some
/// hundred KiB, whose samples span many pages each.
fn large_image(n: u16, len: u16) -> Tables {
    let mut config = Config::demo();
    let mut device = config.devices[0].clone();
    let template = device.submodules[0].clone();
    device.submodules = (0..n)
        .map(|i| SubmoduleConfig {
            slot: i + 1,
            subslot: 1,
            input_length: len,
            output_length: len,
            input_address: u32::from(i) * u32::from(len),
            output_address: u32::from(i) * u32::from(len),
            records: Vec::new(),
            ..template.clone()
        })
        .collect();
    config.devices = vec![device];
    Tables::from_config(&config).expect("the layout")
}

/// The resident bytes of the mapping at `start`, from `/proc/self/smaps`.
fn resident_bytes(start: usize) -> usize {
    let smaps = std::fs::read_to_string("/proc/self/smaps").expect("read /proc/self/smaps");
    let header = format!("{start:x}-");
    let mut lines = smaps.lines().skip_while(|l| !l.starts_with(&header));
    assert!(lines.next().is_some(), "no mapping at {start:#x} in smaps");
    let rss = lines.find(|l| l.starts_with("Rss:")).expect("an Rss line");
    let kib: usize = rss
        .split_whitespace()
        .nth(1)
        .and_then(|v| v.parse().ok())
        .expect("Rss in kB");
    kib * 1024
}

#[test]
fn input_samples_are_faulted_in_as_readers_come_to_hold_them() {
    if !populate::supported() {
        eprintln!("skipped: this kernel has no MADV_POPULATE_READ (Linux 5.14)");
        return;
    }
    let tables = large_image(64, 1024);
    let instance = procimg_testkit::unique_instance("reserve");
    let generation = now_ns();
    let mut ports = CyclePorts::create(&instance, generation, &tables).expect("cycle ports");
    let len = tables.layout.input_payload_size as usize;
    let reserve = Arc::new(InputReserve::default());
    let segment = ports
        .set_up_reserve(reserve.clone(), len)
        .expect("a sample and its segment");
    let segment_len = populate::mapping_of(segment).expect("the segment").len;
    let span = len + 4096;

    // Readers as clients and tools are: each takes the newest image every so many cycles
    // and holds it until then, so that up to four old images are held at once.
    let node = server_node(&instance, "readers").expect("a node");
    let service = ServiceName::new(&control::input_service(&instance, generation)).unwrap();
    let mut readers: Vec<_> = [1u32, 3, 7, 50]
        .into_iter()
        .map(|every| {
            let subscriber = node
                .service_builder(&service)
                .publish_subscribe::<[u8]>()
                .user_header::<ImageHeader>()
                .open()
                .expect("the input image service")
                .subscriber_builder()
                .buffer_size(1)
                .create()
                .expect("a subscriber");
            (every, subscriber, None)
        })
        .collect();

    let mut highest = 0;
    for round in 0..600u32 {
        let sample = ports.loan_image(len).expect("a loan");
        let at = sample.as_ptr() as usize;
        highest = highest.max(at + len - segment);
        // SAFETY: the loan is the test's until it is published, `len` bytes long.
        #[allow(unsafe_code)]
        unsafe {
            core::ptr::write_bytes(sample.as_ptr(), round as u8, len)
        };
        assert!(
            ports.publish(&mut |_| ImageHeader::default()),
            "round {round}"
        );
        for (every, subscriber, held) in &mut readers {
            if round.is_multiple_of(*every) {
                drop(held.take());
                *held = subscriber.receive().expect("receive");
            }
        }
        // What the cycle thread asks and the control thread does.
        if reserve.needs_extending() {
            reserve.extend();
        }
    }

    // Four readers, the newest image and the loan: iceoryx2 took the lowest samples.
    let in_use = readers.len() + 2;
    assert!(
        highest <= (in_use + 1) * span,
        "the highest sample loaned ends {highest} bytes into the segment, beyond {in_use} \
         samples of {span}: iceoryx2 no longer loans the lowest free sample"
    );
    assert_eq!(
        reserve.unready_loans(),
        0,
        "loans of samples not faulted in"
    );
    let ready = reserve.ready_bytes();
    assert!(
        ready >= highest && ready <= highest + (AHEAD + 1) * span,
        "{ready} bytes faulted in for samples up to {highest}"
    );
    let resident = resident_bytes(segment);
    eprintln!(
        "samples of {span} bytes: loans up to {highest} bytes into the segment, {ready} \
         faulted in, {resident} resident of {segment_len}"
    );
    assert!(
        resident <= ready + populate::PAGE && resident * 4 < segment_len,
        "{resident} bytes of the {segment_len}-byte segment resident, {ready} faulted in"
    );
}
