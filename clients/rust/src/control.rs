// SPDX-License-Identifier: MIT OR Apache-2.0
//! Requests to the server over the control service, without attaching as a client: what
//! tools such as `procimg status` use, and what [`crate::Client`] uses underneath.

use crate::connection::{ControlPort, Ipc, client_node, open_control};
use crate::error::{AttachError, ControlError};
use iceoryx2::node::Node;
use procimg_control::doorbell::Doorbell;
use procimg_control::{
    self as control, CoreRequest, HistogramsReport, Request, Response, Space, StatusReport,
};
use procimg_shm_layout::Mode;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How long a control request waits for its answer by default: the server answers at
/// normal priority, and late on a loaded machine.
pub const DEFAULT_CONTROL_TIMEOUT: Duration = Duration::from_secs(5);

/// How often a request looks for its answer.
const ANSWER_POLL: Duration = Duration::from_micros(50);
/// How long a request whose server went without taking it waits for that server's
/// successor (procimgd running its station anew starts the next one within this).
const SUCCESSOR_WAIT: Duration = Duration::from_secs(1);
/// How often it looks for the successor meanwhile.
const SUCCESSOR_POLL: Duration = Duration::from_millis(5);

/// A connection to an instance's control service.
pub struct ControlHandle {
    instance: String,
    // The port must be dropped before its node.
    port: ControlPort,
    node: Node<Ipc>,
    /// The server's doorbell, rung after each request (`None`: not found yet, or this server
    /// has none; the request is then answered at the server's next round).
    doorbell: Mutex<Option<Doorbell>>,
    // Last: after every port of this handle (and of the client or services handle it is the
    // last field of) is gone.
    sweep: ConnectionSweep,
}

/// The ports of one handle, whose connection files an access group's client removes itself
/// when they are gone (see [`procimg_shm_layout::share::remove_own_connections`]).
#[derive(Default)]
pub(crate) struct ConnectionSweep {
    ids: std::sync::Mutex<Vec<u128>>,
}

impl ConnectionSweep {
    fn add(&self, ids: &[u128]) {
        self.ids
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .extend_from_slice(ids);
    }
}

impl Drop for ConnectionSweep {
    fn drop(&mut self) {
        let ids = std::mem::take(&mut *self.ids.lock().unwrap_or_else(|e| e.into_inner()));
        if crate::connection::access_group_active() {
            procimg_shm_layout::share::remove_own_connections(control::IOX2_PREFIX, &ids);
        }
    }
}

impl ControlHandle {
    /// Opens the control service of `instance`; `name` names this process in the server's
    /// node list.
    pub fn open(instance: &str, name: &str) -> Result<ControlHandle, AttachError> {
        let node = client_node(instance, name)?;
        let port = open_control(&node, instance)?;
        crate::connection::share_own_files();
        let sweep = ConnectionSweep::default();
        sweep.add(&[port.id().value()]);
        Ok(ControlHandle {
            instance: instance.to_string(),
            port,
            node,
            doorbell: Mutex::new(Doorbell::open(instance).ok()),
            sweep,
        })
    }

    /// Ports made on this handle's node, whose connection files go with the handle.
    pub(crate) fn own_ports(&self, ids: &[u128]) {
        self.sweep.add(ids);
    }

    /// The instance name.
    pub fn instance(&self) -> &str {
        &self.instance
    }

    /// Wakes the server's control thread: a request or a new port waits for it. After a
    /// server restart the new server's doorbell is opened first.
    pub(crate) fn ring_server(&self) {
        let mut doorbell = self.doorbell.lock().unwrap_or_else(|e| e.into_inner());
        if !doorbell
            .as_ref()
            .is_some_and(|d| d.is_current(&self.instance))
        {
            *doorbell = Doorbell::open(&self.instance).ok();
        }
        if let Some(d) = doorbell.as_ref() {
            d.ring();
        }
    }

    /// The node of this handle (clients build their data ports on it).
    pub(crate) fn node(&self) -> &Node<Ipc> {
        &self.node
    }

    /// Sends `req` and waits up to `timeout` for the answer.
    pub fn request(
        &self,
        req: impl Into<Request>,
        timeout: Duration,
    ) -> Result<Response, ControlError> {
        let transport = |detail: String| ControlError::Transport {
            instance: self.instance.clone(),
            detail,
        };
        let bytes = control::encode(&req.into());
        let send = || {
            let sample = self
                .port
                .loan_slice_uninit(bytes.len())
                .map_err(|e| transport(format!("cannot loan a request: {e:?}")))?;
            let pending = sample
                .write_from_slice(&bytes)
                .send()
                .map_err(|e| transport(format!("cannot send the request: {e:?}")))?;
            if pending.number_of_server_connections() == 0 {
                return Err(ControlError::NoServer {
                    instance: self.instance.clone(),
                });
            }
            self.ring_server();
            Ok(pending)
        };
        let mut pending = send()?;
        let mut sent_again = false;
        let mut gone_since: Option<Instant> = None;
        let until = Instant::now() + timeout;
        loop {
            // Asked before the answer is looked for, so that an answer sent just before the
            // server let the request go is still read.
            let held = pending.is_connected();
            match pending.receive() {
                Ok(Some(answer)) => {
                    return control::decode(answer.payload()).map_err(|detail| {
                        ControlError::Protocol {
                            instance: self.instance.clone(),
                            detail,
                        }
                    });
                }
                // The server went without taking the request (procimgd ended a generation,
                // having answered what it took; the next generation's server takes new
                // requests): the request goes once to that successor, as soon as it is
                // there, rather than the caller waiting out its timeout; without one soon,
                // the caller learns at once that there is no server.
                Ok(None) if !held => {
                    let since = *gone_since.get_or_insert_with(Instant::now);
                    if sent_again || since.elapsed() >= SUCCESSOR_WAIT {
                        return Err(ControlError::NoServer {
                            instance: self.instance.clone(),
                        });
                    }
                    match send() {
                        Ok(p) => {
                            pending = p;
                            sent_again = true;
                        }
                        Err(ControlError::NoServer { .. }) => {
                            std::thread::sleep(SUCCESSOR_POLL);
                        }
                        Err(e) => return Err(e),
                    }
                }
                Ok(None) => {}
                Err(e) => return Err(transport(format!("cannot read the answer: {e:?}"))),
            }
            if Instant::now() >= until {
                return Err(ControlError::NoAnswer {
                    instance: self.instance.clone(),
                    timeout,
                });
            }
            // The answer's connection is made when it comes: the access group needs it too.
            crate::connection::share_own_files();
            // Control requests are rare and not on the real-time path: a short sleep between
            // polls costs nothing that matters. The server, woken by the doorbell, answers
            // within tens of microseconds.
            std::thread::sleep(ANSWER_POLL);
        }
    }

    /// Sends a request that is answered with `Done` or a refusal.
    pub fn request_done(&self, req: impl Into<Request>) -> Result<(), ControlError> {
        match self.request(req, DEFAULT_CONTROL_TIMEOUT)? {
            Response::Done => Ok(()),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.instance.clone(),
                detail: format!("{other:?}"),
            }),
        }
    }

    /// The server's state.
    pub fn status(&self) -> Result<StatusReport, ControlError> {
        match self.request(CoreRequest::Status, DEFAULT_CONTROL_TIMEOUT)? {
            Response::Status(s) => Ok(*s),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.instance.clone(),
                detail: format!("{other:?}"),
            }),
        }
    }

    /// The cycle thread's latency histograms since the server started (wake-up, STARTOP →
    /// OPDONE round trip, OPDONE one way, cycle work).
    pub fn histograms(&self) -> Result<HistogramsReport, ControlError> {
        match self.request(CoreRequest::Histograms, DEFAULT_CONTROL_TIMEOUT)? {
            Response::Histograms(h) => Ok(*h),
            Response::Refused(r) => Err(ControlError::Refused(r)),
            other => Err(ControlError::Protocol {
                instance: self.instance.clone(),
                detail: format!("{other:?}"),
            }),
        }
    }

    /// Asks for a mode change. Like IO-Base's `PNIO_set_mode` it returns at once; the change
    /// is confirmed by a MODE event (one per step: OFFLINE ↔ OPERATE passes through CLEAR).
    pub fn set_mode(&self, mode: Mode) -> Result<(), ControlError> {
        self.request_done(CoreRequest::SetMode { mode })
    }

    /// Forces `data` at `address` in `space`, as a PLC's force table does: from the next
    /// cycle on the server holds those bytes at these values (inputs over what the devices
    /// deliver, outputs over what clients write, sent valid in OPERATE), after this handle
    /// and its process are gone, until [`ControlHandle::unforce`] or the server's end. The
    /// bytes must lie in one submodule.
    pub fn force(&self, space: Space, address: u32, data: &[u8]) -> Result<(), ControlError> {
        self.request_done(CoreRequest::Force {
            space,
            address,
            data: data.to_vec(),
        })
    }

    /// Ends the forcing of `length` bytes from `address` in `space` (to the end of the
    /// submodule when `None`).
    pub fn unforce(
        &self,
        space: Space,
        address: u32,
        length: Option<u32>,
    ) -> Result<(), ControlError> {
        self.request_done(CoreRequest::Unforce {
            space,
            address: Some(address),
            length,
        })
    }

    /// Ends every force, in both spaces.
    pub fn unforce_all(&self) -> Result<(), ControlError> {
        self.request_done(CoreRequest::Unforce {
            space: Space::Output,
            address: None,
            length: None,
        })
    }
}
