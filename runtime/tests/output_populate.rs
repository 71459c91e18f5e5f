// SPDX-License-Identifier: MIT OR Apache-2.0
//! A client's output samples are in procimgd's page tables once its control thread has
//! connected them (`shm::outputs::connect`): faulted in there, 64 KiB at a time, so that the
//! cycle thread, which reads them later, takes no page fault for them, and no `mmap` held the
//! process's memory-map lock while a whole segment was populated (docs/ARCHITECTURE.md,
//! *Shared memory*).

use procimg_runtime::shm::outputs::{self, IpcThreadsafe};
use procimg_runtime::shm::server_node_of;
use procimg_runtime::sys::populate::{self, Mapping};
use procimg_testkit::memory::resident_bytes;
use procimg_testkit::unique_instance;

/// An output payload of 64 pages: a segment that `connect` left unpopulated would show it.
const PAYLOAD: usize = 256 * 1024;

#[test]
fn a_clients_output_samples_are_faulted_in_when_procimgd_connects_them() {
    if !populate::supported() {
        eprintln!("skipped: this kernel has no MADV_POPULATE_READ (Linux 5.14)");
        return;
    }
    let instance = unique_instance("populate");
    let (generation, token) = (1, 7);
    let server = outputs::output_node(&instance).expect("the server's output node");
    let port = outputs::create(&server, &instance, generation, token).expect("output port");
    let client = server_node_of::<IpcThreadsafe>(&instance, "client").expect("client node");
    let (_service, publisher) =
        procimg_client::output_publisher(&client, &instance, generation, token, PAYLOAD)
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
    assert!(
        samples.len >= PAYLOAD,
        "the largest new mapping holds no sample: {samples:?}"
    );
    let resident = resident_bytes(samples.start);
    let pages = samples.len / 4096 * 4096;
    assert!(
        resident >= pages,
        "{resident} of {} bytes of the client's samples are in procimgd's page tables",
        samples.len
    );
    drop(port);
    drop(publisher);
}
