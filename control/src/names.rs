// SPDX-License-Identifier: MIT OR Apache-2.0
//! The names of the iceoryx2 services and nodes of an instance.

/// The request-response service of an instance: the one name that survives server restarts.
pub fn control_service(instance: &str) -> String {
    format!("procimg/{instance}/control")
}

/// The input-image publish-subscribe service of one server generation.
pub fn input_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/inputs")
}

/// The layout publish-subscribe service of one server generation.
pub fn layout_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/layout")
}

/// The output publish-subscribe service of one client of one server generation, named by the
/// token of its registration: the client creates it and publishes, the server subscribes once
/// the client asks it to (`CoreRequest::ConnectOutputs`). One service per client lets the
/// server set up each client's connection off its cycle thread.
pub fn client_output_service(instance: &str, generation: u64, token: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/outputs/{token:016x}")
}

/// Output samples a client's output service buffers for the server's subscriber, sent
/// between two of its cycles.
pub const OUTPUT_BUFFER: usize = 8;

/// Output samples a synchronous client may have sent that the server has not taken yet. Its
/// OPDONE needs none: the server reads it where the client wrote it
/// (`procimg_shm_layout::posts`), after the first. What is left is room for writes between
/// two cycles, and a smaller output segment: at a 360 KiB image, half of what procimgd maps,
/// faults in and locks for each client, and half the time that takes at attach.
pub const SYNCHRONOUS_OUTPUT_BUFFER: usize = 2;

/// Output samples the server borrows at once: one it reads, and one it keeps to hold a busy
/// client's segment mapped (`procimg_runtime::shm::outputs`).
pub const OUTPUT_BORROWED: usize = 2;

/// Output samples a client loans at once: the one being written, and the next cycle's,
/// loaned ahead.
pub const OUTPUT_LOANS: usize = 2;

/// Output samples a client of `role` may have sent that the server has not taken yet: more
/// writes in one cycle are not delivered.
pub fn output_buffer(role: crate::ClientRole) -> usize {
    match role {
        crate::ClientRole::Synchronous => SYNCHRONOUS_OUTPUT_BUFFER,
        crate::ClientRole::Asynchronous => OUTPUT_BUFFER,
    }
}

/// Output samples the output segment of a client of `role` holds: those it may have sent
/// and the server not taken yet ([`output_buffer`]), and the ones borrowed and loaned.
pub fn output_samples(role: crate::ClientRole) -> usize {
    OUTPUT_BORROWED + output_buffer(role) + OUTPUT_LOANS
}

/// The event service on which the server signals NEWCYCLE, MODE, OPFAULT and shutdown, and
/// STARTOP to clients that wait on its descriptor (the others sleep on the handshake block's
/// futex word, see `procimg_shm_layout::handshake`).
pub fn cycle_event_service(instance: &str, generation: u64) -> String {
    format!("procimg/{instance}/{generation:016x}/cycle-events")
}

/// The iceoryx2 node name of the server of an instance.
pub fn server_node_name(instance: &str) -> String {
    format!("procimgd/{instance}")
}

/// The file prefix of every procimg service: the shared memory's, since the handshake block's
/// file in `/dev/shm` carries it too.
pub use procimg_shm_layout::share::IOX2_PREFIX;
