// SPDX-License-Identifier: MIT OR Apache-2.0
//! A client's output samples are in procimgd's page tables once its control thread has
//! connected them (`shm::outputs::connect`): faulted in there, 64 KiB at a time, so that the
//! cycle thread, which reads them later, takes no page fault for them, and no `mmap` held the
//! process's memory-map lock while a whole segment was populated (docs/ARCHITECTURE.md,
//! *Shared memory*). A synchronous client's segment holds fewer samples than an asynchronous
//! one's: what procimgd maps and locks per client.

use procimg_client::Registration;
use procimg_control::{ClientRole, output_samples};
use procimg_runtime::shm::outputs::{self, IpcThreadsafe};
use procimg_runtime::shm::server_node_of;
use procimg_runtime::sys::populate::{self, Mapping};
use procimg_testkit::memory::resident_bytes;
use procimg_testkit::unique_instance;
use std::sync::Mutex;

/// An output payload of 64 pages: a segment that `connect` left unpopulated would show it.
const PAYLOAD: usize = 256 * 1024;

/// Connects procimgd's port to a client of `role`, as the control thread does, and returns
/// the mapping of the client's samples that connecting added, with how much of it is
/// resident then.
fn connect_a_client(role: ClientRole) -> (Mapping, usize) {
    // One at a time: the new mapping is told from the ones before by its address, and a
    // segment another test unmapped meanwhile may leave its address to this one's.
    static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let instance = unique_instance("populate");
    let reg = Registration {
        generation: 1,
        token: 7,
        role,
    };
    let server = outputs::output_node(&instance).expect("the server's output node");
    let port = outputs::create(&server, &instance, reg.generation, reg.token).expect("output port");
    let client = server_node_of::<IpcThreadsafe>(&instance, "client").expect("client node");
    let (_service, publisher) = procimg_client::output_publisher(&client, &instance, reg, PAYLOAD)
        .expect("the client's publisher");
    let before: std::collections::HashSet<usize> = populate::mappings()
        .expect("read /proc/self/maps")
        .iter()
        .map(|m| m.start)
        .collect();

    outputs::connect(&port, &instance).expect("connect");

    // What connecting mapped: the client's samples are the largest.
    let samples: Mapping = populate::mappings()
        .expect("read /proc/self/maps")
        .into_iter()
        .filter(|m| m.is_shared_memory() && !before.contains(&m.start))
        .max_by_key(|m| m.len)
        .expect("connecting maps the client's samples");
    let resident = resident_bytes(samples.start);
    drop(port);
    drop(publisher);
    (samples, resident)
}

#[test]
fn a_clients_output_samples_are_faulted_in_when_procimgd_connects_them() {
    if !populate::supported() {
        eprintln!("skipped: this kernel has no MADV_POPULATE_READ (Linux 5.14)");
        return;
    }
    let (samples, resident) = connect_a_client(ClientRole::Synchronous);
    assert!(
        samples.len >= PAYLOAD,
        "the largest new mapping holds no sample: {samples:?}"
    );
    let pages = samples.len / 4096 * 4096;
    assert!(
        resident >= pages,
        "{resident} of {} bytes of the client's samples are in procimgd's page tables",
        samples.len
    );
}

#[test]
fn a_synchronous_clients_output_segment_holds_half_the_samples_of_an_asynchronous_ones() {
    let (synchronous, _) = connect_a_client(ClientRole::Synchronous);
    let (asynchronous, _) = connect_a_client(ClientRole::Asynchronous);
    let samples = output_samples;
    assert_eq!(
        (
            samples(ClientRole::Synchronous),
            samples(ClientRole::Asynchronous)
        ),
        (6, 12)
    );
    // Each sample is the payload and iceoryx2's header for it, aligned: a little more.
    for (mapping, role) in [
        (synchronous, ClientRole::Synchronous),
        (asynchronous, ClientRole::Asynchronous),
    ] {
        let n = samples(role);
        assert!(
            mapping.len >= n * PAYLOAD && mapping.len < (n + 1) * PAYLOAD,
            "{role:?}: a segment of {} bytes for {n} samples of {PAYLOAD}",
            mapping.len
        );
    }
}
