// SPDX-License-Identifier: MIT OR Apache-2.0
//! The clients' output ports: one iceoryx2 service per client, subscribed to off the cycle
//! thread.
//!
//! The control thread creates each client's output service
//! (`procimg_control::client_output_service`) and its subscriber when the client registers.
//! The client opens it, creates its publisher and asks the control thread to connect
//! (`CoreRequest::ConnectOutputs`). The control thread connects the subscriber there: iceoryx2
//! maps the client's output samples (about 4 MiB at a 360 KiB image), and faulting in and
//! locking every page of them costs a cycle or more. The port ready, it goes to the cycle
//! thread through [`OutputHandoff`]; the cycle thread hands the ports of clients that left
//! back the same way, so that the control thread unmaps them. The ports are of iceoryx2's
//! thread-safe variant, whose ports may move between threads; only one thread uses a port at
//! a time, so its mutex is never contended.

use super::node::{self, ShmError, server_node_of};
use crate::sys::populate;
use crossbeam_queue::ArrayQueue;
use iceoryx2::node::Node;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::prelude::ServiceName;
use procimg_control::OUTPUT_BUFFER;
use procimg_shm_layout::{MAX_CLIENTS, OutputHeader};

/// iceoryx2's inter-process variant whose ports may move between threads.
pub type IpcThreadsafe = iceoryx2::service::ipc_threadsafe::Service;

/// The server's subscriber to one client's outputs.
pub type OutputPort = Subscriber<IpcThreadsafe, [u8], OutputHeader>;

/// A connected output port on its way to the cycle thread.
pub struct Arrival {
    /// The client's slot.
    pub slot: u32,
    /// The token of the registration it belongs to.
    pub token: u64,
    /// The port.
    pub port: Box<OutputPort>,
}

/// Output ports between the control thread and the cycle thread, both ways.
pub struct OutputHandoff {
    arriving: ArrayQueue<Arrival>,
    spent: ArrayQueue<Box<OutputPort>>,
}

impl Default for OutputHandoff {
    fn default() -> Self {
        OutputHandoff {
            arriving: ArrayQueue::new(MAX_CLIENTS),
            // Every client's port, and as many arrivals refused (a client gone meanwhile).
            spent: ArrayQueue::new(2 * MAX_CLIENTS),
        }
    }
}

impl OutputHandoff {
    /// Sends a connected port to the cycle thread; gives it back when MAX_CLIENTS are already
    /// on their way (the cycle thread is not taking them).
    pub fn send(&self, arrival: Arrival) -> Result<(), Arrival> {
        self.arriving.push(arrival)
    }

    /// The next port that arrived (cycle thread).
    pub fn receive(&self) -> Option<Arrival> {
        self.arriving.pop()
    }

    /// Hands a port back to be dropped off the cycle thread (cycle thread). Without room the
    /// port is dropped here, at the cost of an unmapping in the cycle.
    pub fn retire(&self, port: Box<OutputPort>) {
        let _ = self.spent.push(port);
    }

    /// Drops the ports handed back (control thread): their mappings go here.
    pub fn drop_retired(&self) -> usize {
        let mut n = 0;
        while self.spent.pop().is_some() {
            n += 1;
        }
        n
    }
}

/// Creates a node for the server's output ports.
pub fn output_node(instance: &str) -> Result<Node<IpcThreadsafe>, ShmError> {
    server_node_of(instance, "outputs")
}

/// Creates the output service of the client registered with `token`, and the server's
/// subscriber to it. procimgd creates it, not the client: its files are then procimgd's, which
/// removes them when its port goes, also when the client is another user and left first.
pub fn create(
    node: &Node<IpcThreadsafe>,
    instance: &str,
    generation: u64,
    token: u64,
) -> Result<OutputPort, ShmError> {
    let service = procimg_control::client_output_service(instance, generation, token);
    let err =
        |what: &str, e: &dyn core::fmt::Debug| node::err(instance, format!("{what} {service}"), e);
    let name = ServiceName::new(&service).map_err(|e| err("the service name", &e))?;
    node.service_builder(&name)
        .publish_subscribe::<[u8]>()
        .user_header::<OutputHeader>()
        // The client publishes, the cycle thread alone subscribes: its buffer holds what is
        // sent between two of its cycles, it borrows one sample at a time and lets go of it
        // at once, and a full buffer makes the client's send fail rather than drop a sample
        // the server has not seen.
        .max_nodes(2)
        .max_publishers(1)
        .max_subscribers(1)
        .subscriber_max_buffer_size(OUTPUT_BUFFER)
        .subscriber_max_borrowed_samples(1)
        .history_size(0)
        .enable_safe_overflow(false)
        .create()
        .map_err(|e| err("a client's output service", &e))?
        .subscriber_builder()
        .buffer_size(OUTPUT_BUFFER)
        .create()
        .map_err(|e| err("a subscriber to", &e))
}

/// Connects `port` to the client's publisher, which maps the client's output samples, and
/// faults them in a chunk at a time (`sys::populate`): the cycle reads them without a fault,
/// and the memory-map lock is never held for the whole segment.
pub fn connect(port: &OutputPort, instance: &str) -> Result<(), ShmError> {
    let before = populate::shared_memory_starts();
    port.update_connections()
        .map_err(|e| node::err(instance, "the connection to a client's output publisher", e))?;
    populate::populate_shared_memory_since(&before);
    Ok(())
}

/// The output ports the cycle thread holds, by client slot.
pub struct OutputPorts {
    ports: Vec<Option<(u64, Box<OutputPort>)>>,
    /// Where the next look for a sample begins: the port that had the last one, so that a
    /// client's samples are taken in the order sent and the ports in turn.
    cursor: usize,
}

impl Default for OutputPorts {
    fn default() -> Self {
        OutputPorts {
            ports: (0..MAX_CLIENTS).map(|_| None).collect(),
            cursor: 0,
        }
    }
}

impl OutputPorts {
    /// Takes the ports that arrived: those `current(slot, token)` accepts replace what their
    /// slot held; the others (their client left meanwhile) go back at once.
    pub fn adopt(&mut self, handoff: &OutputHandoff, current: &dyn Fn(u32, u64) -> bool) {
        while let Some(Arrival { slot, token, port }) = handoff.receive() {
            match self.ports.get_mut(slot as usize) {
                Some(entry) if current(slot, token) => {
                    if let Some((_, old)) = entry.replace((token, port)) {
                        handoff.retire(old);
                    }
                }
                _ => handoff.retire(port),
            }
        }
    }

    /// Hands back the port of `slot`, whose client left or registered anew.
    pub fn retire(&mut self, slot: u32, handoff: &OutputHandoff) {
        if let Some((_, port)) = self.ports.get_mut(slot as usize).and_then(Option::take) {
            handoff.retire(port);
        }
    }

    /// Moves the cursor past the port it is on (whose receive failed), so that the next look
    /// begins with the others.
    pub fn pass(&mut self) {
        self.cursor = (self.cursor + 1) % self.ports.len();
    }

    /// Looks at the ports in turn from the cursor and calls `look` on each until it returns
    /// `Some`; the cursor stays on that port. `None` when no port gave an answer.
    pub fn find<R>(&mut self, mut look: impl FnMut(&OutputPort) -> Option<R>) -> Option<R> {
        let n = self.ports.len();
        for i in 0..n {
            let at = (self.cursor + i) % n;
            if let Some((_, port)) = &self.ports[at]
                && let Some(r) = look(port)
            {
                self.cursor = at;
                return Some(r);
            }
        }
        None
    }
}
