// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the image's carry-over relies on from iceoryx2 (`image::region`): a sample of the
//! input image publisher comes back to it, through readers and loans, holding exactly what
//! it was published with. Checked against the iceoryx2 procimg is built with, so that a
//! version that clears or reuses samples otherwise fails here first.

use iceoryx2::prelude::*;
use procimg_control as control;
use procimg_runtime::config::Config;
use procimg_runtime::cycle::ClientLink;
use procimg_runtime::image::Tables;
use procimg_runtime::shm::{CyclePorts, server_node};
use procimg_runtime::sys::clock::now_ns;
use procimg_shm_layout::ImageHeader;
use std::collections::HashMap;

#[test]
fn an_input_sample_comes_back_holding_what_it_was_published_with() {
    let instance = procimg_testkit::unique_instance("samples");
    let tables = Tables::from_config(&Config::demo()).expect("the demo layout");
    let generation = now_ns();
    let mut ports = CyclePorts::create(&instance, generation, &tables).expect("cycle ports");
    let len = tables.layout.input_payload_size as usize;

    // A reader as a client is: it takes the newest image and holds it for a while, so the
    // publisher's loans go round more samples than two.
    let node = server_node(&instance, "reader").expect("a node");
    let service = ServiceName::new(&control::input_service(&instance, generation)).unwrap();
    let reader = node
        .service_builder(&service)
        .publish_subscribe::<[u8]>()
        .user_header::<ImageHeader>()
        .open()
        .expect("the input image service")
        .subscriber_builder()
        .buffer_size(1)
        .create()
        .expect("a subscriber");
    let mut held = None;

    // Sample (by its payload's address) → the byte it was filled with when published.
    let mut published: HashMap<usize, u8> = HashMap::new();
    let mut came_back = 0;
    for round in 0..200u32 {
        let sample = ports.loan_image(len).expect("a loan");
        // SAFETY: the loan is the test's until it is published, `len` bytes long.
        #[allow(unsafe_code)]
        let payload = unsafe { std::slice::from_raw_parts_mut(sample.as_ptr(), len) };
        if let Some(&fill) = published.get(&(sample.as_ptr() as usize)) {
            assert!(
                payload.iter().all(|&b| b == fill),
                "round {round}: a sample came back changed (published with {fill:#04x})"
            );
            came_back += 1;
        }
        let fill = (round % 251) as u8;
        payload.fill(fill);
        published.insert(sample.as_ptr() as usize, fill);
        assert!(
            ports.publish(&mut |_| ImageHeader::default()),
            "round {round}"
        );
        // Every third round the reader lets go of its image and takes the newest.
        if round % 3 == 0 {
            drop(held.take());
            held = reader.receive().expect("receive");
        }
    }
    drop(held);
    eprintln!(
        "{} samples went round, {came_back} loans gave one back",
        published.len()
    );
    assert!(
        published.len() > 2 && came_back > 150,
        "{} samples, {came_back} came back",
        published.len()
    );
}
