// SPDX-License-Identifier: MIT OR Apache-2.0
//! The AR indications as the program's `PNIO_CBF_*` callbacks, on the device's library
//! thread. Which indication comes when, and the ArNumber and SessionKey rules of the per-AR
//! calls, are [`IoBaseDevice`]'s, the library's Rust core; this file converts its
//! [`DeviceCallbacks`] to the C types.
//!
//! [`IoBaseDevice`]: procimg_client::iobase::IoBaseDevice
//!
//! # Callbacks and when they come
//!
//! The device checks the station's ARs and holds its ApplicationReady from
//! `PNIO_device_open` to `PNIO_device_close`. For a PLC's Connect (the station's AR check):
//!
//! 1. `PNIO_CBF_AR_CHECK_IND` with the new ArNumber (1, 2, … per open), the station's
//!    SessionKey, and of the Connect: the PLC's IP address as HostIp (as `struct in_addr`'s
//!    `s_addr`, network byte order), the ARType, ARUUID, ARProperties, the
//!    CMInitiatorObjectUUID as CmiObjUUID and the PLC's station name (its MAC address has
//!    no place in the callback).
//! 2. `PNIO_CBF_CHECK_IND` once per expected submodule where something other than the
//!    expected ident numbers is plugged (not where nothing is: the station reports that
//!    itself). The out parameters come filled with what is plugged, the states WRONG (or
//!    PROPER_MODULE where the module ident matches). If the program answers a submodule
//!    state PROPER or SUBSTITUTED with other ident numbers than plugged, those are plugged
//!    there before the Connect is answered (the PLC then sees them; procimgd knows no
//!    "substitute", so ident numbers other than the expected ones are wrong to the PLC).
//! 3. The station's AR check is answered accepting once these callbacks returned: the
//!    manual's way to refuse is `PNIO_device_ar_abort`, which the program calls after the
//!    callback.
//! 4. `PNIO_CBF_AR_INFO_IND` with the AR's IOCRs and modules, built from the Connect: the
//!    input IOCR and the output IOCR as the PLC asked for them (IOCRProperties its RT
//!    class, SendClock, ReductioFactor, Phase; CycleTime in ms, SendClock × 31.25 µs ×
//!    ReductioFactor rounded down; `reserved[0]` the FrameID of its frames, `reserved[1]`
//!    their C_SDU length), each listing the submodules whose data objects it carries
//!    (`PNIO_IOCS_TYPE::reserved` the data object's offset in the C_SDU); a module per
//!    (API, slot) with its expected ModuleIdentNumber, and per submodule its ident, type
//!    and lengths (one byte of IOPS and IOCS per direction it has; a submodule without data
//!    has the input side's). From a server too old to report the CRs, the IOCRs list the
//!    submodules by direction with RT class 1 and no timing. The memory is the library's
//!    and valid only during the callback.
//! 5. `PNIO_CBF_PRM_END_IND` (API, slot and subslot 0) when the station reports the AR
//!    [`ArState::Parameterized`](procimg_client::ArState::Parameterized) (the PLC's PrmEnd); the ApplicationReady waits for
//!    `PNIO_set_appl_state_ready` (procimgd sends it by itself after 10 s).
//! 6. `PNIO_CBF_AR_INDATA_IND` when the station reports [`ArState::Data`](procimg_client::ArState::Data).
//! 7. `PNIO_CBF_APDU_STATUS_IND` when the DataStatus of the PLC's frames changes:
//!    `PNIO_EVENT_APDU_STATUS_RUN` or `_STOP`, `_STATION_OK` or `_STATION_PROBLEM`,
//!    `_PRIMARY` or `_BACKUP`; a change before data exchange is given right after
//!    `AR_INDATA_IND`.
//! 8. `PNIO_CBF_AR_OFFLINE_IND` when the AR ends after `AR_INDATA_IND`, else
//!    `PNIO_CBF_AR_ABORT_IND`, with the reason of [`ArEndReason::iobase_code`]. An AR that a new
//!    Connect replaced before its end was reported ends with `PNIO_AR_REASON_RERUN`; one
//!    whose end a stop or `PNIO_device_ar_abort` waited for in vain (5 s) with
//!    `PNIO_AR_REASON_ABORT`.
//!
//! Notifications about an AR whose check this device did not get (one that connected
//! before `PNIO_device_open`) give no callbacks.
//!
//! # ArNumber and SessionKey
//!
//! Only the current AR is known. In `PNIO_set_appl_state_ready` and `PNIO_device_ar_abort`
//! an ArNumber this open never gave answers `PNIO_ERR_SEQUENCE`; the ArNumber of an AR that
//! has ended, or the current one's with another SessionKey, `PNIO_ERR_SESSION`.

use super::Pos;
use super::alarms;
use super::records;
use super::state::Device;
use super::station::{Occupants, plug};
use crate::iobase::callbacks::invoke_device;
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use crate::iobase::types::PNIO_IO_IN;
use procimg_client::StationRecordJob;
use procimg_client::iobase::{ApduStatus, ArEndReason, ArId, DeviceCallbacks};
use procimg_control::services::{ArCr, ExpectedSubmodule, StationArCheckJob};
use std::time::Duration;

/// The UUID procimgd writes ("0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2"); zero if it is none.
pub(crate) fn uuid(text: &str) -> PNIO_UUID_TYPE {
    let hex: String = text.chars().filter(|c| *c != '-').collect();
    let mut b = [0u8; 16];
    if hex.len() != 32 || !hex.chars().all(|c| c.is_ascii_hexdigit()) {
        return PNIO_UUID_TYPE::default();
    }
    for (i, byte) in b.iter_mut().enumerate() {
        *byte = u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).unwrap_or(0);
    }
    PNIO_UUID_TYPE {
        TimeLow: u32::from_be_bytes([b[0], b[1], b[2], b[3]]),
        TimeMid: u16::from_be_bytes([b[4], b[5]]),
        TimeHiAndVersion: u16::from_be_bytes([b[6], b[7]]),
        ClockSeqHiAndReserved: b[8],
        ClockSeqLow: b[9],
        Node: [b[10], b[11], b[12], b[13], b[14], b[15]],
    }
}

/// `APDU_STATUS_IND`'s bits for the DataStatus of the PLC's frames.
pub(crate) fn apdu_bits(s: ApduStatus) -> PNIO_APDU_STATUS_IND {
    let pick = |on: bool, yes, no| if on { yes } else { no };
    pick(
        s.running,
        PNIO_EVENT_APDU_STATUS_RUN,
        PNIO_EVENT_APDU_STATUS_STOP,
    ) | pick(
        s.station_problem,
        PNIO_EVENT_APDU_STATUS_STATION_PROBLEM,
        PNIO_EVENT_APDU_STATUS_STATION_OK,
    ) | pick(
        s.backup,
        PNIO_EVENT_APDU_STATUS_BACKUP,
        PNIO_EVENT_APDU_STATUS_PRIMARY,
    )
}

/// `AR_CHECK_IND`'s HostIp: the PLC's address as `struct in_addr`'s `s_addr` holds it
/// (network byte order in memory); 0 when procimgd did not say.
pub(crate) fn host_ip(text: &str) -> u32 {
    text.parse::<std::net::Ipv4Addr>()
        .map_or(0, |ip| u32::from_ne_bytes(ip.octets()))
}

/// The structures of `PNIO_CBF_AR_INFO_IND`: `ar` points into the vectors, whose buffers
/// do not move while this lives.
pub(crate) struct ArTree {
    /// The AR.
    pub ar: PNIO_AR_TYPE,
    _iocrs: Vec<PNIO_IOCR_TYPE>,
    _iocs: [Vec<PNIO_IOCS_TYPE>; 2],
    _modules: Vec<PNIO_MODULE_TYPE>,
    _subs: Vec<Vec<PNIO_SUBMOD_TYPE>>,
}

/// `PNIO_SUB_PROP_TYPE_*` of a submodule with these lengths.
fn sub_type(e: &ExpectedSubmodule) -> u32 {
    match (e.input_length > 0, e.output_length > 0) {
        (true, true) => PNIO_SUB_PROP_TYPE_INPUT_OUTPUT,
        (true, false) => PNIO_SUB_PROP_TYPE_INPUT,
        (false, true) => PNIO_SUB_PROP_TYPE_OUTPUT,
        (false, false) => PNIO_SUB_PROP_TYPE_NO_DATA,
    }
}

/// `PNIO_IOCR_TYPE::CycleTime`: the CR's period in whole ms.
fn cycle_time_ms(cr: &ArCr) -> u32 {
    // SendClockFactor × ReductionRatio × 31.25 µs = × 1/32 ms.
    (u32::from(cr.send_clock_factor) * u32::from(cr.reduction_ratio)) / 32
}

/// The IOCR `cr` of the Connect, listing `list`.
fn iocr(cr: &ArCr, list: &mut Vec<PNIO_IOCS_TYPE>) -> PNIO_IOCR_TYPE {
    PNIO_IOCR_TYPE {
        CycleTime: cycle_time_ms(cr),
        Direction: if cr.input {
            PNIO_IOCR_TYPE_INPUT
        } else {
            PNIO_IOCR_TYPE_OUTPUT
        },
        IOCRProperties: u32::from(cr.rt_class),
        SendClock: cr.send_clock_factor.into(),
        ReductioFactor: cr.reduction_ratio.into(),
        Phase: cr.phase.into(),
        NumOfIoCs: list.len() as u32,
        pIoCsList: list.as_mut_ptr(),
        reserved: [cr.frame_id.into(), cr.data_length.into(), 0],
    }
}

/// Builds the AR's IOCRs and modules from the Connect's expected submodules and CRs (`crs`
/// empty from an older server).
pub(crate) fn tree(
    number: u16,
    session_key: u16,
    expected: &[ExpectedSubmodule],
    crs: &[ArCr],
) -> ArTree {
    let mut sorted: Vec<&ExpectedSubmodule> = expected.iter().collect();
    sorted.sort_by_key(|e| (e.api, e.slot, e.subslot));
    let mut subs: Vec<Vec<PNIO_SUBMOD_TYPE>> = Vec::new();
    let mut keys: Vec<(u32, u16, u32)> = Vec::new();
    let mut iocs = [Vec::new(), Vec::new()];
    for e in sorted {
        let t = sub_type(e);
        let input_side = t != PNIO_SUB_PROP_TYPE_OUTPUT;
        let output_side = t == PNIO_SUB_PROP_TYPE_OUTPUT || t == PNIO_SUB_PROP_TYPE_INPUT_OUTPUT;
        let s = PNIO_SUBMOD_TYPE {
            SlotNum: e.slot.into(),
            SubSlotNum: e.subslot.into(),
            SubMProperties: t,
            SubMIdent: e.submodule_ident,
            InDatLen: e.input_length.into(),
            InIopsLen: input_side.into(),
            InIocsLen: input_side.into(),
            OutDatLen: e.output_length.into(),
            OutIopsLen: output_side.into(),
            OutIocsLen: output_side.into(),
            reserved: [0; 8],
        };
        // Without the Connect's CRs (an older server): the submodules by direction.
        if crs.is_empty() {
            let io = PNIO_IOCS_TYPE {
                SlotNum: e.slot.into(),
                SubslotNum: e.subslot.into(),
                reserved: 0,
            };
            if input_side {
                iocs[0].push(io);
            }
            if output_side {
                iocs[1].push(io);
            }
        }
        match keys.last() {
            Some(&(api, slot, _)) if (api, slot) == (e.api, e.slot) => {
                if let Some(v) = subs.last_mut() {
                    v.push(s);
                }
            }
            _ => {
                keys.push((e.api, e.slot, e.module_ident));
                subs.push(vec![s]);
            }
        }
    }
    let mut modules: Vec<PNIO_MODULE_TYPE> = keys
        .iter()
        .zip(subs.iter_mut())
        .map(|(&(api, slot, ident), v)| PNIO_MODULE_TYPE {
            Api: api,
            SlotNum: slot.into(),
            NumOfSubmod: v.len() as u32,
            ModProperties: 0,
            ModIdent: ident,
            pSubList: v.as_mut_ptr(),
        })
        .collect();
    // The Connect's own lists, with each data object's offset.
    for (k, cr) in crs.iter().take(2).enumerate() {
        iocs[k] = cr
            .data_objects
            .iter()
            .map(|o| PNIO_IOCS_TYPE {
                SlotNum: o.slot.into(),
                SubslotNum: o.subslot.into(),
                reserved: o.frame_offset.into(),
            })
            .collect();
    }
    let mut iocrs: Vec<PNIO_IOCR_TYPE> = if crs.is_empty() {
        legacy_iocrs(&mut iocs)
    } else {
        crs.iter()
            .take(2)
            .zip(iocs.iter_mut())
            .map(|(cr, list)| iocr(cr, list))
            .collect()
    };
    let ar = PNIO_AR_TYPE {
        pNextAr: std::ptr::null_mut(),
        ArNumber: number,
        SessionKey: session_key,
        NumOfIocr: iocrs.len() as u32,
        pIoCrList: iocrs.as_mut_ptr(),
        NumOfMod: modules.len() as u32,
        pModList: modules.as_mut_ptr(),
    };
    ArTree {
        ar,
        _iocrs: iocrs,
        _iocs: iocs,
        _modules: modules,
        _subs: subs,
    }
}

/// The IOCRs of an AR whose CRs an older server did not report: the submodules by
/// direction, RT class 1, no timing.
fn legacy_iocrs(iocs: &mut [Vec<PNIO_IOCS_TYPE>; 2]) -> Vec<PNIO_IOCR_TYPE> {
    [PNIO_IOCR_TYPE_INPUT, PNIO_IOCR_TYPE_OUTPUT]
        .into_iter()
        .zip(iocs.iter_mut())
        .map(|(direction, list)| PNIO_IOCR_TYPE {
            CycleTime: 0,
            Direction: direction,
            IOCRProperties: PNIO_IOCR_PROP_RT_CLASS_1,
            SendClock: 0,
            ReductioFactor: 0,
            Phase: 0,
            NumOfIoCs: list.len() as u32,
            pIoCsList: list.as_mut_ptr(),
            reserved: [0; 3],
        })
        .collect()
}

/// The program's callbacks for the notifications [`IoBaseDevice`] turns into them: each
/// converts the types and calls the `PNIO_CBF_*` function the program gave
/// `PNIO_device_open`, if any. `occupants` is the library thread's view of the station,
/// where a `CHECK_IND` answer plugs.
///
/// [`IoBaseDevice`]: procimg_client::iobase::IoBaseDevice
pub(crate) struct Callbacks<'a> {
    pub dev: &'a Device,
    pub occupants: &'a mut Occupants,
}

impl Callbacks<'_> {
    /// Calls `f` with the device's handle, as a callback of the program.
    fn call<F: Copy>(&self, f: Option<F>, with: impl FnOnce(F, u32)) {
        if let Some(f) = f {
            invoke_device(|| with(f, self.dev.handle));
        }
    }
}

// Every `unsafe` call below is of a callback the program gave PNIO_device_open, callable
// until PNIO_device_close, which waits for the library thread that delivers these.
impl DeviceCallbacks for Callbacks<'_> {
    fn ar_check(&mut self, ar: ArId, check: &StationArCheckJob) {
        let mut tree = PNIO_AR_TYPE {
            pNextAr: std::ptr::null_mut(),
            ArNumber: ar.number,
            SessionKey: ar.session_key,
            NumOfIocr: 0,
            pIoCrList: std::ptr::null_mut(),
            NumOfMod: 0,
            pModList: std::ptr::null_mut(),
        };
        let mut name = check.controller_name.as_bytes().to_vec();
        let name_len = name.len().min(u16::MAX as usize) as u16;
        let (ar_ptr, name_ptr): (*mut PNIO_AR_TYPE, *mut u8) = (&mut tree, name.as_mut_ptr());
        let ar_uuid = uuid(&check.ar_uuid);
        let cmi_uuid = uuid(&check.cmi_object_uuid);
        let host_ip = host_ip(&check.controller_ip);
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_ar_check_ind, |f, h| unsafe {
            f(
                h,
                host_ip,
                check.ar_type,
                ar_uuid,
                check.ar_properties,
                cmi_uuid,
                name_len,
                name_ptr,
                ar_ptr,
            )
        });
    }

    fn check_submodule(&mut self, ar: ArId, e: &ExpectedSubmodule, plugged: (u32, u32)) {
        check_ind(self.dev, self.occupants, ar, e, plugged);
    }

    fn ar_info(&mut self, ar: ArId, check: &StationArCheckJob) {
        let mut t = tree(ar.number, ar.session_key, &check.expected, &check.crs);
        let p: *mut PNIO_AR_TYPE = &mut t.ar;
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_ar_info_ind, |f, h| unsafe {
            f(h, ar.number, ar.session_key, p)
        });
    }

    fn prm_end(&mut self, ar: ArId, submodule: Option<Pos>) {
        let (api, slot, subslot) = submodule.unwrap_or((0, 0, 0));
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_prm_end_ind, |f, h| unsafe {
            f(h, ar.number, ar.session_key, api, slot, subslot)
        });
    }

    fn in_data(&mut self, ar: ArId) {
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_ar_indata_ind, |f, h| unsafe {
            f(h, ar.number, ar.session_key)
        });
    }

    fn apdu_status(&mut self, ar: ArId, apdu: ApduStatus) {
        let status = apdu_bits(apdu);
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_apdu_status_ind, |f, h| unsafe {
            f(h, ar.number, ar.session_key, status)
        });
    }

    fn ar_abort(&mut self, ar: ArId, reason: ArEndReason) {
        let code = reason.iobase_code();
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_ar_abort_ind, |f, h| unsafe {
            f(h, ar.number, ar.session_key, code)
        });
    }

    fn ar_offline(&mut self, ar: ArId, reason: ArEndReason) {
        let code = reason.iobase_code();
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_ar_offline_ind, |f, h| unsafe {
            f(h, ar.number, ar.session_key, code)
        });
    }

    fn led_flash_start(&mut self, hz: u32) {
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_start_led_flash, |f, h| unsafe { f(h, hz) });
    }

    fn led_flash_stop(&mut self) {
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_stop_led_flash, |f, h| unsafe { f(h) });
    }

    fn stop_request(&mut self) {
        // SAFETY: the program's callback (see the impl); the pointers live until it returned.
        self.call(self.dev.cbf.cbf_cp_stop_req, |f, h| unsafe { f(h) });
    }

    fn record(&mut self, ar: Option<ArId>, job: &StationRecordJob) {
        records::job(self.dev, ar, job);
    }

    fn alarm_done(&mut self, tag: u64, status: Option<[u8; 4]>) {
        alarms::acknowledged(self.dev, tag, status);
    }
}

/// Delivers the station's notifications until the AR `uuid` has ended (its callback given)
/// or `timeout` passed; then, if it is still current, ends it with `PNIO_AR_REASON_ABORT`.
pub(crate) fn until_ended(dev: &Device, occupants: &mut Occupants, uuid: &str, timeout: Duration) {
    dev.iobase
        .until_ended(uuid, timeout, &mut Callbacks { dev, occupants });
}

/// `CHECK_IND` for a submodule the PLC expects other than plugged; plugs what the program
/// answers as proper or substituted if it is not what is plugged.
fn check_ind(
    dev: &Device,
    occupants: &mut Occupants,
    ar: ArId,
    e: &ExpectedSubmodule,
    plugged: (u32, u32),
) {
    let Some(f) = dev.cbf.cbf_check_ind else {
        return;
    };
    let mut addr = PNIO_DEV_ADDR::geo(PNIO_IO_IN, e.slot.into(), e.subslot.into());
    let mut mod_ident = plugged.0;
    let mut mod_state = if plugged.0 == e.module_ident {
        PNIO_MOD_STATE_PROPER_MODULE
    } else {
        PNIO_MOD_STATE_WRONG_MODULE
    } as u16;
    let mut sub_ident = plugged.1;
    let mut sub_state = PNIO_SUB_CHECK_WRONG_SUBMODULE as u16;
    {
        let pa: *mut PNIO_DEV_ADDR = &mut addr;
        let (pmi, pms, psi, pss): (*mut u32, *mut u16, *mut u32, *mut u16) = (
            &mut mod_ident,
            &mut mod_state,
            &mut sub_ident,
            &mut sub_state,
        );
        let (number, key) = (ar.number, ar.session_key);
        // SAFETY: a callback the program gave PNIO_device_open, callable until
        // PNIO_device_close; every pointer is valid for the call.
        invoke_device(|| unsafe { f(dev.handle, e.api, number, key, pa, pmi, pms, psi, pss) });
    }
    let Some(idents) = substitute(plugged, (mod_ident, sub_ident), sub_state) else {
        return;
    };
    let at: Pos = (e.api, e.slot, e.subslot);
    if plug(&lock(&dev.client), occupants, at, idents) == PNIO_OK {
        let mut c = lock(&dev.config);
        c.subs.insert(at, idents.1);
        c.modules.insert((at.0, at.1), idents.0);
    }
}

/// What `CHECK_IND`'s answer plugs at a position where `plugged` is: the ident numbers the
/// program answered, if it says its submodule there is proper or a substitute and they are
/// not what is plugged.
fn substitute(plugged: (u32, u32), answer: (u32, u32), sub_state: u16) -> Option<(u32, u32)> {
    let ident_bits = u32::from(sub_state) & PNIO_SUB_STATE_IDENT_MASK;
    let takes =
        ident_bits == PNIO_SUB_STATE_IDENT_OK || ident_bits == PNIO_SUB_STATE_IDENT_SUBSTITUTE;
    (takes && answer != plugged).then_some(answer)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rust_reasons_are_the_headers() {
        use procimg_client::iobase::*;
        assert_eq!(REASON_NONE, PNIO_AR_REASON_NONE);
        assert_eq!(REASON_ABORT, PNIO_AR_REASON_ABORT);
        assert_eq!(REASON_RERUN, PNIO_AR_REASON_RERUN);
        assert_eq!(REASON_REL, PNIO_AR_REASON_REL);
        assert_eq!(REASON_HIGHEST_ABORT_CODE, PNIO_AR_REASON_IRDATA);
        assert_eq!(PNIO_AR_REASON_RESERVED1, 1);
        assert_eq!(
            u32::from(CHAN_PROP_MAINT_REQUIRED),
            PNIO_CHAN_PROP_MAINT_REQUIRED_BIT
        );
        assert_eq!(
            u32::from(CHAN_PROP_MAINT_DEMANDED),
            PNIO_CHAN_PROP_MAINT_DEMANDED_BIT
        );
        assert_eq!(FLASH_HZ, 2);
    }

    #[test]
    fn check_ind_plugs_a_proper_or_substitute_answer() {
        let plugged = (0x10, 2);
        let proper = PNIO_SUB_CHECK_PROPER_SUBMODULE as u16;
        let subst = PNIO_SUB_CHECK_SUBSTITUTED_SUBMODULE as u16;
        let wrong = PNIO_SUB_CHECK_WRONG_SUBMODULE as u16;
        assert_eq!(substitute(plugged, (0x10, 1), proper), Some((0x10, 1)));
        assert_eq!(substitute(plugged, (0x10, 3), subst), Some((0x10, 3)));
        assert_eq!(
            substitute(plugged, (0x10, 1), wrong),
            None,
            "wrong: left as it is"
        );
        assert_eq!(substitute(plugged, plugged, proper), None, "already there");
    }

    #[test]
    fn the_apdu_status_says_what_the_data_status_says() {
        let s = |running, station_problem, backup| ApduStatus {
            running,
            station_problem,
            backup,
        };
        assert_eq!(apdu_bits(s(true, false, false)), 0x02 | 0x04 | 0x10);
        assert_eq!(apdu_bits(s(false, true, true)), 0x01 | 0x08 | 0x20);
    }

    #[test]
    fn the_host_ip_is_in_network_byte_order() {
        assert_eq!(host_ip("192.168.0.1").to_ne_bytes(), [192, 168, 0, 1]);
        assert_eq!(host_ip("0.0.0.0"), 0);
        assert_eq!(host_ip(""), 0, "an older server does not say");
    }

    #[test]
    fn uuids_are_read_big_endian() {
        let u = uuid("0f2c0a43-1b53-4a8f-9e57-8c4bd8b1f7a2");
        assert_eq!(u.TimeLow, 0x0f2c0a43);
        assert_eq!(u.TimeMid, 0x1b53);
        assert_eq!(u.TimeHiAndVersion, 0x4a8f);
        assert_eq!((u.ClockSeqHiAndReserved, u.ClockSeqLow), (0x9e, 0x57));
        assert_eq!(u.Node, [0x8c, 0x4b, 0xd8, 0xb1, 0xf7, 0xa2]);
        assert_eq!(uuid("none"), PNIO_UUID_TYPE::default());
    }

    #[test]
    fn the_tree_has_a_module_per_slot_and_an_iocr_per_direction() {
        let e = |slot, subslot, i, o| ExpectedSubmodule {
            api: 0,
            slot,
            subslot,
            module_ident: 0x10 + u32::from(slot),
            submodule_ident: 1,
            input_length: i,
            output_length: o,
            plugged: None,
        };
        let t = tree(
            3,
            7,
            &[
                e(1, 1, 2, 0),
                e(0, 1, 0, 0),
                e(0, 0x8000, 0, 0),
                e(2, 1, 0, 4),
            ],
            &[],
        );
        assert_eq!((t.ar.ArNumber, t.ar.SessionKey), (3, 7));
        assert_eq!((t.ar.NumOfIocr, t.ar.NumOfMod), (2, 3));
        // SAFETY: the tree's pointers point into its own vectors, alive with it.
        unsafe {
            let m0 = &*t.ar.pModList;
            assert_eq!((m0.SlotNum, m0.NumOfSubmod, m0.ModIdent), (0, 2, 0x10));
            let m2 = &*t.ar.pModList.add(2);
            let s = &*m2.pSubList;
            assert_eq!(
                (s.SubMProperties, s.OutDatLen, s.OutIocsLen, s.InIopsLen),
                (2, 4, 1, 0)
            );
            let input = &*t.ar.pIoCrList;
            let output = &*t.ar.pIoCrList.add(1);
            assert_eq!(
                (input.Direction, input.NumOfIoCs),
                (PNIO_IOCR_TYPE_INPUT, 3)
            );
            assert_eq!(
                (output.Direction, output.NumOfIoCs),
                (PNIO_IOCR_TYPE_OUTPUT, 1)
            );
            assert_eq!((*output.pIoCsList).SlotNum, 2);
        }
    }

    #[test]
    fn the_iocrs_carry_the_connects_timing_frame_ids_and_offsets() {
        use procimg_control::services::CrDataObject;
        let e = |slot, i, o| ExpectedSubmodule {
            api: 0,
            slot,
            subslot: 1,
            module_ident: 0x10,
            submodule_ident: 1,
            input_length: i,
            output_length: o,
            plugged: None,
        };
        let object = |slot, frame_offset| CrDataObject {
            api: 0,
            slot,
            subslot: 1,
            frame_offset,
        };
        let cr = |input, frame_id, data_objects| ArCr {
            input,
            rt_class: 2,
            frame_id,
            send_clock_factor: 32,
            reduction_ratio: 4,
            phase: 2,
            data_hold_factor: 3,
            data_length: 40,
            data_objects,
        };
        let crs = [
            cr(true, 0x8002, vec![object(1, 0), object(2, 3)]),
            cr(false, 0x8003, vec![object(2, 0)]),
        ];
        let t = tree(1, 1, &[e(1, 2, 0), e(2, 0, 4)], &crs);
        // SAFETY: the tree's pointers point into its own vectors, alive with it.
        unsafe {
            let input = &*t.ar.pIoCrList;
            let output = &*t.ar.pIoCrList.add(1);
            assert_eq!(
                (
                    input.Direction,
                    input.IOCRProperties,
                    input.SendClock,
                    input.ReductioFactor,
                    input.Phase,
                    input.CycleTime
                ),
                (PNIO_IOCR_TYPE_INPUT, PNIO_IOCR_PROP_RT_CLASS_2, 32, 4, 2, 4)
            );
            assert_eq!(input.reserved[..2], [0x8002, 40]);
            assert_eq!(
                (output.Direction, output.reserved[0]),
                (PNIO_IOCR_TYPE_OUTPUT, 0x8003)
            );
            assert_eq!(input.NumOfIoCs, 2);
            let second = &*input.pIoCsList.add(1);
            assert_eq!((second.SlotNum, second.reserved), (2, 3));
        }
    }
}
