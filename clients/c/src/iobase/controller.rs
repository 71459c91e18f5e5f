// SPDX-License-Identifier: MIT OR Apache-2.0
//! One open IO-Base controller: its client, its mode, its callbacks and the library threads
//! that deliver them; and the process-wide table of handles.
//!
//! Threads of a controller:
//! * the **event thread** waits on the client's event descriptor (without holding the
//!   client), takes STARTOP windows, mode changes, OPFAULT and NEWCYCLE from the client and
//!   calls MODE_IND and the isochronous callbacks, one at a time, in the order they happened
//!   (its loop is `super::cycle_thread`'s, shared with the device's isochronous thread; the
//!   modes are the controller's part);
//! * the services worker (`super::services`) delivers record, alarm, activation and
//!   diagnosis callbacks, and keeps which devices are in data exchange (for
//!   `PNIO_ERR_NO_CONNECTION`) as the server's notifications say, before the callbacks of
//!   the same change: the data functions and DEV_FAILURE / DEV_RETURN agree. At open the
//!   server's status report gives the first value.

use super::callbacks::CallbackTable;
use super::cycle_thread::{self, CycleSide};
use super::devices_up::DevicesUp;
use super::errors::*;
use super::handles;
use super::isochronous::{self, Window};
use super::services::{ServiceContext, ServiceWorker};
use super::stopped;
use super::sync::lock;
use super::types::*;
use super::wake_ahead_env;
use procimg_client::{
    AttachError, AttachOptions, Client, ControlError, ControlHandle, DeviceState, Event, Layout,
    Mode, Refusal,
};
use std::collections::{BTreeMap, VecDeque};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long `PNIO_controller_open` waits for the server to reach OFFLINE (and for the
/// first image).
const OPEN_WAIT: Duration = Duration::from_secs(5);

/// The client side of a controller, behind one lock: IO-Base's data functions are not
/// reentrant, and callbacks on library threads may call them while the program does.
pub(crate) struct Io {
    /// `None` only when re-attaching failed (the server went away meanwhile).
    pub client: Option<Client>,
    /// The open STARTOP..OPDONE window of an isochronous controller.
    pub window: Window,
}

/// The controller's mode as the program sees it.
struct ModeState {
    /// The mode last reported (or found at open).
    mode: PNIO_MODE_TYPE,
    /// The mode a `PNIO_set_mode` asked for, until it is reported.
    pending: Option<PNIO_MODE_TYPE>,
    /// Modes to report without a change on the server (set_mode to the current mode).
    echo: VecDeque<PNIO_MODE_TYPE>,
}

/// One open controller.
pub(crate) struct Controller {
    /// The PNIO handle.
    pub handle: u32,
    /// The CpIndex it was opened with.
    pub cp_index: u32,
    /// The procimgd instance the CpIndex names.
    pub instance: String,
    /// Opened with `PNIO_CEP_MODE_CTRL`: the program controls the server's mode.
    pub mode_ctrl: bool,
    /// Opened with `PNIO_CEP_SLICE_ACCESS`.
    pub slice: bool,
    /// The server's layout (the logical addresses).
    pub layout: Layout,
    /// The program's callbacks.
    pub callbacks: Arc<CallbackTable>,
    /// True once STARTOP is registered (and the client synchronous).
    pub isochronous: Arc<AtomicBool>,
    /// The client and the open window.
    pub io: Mutex<Io>,
    mode: Mutex<ModeState>,
    /// Per device of the layout: in data exchange, as the server's notifications said
    /// (kept by the services worker).
    devices_up: Arc<DevicesUp>,
    control: Mutex<ControlHandle>,
    /// Set by close: the threads end.
    stop: AtomicBool,
    /// Set once close began: the handle is no longer usable.
    closed: AtomicBool,
    threads: Mutex<Vec<JoinHandle<()>>>,
    services: Mutex<Option<ServiceWorker>>,
}

static CONTROLLERS: Mutex<BTreeMap<u32, Arc<Controller>>> = Mutex::new(BTreeMap::new());

/// The open controller with this handle (not one being closed, nor one the watchdog's
/// expiry stopped).
pub(crate) fn lookup(handle: u32) -> Option<Arc<Controller>> {
    lookup_any(handle).filter(|c| !stopped::expired(c.handle))
}

/// The open controller with this handle, also after the watchdog's expiry (for close).
fn lookup_any(handle: u32) -> Option<Arc<Controller>> {
    lock(&CONTROLLERS)
        .get(&handle)
        .filter(|c| !c.closed.load(Ordering::Acquire))
        .cloned()
}

/// The controller with this handle for the IO data functions: also while it is being
/// closed, because its callbacks may still run then and may use them.
pub(crate) fn lookup_io(handle: u32) -> Option<Arc<Controller>> {
    lock(&CONTROLLERS)
        .get(&handle)
        .filter(|c| !stopped::expired(c.handle))
        .cloned()
}

/// Whether `handle` is a controller's (open, or being closed).
pub(crate) fn is_controller(handle: u32) -> bool {
    lock(&CONTROLLERS).contains_key(&handle)
}

/// The open controllers on procimgd instance `instance`.
pub(crate) fn on_instance(instance: &str) -> Vec<Arc<Controller>> {
    lock(&CONTROLLERS)
        .values()
        .filter(|c| c.instance == instance && !c.closed.load(Ordering::Acquire))
        .cloned()
        .collect()
}

/// The text for a handle that is not (or no longer) open; for one the watchdog's expiry
/// stopped, the watchdog's answer.
pub(crate) fn wrong_handle(function: &str, handle: u32) -> u32 {
    if stopped::expired(handle) && is_controller(handle) {
        return stopped::refused(function, handle);
    }
    fail(
        function,
        PNIO_ERR_WRONG_HND,
        format_args!(
            "handle {handle} is not an open controller (closed, or never returned by \
             PNIO_controller_open)"
        ),
    )
}

/// The handles of the controllers open now.
pub(crate) fn open_handles() -> Vec<u32> {
    lock(&CONTROLLERS).keys().copied().collect()
}

/// `PNIO_ERR_PRM_CP_ID`, said for function `f`, unless `cp` is a CpIndex (1..255).
pub(crate) fn check_cp_index(f: &str, cp: u32) -> Result<(), u32> {
    if cp == 0 || cp > 255 {
        return Err(fail(
            f,
            PNIO_ERR_PRM_CP_ID,
            format_args!("CpIndex {cp} is not 1..255"),
        ));
    }
    Ok(())
}

/// The procimgd instance CpIndex `cp` names, once [`check_cp_index`] took it.
pub(crate) fn cp_instance(f: &str, cp: u32) -> Result<String, u32> {
    check_cp_index(f, cp).map(|()| instance_for(cp))
}

/// The procimgd instance that CpIndex `cp` names.
pub(crate) fn instance_for(cp: u32) -> String {
    std::env::var(format!("PROCIMG_CP{cp}"))
        .ok()
        .filter(|s| !s.is_empty())
        .or_else(|| {
            std::env::var("PROCIMG_INSTANCE")
                .ok()
                .filter(|s| !s.is_empty())
        })
        .unwrap_or_else(|| "procimg".to_string())
}

/// IO-Base's mode value of a procimg mode.
pub(crate) fn pnio_mode(m: Mode) -> PNIO_MODE_TYPE {
    match m {
        Mode::Offline => PNIO_MODE_OFFLINE,
        Mode::Clear => PNIO_MODE_CLEAR,
        Mode::Operate => PNIO_MODE_OPERATE,
    }
}

/// What opening needs besides the callbacks.
pub(crate) struct OpenRequest {
    /// `CpIndex`.
    pub cp_index: u32,
    /// `ExtPar`, checked.
    pub ext_par: u32,
    /// `cbf_rec_read_conf`, not NULL.
    pub rec_read: PNIO_CBF,
    /// `cbf_rec_write_conf`, not NULL.
    pub rec_write: PNIO_CBF,
    /// `cbf_alarm_ind`, may be NULL.
    pub alarm: PNIO_CBF,
}

const OPEN: &str = "PNIO_controller_open";

/// The IO-Base code and text for a failed attach.
fn attach_failure(cp: u32, instance: &str, e: &AttachError) -> u32 {
    let code = match e {
        AttachError::NoServer { .. } => PNIO_ERR_NO_CONFIG,
        AttachError::Timeout { .. } => PNIO_ERR_NO_FW_COMMUNICATION,
        AttachError::Refused {
            refusal: Refusal::TooManyClients { .. },
            ..
        } => PNIO_ERR_MAX_REACHED,
        _ => PNIO_ERR_CREATE_INSTANCE,
    };
    fail(
        OPEN,
        code,
        format_args!(
            "CpIndex {cp} is procimg instance \"{instance}\" (PROCIMG_CP{cp} or PROCIMG_INSTANCE): {e}"
        ),
    )
}

/// Attaches with `opts` and claims every output submodule.
fn attach_and_claim(cp: u32, instance: &str, opts: AttachOptions) -> Result<Client, u32> {
    let mut client =
        Client::attach(instance, opts).map_err(|e| attach_failure(cp, instance, &e))?;
    if client.is_device() {
        return Err(fail(
            OPEN,
            PNIO_ERR_INVALID_CONFIG,
            format_args!(
                "instance \"{instance}\" is an IO device (role = \"device\"): the IO-Base \
                 controller interface needs a procimgd in the controller role"
            ),
        ));
    }
    let outputs: Vec<usize> = client.layout().output_submodules().collect();
    if !outputs.is_empty() {
        client.claim(&outputs).map_err(|e| {
            let code = match e {
                ControlError::Refused(_) => PNIO_ERR_MAX_REACHED,
                _ => PNIO_ERR_NO_FW_COMMUNICATION,
            };
            fail(
                OPEN,
                code,
                format_args!(
                    "the controller owns every output of instance \"{instance}\", but they \
                     cannot be claimed: {e}; close the other controller or client first \
                     (`procimg status --instance {instance}` names it)"
                ),
            )
        })?;
    }
    Ok(client)
}

/// Waits until the client has an image, and with `offline` until it shows OFFLINE.
fn wait_for_image(client: &mut Client, offline: bool) -> bool {
    let until = Instant::now() + OPEN_WAIT;
    loop {
        let ok = match client.mode() {
            Some(m) => !offline || m == Mode::Offline,
            None => false,
        };
        if ok {
            return true;
        }
        if Instant::now() >= until {
            return false;
        }
        // The cycle is only a way to wait for the next image (the client is asynchronous).
        let _ = client.wait_startop(Duration::from_millis(20));
    }
}

/// Which devices of `layout` are in data exchange according to the server.
fn devices_running(control: &ControlHandle, layout: &Layout) -> Option<Vec<bool>> {
    let report = control.status().ok()?;
    Some(
        (0..layout.devices.len())
            .map(|d| {
                let name = layout.device_name(d);
                report
                    .devices
                    .iter()
                    .find(|r| r.name == name)
                    .is_some_and(|r| r.state == DeviceState::Running)
            })
            .collect(),
    )
}

impl Controller {
    /// `PNIO_controller_open` after the parameter checks.
    pub(crate) fn open(req: OpenRequest) -> Result<u32, u32> {
        let cp = req.cp_index;
        let instance = instance_for(cp);
        let handle = handles::next();
        let mode_ctrl = req.ext_par & PNIO_CEP_MODE_CTRL != 0;
        let slice = req.ext_par & PNIO_CEP_SLICE_ACCESS != 0;
        let name = format!("PNIO controller {handle} (CP {cp})");
        let opts = AttachOptions::asynchronous(&name).slice_access(slice);
        let mut client = attach_and_claim(cp, &instance, opts)?;
        let control = ControlHandle::open(&instance, &format!("{name} control"))
            .map_err(|e| attach_failure(cp, &instance, &e))?;
        if mode_ctrl {
            // IO-Base: the controller is OFFLINE after open.
            control.set_mode(Mode::Offline).map_err(|e| {
                fail(
                    OPEN,
                    PNIO_ERR_NO_FW_COMMUNICATION,
                    format_args!("instance \"{instance}\" did not take the mode OFFLINE: {e}"),
                )
            })?;
        }
        if !wait_for_image(&mut client, mode_ctrl) {
            return Err(fail(
                OPEN,
                PNIO_ERR_NO_FW_COMMUNICATION,
                format_args!(
                    "instance \"{instance}\" did not {} within {OPEN_WAIT:?}: is procimgd \
                     cycling? (`procimg status --instance {instance}`)",
                    if mode_ctrl {
                        "reach OFFLINE"
                    } else {
                        "publish an image"
                    }
                ),
            ));
        }
        // The way to OFFLINE is not reported (IO-Base: nothing is registered yet).
        let _ = client.events();
        let mode = client.mode().map_or(PNIO_MODE_OFFLINE, pnio_mode);
        let layout = client.layout().clone();
        let devices_up = Arc::new(DevicesUp::new(layout.devices.len()));
        let callbacks = Arc::new(CallbackTable::new());
        callbacks.set_once(PNIO_CBE_REC_READ_CONF, req.rec_read);
        callbacks.set_once(PNIO_CBE_REC_WRITE_CONF, req.rec_write);
        if req.alarm.is_some() {
            callbacks.set_once(PNIO_CBE_ALARM_IND, req.alarm);
        }
        let isochronous = Arc::new(AtomicBool::new(false));
        let services = ServiceWorker::start(ServiceContext {
            instance: instance.clone(),
            handle,
            cp_index: cp,
            layout: layout.clone(),
            callbacks: callbacks.clone(),
            devices_up: devices_up.clone(),
        })?;
        // Read after the worker subscribed, so that no change between falls through. In
        // OFFLINE no device exchanges data, whatever the report (which may lag behind the
        // mode) says.
        if mode != PNIO_MODE_OFFLINE {
            devices_up.take_status(|| devices_running(&control, &layout));
        }
        let ctl = Arc::new(Controller {
            handle,
            cp_index: cp,
            instance,
            mode_ctrl,
            slice,
            layout,
            callbacks,
            isochronous,
            io: Mutex::new(Io {
                client: Some(client),
                window: Window::default(),
            }),
            mode: Mutex::new(ModeState {
                mode,
                pending: None,
                echo: VecDeque::new(),
            }),
            devices_up,
            control: Mutex::new(control),
            stop: AtomicBool::new(false),
            closed: AtomicBool::new(false),
            threads: Mutex::new(Vec::new()),
            services: Mutex::new(Some(services)),
        });
        let started = [("ev", event_thread as fn(Arc<Controller>))]
            .into_iter()
            .try_for_each(|(tag, f)| {
                let c = ctl.clone();
                let t = std::thread::Builder::new()
                    .name(format!("pnio-{tag}-{handle}"))
                    .spawn(move || f(c))?;
                lock(&ctl.threads).push(t);
                Ok::<(), std::io::Error>(())
            });
        if let Err(e) = started {
            ctl.shut_down();
            return Err(fail(
                OPEN,
                PNIO_ERR_START_THREAD_FAILED,
                format_args!("cannot start the controller's threads: {e}"),
            ));
        }
        lock(&CONTROLLERS).insert(handle, ctl);
        Ok(handle)
    }

    /// `PNIO_controller_close` after the checks: stops the threads (a callback running now
    /// finishes first), then lets go of the client and the handle.
    pub(crate) fn close(handle: u32) -> u32 {
        let Some(ctl) = lookup_any(handle) else {
            return wrong_handle("PNIO_controller_close", handle);
        };
        if ctl.closed.swap(true, Ordering::AcqRel) {
            return wrong_handle("PNIO_controller_close", handle);
        }
        ctl.shut_down();
        PNIO_OK
    }

    /// Stops the threads and the services (a callback running now finishes first), forgets
    /// the callbacks, frees the handle, then lets go of the client.
    fn shut_down(&self) {
        self.closed.store(true, Ordering::Release);
        self.stop.store(true, Ordering::Release);
        let threads: Vec<_> = lock(&self.threads).drain(..).collect();
        for t in threads {
            // A panic on that thread already ended it.
            let _ = t.join();
        }
        if let Some(s) = lock(&self.services).take() {
            s.stop();
        }
        self.callbacks.clear();
        lock(&CONTROLLERS).remove(&self.handle);
        stopped::forget(self.handle);
        let mut io = lock(&self.io);
        io.window = Window::default();
        // Unregisters from the server: the claims go with it.
        io.client = None;
    }

    /// The watchdog expired: the outputs go out BAD from now on (the event thread answers
    /// every later cycle so).
    pub(crate) fn outputs_bad(&self) {
        let mut guard = lock(&self.io);
        let io = &mut *guard;
        let Some(client) = io.client.as_mut() else {
            return;
        };
        if io.window.is_open() {
            io.window.finish_bad(client);
        } else {
            isochronous::outputs_bad(client);
        }
    }

    /// The services worker (for the record, activation and diagnosis functions).
    pub(crate) fn with_services<R>(&self, f: impl FnOnce(&ServiceWorker) -> R) -> Option<R> {
        lock(&self.services).as_ref().map(f)
    }

    /// Whether the controller is in OFFLINE and not on its way out of it.
    pub(crate) fn offline(&self) -> bool {
        let m = lock(&self.mode);
        m.mode == PNIO_MODE_OFFLINE && m.pending.is_none_or(|p| p == PNIO_MODE_OFFLINE)
    }

    /// The mode as last reported.
    pub(crate) fn mode(&self) -> PNIO_MODE_TYPE {
        lock(&self.mode).mode
    }

    /// Whether callbacks may be registered now: in OFFLINE (a controller without
    /// PNIO_CEP_MODE_CTRL never changes its own mode, so it may register at any time).
    pub(crate) fn may_register(&self) -> bool {
        !self.mode_ctrl || self.offline()
    }

    /// Whether device `d` is in data exchange.
    pub(crate) fn device_up(&self, d: usize) -> bool {
        self.devices_up.get(d)
    }

    /// `PNIO_set_mode` after the checks of the handle and the caller.
    pub(crate) fn set_mode(&self, mode: PNIO_MODE_TYPE) -> u32 {
        const F: &str = "PNIO_set_mode";
        let target = match mode {
            PNIO_MODE_OFFLINE => Mode::Offline,
            PNIO_MODE_CLEAR => Mode::Clear,
            PNIO_MODE_OPERATE => Mode::Operate,
            other => {
                return fail(
                    F,
                    PNIO_ERR_MODE_VALUE,
                    format_args!(
                        "Mode {other} is none of PNIO_MODE_OFFLINE (0), PNIO_MODE_CLEAR (1), \
                         PNIO_MODE_OPERATE (2)"
                    ),
                );
            }
        };
        if !self.mode_ctrl {
            return fail(
                F,
                PNIO_ERR_SET_MODE_NOT_ALLOWED,
                format_args!(
                    "controller {} was opened without PNIO_CEP_MODE_CTRL: it observes the \
                     mode of instance \"{}\" but may not change it",
                    self.handle, self.instance
                ),
            );
        }
        if self.callbacks.get(PNIO_CBE_MODE_IND).is_none() {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                "register the PNIO_CBE_MODE_IND callback (PNIO_register_cbf, in OFFLINE) \
                 before changing the mode: it reports the change",
            );
        }
        {
            let mut m = lock(&self.mode);
            if let Some(p) = m.pending {
                return fail(
                    F,
                    PNIO_ERR_SEQUENCE,
                    format_args!(
                        "the mode {p} asked for before has not been reported by \
                         PNIO_CBE_MODE_IND yet; wait for it, then ask again"
                    ),
                );
            }
            m.pending = Some(mode);
            if m.mode == mode {
                // No change on the server, so no MODE event: report the mode as it is.
                m.echo.push_back(mode);
                return PNIO_OK;
            }
        }
        // Outside the mode lock: the event thread reports steps meanwhile.
        match lock(&self.control).set_mode(target) {
            Ok(()) => PNIO_OK,
            Err(e) => {
                lock(&self.mode).pending = None;
                let code = match e {
                    ControlError::Refused(_) => PNIO_ERR_SET_MODE_NOT_ALLOWED,
                    _ => PNIO_ERR_NO_FW_COMMUNICATION,
                };
                fail(
                    F,
                    code,
                    format_args!("instance \"{}\" did not take the mode: {e}", self.instance),
                )
            }
        }
    }

    /// Re-attaches the client as the registered isochronous callbacks need: synchronous
    /// once STARTOP is registered, with NEWCYCLE events once NEWCYCLE is. In OFFLINE,
    /// where the outputs are lost anyway.
    pub(crate) fn reattach(&self) -> Result<(), u32> {
        let sync = self.callbacks.get_cp(PNIO_CP_CBE_STARTOP_IND).is_some();
        let newcycle = self.callbacks.get_cp(PNIO_CP_CBE_NEWCYCLE_IND).is_some();
        let name = format!("PNIO controller {} (CP {})", self.handle, self.cp_index);
        let opts = if sync {
            AttachOptions::synchronous(&name).wake_ahead(
                wake_ahead_env::from_env()
                    .map_err(|e| fail(isochronous::REGISTER, PNIO_ERR_INVALID_CONFIG, e))?,
            )
        } else {
            AttachOptions::asynchronous(&name)
        }
        .slice_access(self.slice)
        .newcycle(newcycle)
        .expect_layout_hash(self.layout.hash());
        let mut io = lock(&self.io);
        // A window open now (a STARTOP_IND still running on the event thread) ends here: its
        // PNIO_CP_set_opdone is answered as a late one, not refused.
        io.window.end();
        // The old registration goes first: its claims are the new one's to take.
        io.client = None;
        let mut client = attach_and_claim(self.cp_index, &self.instance, opts)?;
        let _ = wait_for_image(&mut client, false);
        let _ = client.events();
        io.client = Some(client);
        self.isochronous.store(sync, Ordering::Release);
        Ok(())
    }

    /// Reports a mode: updates the state first (the program may ask for the next mode as
    /// soon as it sees this one), then calls MODE_IND.
    fn report_mode(&self, mode: PNIO_MODE_TYPE) {
        // OFFLINE takes the connections down, and each device's state notification says so
        // (the data functions refuse in OFFLINE meanwhile). Clearing every device here would
        // race with them: this report comes from the image stream, the notifications from the
        // services worker, and a report of the OFFLINE that `PNIO_controller_open` asked for
        // could come after the devices had come up again, leaving them down for good.
        {
            let mut m = lock(&self.mode);
            m.mode = mode;
            if m.pending == Some(mode) {
                m.pending = None;
            }
        }
        let mut prm = PNIO_CBE_PRM::new(PNIO_CBE_MODE_IND, self.handle);
        prm.u.ModeInd = PNIO_CBE_PRM_MODE_IND { Mode: mode };
        CallbackTable::invoke(self.callbacks.get(PNIO_CBE_MODE_IND), &mut prm);
    }
}

/// The event thread's view of a controller: MODE_IND besides the isochronous callbacks.
struct EventThread {
    ctl: Arc<Controller>,
    /// The client re-attached to a restarted server: its mode is to be compared with the
    /// one reported.
    resync: bool,
}

impl CycleSide for EventThread {
    // MODE_IND and the events go on: only the cycles end (the watchdog's rule).
    const EVENTS_WHEN_STOPPED: bool = true;

    fn stopping(&self) -> bool {
        self.ctl.stop.load(Ordering::Acquire)
    }

    fn handle(&self) -> u32 {
        self.ctl.handle
    }

    fn cp_index(&self) -> u32 {
        self.ctl.cp_index
    }

    fn callbacks(&self) -> &CallbackTable {
        &self.ctl.callbacks
    }

    fn synchronous(&self) -> bool {
        self.ctl.isochronous.load(Ordering::Acquire)
    }

    fn with_io<R>(&self, f: impl FnOnce(&mut Client, &mut Window) -> R) -> Option<R> {
        let mut guard = lock(&self.ctl.io);
        let io = &mut *guard;
        io.client.as_mut().map(|client| f(client, &mut io.window))
    }

    fn look_asynchronous(&self, client: &mut Client) {
        if !client.connected() {
            // Waiting is also how the client finds a restarted server.
            let _ = client.wait_startop(Duration::ZERO);
        }
    }

    fn event(&mut self, e: Event) {
        match e {
            Event::Mode(m) => self.ctl.report_mode(pnio_mode(m)),
            Event::ServerShutdown => lock(&self.ctl.mode).pending = None,
            Event::Reattached { .. } | Event::LayoutChanged { .. } => self.resync = true,
            Event::OpFault { .. } | Event::NewCycle | Event::ClaimLost { .. } => {}
        }
    }

    fn after_events(&mut self, mode: Option<Mode>) {
        let ctl = &self.ctl;
        if self.resync
            && let Some(m) = mode
        {
            // A restarted server starts in its own mode: report it if it differs.
            self.resync = false;
            if pnio_mode(m) != ctl.mode() {
                ctl.report_mode(pnio_mode(m));
            }
        }
        let echoed: Vec<_> = lock(&ctl.mode).echo.drain(..).collect();
        for m in echoed {
            ctl.report_mode(m);
        }
    }
}

/// The event thread: delivers MODE_IND, OPFAULT_IND, NEWCYCLE_IND and STARTOP_IND.
fn event_thread(ctl: Arc<Controller>) {
    cycle_thread::run(EventThread { ctl, resync: false });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_map_to_the_manuals_values() {
        assert_eq!(pnio_mode(Mode::Offline), PNIO_MODE_OFFLINE);
        assert_eq!(pnio_mode(Mode::Clear), PNIO_MODE_CLEAR);
        assert_eq!(pnio_mode(Mode::Operate), PNIO_MODE_OPERATE);
    }
}
