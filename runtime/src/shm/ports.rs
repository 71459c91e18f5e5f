// SPDX-License-Identifier: MIT OR Apache-2.0
//! Creating the server's ports, with the quality of service each service needs.

use super::Ipc;
use super::aside::{Aside, INPUT_LOANS, InputSample, Loan};
use super::node::{ShmError, err, server_node};
use super::outputs::{IpcThreadsafe, OutputPorts};
use super::reserve::InputReserve;
use crate::image::Tables;
use crate::sys::populate;
use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::server::Server;
use iceoryx2::prelude::{AllocationStrategy, CallbackProgression, ServiceName, ZeroCopySend};
use iceoryx2::sample_mut::SampleMut;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;
use procimg_control::{self as control, services};
use procimg_shm_layout::events::EVENT_ID_MAX;
use procimg_shm_layout::handshake_map::HandshakeMap;
use procimg_shm_layout::{ImageHeader, LayoutHeader, MAX_CLIENTS};
use std::sync::Arc;

/// Readers beyond clients that may look at the image (tools such as `procimg io watch`).
const EXTRA_READERS: usize = 16;
/// Nodes one service may have: every client and reader, and the server's two (iceoryx2's
/// default, 20, would stop the 20th process at attaching).
const MAX_NODES: usize = MAX_CLIENTS + EXTRA_READERS + 2;
/// Notifications the control thread loans at once (it sends each at once).
const NOTIFICATION_LOANS: usize = 1;
/// Input images that may exist at once: the one being written, the newest (in the history and
/// every subscriber's buffer: a publication replaces what a buffer holds), the one named to
/// the clients that read by their mark and not yet sent (`CyclePorts::unsent`: the next is
/// loaned before it is sent), and one for each
/// reader, which holds at most one (the image it read last, until it takes the next). Fewer
/// would let a few readers holding distinct old images (asynchronous clients, tools, a client
/// stopped in a debugger) stop the publication for everyone. iceoryx2 would reserve
/// `subscribers × (buffer + borrowed) + history + loans` (162 for 80 subscribers). A cycle
/// that cannot loan an image anyway counts `unpublished_images`.
pub const INPUT_IMAGES: usize = MAX_CLIENTS + EXTRA_READERS + 3;

// No `payload_alignment`: iceoryx2 0.10 pads every element of a slice payload to it
// (`align(size_of::<u8>(), alignment) × len`), so 64 made each `[u8]` sample 64 times its
// length. The regions inside a payload are 64-byte aligned relative to its start.

fn name(instance: &str, s: String) -> Result<ServiceName, ShmError> {
    ServiceName::new(&s).map_err(|e| err(instance, format!("service name {s}"), e))
}

/// A byte-slice service whose subscribers see only the newest sample: one publisher, every
/// client and reader a subscriber that holds one sample (a client lets go of its image before
/// it takes the next, `Client::refresh`), and the newest sample kept for late subscribers.
fn newest_sample_service<H: core::fmt::Debug + ZeroCopySend>(
    node: &Node<Ipc>,
    instance: &str,
    service: String,
    what: &str,
) -> Result<PortFactory<Ipc, [u8], H>, ShmError> {
    node.service_builder(&name(instance, service)?)
        .publish_subscribe::<[u8]>()
        .max_nodes(MAX_NODES)
        .user_header::<H>()
        .max_publishers(1)
        .max_subscribers(MAX_CLIENTS + EXTRA_READERS)
        .subscriber_max_buffer_size(1)
        .subscriber_max_borrowed_samples(1)
        .history_size(1)
        .enable_safe_overflow(true)
        .create()
        .map_err(|e| err(instance, what, e))
}

/// Removes what dead processes left behind, and checks that no other live server of the same
/// instance exists. Returns the names of the dead nodes cleaned up.
pub fn cleanup_dead_nodes(instance: &str) -> Result<Vec<String>, ShmError> {
    let server_prefix = format!("{}/", control::server_node_name(instance));
    let mut cleaned = Vec::new();
    let mut live_server = false;
    let config = super::iox2_config();
    let me = std::process::id();
    let _ = Node::<Ipc>::list(config, |state| {
        match state {
            NodeState::Alive(view) => {
                if let Some(d) = view.details()
                    && d.name().as_str().starts_with(&server_prefix)
                    && d.process_id().value() as u32 != me
                {
                    live_server = true;
                }
            }
            NodeState::Dead(view) => {
                let name = view
                    .details()
                    .as_ref()
                    .map(|d| d.name().as_str().to_string())
                    .unwrap_or_default();
                if view.try_remove_stale_resources().is_ok() {
                    cleaned.push(name);
                }
            }
            _ => {}
        }
        CallbackProgression::Continue
    });
    if live_server {
        return Err(ShmError::AlreadyRunning {
            instance: instance.to_string(),
        });
    }
    Ok(cleaned)
}

/// The ports the cycle thread owns.
pub struct CyclePorts {
    /// The sample this cycle's input image is being built in (first: it goes back to the
    /// publisher before the publisher goes).
    pub loaned: Option<InputSample>,
    /// The sample the next image is built in, loaned at the end of the last cycle
    /// (`ClientLink::loan_ahead`), and where it lies in the input segment.
    pub ahead: Option<(Loan, Option<u32>)>,
    /// The image named to the clients that read by their mark but not yet sent through
    /// iceoryx2 (sent at the end of its cycle: `ClientLink::send_named`).
    pub unsent: Option<SampleMut<Ipc, [u8], ImageHeader>>,
    /// Where the loaned sample's payload lies in the input segment (see [`Aside`]).
    pub loaned_offset: Option<u32>,
    /// Loaned samples busy clients hold, kept out of use.
    pub aside: Aside,
    /// The cycle thread's node.
    pub node: Node<Ipc>,
    /// Publishes one input image per cycle.
    pub inputs: Publisher<Ipc, [u8], ImageHeader>,
    /// Each client's output port, adopted from the control thread, which connected it.
    pub outputs: OutputPorts,
    /// Signals NEWCYCLE, MODE, OPFAULT and shutdown, and STARTOP to clients that wait on its
    /// descriptor.
    pub events: Notifier<Ipc>,
    /// The futex words of STARTOP and OPDONE (see `procimg_shm_layout::handshake`).
    pub handshake: HandshakeMap,
    /// What of the input samples is faulted in: each loan is noted there.
    pub reserve: Arc<InputReserve>,
}

impl CyclePorts {
    /// Creates the cycle services of one server generation and the cycle thread's ports.
    pub fn create(
        instance: &str,
        generation: u64,
        tables: &Tables,
    ) -> Result<CyclePorts, ShmError> {
        let node = server_node(instance, "cycle")?;
        let l = &tables.layout;
        // Before the image services: a client that finds them finds the block too.
        let handshake = HandshakeMap::create(instance, generation)
            .map_err(|e| err(instance, "handshake block", e))?;

        let inputs = newest_sample_service::<ImageHeader>(
            &node,
            instance,
            control::input_service(instance, generation),
            "input image service",
        )?
        .publisher_builder()
        .initial_max_slice_len(l.input_payload_size as usize)
        .max_loaned_samples(INPUT_LOANS)
        .override_sample_preallocation(|_| INPUT_IMAGES)
        .create()
        .map_err(|e| err(instance, "input image publisher", e))?;

        let events = node
            .service_builder(&name(
                instance,
                control::cycle_event_service(instance, generation),
            )?)
            .event()
            .max_nodes(MAX_NODES)
            .max_notifiers(1)
            .max_listeners(MAX_CLIENTS + EXTRA_READERS)
            .event_id_max_value(EVENT_ID_MAX)
            .create()
            .map_err(|e| err(instance, "cycle event service", e))?
            .notifier_builder()
            .create()
            .map_err(|e| err(instance, "cycle event notifier", e))?;

        Ok(CyclePorts {
            loaned: None,
            ahead: None,
            unsent: None,
            loaned_offset: None,
            aside: Aside::default(),
            node,
            inputs,
            outputs: OutputPorts::default(),
            events,
            handshake,
            reserve: Arc::default(),
        })
    }

    /// Faults in the input samples the first cycles use, and no more (see
    /// [`super::reserve`]), noting loans in `reserve` from now on. Returns the first address
    /// of the input samples' segment, `None` if no sample could be loaned or found, or the
    /// kernel cannot fault pages in ahead (before Linux 5.14 `mlockall` locks, and so faults
    /// in, every mapping whole at mapping time).
    pub fn set_up_reserve(&mut self, reserve: Arc<InputReserve>, len: usize) -> Option<usize> {
        self.loaned = None;
        let mut sample = self.inputs.loan_slice_uninit(len).ok()?;
        let first = sample.payload_mut().as_mut_ptr() as usize;
        // Back on top of the free list: the first cycle loans it again.
        drop(sample);
        let segment = populate::mapping_of(first)?;
        // Busy clients' offsets count from here.
        self.aside.set_segment(segment.start);
        if !populate::supported() {
            return None;
        }
        self.reserve = reserve;
        self.reserve.set_up(&segment, first, len);
        Some(segment.start)
    }
}

/// The ports the acyclic (control) thread owns.
pub struct ControlPorts {
    /// The control thread's node.
    pub node: Node<Ipc>,
    /// Answers client requests.
    pub server: Server<Ipc, [u8], (), [u8], ()>,
    /// Holds the layout sample (history 1) for clients that attach later.
    pub layout: Publisher<Ipc, [u8], LayoutHeader>,
    /// Device events, alarms and confirmations for subscribers.
    pub notifications: Publisher<Ipc, [u8], ()>,
    /// Wakes subscribers when notifications were published.
    pub notify: Notifier<Ipc>,
    /// The node of the clients' output ports, which this thread connects for the cycle
    /// thread.
    pub outputs_node: Node<IpcThreadsafe>,
}

impl ControlPorts {
    /// Opens (or creates) the control service, creates the layout service of this generation
    /// and publishes the layout.
    pub fn create(
        instance: &str,
        generation: u64,
        tables: &Tables,
        cycle_ns: u64,
        opdone_deadline_ns: u64,
    ) -> Result<ControlPorts, ShmError> {
        let node = server_node(instance, "control")?;
        let server = node
            .service_builder(&name(instance, control::control_service(instance))?)
            .request_response::<[u8], [u8]>()
            .max_nodes(MAX_NODES)
            .max_servers(2)
            .max_clients(MAX_CLIENTS + EXTRA_READERS)
            .max_active_requests_per_client(2)
            .max_response_buffer_size(2)
            .open_or_create()
            .map_err(|e| err(instance, "control service", e))?
            .server_builder()
            .initial_max_slice_len(4096)
            .allocation_strategy(AllocationStrategy::PowerOfTwo)
            // One answer per request, and a client has at most two requests active: iceoryx2's
            // general bound (every request with a stream of buffered, borrowed and loaned
            // answers, 1920 here) made each growth of the answers' size cost seconds.
            .override_response_preallocation(|_| 2 * (MAX_CLIENTS + EXTRA_READERS) + 1)
            .create()
            .map_err(|e| err(instance, "control server", e))?;

        let devices = tables.devices.len() as u32;
        let payload_len = tables.layout.layout_payload_size(devices) as usize;
        let layout = newest_sample_service::<LayoutHeader>(
            &node,
            instance,
            control::layout_service(instance, generation),
            "layout service",
        )?
        .publisher_builder()
        .initial_max_slice_len(payload_len)
        // Published once and kept in the history: every reader gets the same sample.
        .override_sample_preallocation(|_| 1)
        .create()
        .map_err(|e| err(instance, "layout publisher", e))?;

        let mut sample = layout
            .loan_slice_uninit(payload_len)
            .map_err(|e| err(instance, "layout sample", e))?;
        *sample.user_header_mut() = tables.layout.header(
            tables.role,
            devices,
            tables.hash,
            generation,
            cycle_ns,
            opdone_deadline_ns,
        );
        let mut bytes = vec![0u8; payload_len];
        procimg_shm_layout::encode_tables(&mut bytes, &tables.devices, &tables.submodules);
        let sample = sample.write_from_slice(&bytes);
        sample
            .send()
            .map_err(|e| err(instance, "layout publication", e))?;
        let notifications = node
            .service_builder(&name(instance, services::notification_service(instance))?)
            .publish_subscribe::<[u8]>()
            .max_nodes(MAX_NODES)
            // Two: a dead predecessor's port may linger until its node is cleaned up.
            .max_publishers(2)
            .max_subscribers(MAX_CLIENTS + EXTRA_READERS)
            .subscriber_max_buffer_size(services::NOTIFICATION_BUFFER)
            .subscriber_max_borrowed_samples(1)
            .history_size(0)
            // A subscriber that falls behind loses its oldest notifications; the server
            // never waits for one.
            .enable_safe_overflow(true)
            .open_or_create()
            .map_err(|e| err(instance, "notification service", e))?
            .publisher_builder()
            .initial_max_slice_len(1024)
            .allocation_strategy(AllocationStrategy::PowerOfTwo)
            .max_loaned_samples(NOTIFICATION_LOANS)
            // Every subscriber's buffer holds some of the last NOTIFICATION_BUFFER sent (the
            // same samples for all), and each borrows at most one: iceoryx2's general bound
            // counts a buffer per subscriber (20 562 samples here).
            .override_sample_preallocation(|_| {
                services::NOTIFICATION_BUFFER + MAX_CLIENTS + EXTRA_READERS + NOTIFICATION_LOANS
            })
            .create()
            .map_err(|e| err(instance, "notification publisher", e))?;
        let notify = node
            .service_builder(&name(instance, services::notify_event_service(instance))?)
            .event()
            .max_nodes(MAX_NODES)
            .max_notifiers(2)
            .max_listeners(MAX_CLIENTS + EXTRA_READERS)
            .event_id_max_value(services::EVENT_NOTIFICATIONS)
            .open_or_create()
            .map_err(|e| err(instance, "notify event service", e))?
            .notifier_builder()
            .create()
            .map_err(|e| err(instance, "notify event notifier", e))?;
        Ok(ControlPorts {
            node,
            server,
            layout,
            notifications,
            notify,
            outputs_node: super::outputs::output_node(instance)?,
        })
    }
}
