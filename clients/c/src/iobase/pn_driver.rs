// SPDX-License-Identifier: MIT OR Apache-2.0
//! PN Driver's start-up (`servusrx.h`): `SERV_CP_init`, `SERV_CP_get_network_adapters`,
//! `SERV_CP_startup`, `SERV_CP_set_trace_level`, `SERV_CP_shutdown`, `SERV_CP_undo_init`,
//! with the manual's order rules, over the Rust client's [`Stack`] (a procimgd started for
//! the program) and [`network_adapters`]. The header says what each answers.

#![allow(non_snake_case)]

use super::callbacks::{in_callback, invoke_call};
use super::errors::*;
use super::pn_driver_types::*;
use super::rema::RemanentData;
use super::types::{PNIO_UINT8, PNIO_UINT32};
use crate::ffi::guard;
use procimg_client::iobase::{
    NetworkAdapter, PciLocation, Stack, StackStart, StackStartError, network_adapters,
};
use procimg_client::{ControllerAddress, ServiceOptions, Services};
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Where a PN Driver program is in its start-up.
enum Phase {
    /// `SERV_CP_init` not called (or undone): the library serves running instances, as for
    /// a CP program.
    Idle,
    /// After `SERV_CP_init`.
    Initialised(Trace),
    /// After `SERV_CP_startup`: the stack runs.
    Started(Trace, Stack),
    /// After `SERV_CP_shutdown`.
    ShutDown,
}

static PHASE: Mutex<Phase> = Mutex::new(Phase::Idle);

fn phase() -> std::sync::MutexGuard<'static, Phase> {
    PHASE.lock().unwrap_or_else(|e| e.into_inner())
}

/// The trace of a PN Driver program: the callback and the levels `SERV_CP_init` got.
struct Trace {
    /// Receives full buffers; `None`: procimgd's log goes to standard error.
    buffer_full: PNIO_PNTRC_BUFFER_FULL,
    /// The level of each component (only PND's is used: procimgd's log).
    levels: [u8; PNIO_TRACE_COMP_NUM as usize],
    /// PND's level as the log thread reads it.
    pnd: Arc<AtomicU8>,
    /// The lines gathered so far.
    buffer: Arc<Mutex<Vec<u8>>>,
}

impl Trace {
    fn new(settings: Option<&PNIO_DEBUG_SETTINGS_TYPE>) -> Trace {
        let levels = settings.map_or([0; PNIO_TRACE_COMP_NUM as usize], |s| s.TraceLevels);
        Trace {
            buffer_full: settings.and_then(|s| s.CbfPntrcBufferFull),
            levels,
            pnd: Arc::new(AtomicU8::new(levels[PNIO_TRACE_COMP_PND as usize])),
            buffer: Arc::new(Mutex::new(Vec::new())),
        }
    }

    /// procimgd's log filter for PND's level (`None`: no trace, procimgd's default).
    fn log_filter(&self) -> Option<&'static str> {
        self.buffer_full?;
        Some(match u32::from(self.levels[PNIO_TRACE_COMP_PND as usize]) {
            PNIO_TRACE_LEVEL_OFF => "off",
            PNIO_TRACE_LEVEL_FATAL..=PNIO_TRACE_LEVEL_UNEXP => "error",
            PNIO_TRACE_LEVEL_WARN => "warn",
            PNIO_TRACE_LEVEL_NOTE_HIGH | PNIO_TRACE_LEVEL_NOTE => "info",
            _ => "debug",
        })
    }

    /// Where procimgd's lines go: into the buffer, or (`None`) to standard error.
    fn sink(&self) -> Option<procimg_client::iobase::LogSink> {
        let callback = self.buffer_full?;
        let pnd = self.pnd.clone();
        let buffer = self.buffer.clone();
        Some(Box::new(move |line: &str| {
            if line_level(line) > u32::from(pnd.load(Ordering::Relaxed)) {
                return;
            }
            let mut buffer = buffer.lock().unwrap_or_else(|e| e.into_inner());
            if !buffer.is_empty()
                && buffer.len() + line.len() + 1 > PROCIMG_TRACE_BUFFER_SIZE as usize
            {
                hand_over(callback, &mut buffer);
            }
            buffer.extend_from_slice(line.as_bytes());
            buffer.push(b'\n');
        }))
    }

    /// Hands what is gathered to the callback (at shutdown).
    fn flush(&self) {
        if let Some(callback) = self.buffer_full {
            let mut buffer = self.buffer.lock().unwrap_or_else(|e| e.into_inner());
            if !buffer.is_empty() {
                hand_over(callback, &mut buffer);
            }
        }
    }
}

/// Calls `CbfPntrcBufferFull` with the buffer and empties it.
fn hand_over(callback: unsafe extern "C" fn(*mut u8, u32), buffer: &mut Vec<u8>) {
    let len = u32::try_from(buffer.len()).unwrap_or(u32::MAX);
    let ptr = buffer.as_mut_ptr();
    // SAFETY: the program registered a function of this type; the buffer lives, unshared
    // (its lock is held), for the call.
    invoke_call(|| unsafe { callback(ptr, len) });
    buffer.clear();
}

/// The trace level of one of procimgd's log lines (`2026-11-28T…Z  INFO target: …`); a
/// line without one (procimgd's last words) is an error.
fn line_level(line: &str) -> u32 {
    match line.split_whitespace().nth(1) {
        Some("WARN") => PNIO_TRACE_LEVEL_WARN,
        Some("INFO") => PNIO_TRACE_LEVEL_NOTE_HIGH,
        Some("DEBUG") => PNIO_TRACE_LEVEL_NOTE_LOW,
        Some("TRACE") => PNIO_TRACE_LEVEL_CHAT,
        _ => PNIO_TRACE_LEVEL_ERROR,
    }
}

/// Whether `PNIO_controller_open` may open now: not between `SERV_CP_init` and
/// `SERV_CP_startup` (nor after `SERV_CP_shutdown`).
pub(crate) fn controller_may_open() -> Result<(), &'static str> {
    match &*phase() {
        Phase::Idle | Phase::Started(..) => Ok(()),
        Phase::Initialised(_) => Err("SERV_CP_init was called: call SERV_CP_startup first"),
        Phase::ShutDown => Err("the stack was shut down (SERV_CP_shutdown)"),
    }
}

/// The adapter a `PNIO_CP_ID_TYPE` names, among this machine's.
fn chosen_adapter(id: &PNIO_CP_ID_TYPE) -> Result<NetworkAdapter, (u32, String)> {
    let adapters = network_adapters().map_err(|e| {
        (
            PNIO_ERR_CREATE_INSTANCE,
            format!("cannot list the network adapters (/sys/class/net): {e}"),
        )
    })?;
    let (found, named) = match id.CpSelection {
        PNIO_CP_SELECT_WITH_MAC_ADDRESS => {
            let mac = id.CpMacAddr;
            (
                adapters.into_iter().find(|a| a.mac == mac),
                format!("MAC address {}", mac.map(|b| format!("{b:02x}")).join(":")),
            )
        }
        PNIO_CP_SELECT_WITH_PCI_LOCATION => {
            let l = id.CpPciLocation;
            let want = PciLocation {
                bus: l.BusNr,
                device: l.DeviceNr,
                function: l.FunctionNr,
            };
            (
                adapters.into_iter().find(|a| a.pci == Some(want)),
                format!(
                    "PCI location bus {} device {} function {}",
                    l.BusNr, l.DeviceNr, l.FunctionNr
                ),
            )
        }
        other => {
            return Err((
                PNIO_ERR_PRM_INVALIDARG,
                format!(
                    "CpSelection {other} is neither PNIO_CP_SELECT_WITH_MAC_ADDRESS nor \
                     PNIO_CP_SELECT_WITH_PCI_LOCATION"
                ),
            ));
        }
    };
    found.ok_or_else(|| {
        (
            PNIO_ERR_CREATE_INSTANCE,
            format!(
                "no network adapter of this machine has {named}: take an entry of \
                 SERV_CP_get_network_adapters"
            ),
        )
    })
}

/// Writes one adapter as a `PNIO_CP_ID_TYPE`.
fn cp_id(adapter: &NetworkAdapter) -> PNIO_CP_ID_TYPE {
    let mut description = [0u8; 300];
    let name = adapter.name.as_bytes();
    let n = name.len().min(description.len() - 1);
    description[..n].copy_from_slice(&name[..n]);
    let pci = adapter.pci.unwrap_or(PciLocation {
        bus: 0,
        device: 0,
        function: 0,
    });
    PNIO_CP_ID_TYPE {
        CpSelection: PNIO_CP_SELECT_WITH_MAC_ADDRESS,
        CpMacAddr: adapter.mac,
        CpPciLocation: PNIO_PCI_LOCATION_TYPE {
            BusNr: pci.bus,
            DeviceNr: pci.device,
            FunctionNr: pci.function,
        },
        Description: description,
    }
}

/// The code and text of a stack that did not start.
fn start_failure(e: &StackStartError) -> u32 {
    match e {
        StackStartError::Configuration { .. } => PNIO_ERR_CORRUPTED_DATA,
        StackStartError::Handover(_) => PNIO_ERR_INTERNAL,
        _ => PNIO_ERR_CREATE_INSTANCE,
    }
}

/// Starts PN Driver's use of the library: the trace settings are taken.
///
/// # Safety
/// `DebugSetting` is NULL or points to a readable `PNIO_DEBUG_SETTINGS_TYPE`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_init(DebugSetting: *mut PNIO_DEBUG_SETTINGS_TYPE) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_init";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let mut phase = phase();
        if !matches!(*phase, Phase::Idle) {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                "SERV_CP_init was called already: call SERV_CP_undo_init first",
            );
        }
        // SAFETY: NULL or readable by the caller's contract; read unaligned, as C may place it.
        let settings = (!DebugSetting.is_null()).then(|| unsafe { DebugSetting.read_unaligned() });
        *phase = Phase::Initialised(Trace::new(settings.as_ref()));
        PNIO_OK
    })
}

/// Ends PN Driver's use of the library.
///
/// # Safety
/// None beyond the C ABI.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_undo_init() -> PNIO_UINT32 {
    const F: &str = "SERV_CP_undo_init";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let mut phase = phase();
        match *phase {
            Phase::Idle => fail(F, PNIO_ERR_SEQUENCE, "SERV_CP_init was not called"),
            Phase::Started(..) => fail(
                F,
                PNIO_ERR_SEQUENCE,
                "the stack still runs: call SERV_CP_shutdown first",
            ),
            Phase::Initialised(_) | Phase::ShutDown => {
                *phase = Phase::Idle;
                PNIO_OK
            }
        }
    })
}

/// Lists this machine's Ethernet adapters.
///
/// # Safety
/// `CpList` is NULL or points to `PROCIMG_MAX_NETWORK_ADAPTERS` writable entries; `NrOfCp`
/// is NULL or points to a writable byte.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_get_network_adapters(
    CpList: *mut PNIO_CP_ID_TYPE,
    NrOfCp: *mut PNIO_UINT8,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_get_network_adapters";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        if matches!(*phase(), Phase::Idle) {
            return fail(F, PNIO_ERR_SEQUENCE, "call SERV_CP_init first");
        }
        if CpList.is_null() || NrOfCp.is_null() {
            return fail(F, PNIO_ERR_PRM_POINTER, "CpList or NrOfCp is NULL");
        }
        let adapters = match network_adapters() {
            Ok(a) => a,
            Err(e) => {
                return fail(
                    F,
                    PNIO_ERR_NO_ADAPTER_FOUND,
                    format_args!("cannot read /sys/class/net: {e}"),
                );
            }
        };
        let n = adapters.len().min(PROCIMG_MAX_NETWORK_ADAPTERS as usize);
        for (i, adapter) in adapters.iter().take(n).enumerate() {
            // SAFETY: i < PROCIMG_MAX_NETWORK_ADAPTERS entries, writable by the contract.
            unsafe { CpList.add(i).write_unaligned(cp_id(adapter)) };
        }
        // SAFETY: not NULL, writable by the contract; n <= 50 fits a byte.
        unsafe { NrOfCp.write(n as u8) };
        if n == 0 {
            return fail(
                F,
                PNIO_ERR_NO_ADAPTER_FOUND,
                "this machine (or network namespace) has no Ethernet interface but loopback",
            );
        }
        PNIO_OK
    })
}

/// Starts the stack: a procimgd with the configuration given, on the adapter chosen.
///
/// # Safety
/// `CpList` is NULL or points to `NrOfCp` readable entries; `pConfigData` is NULL or points
/// to `ConfigDataLen` readable bytes; `pRemaData` is NULL or points to `RemaDataLen`
/// readable bytes; `pSysDescr` is not read.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_startup(
    CpList: *mut PNIO_CP_ID_TYPE,
    NrOfCp: PNIO_UINT32,
    pConfigData: *mut PNIO_UINT8,
    ConfigDataLen: PNIO_UINT32,
    pRemaData: *mut PNIO_UINT8,
    RemaDataLen: PNIO_UINT32,
    pSysDescr: *mut PNIO_SYSTEM_DESCR,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_startup";
    let _ = pSysDescr;
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let mut phase = phase();
        let trace = match std::mem::replace(&mut *phase, Phase::Idle) {
            Phase::Initialised(trace) => trace,
            other => {
                let why = match other {
                    Phase::Idle => "call SERV_CP_init first",
                    Phase::Started(..) => "the stack runs already",
                    _ => "the stack was shut down: SERV_CP_undo_init and SERV_CP_init start anew",
                };
                *phase = other;
                return fail(F, PNIO_ERR_SEQUENCE, why);
            }
        };
        let refuse = |phase: &mut Phase, trace: Trace, code: u32, why: &dyn std::fmt::Display| {
            *phase = Phase::Initialised(trace);
            fail(F, code, why)
        };
        if NrOfCp != 1 {
            return refuse(
                &mut phase,
                trace,
                PNIO_ERR_PRM_INVALIDARG,
                &format_args!("NrOfCp is {NrOfCp}: the stack drives one adapter, NrOfCp 1"),
            );
        }
        if CpList.is_null() || pConfigData.is_null() {
            return refuse(
                &mut phase,
                trace,
                PNIO_ERR_PRM_POINTER,
                &"CpList or pConfigData is NULL",
            );
        }
        if ConfigDataLen == 0 {
            return refuse(
                &mut phase,
                trace,
                PNIO_ERR_PRM_INVALIDARG,
                &"ConfigDataLen is 0: give the configuration's length",
            );
        }
        let rema = if !pRemaData.is_null() && RemaDataLen > 0 {
            // SAFETY: not NULL; RemaDataLen readable bytes by the contract.
            let bytes = unsafe { std::slice::from_raw_parts(pRemaData, RemaDataLen as usize) };
            let text = bytes.split(|b| *b == 0).next().unwrap_or_default();
            let parsed = std::str::from_utf8(text)
                .map_err(|_| "not UTF-8 text".to_owned())
                .and_then(RemanentData::parse);
            match parsed {
                Ok(r) => Some(r),
                Err(why) => {
                    return refuse(
                        &mut phase,
                        trace,
                        PNIO_ERR_INVALID_REMA,
                        &format_args!(
                            "pRemaData is not the retentive data PNIO_CBE_REMA_READ_CONF \
                             handed out: {why}"
                        ),
                    );
                }
            }
        } else {
            None
        };
        // SAFETY: not NULL; one readable entry by the contract (NrOfCp is 1).
        let id = unsafe { CpList.read_unaligned() };
        // SAFETY: not NULL; ConfigDataLen readable bytes by the contract.
        let config = unsafe { std::slice::from_raw_parts(pConfigData, ConfigDataLen as usize) };
        let config = config.split(|b| *b == 0).next().unwrap_or_default();
        let adapter = match chosen_adapter(&id) {
            Ok(a) => a,
            Err((code, why)) => return refuse(&mut phase, trace, code, &why),
        };
        let instance = super::controller::instance_for(1);
        let started = Stack::start(StackStart {
            adapter: Some(&adapter.name),
            log: trace.sink(),
            log_filter: trace.log_filter(),
            ..StackStart::new(config, &instance)
        });
        match started {
            Ok(stack) => {
                if let Some(r) = &rema
                    && let Err(why) = take_rema(&instance, r)
                {
                    let _ = stack.shutdown();
                    return refuse(&mut phase, trace, PNIO_ERR_INVALID_REMA, &why);
                }
                *phase = Phase::Started(trace, stack);
                PNIO_OK
            }
            Err(e) => {
                let code = start_failure(&e);
                refuse(&mut phase, trace, code, &e)
            }
        }
    })
}

/// Gives the started stack's station the name and IP suite of its retentive data, where
/// the configuration lets programs set them (elsewhere the configuration's stay).
fn take_rema(instance: &str, rema: &RemanentData) -> Result<(), String> {
    let mut services =
        Services::open(instance, ServiceOptions::new("SERV_CP_startup")).map_err(|e| {
            format!("cannot reach the started stack to give it its retentive data: {e}")
        })?;
    let now = services
        .control()
        .status()
        .map_err(|e| e.to_string())?
        .controller
        .ok_or("the started stack runs no controller")?;
    let name = (now.name_by_program && now.station_name != rema.name).then(|| rema.name.clone());
    let [ip, mask, gateway] = rema.ip_suite;
    let suite = [ip, mask, gateway].map(|a| a.to_string());
    let ip_suite = (now.address_by_program
        && [&now.ip, &now.netmask, &now.gateway] != suite.each_ref())
    .then_some(rema.ip_suite);
    if name.is_none() && ip_suite.is_none() {
        return Ok(());
    }
    let change = ControllerAddress {
        name,
        ip_suite,
        permanent: true,
    };
    services
        .change_controller_address(&change, REMA_TIMEOUT)
        .map_err(|e| format!("the retentive name or address was not taken: {e}"))
}

/// How long the station may take to take its retentive name and address.
const REMA_TIMEOUT: Duration = Duration::from_secs(10);

/// Stops the stack.
///
/// # Safety
/// None beyond the C ABI.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_shutdown() -> PNIO_UINT32 {
    const F: &str = "SERV_CP_shutdown";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let mut phase = phase();
        if !matches!(*phase, Phase::Started(..)) {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                "the stack was not started (SERV_CP_startup)",
            );
        }
        let open = super::controller::open_handles();
        if let Some(handle) = open.first() {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                format_args!(
                    "controller handle {handle} is still open: PNIO_controller_close first"
                ),
            );
        }
        if let Some(handle) = super::interface_worker::open_handles().first() {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                format_args!("interface handle {handle} is still open: PNIO_interface_close first"),
            );
        }
        let Phase::Started(trace, stack) = std::mem::replace(&mut *phase, Phase::ShutDown) else {
            unreachable!("matched above");
        };
        let stopped = stack.shutdown();
        trace.flush();
        match stopped {
            Ok(_) => PNIO_OK,
            Err(e) => fail(F, PNIO_ERR_INTERNAL, e),
        }
    })
}

/// Changes the trace level of one component.
///
/// # Safety
/// `CbfSetTraceLevelDone` is NULL or a function of its type.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn SERV_CP_set_trace_level(
    Component: PNIO_UINT32,
    TraceLevel: PNIO_UINT32,
    CbfSetTraceLevelDone: PNIO_PNTRC_SET_TRACE_LEVEL_DONE,
) -> PNIO_UINT32 {
    const F: &str = "SERV_CP_set_trace_level";
    guard(PNIO_ERR_INTERNAL, || {
        if in_callback() {
            return fail(F, PNIO_ERR_SEQUENCE, "not allowed inside a callback");
        }
        let mut phase = phase();
        let Phase::Started(trace, _) = &mut *phase else {
            return fail(
                F,
                PNIO_ERR_SEQUENCE,
                "the stack was not started (SERV_CP_startup)",
            );
        };
        if Component >= PNIO_TRACE_COMP_NUM || TraceLevel >= PNIO_TRACE_LEVEL_NUM {
            return fail(
                F,
                PNIO_ERR_PRM_INVALIDARG,
                format_args!(
                    "Component {Component} or TraceLevel {TraceLevel} is out of range \
                     (components 0..{PNIO_TRACE_COMP_NUM}, levels 0..{PNIO_TRACE_LEVEL_NUM})"
                ),
            );
        }
        let level = TraceLevel as u8;
        trace.levels[Component as usize] = level;
        if Component == PNIO_TRACE_COMP_PND {
            trace.pnd.store(level, Ordering::Relaxed);
        }
        if let Some(done) = CbfSetTraceLevelDone {
            // The level holds now; the confirmation comes on a thread of its own, as PN
            // Driver's does, so a program may wait for it on the calling thread.
            // SAFETY: a function of the callback's type, by the contract.
            let confirm = move || invoke_call(|| unsafe { done() });
            if std::thread::Builder::new()
                .name("pnd-trace-level".into())
                .spawn(confirm)
                .is_err()
            {
                return fail(
                    F,
                    PNIO_ERR_INTERNAL,
                    "cannot start the confirmation's thread",
                );
            }
        }
        PNIO_OK
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_lines_have_the_trace_levels_of_their_log_levels() {
        let at = |l: &str| line_level(&format!("2026-11-28T23:52:55.007003Z  {l} procimgd: x"));
        assert_eq!(at("ERROR"), PNIO_TRACE_LEVEL_ERROR);
        assert_eq!(at("WARN"), PNIO_TRACE_LEVEL_WARN);
        assert_eq!(at("INFO"), PNIO_TRACE_LEVEL_NOTE_HIGH);
        assert_eq!(at("DEBUG"), PNIO_TRACE_LEVEL_NOTE_LOW);
        assert_eq!(at("TRACE"), PNIO_TRACE_LEVEL_CHAT);
        assert_eq!(
            line_level("procimgd: cannot open eth9"),
            PNIO_TRACE_LEVEL_ERROR
        );
    }

    #[test]
    fn an_adapter_is_written_with_its_name_as_description() {
        let id = cp_id(&NetworkAdapter {
            name: "enp3s0".into(),
            mac: [0, 0x1b, 0x1b, 1, 2, 3],
            pci: Some(PciLocation {
                bus: 3,
                device: 0,
                function: 1,
            }),
        });
        assert_eq!(id.CpSelection, PNIO_CP_SELECT_WITH_MAC_ADDRESS);
        assert_eq!(id.CpMacAddr, [0, 0x1b, 0x1b, 1, 2, 3]);
        assert_eq!(id.CpPciLocation.BusNr, 3);
        assert_eq!(id.CpPciLocation.FunctionNr, 1);
        assert_eq!(&id.Description[..7], b"enp3s0\0");
    }
}
