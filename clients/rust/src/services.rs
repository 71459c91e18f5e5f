// SPDX-License-Identifier: MIT OR Apache-2.0
//! The services besides the process image. Of an IO controller: device events, alarms with
//! acknowledgement, asynchronous record read/write, device activation and diagnosis. Of an
//! IO device (`role = "device"`): the station's events, its AR coming up and ending, the
//! PLC's RUN/STOP and DCP (see [`crate::Client::is_device`] and the device role's notes in
//! its module docs); the controller's requests are refused there with
//! [`Refusal::WrongRole`](crate::Refusal::WrongRole).
//!
//! A [`Services`] handle has its own iceoryx2 node and ports, independent of a [`Client`]:
//! open it on the thread that waits for notifications (the ports are not `Send`), as IO-Base
//! programs get their callbacks on a thread of their own. Jobs are asynchronous as in
//! IO-Base: [`Services::record_read`] returns once the server has taken the job, and its
//! confirmation arrives later as a [`Notification::Record`] carrying the job's reference.
//! [`Services::read_record`] and [`Services::write_record`] wrap that for programs that
//! would rather wait.
//!
//! [`Client`]: crate::Client

mod activation;
mod own_interface;
mod pe;
mod restart;

pub use activation::ActivationError;
pub use restart::RestartError;

pub use own_interface::{AddressChangeError, ControllerAddress, INTERFACE_SUBSLOT, PORT_SUBSLOT};

use crate::connection::{Ipc, event_error, pubsub_error, service_name, shm};
use crate::control::{ControlHandle, DEFAULT_CONTROL_TIMEOUT};
use crate::error::{AttachError, ControlError};
use iceoryx2::port::listener::Listener;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::FileDescriptorBased;
use procimg_control::services::{
    self, AlarmReport, DiagnosisReport, NOTIFICATION_BUFFER, Notification, RecordConfirmation,
    RecordStatus, RecordTarget,
};
use procimg_control::{ControllerRequest, CoreRequest, Response, Tailoring};
use std::collections::VecDeque;
use std::hash::{Hash, Hasher};
use std::os::fd::RawFd;
use std::time::{Duration, Instant};

/// What a [`Services`] handle announces to the server.
#[derive(Clone, Debug)]
pub struct ServiceOptions {
    /// A name for status displays and messages.
    pub name: String,
    /// The server waits for this handle's [`Services::acknowledge`] before it acknowledges
    /// an alarm to the device (IO-Base: when the alarm callback returns). Without it, alarms
    /// are acknowledged as soon as they are delivered. Ignored in the device role, whose
    /// alarms the PLC acknowledges.
    pub acknowledge_alarms: bool,
}

impl ServiceOptions {
    /// Options with `name`, alarms acknowledged by the server.
    pub fn new(name: &str) -> ServiceOptions {
        ServiceOptions {
            name: name.to_string(),
            acknowledge_alarms: false,
        }
    }

    /// Take part in alarm acknowledgement.
    pub fn acknowledge_alarms(mut self, on: bool) -> ServiceOptions {
        self.acknowledge_alarms = on;
        self
    }
}

/// Why a waited-for record job failed.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The server did not take the job.
    #[error(transparent)]
    Control(#[from] ControlError),
    /// No confirmation came in time.
    #[error(
        "no confirmation of the record job within {0:?}: the device may be slow or gone; \
         check `procimg status`"
    )]
    Timeout(Duration),
    /// The device (or the controller) answered with an error.
    #[error(
        "record job failed with status {:02X} {:02X} {:02X} {:02X}: {message}",
        status.error_code, status.error_decode, status.error_code1, status.error_code2
    )]
    Failed {
        /// The PNIOStatus and additional values.
        status: RecordStatus,
        /// The failure in words.
        message: String,
    },
}

/// A handle on the services of an instance: an IO controller's, or an IO device's station
/// events.
pub struct Services {
    id: u64,
    options: ServiceOptions,
    queue: VecDeque<Notification>,
    next_reference: u64,
    lost: u64,
    /// The generation of the server this handle is announced to, once known.
    generation: Option<u64>,
    /// That server's process id (0: not known).
    server_pid: u32,
    fd: RawFd,
    // Ports before the node (in `control`) they live on.
    listener: Listener<Ipc>,
    subscriber: Subscriber<Ipc, [u8], ()>,
    control: ControlHandle,
}

impl Services {
    /// Opens the services of `instance` and announces this handle.
    pub fn open(instance: &str, options: ServiceOptions) -> Result<Services, AttachError> {
        let control = ControlHandle::open(instance, &options.name)?;
        let node = control.node();
        let subscriber = node
            .service_builder(&service_name(
                instance,
                services::notification_service(instance),
            )?)
            .publish_subscribe::<[u8]>()
            .open()
            .map_err(|e| pubsub_error(instance, "the notification service", e))?
            .subscriber_builder()
            .buffer_size(NOTIFICATION_BUFFER)
            .create()
            .map_err(|e| shm(instance, "a notification subscriber", e))?;
        let listener = node
            .service_builder(&service_name(
                instance,
                services::notify_event_service(instance),
            )?)
            .event()
            .open()
            .map_err(|e| event_error(instance, "the notify event service", e))?
            .listener_builder()
            .create()
            .map_err(|e| shm(instance, "a notify event listener", e))?;
        crate::connection::share_own_files();
        control.own_ports(&[subscriber.id().value()]);
        // SAFETY: the descriptor belongs to `listener`, which lives as long as this handle
        // and so outlives every use of the descriptor.
        #[allow(unsafe_code)]
        let fd = unsafe { listener.file_descriptor().native_handle() };
        let mut h = std::collections::hash_map::DefaultHasher::new();
        node.id().to_string().hash(&mut h);
        std::process::id().hash(&mut h);
        let mut s = Services {
            id: h.finish(),
            options,
            queue: VecDeque::new(),
            next_reference: 1,
            lost: 0,
            generation: None,
            server_pid: 0,
            fd,
            listener,
            subscriber,
            control,
        };
        s.announce().map_err(|e| match e {
            ControlError::NoServer { .. } => AttachError::NoServer {
                instance: instance.to_string(),
            },
            ControlError::NoAnswer { timeout, .. } => AttachError::Timeout {
                instance: instance.to_string(),
                what: "the subscription",
                timeout,
            },
            ControlError::Refused(refusal) => AttachError::Refused {
                instance: instance.to_string(),
                refusal,
            },
            e => AttachError::Shm {
                instance: instance.to_string(),
                what: "a subscription",
                detail: e.to_string(),
            },
        })?;
        s.learn_server();
        Ok(s)
    }

    /// Asks the server announced to for its generation and process id; left unknown when it
    /// does not answer.
    pub(crate) fn learn_server(&mut self) {
        match self.control.status() {
            Ok(st) => {
                self.generation = Some(st.generation);
                self.server_pid = st.pid;
            }
            Err(_) => self.server_pid = 0,
        }
    }

    pub(crate) fn announce(&self) -> Result<(), ControlError> {
        self.control.request_done(CoreRequest::Subscribe {
            subscriber: self.id,
            name: self.options.name.clone(),
            pid: std::process::id(),
            node_id: self.control.node().id().to_string(),
            acknowledge_alarms: self.options.acknowledge_alarms,
        })
    }

    /// This handle's id: the `reply_to` of its jobs.
    pub fn id(&self) -> u64 {
        self.id
    }

    /// The control connection, for other requests (status, mode).
    pub fn control(&self) -> &ControlHandle {
        &self.control
    }

    /// The descriptor that becomes readable when notifications arrive, for a caller that waits
    /// in its own `poll` and then calls [`Services::try_next`].
    pub fn notify_fd(&self) -> RawFd {
        self.fd
    }

    /// The generation of the server this handle is announced to: learnt at
    /// [`Services::open`] and from every [`Notification::ServerStarted`] taken since. Jobs
    /// sent now go to that server; `None` when it did not say.
    pub fn generation(&self) -> Option<u64> {
        self.generation
    }

    /// Whether the server this handle is announced to still runs: `Some(false)` once its
    /// process is gone (a crash, a kill: it sends no notification then), `None` when that
    /// cannot be told now. A new server's [`Notification::ServerStarted`] makes it the one
    /// looked for.
    pub fn server_alive(&self) -> Option<bool> {
        crate::client::server_listed(self.control.instance(), self.server_pid)
    }

    /// Notifications lost because this handle fell more than the subscriber buffer behind.
    pub fn lost(&self) -> u64 {
        self.lost
    }

    /// Takes what arrived, keeping what is for this handle.
    fn drain(&mut self) {
        let _ = self.listener.try_wait(|_| {});
        while let Ok(Some(sample)) = self.subscriber.receive() {
            let Ok(n) = procimg_control::decode::<Notification>(sample.payload()) else {
                continue;
            };
            if n.reply_to().is_some_and(|to| to != self.id) {
                continue;
            }
            if let Notification::ServerStarted { generation } = n {
                // A new server knows nothing of this handle: announce again, so that its
                // alarms wait for our acknowledgement again.
                let _ = self.announce();
                if self.generation != Some(generation) {
                    self.generation = Some(generation);
                    self.server_pid = self
                        .control
                        .status()
                        .ok()
                        .filter(|st| st.generation == generation)
                        .map_or(0, |st| st.pid);
                }
            }
            if self.queue.len() >= NOTIFICATION_BUFFER * 4 {
                self.queue.pop_front();
                self.lost += 1;
            }
            self.queue.push_back(n);
        }
    }

    /// The next notification if one is there.
    pub fn try_next(&mut self) -> Option<Notification> {
        if self.queue.is_empty() {
            self.drain();
        }
        self.queue.pop_front()
    }

    /// The next notification, waiting up to `timeout` for one.
    pub fn next(&mut self, timeout: Duration) -> Option<Notification> {
        let until = Instant::now() + timeout;
        loop {
            if let Some(n) = self.try_next() {
                return Some(n);
            }
            let now = Instant::now();
            if now >= until {
                return None;
            }
            let ns = (until - now).as_nanos().min(u64::MAX as u128) as u64;
            // A wake-up may come before the sample is visible, or without one for us: the
            // loop looks again either way.
            procimg_shm_layout::os::wait_readable(self.fd, ns.min(100_000_000));
        }
    }

    /// Acknowledges an alarm (IO-Base: the alarm callback returned). Needed only with
    /// [`ServiceOptions::acknowledge_alarms`]; an alarm that no longer waits for this handle
    /// (acknowledged by a timeout, or older than the subscription) is refused with
    /// `UnknownAlarm`, which callers may ignore.
    pub fn acknowledge(&self, alarm: &AlarmReport) -> Result<(), ControlError> {
        self.control
            .request_done(ControllerRequest::AcknowledgeAlarm {
                subscriber: self.id,
                alarm: alarm.id,
            })
    }

    fn accepted(&self, req: impl Into<procimg_control::Request>) -> Result<(), ControlError> {
        match self.control.request(req, DEFAULT_CONTROL_TIMEOUT)? {
            Response::Accepted | Response::Done => Ok(()),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.control.instance().to_string(),
                detail: format!("{other:?}"),
            }),
        }
    }

    /// Starts a record read of at most `max_len` bytes; the data arrives as a
    /// [`Notification::Record`] with `reference`.
    pub fn record_read(
        &self,
        target: RecordTarget,
        max_len: u32,
        reference: u64,
    ) -> Result<(), ControlError> {
        self.accepted(ControllerRequest::RecordRead {
            reply_to: self.id,
            reference,
            target,
            max_len,
        })
    }

    /// Starts a record write; the result arrives as a [`Notification::Record`] with
    /// `reference`.
    pub fn record_write(
        &self,
        target: RecordTarget,
        data: &[u8],
        reference: u64,
    ) -> Result<(), ControlError> {
        self.accepted(ControllerRequest::RecordWrite {
            reply_to: self.id,
            reference,
            target,
            data: data.to_vec(),
        })
    }

    /// Reads a record and waits for it; other notifications that arrive meanwhile stay
    /// queued for [`Services::next`].
    pub fn read_record(
        &mut self,
        target: RecordTarget,
        max_len: u32,
        timeout: Duration,
    ) -> Result<Vec<u8>, RecordError> {
        let reference = self.take_reference();
        self.record_read(target, max_len, reference)?;
        self.await_record(reference, timeout).map(|c| c.data)
    }

    /// Writes a record and waits for the device's answer.
    pub fn write_record(
        &mut self,
        target: RecordTarget,
        data: &[u8],
        timeout: Duration,
    ) -> Result<(), RecordError> {
        let reference = self.take_reference();
        self.record_write(target, data, reference)?;
        self.await_record(reference, timeout).map(|_| ())
    }

    /// A reference for a waited-for job, from a range callers of the asynchronous functions
    /// are unlikely to use.
    fn take_reference(&mut self) -> u64 {
        self.next_reference += 1;
        (1 << 63) | self.next_reference
    }

    fn await_record(
        &mut self,
        reference: u64,
        timeout: Duration,
    ) -> Result<RecordConfirmation, RecordError> {
        let found = self.await_notification(timeout, |n| {
            matches!(n, Notification::Record { confirmation, .. }
                if confirmation.reference == reference)
        });
        match found {
            Some(Notification::Record { confirmation, .. }) if confirmation.status.is_ok() => {
                Ok(confirmation)
            }
            Some(Notification::Record { confirmation, .. }) => Err(RecordError::Failed {
                status: confirmation.status,
                message: confirmation.message,
            }),
            _ => Err(RecordError::Timeout(timeout)),
        }
    }

    /// Waits up to `timeout` for the first notification `wanted` picks and takes it from
    /// the queue; the others stay.
    fn await_notification(
        &mut self,
        timeout: Duration,
        wanted: impl Fn(&Notification) -> bool,
    ) -> Option<Notification> {
        let until = Instant::now() + timeout;
        loop {
            self.drain();
            if let Some(i) = self.queue.iter().position(&wanted) {
                return self.queue.remove(i);
            }
            let now = Instant::now();
            if now >= until {
                return None;
            }
            let ns = (until - now).as_nanos().min(u64::MAX as u128) as u64;
            procimg_shm_layout::os::wait_readable(self.fd, ns.min(100_000_000));
        }
    }

    /// Activates or deactivates a device (IO-Base `PNIO_device_activate`; not in OFFLINE).
    /// Confirmed by a [`Notification::Activation`]; the state change itself follows as
    /// device notifications (DEV_RETURN, DEV_FAILURE), in either order.
    pub fn activate(&self, device: u32, active: bool) -> Result<(), ControlError> {
        self.control
            .request_done(ControllerRequest::ActivateDevice {
                reply_to: self.id,
                device,
                active,
            })
    }

    /// Reconfigures the IO system (IO-Base `PNIO_iosystem_reconfig`): with `None`
    /// deactivates every device; with a [`Tailoring`] takes every device down, writes the
    /// joined ports' expected neighbours, and brings up the mandatory devices and the
    /// optional ones it names. Confirmed by a [`Notification::Reconfigured`] (which says
    /// why, if the tailoring was refused); the devices' state changes follow as device
    /// notifications.
    pub fn reconfigure_io_system(&self, tailoring: Option<Tailoring>) -> Result<(), ControlError> {
        self.control
            .request_done(ControllerRequest::ReconfigureIoSystem {
                reply_to: self.id,
                tailoring,
            })
    }

    /// The state of every device.
    pub fn diagnosis(&self) -> Result<DiagnosisReport, ControlError> {
        match self
            .control
            .request(ControllerRequest::Diagnosis, DEFAULT_CONTROL_TIMEOUT)?
        {
            Response::Diagnosis(d) => Ok(*d),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.control.instance().to_string(),
                detail: format!("{other:?}"),
            }),
        }
    }

    /// Starts the controller interface's communication counters
    /// ([`StatusReport::controller`](crate::StatusReport)'s `counters`) again from 0, as
    /// IO-Base's RESET_COMM_COUNTERS does.
    pub fn reset_comm_counters(&self) -> Result<(), ControlError> {
        match self.control.request(
            ControllerRequest::ResetCommCounters,
            DEFAULT_CONTROL_TIMEOUT,
        )? {
            Response::Done => Ok(()),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.control.instance().to_string(),
                detail: format!("{other:?}"),
            }),
        }
    }
}

impl Drop for Services {
    fn drop(&mut self) {
        let _ = self.control.request(
            CoreRequest::Unsubscribe {
                subscriber: self.id,
            },
            Duration::from_millis(500),
        );
    }
}
