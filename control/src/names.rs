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
