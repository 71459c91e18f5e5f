// SPDX-License-Identifier: MIT OR Apache-2.0
//! What procimgd relies on from iceoryx2's input image samples, checked against the iceoryx2
//! procimg is built with, so that a version that behaves otherwise fails here first:
//!
//! - the image's carry-over (`image::region`): a sample comes back to the publisher, through
//!   readers and loans, holding exactly what it was published with;
//! - faulting the samples in as they come into use (`shm::reserve`): iceoryx2 loans the free
//!   sample at the lowest address, so that procimgd's locked memory grows with the readers
//!   that actually hold an image, not with the readers that may.

use iceoryx2::prelude::*;
use procimg_control as control;
use procimg_runtime::config::{Config, SubmoduleConfig};
use procimg_runtime::cycle::ClientLink;
use procimg_runtime::image::Tables;
use procimg_runtime::shm::reserve::{AHEAD, InputReserve};
use procimg_runtime::shm::{CyclePorts, Ipc, server_node};
use procimg_runtime::sys::clock::now_ns;
use procimg_runtime::sys::populate;
use procimg_shm_layout::ImageHeader;
use procimg_shm_layout::pins::Pins;
use procimg_testkit::memory::resident_bytes;
use std::collections::HashMap;
use std::sync::Arc;

/// A reader of the input images of `instance`'s server `generation`, as a client is.
fn reader(node: &Node<Ipc>, instance: &str, generation: u64) -> InputReader {
    let service = ServiceName::new(&control::input_service(instance, generation)).unwrap();
    node.service_builder(&service)
        .publish_subscribe::<[u8]>()
        .user_header::<ImageHeader>()
        .open()
        .expect("the input image service")
        .subscriber_builder()
        .buffer_size(1)
        .create()
        .expect("a subscriber")
}

type InputReader = iceoryx2::port::subscriber::Subscriber<Ipc, [u8], ImageHeader>;

/// The cycle ports of a new instance (`what`) for `tables`, the input samples' reserve set
/// up, the image's length, and a reader of the images with its node.
fn ports_and_reader(tables: &Tables, what: &str) -> (CyclePorts, usize, Node<Ipc>, InputReader) {
    let instance = procimg_testkit::unique_instance(what);
    let generation = now_ns();
    let mut ports = CyclePorts::create(&instance, generation, tables).expect("cycle ports");
    let len = tables.layout.input_payload_size as usize;
    ports.set_up_reserve(Arc::new(InputReserve::default()), len);
    let node = server_node(&instance, what).expect("a node");
    let reader = reader(&node, &instance, generation);
    (ports, len, node, reader)
}

/// Loans a sample, fills it with the cycle's low byte and publishes it as that cycle's
/// image (with `send_later`, only named); returns where it lies.
fn publish_filled(ports: &mut CyclePorts, len: usize, cycle: u64, send_later: bool) -> usize {
    let sample = ports.loan_image(len).expect("a loan");
    // SAFETY: the loan is the test's until it is published, `len` bytes long.
    #[allow(unsafe_code)]
    unsafe {
        core::ptr::write_bytes(sample.as_ptr(), cycle as u8, len)
    };
    let mut header = ImageHeader::default();
    header.cycle.cycle_number = cycle;
    header.cycle.cycle_start_ns = now_ns();
    let published = ports.publish(&mut header, send_later);
    assert!(published, "cycle {cycle}: not published");
    let c = header.cycle;
    assert!(
        c.clock_ns >= c.cycle_start_ns && c.clock_ns <= now_ns(),
        "cycle {cycle}: stamped while published, {c:?}"
    );
    assert_eq!(c.since_cycle_start_ns, c.clock_ns - c.cycle_start_ns);
    sample.as_ptr() as usize
}

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
    let reader = reader(&node, &instance, generation);
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
            ports.publish(&mut ImageHeader::default(), false),
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
    let mut readers: Vec<_> = [1u32, 3, 7, 50]
        .into_iter()
        .map(|every| (every, reader(&node, &instance, generation), None))
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
            ports.publish(&mut ImageHeader::default(), false),
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

#[test]
fn a_busy_reader_holds_its_image_by_its_mark_alone() {
    let tables = large_image(8, 1024);
    let (mut ports, len, _node, subscriber) = ports_and_reader(&tables, "pins");
    let slot = 5;
    let pins = &ports.handshake.block().pins as *const Pins;
    // SAFETY: the handshake block lives as long as `ports`, which outlives every use here;
    // the test reads it as a client in another process would, through shared memory.
    #[allow(unsafe_code)]
    let pins = unsafe { &*pins };
    pins.join(slot);

    // Every other image only named, sent with the next publication (after the next loan,
    // as the cycle does when every client reads by its mark), and every third image's
    // sample loaned ahead: two loans at once, and the samples aside beside them.
    let publish = |ports: &mut CyclePorts, round: u32| {
        publish_filled(ports, len, u64::from(round), round.is_multiple_of(2));
        if round.is_multiple_of(3) {
            ports.loan_ahead(len);
        }
    };

    // The slow path once, as a client at its attach: where the segment starts here.
    publish(&mut ports, 1);
    let first = subscriber
        .receive()
        .expect("receive")
        .expect("the first image");
    let newest = pins.newest().expect("the first image's place");
    assert_eq!(
        u64::from(newest.cycle),
        first.user_header().cycle.cycle_number
    );
    let base = first.payload().as_ptr() as usize - newest.offset as usize;
    drop(first);

    // Then only marks: the reader holds an image while 5 more are published, and a sample
    // it holds is never written meanwhile, though iceoryx2 would have loaned it again.
    let mut round = 1;
    let mut aside_seen = 0;
    for _ in 0..40 {
        let held = pins.pin_newest(slot).expect("an image");
        // SAFETY: the offset lies in the input segment, mapped by the subscriber's
        // connection for as long as it lives; the sample is held by the mark.
        #[allow(unsafe_code)]
        let image =
            unsafe { std::slice::from_raw_parts((base + held.offset as usize) as *const u8, len) };
        assert!(image.iter().all(|&b| b == held.cycle as u8));
        for _ in 0..5 {
            round += 1;
            publish(&mut ports, round);
            aside_seen = aside_seen.max(ports.aside.kept());
            assert!(
                image.iter().all(|&b| b == held.cycle as u8),
                "round {round}: the image of cycle {} changed while held",
                held.cycle
            );
        }
        pins.unpin(slot);
    }
    assert!(
        aside_seen > 0,
        "no loan ever met the held sample: the test tests nothing"
    );
    publish(&mut ports, round + 1);
    assert_eq!(
        ports.aside.kept(),
        0,
        "a sample stays aside after it was let go of"
    );
}

#[test]
fn an_image_only_named_reaches_iceoryx2_readers_when_sent_and_a_loan_ahead_is_used() {
    let tables = large_image(2, 1024);
    let (mut ports, len, _node, subscriber) = ports_and_reader(&tables, "named");
    assert!(
        ports.read_by_mark(0),
        "no client: nobody needs iceoryx2 first"
    );
    assert!(
        !ports.read_by_mark(1 << 4),
        "a client not reading by its mark"
    );
    ports.handshake.block().pins.join(4);
    assert!(ports.read_by_mark(1 << 4));

    let mut loaned_ahead = None;
    for cycle in 1..=3u64 {
        let named_sample = publish_filled(&mut ports, len, cycle, true);
        if let Some(ahead) = loaned_ahead {
            assert_eq!(
                named_sample, ahead,
                "the sample loaned ahead is the one used"
            );
        }
        let pins = &ports.handshake.block().pins;
        let named = pins.newest().expect("named");
        assert_eq!(u64::from(named.cycle), cycle, "named at once");
        let recorded = pins
            .record_of(named)
            .expect("the named image's record")
            .cycle;
        assert!(
            subscriber.receive().expect("receive").is_none(),
            "cycle {cycle}: iceoryx2's reader had the image before it was sent"
        );
        // The next sample is loaned before the named one is sent, as in the cycle.
        let next = ports.loan_image(len).expect("a second loan");
        assert_ne!(next.as_ptr() as usize, named_sample);
        assert!(ports.send_named());
        let got = subscriber
            .receive()
            .expect("receive")
            .expect("the image, once sent");
        assert_eq!(
            got.user_header().cycle,
            recorded,
            "the sample carries the stamp the busy readers follow"
        );
        assert!(got.payload().iter().all(|&b| b == cycle as u8));
        assert!(ports.send_named(), "nothing left to send");
        // The end of the cycle: the next cycle's sample loaned ahead.
        ports.loan_ahead(len);
        let (ahead, _) = ports.ahead.as_ref().expect("a sample loaned ahead");
        loaned_ahead = Some(ahead.at);
    }
}
