// SPDX-License-Identifier: MIT OR Apache-2.0
//! The iceoryx2 side of a client: its node, the control port, and the data ports of one
//! server generation.

use crate::error::AttachError;
use crate::layout::Layout;
use iceoryx2::config::Config;
use iceoryx2::node::{Node, NodeBuilder};
use iceoryx2::port::client::Client as RrClient;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::port::update_connections::UpdateConnections as _;
use iceoryx2::prelude::{
    AllocationStrategy, BackpressureStrategy, FileDescriptorBased, FileName, NodeName,
    SemanticString, ServiceName, SignalHandlingMode,
};
use iceoryx2::service::builder::event::EventOpenError;
use iceoryx2::service::builder::publish_subscribe::PublishSubscribeOpenError;
use iceoryx2::service::builder::request_response::RequestResponseOpenError;
use iceoryx2::service::port_factory::PortFactory as _;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory;
use procimg_control as control;
use procimg_shm_layout::handshake_map::HandshakeMap;
use procimg_shm_layout::share;
use procimg_shm_layout::{IMAGE_MAGIC, ImageHeader, LAYOUT_VERSION, LayoutHeader, OutputHeader};
use std::os::fd::RawFd;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// The iceoryx2 service variant: inter-process, with ports that may move between threads (a C
/// program hands its handle to another thread; IO-Base calls back on threads of its own). The
/// server keeps the single-threaded variant: both share the same shared-memory format.
pub type Ipc = iceoryx2::service::ipc_threadsafe::Service;

/// iceoryx2's configuration with procimg's file prefix (the server uses the same).
pub fn iox2_config() -> &'static Config {
    static CONFIG: OnceLock<Config> = OnceLock::new();
    CONFIG.get_or_init(|| {
        let mut c = Config::default();
        if let Ok(prefix) = FileName::new(control::IOX2_PREFIX.as_bytes()) {
            c.global.prefix = prefix;
        }
        if let Ok(path) =
            iceoryx2::prelude::Path::new(procimg_shm_layout::share::iceoryx2_directory().as_bytes())
        {
            c.global.set_root_path(&path);
        }
        c
    })
}

pub(crate) fn shm(instance: &str, what: &'static str, e: impl core::fmt::Debug) -> AttachError {
    AttachError::Shm {
        instance: instance.to_string(),
        what,
        detail: format!("{e:?}"),
    }
}

pub(crate) fn service_name(instance: &str, name: String) -> Result<ServiceName, AttachError> {
    ServiceName::new(&name).map_err(|e| shm(instance, "a service name", e))
}

/// A client's node, named after the client.
pub fn client_node(instance: &str, name: &str) -> Result<Node<Ipc>, AttachError> {
    let clean: String = name
        .chars()
        .map(|c| if c.is_ascii_graphic() { c } else { '_' })
        .take(64)
        .collect();
    let node_name = NodeName::new(&format!("procimg-client/{clean}"))
        .map_err(|e| shm(instance, "a node name", e))?;
    // No directory, no server; and a client must not be the one to create it: procimgd makes
    // it its access group's.
    if !root_dir().is_dir() {
        return Err(AttachError::NoServer {
            instance: instance.to_string(),
        });
    }
    NodeBuilder::new()
        .name(&node_name)
        .config(iox2_config())
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<Ipc>()
        .map_err(|e| root_dir_denied(instance).unwrap_or_else(|| shm(instance, "a node", e)))
}

/// iceoryx2's directory (`/dev/shm/procimg-iceoryx2`, or where `PROCIMG_SHM_DIR` puts it).
fn root_dir() -> std::path::PathBuf {
    let root = iox2_config().global.root_path().to_string();
    std::path::PathBuf::from(root.trim_end_matches('/'))
}

/// When iceoryx2's directory exists but this process may not use it (another user's, or an
/// access group this user is not in), says so; iceoryx2 itself only reports an internal error
/// then.
fn root_dir_denied(instance: &str) -> Option<AttachError> {
    let root = root_dir();
    if let Some(gid) = share::access_group(&root)
        && !procimg_shm_layout::os::may_create_in(&root)
    {
        return Some(AttachError::AccessDenied {
            instance: instance.to_string(),
            detail: share::denied_text(&root, gid),
        });
    }
    procimg_shm_layout::os::foreign_iox2_directory(&root, control::IOX2_PREFIX).map(|problem| {
        AttachError::ForeignDirectory {
            instance: instance.to_string(),
            problem,
        }
    })
}

/// Whether procimgd's `[access] group` is in force.
pub(crate) fn access_group_active() -> bool {
    share::access_group(&root_dir()).is_some()
}

/// With procimgd's `[access] group`, gives the group the files this process created (procimgd
/// runs as another user and must open them); nothing otherwise. For the loops that wait for
/// the server: it looks at most every 10 ms.
pub(crate) fn share_own_files() {
    static LAST_MS: AtomicU64 = AtomicU64::new(0);
    let now_ms = procimg_shm_layout::os::monotonic_ns() / 1_000_000 + 1;
    let last = LAST_MS.load(Ordering::Relaxed);
    if last != 0 && now_ms.saturating_sub(last) < 10 {
        return;
    }
    LAST_MS.store(now_ms, Ordering::Relaxed);
    share_own_files_now();
}

/// [`share_own_files`] at once, for a step that has just created files procimgd will open.
fn share_own_files_now() {
    share::share_with_group_now(&root_dir());
}

/// A client port of the control service: JSON requests and responses in byte slices.
pub type ControlPort = RrClient<Ipc, [u8], (), [u8], ()>;

/// Opens the instance's control service and a client port on it.
pub fn open_control(node: &Node<Ipc>, instance: &str) -> Result<ControlPort, AttachError> {
    let service = node
        .service_builder(&service_name(instance, control::control_service(instance))?)
        .request_response::<[u8], [u8]>()
        .open()
        .map_err(|e| match e {
            RequestResponseOpenError::DoesNotExist => AttachError::NoServer {
                instance: instance.to_string(),
            },
            RequestResponseOpenError::InsufficientPermissions => AttachError::AccessDenied {
                instance: instance.to_string(),
                detail: "control service".into(),
            },
            RequestResponseOpenError::IncompatibleRequestOrResponseType => {
                AttachError::LayoutVersion {
                    instance: instance.to_string(),
                    server: 0,
                    client: LAYOUT_VERSION,
                }
            }
            e => shm(instance, "the control service", e),
        })?;
    service
        .client_builder()
        .initial_max_slice_len(4096)
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .create()
        .map_err(|e| shm(instance, "a control client port", e))
}

pub(crate) fn pubsub_error(
    instance: &str,
    what: &'static str,
    e: PublishSubscribeOpenError,
) -> AttachError {
    match e {
        PublishSubscribeOpenError::DoesNotExist => AttachError::NoServer {
            instance: instance.to_string(),
        },
        PublishSubscribeOpenError::InsufficientPermissions => AttachError::AccessDenied {
            instance: instance.to_string(),
            detail: what.to_string(),
        },
        PublishSubscribeOpenError::IncompatibleTypes => AttachError::LayoutVersion {
            instance: instance.to_string(),
            server: 0,
            client: LAYOUT_VERSION,
        },
        e => shm(instance, what, e),
    }
}

pub(crate) fn event_error(instance: &str, what: &'static str, e: EventOpenError) -> AttachError {
    match e {
        EventOpenError::DoesNotExist => AttachError::NoServer {
            instance: instance.to_string(),
        },
        EventOpenError::InsufficientPermissions => AttachError::AccessDenied {
            instance: instance.to_string(),
            detail: what.to_string(),
        },
        e => shm(instance, what, e),
    }
}

/// The data ports of one server generation.
pub struct Connection {
    /// Input images.
    pub inputs: Subscriber<Ipc, [u8], ImageHeader>,
    /// This client's outputs.
    pub outputs: OutputPublisher,
    /// Their service, to see when procimgd let go of them.
    outputs_service: OutputService,
    /// NEWCYCLE, MODE, OPFAULT, shutdown; STARTOP too once the client waits on its
    /// descriptor.
    pub events: Listener<Ipc>,
    /// The events listener's socket, for callers that wait in their own `poll`.
    pub events_fd: RawFd,
    /// The futex words of STARTOP and OPDONE (see `procimg_shm_layout::handshake`).
    pub handshake: std::sync::Arc<HandshakeMap>,
    /// The layout of this generation.
    pub layout: Layout,
    /// The ids of the ports that have connections (inputs, outputs and the layout's
    /// subscriber, already gone).
    pub port_ids: [u128; 3],
}

impl Connection {
    /// Opens the data services of the generation registered with and reads its layout, opens
    /// the output service procimgd made for this client (`reg`) and has the server connect to it:
    /// `ring_server` wakes the server's control thread (`ControlHandle::ring_server`), which
    /// hands the layout over; `connect_outputs` asks it to connect (`CoreRequest::ConnectOutputs`).
    pub fn open(
        node: &Node<Ipc>,
        instance: &str,
        reg: Registration,
        timeout: Duration,
        ring_server: &dyn Fn(),
        connect_outputs: &dyn Fn() -> Result<(), AttachError>,
    ) -> Result<Connection, AttachError> {
        let generation = reg.generation;
        let (layout, layout_port) = read_layout(node, instance, generation, timeout, ring_server)?;
        let inputs = node
            .service_builder(&service_name(
                instance,
                control::input_service(instance, generation),
            )?)
            .publish_subscribe::<[u8]>()
            .user_header::<ImageHeader>()
            .open()
            .map_err(|e| pubsub_error(instance, "the input image service", e))?
            .subscriber_builder()
            .buffer_size(1)
            .create()
            .map_err(|e| shm(instance, "an input subscriber", e))?;
        let (outputs_service, outputs) = output_publisher(
            node,
            instance,
            reg,
            layout.header.output_payload_size as usize,
        )?;
        let events = node
            .service_builder(&service_name(
                instance,
                control::cycle_event_service(instance, generation),
            )?)
            .event()
            .open()
            .map_err(|e| event_error(instance, "the cycle event service", e))?
            .listener_builder()
            .create()
            .map_err(|e| shm(instance, "a cycle event listener", e))?;
        let handshake = HandshakeMap::open(instance, generation).map_err(|e| match e.kind() {
            std::io::ErrorKind::PermissionDenied => AttachError::AccessDenied {
                instance: instance.to_string(),
                detail: "the handshake block".into(),
            },
            std::io::ErrorKind::NotFound => AttachError::NoServer {
                instance: instance.to_string(),
            },
            _ => shm(instance, "the handshake block", e),
        })?;
        let handshake = std::sync::Arc::new(handshake);
        // iceoryx2 connects a subscriber to its publishers lazily, at its first receive, and
        // whichever side comes first creates the connection's file, owner-only. procimgd's
        // cycle thread tries a new subscriber's connection once: it waits for a file it may
        // not open yet for iceoryx2's creation timeout (1 s), then gives up until a port comes
        // or goes. So the subscriber connects here, and what it created goes to the group
        // right after, not at some later receive after which nothing shares it.
        let _ = inputs.update_connections();
        share_own_files_now();
        // The server maps this client's output samples on its control thread, never on its
        // cycle thread, and answers once it has; the publisher then opens the connection the
        // server made (shared with the group before the answer).
        connect_outputs()?;
        let _ = outputs.update_connections();
        // SAFETY: the descriptor belongs to `events`, which lives in the same Connection and
        // outlives every use of the descriptor.
        #[allow(unsafe_code)]
        let events_fd = unsafe { events.file_descriptor().native_handle() };
        Ok(Connection {
            port_ids: [inputs.id().value(), outputs.id().value(), layout_port],
            inputs,
            outputs,
            outputs_service,
            events,
            events_fd,
            handshake,
            layout,
        })
    }
}

/// A client's output service.
pub type OutputService = PortFactory<Ipc, [u8], OutputHeader>;
/// A client's output publisher.
pub type OutputPublisher = Publisher<Ipc, [u8], OutputHeader>;

/// A client's registration, as its connection needs it.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Registration {
    /// The server generation registered with.
    pub generation: u64,
    /// The registration's token.
    pub token: u64,
    /// The client's role, which sizes its output segment (`procimg_control::output_samples`).
    pub role: control::ClientRole,
}

/// Opens the output service procimgd made for the client of `reg`, and creates its publisher
/// for samples of `payload_len` bytes, in a segment that holds as many as its role needs
/// (`procimg_control::output_samples`). The server connects to it when asked
/// (`CoreRequest::ConnectOutputs`).
#[doc(hidden)]
pub fn output_publisher(
    node: &Node<Ipc>,
    instance: &str,
    reg: Registration,
    payload_len: usize,
) -> Result<(OutputService, OutputPublisher), AttachError> {
    let service = node
        .service_builder(&service_name(
            instance,
            control::client_output_service(instance, reg.generation, reg.token),
        )?)
        .publish_subscribe::<[u8]>()
        .user_header::<OutputHeader>()
        .open()
        .map_err(|e| pubsub_error(instance, "this client's output service", e))?;
    let publisher = service
        .publisher_builder()
        .initial_max_slice_len(payload_len)
        .backpressure_strategy(BackpressureStrategy::DiscardData)
        .max_loaned_samples(control::OUTPUT_LOANS)
        // iceoryx2 makes room for as many samples as the service's subscriber may buffer
        // (an asynchronous client's); a synchronous client's segment holds fewer, and a
        // loan beyond them fails as a send to a full buffer would.
        .override_sample_preallocation(move |_| control::output_samples(reg.role))
        .create()
        .map_err(|e| shm(instance, "an output publisher", e))?;
    Ok((service, publisher))
}

impl Connection {
    /// After unregistering: waits, at most `timeout`, until procimgd has let go of this
    /// client's outputs (its cycle thread hands the port back at its next cycle, its control
    /// thread drops it). The client's publisher, dropped after, is then the last user of the
    /// output samples, and unmapping them (and freeing their pages) happens in this process,
    /// not on procimgd's cycle thread, which would otherwise notice the publisher gone at
    /// its next look at the port. Returns whether it did.
    pub fn wait_outputs_released(&self, timeout: Duration) -> bool {
        let deadline = Instant::now() + timeout;
        loop {
            if self
                .outputs_service
                .dynamic_config()
                .number_of_subscribers()
                == 0
            {
                return true;
            }
            if Instant::now() >= deadline {
                return false;
            }
            std::thread::sleep(Duration::from_micros(500));
        }
    }
}

fn read_layout(
    node: &Node<Ipc>,
    instance: &str,
    generation: u64,
    timeout: Duration,
    ring_server: &dyn Fn(),
) -> Result<(Layout, u128), AttachError> {
    let sub = node
        .service_builder(&service_name(
            instance,
            control::layout_service(instance, generation),
        )?)
        .publish_subscribe::<[u8]>()
        .user_header::<LayoutHeader>()
        .open()
        .map_err(|e| pubsub_error(instance, "the layout service", e))?
        .subscriber_builder()
        .create()
        .map_err(|e| shm(instance, "a layout subscriber", e))?;
    // The server hands its layout to a new subscriber in its control thread's round.
    ring_server();
    let until = Instant::now() + timeout;
    loop {
        if let Ok(Some(sample)) = sub.receive() {
            let h = *sample.user_header();
            if h.magic != IMAGE_MAGIC || h.layout_version != LAYOUT_VERSION {
                return Err(AttachError::LayoutVersion {
                    instance: instance.to_string(),
                    server: h.layout_version,
                    client: LAYOUT_VERSION,
                });
            }
            let layout = Layout::decode(&h, sample.payload()).ok_or_else(|| AttachError::Shm {
                instance: instance.to_string(),
                what: "the layout",
                detail: "the layout sample is shorter than its header says".into(),
            })?;
            return Ok((layout, sub.id().value()));
        }
        if Instant::now() >= until {
            return Err(AttachError::Timeout {
                instance: instance.to_string(),
                what: "the layout",
                timeout,
            });
        }
        share_own_files();
        std::thread::sleep(LAYOUT_POLL);
    }
}

/// How often a client looks for the layout while it attaches.
const LAYOUT_POLL: Duration = Duration::from_micros(100);
