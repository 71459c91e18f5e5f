// SPDX-License-Identifier: MIT OR Apache-2.0
//! `PNIO_device_open`: the checks of its parameters, and attaching to procimgd's station.
//!
//! Codes where the manual names none for the case: a server that is not in the device role
//! answers `PNIO_ERR_PRM_CP_ID` (CpIndex names no IO device), a VendorId or DeviceId other
//! than the station's `PNIO_ERR_INVALID_CONFIG`, InstanceId other than 1
//! `PNIO_ERR_PRM_INVALIDARG`, a second open of the same instance in one process
//! `PNIO_ERR_SEQUENCE`; no server (or no answer) is `PNIO_ERR_NO_FW_COMMUNICATION`; an
//! instance whose ARs another program checks `PNIO_ERR_CREATE_INSTANCE`.

use super::state::{Device, instance_open};
use crate::iobase::controller::instance_for;
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::types::*;
use procimg_client::iobase::IoBaseDevice;
use procimg_client::{AttachError, AttachOptions, Client, Mode, Refusal, ServiceOptions, Services};

const F: &str = "PNIO_device_open";

/// The ExtPar bits a device takes: PNIO_CEP_MODE_CTRL (required), the MaxAr encoding, the
/// MRP role off (procimgd has no MRP, so it is off) and PROFIenergy (the program answers its
/// submodules' PE records).
const EXT_PAR_ALLOWED: u32 = PNIO_CEP_MODE_CTRL
    | PNIO_CEP_DEV_MAXAR_BY_TYPE
    | PNIO_CEP_SET_MRP_ROLE_OFF
    | PNIO_CEP_PE_MODE_ENABLE;

/// What `PNIO_device_open` and `PNIO_device_open_ext` were given, read from C.
pub(crate) struct OpenRequest {
    /// `CpIndex`.
    pub cp_index: u32,
    /// `ExtPar`.
    pub ext_par: u32,
    /// `VendorId`.
    pub vendor_id: u16,
    /// `DeviceId`.
    pub device_id: u16,
    /// `InstanceId`.
    pub instance_id: u16,
    /// `MaxAr`.
    pub max_ar: u32,
    /// `*pDevAnnotation`, if not NULL.
    pub annotation: Option<PNIO_ANNOTATION>,
    /// `pCbf->size`, if `pCbf` is not NULL.
    pub cbf_size: Option<u32>,
    /// `*pCbf`, if its size is this header's.
    pub cbf: Option<PNIO_CBF_FUNCTIONS>,
    /// `_ext`'s highest slot and subslot numbers.
    pub high: Option<(u16, u16)>,
}

/// Checks MaxAr: 1 to 3, or with PNIO_CEP_DEV_MAXAR_BY_TYPE the three counts (at least one
/// RT AR). procimgd's station serves one AR at a time whatever MaxAr says.
fn max_ar_ok(ext_par: u32, max_ar: u32) -> bool {
    if ext_par & PNIO_CEP_DEV_MAXAR_BY_TYPE != 0 {
        max_ar & !0xFFF == 0 && max_ar & 0xF >= 1
    } else {
        (1..=3).contains(&max_ar)
    }
}

/// Whether a fixed-size C text field holds its terminating NUL.
fn terminated(field: &[u8]) -> bool {
    field.contains(&0)
}

/// The mandatory callbacks missing from the table, by name.
fn missing_callbacks(c: &PNIO_CBF_FUNCTIONS) -> Vec<&'static str> {
    let mandatory = [
        ("cbf_data_write", c.cbf_data_write.is_some()),
        ("cbf_data_read", c.cbf_data_read.is_some()),
        ("cbf_rec_read", c.cbf_rec_read.is_some()),
        ("cbf_rec_write", c.cbf_rec_write.is_some()),
        ("cbf_alarm_done", c.cbf_alarm_done.is_some()),
        ("cbf_check_ind", c.cbf_check_ind.is_some()),
        ("cbf_ar_check_ind", c.cbf_ar_check_ind.is_some()),
        ("cbf_ar_info_ind", c.cbf_ar_info_ind.is_some()),
        ("cbf_ar_indata_ind", c.cbf_ar_indata_ind.is_some()),
        ("cbf_ar_abort_ind", c.cbf_ar_abort_ind.is_some()),
        ("cbf_ar_offline_ind", c.cbf_ar_offline_ind.is_some()),
        ("cbf_apdu_status_ind", c.cbf_apdu_status_ind.is_some()),
        ("cbf_prm_end_ind", c.cbf_prm_end_ind.is_some()),
        ("cbf_cp_stop_req", c.cbf_cp_stop_req.is_some()),
        ("cbf_device_stopped", c.cbf_device_stopped.is_some()),
    ];
    mandatory
        .into_iter()
        .filter(|(_, set)| !set)
        .map(|(n, _)| n)
        .collect()
}

/// Checks the parameters; the callback table when they hold.
pub(crate) fn check(req: &OpenRequest) -> Result<PNIO_CBF_FUNCTIONS, u32> {
    let cp = req.cp_index;
    crate::iobase::controller::check_cp_index(F, cp)?;
    let ext = req.ext_par;
    if ext & PNIO_CEP_MODE_CTRL == 0 {
        return Err(fail(
            F,
            PNIO_ERR_PRM_EXT_PAR,
            format_args!("ExtPar {ext:#x} lacks PNIO_CEP_MODE_CTRL, which a device always has"),
        ));
    }
    if ext & !EXT_PAR_ALLOWED != 0 {
        return Err(fail(
            F,
            PNIO_ERR_PRM_EXT_PAR,
            format_args!(
                "ExtPar {ext:#x} has bits {:#x} a device here does not take: only \
                 PNIO_CEP_MODE_CTRL, PNIO_CEP_DEV_MAXAR_BY_TYPE, PNIO_CEP_SET_MRP_ROLE_OFF and \
                 PNIO_CEP_PE_MODE_ENABLE (procimg offers no slice access on a device)",
                ext & !EXT_PAR_ALLOWED
            ),
        ));
    }
    if req.instance_id != 1 {
        return Err(fail(
            F,
            PNIO_ERR_PRM_INVALIDARG,
            format_args!("InstanceId {} is not 1 (it is reserved)", req.instance_id),
        ));
    }
    if !max_ar_ok(ext, req.max_ar) {
        return Err(fail(
            F,
            PNIO_ERR_PRM_MAX_AR_VALUE,
            format_args!(
                "MaxAr {:#x} is not 1, 2 or 3 (or PNIO_DEVICE_SET_MAXAR_BY_TYPE with at least \
                 one RT AR, with PNIO_CEP_DEV_MAXAR_BY_TYPE)",
                req.max_ar
            ),
        ));
    }
    match &req.annotation {
        None => {
            return Err(fail(
                F,
                PNIO_ERR_PRM_DEV_ANNOTATION,
                "pDevAnnotation is NULL",
            ));
        }
        Some(a) if !terminated(&a.deviceType) || !terminated(&a.orderId) => {
            return Err(fail(
                F,
                PNIO_ERR_PRM_DEV_ANNOTATION,
                "pDevAnnotation's deviceType or orderId has no terminating NUL",
            ));
        }
        Some(_) => {}
    }
    let want = size_of::<PNIO_CBF_FUNCTIONS>() as u32;
    let cbf = match (req.cbf_size, req.cbf) {
        (None, _) => return Err(fail(F, PNIO_ERR_PRM_PCBF, "pCbf is NULL")),
        (Some(_), Some(c)) => c,
        (Some(size), None) => {
            return Err(fail(
                F,
                PNIO_ERR_PRM_PCBF,
                format_args!(
                    "pCbf->size is {size}, not sizeof(PNIO_CBF_FUNCTIONS) = {want}: set it so"
                ),
            ));
        }
    };
    let missing = missing_callbacks(&cbf);
    if !missing.is_empty() {
        return Err(fail(
            F,
            PNIO_ERR_PRM_CALLBACK,
            format_args!(
                "mandatory callbacks are NULL: {} (only cbf_start_led_flash, \
                 cbf_stop_led_flash and cbf_pull_plug_conf may be)",
                missing.join(", ")
            ),
        ));
    }
    Ok(cbf)
}

/// The code and text for a failed attach.
fn attach_failure(cp: u32, instance: &str, e: &AttachError) -> u32 {
    let code = match e {
        AttachError::NoServer { .. } | AttachError::Timeout { .. } => PNIO_ERR_NO_FW_COMMUNICATION,
        AttachError::Refused {
            refusal: Refusal::TooManyClients { .. },
            ..
        } => PNIO_ERR_OS_RES,
        _ => PNIO_ERR_CREATE_INSTANCE,
    };
    fail(
        F,
        code,
        format_args!(
            "CpIndex {cp} is procimg instance \"{instance}\" (PROCIMG_CP{cp} or \
             PROCIMG_INSTANCE): {e}"
        ),
    )
}

/// Attaches to the instance CpIndex names, checks the station, takes it to OFFLINE and
/// registers the device; returns its handle.
pub(crate) fn open(req: &OpenRequest, cbf: PNIO_CBF_FUNCTIONS) -> Result<u32, u32> {
    let cp = req.cp_index;
    let instance = instance_for(cp);
    if instance_open(&instance) {
        return Err(fail(
            F,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "instance \"{instance}\" (CpIndex {cp}) is open as a device already: close it \
                 first"
            ),
        ));
    }
    let name = format!("PNIO device (CP {cp})");
    let client = Client::attach(&instance, AttachOptions::asynchronous(&name))
        .map_err(|e| attach_failure(cp, &instance, &e))?;
    if !client.is_device() {
        return Err(fail(
            F,
            PNIO_ERR_PRM_CP_ID,
            format_args!(
                "instance \"{instance}\" (CpIndex {cp}) is an IO controller: the device \
                 interface needs a procimgd with role = \"device\""
            ),
        ));
    }
    let station = client
        .control()
        .status()
        .ok()
        .and_then(|s| s.station)
        .ok_or_else(|| {
            fail(
                F,
                PNIO_ERR_NO_FW_COMMUNICATION,
                format_args!("instance \"{instance}\" did not report its station"),
            )
        })?;
    if (station.vendor_id, station.device_id) != (req.vendor_id, req.device_id) {
        return Err(fail(
            F,
            PNIO_ERR_INVALID_CONFIG,
            format_args!(
                "VendorId {:#06x} DeviceId {:#06x} are not the station's: instance \
                 \"{instance}\" is VendorID {:#06x} DeviceID {:#06x} (its configuration's \
                 [station] and GSDML)",
                req.vendor_id, req.device_id, station.vendor_id, station.device_id
            ),
        ));
    }
    if station.ip.is_empty() || station.ip == "0.0.0.0" {
        return Err(fail(
            F,
            PNIO_ERR_CONFIG_IN_UPDATE,
            format_args!(
                "station \"{}\" has no IP address yet (the PLC or the engineering tool sets it \
                 by DCP): call PNIO_device_open again until this code stops coming back",
                station.name
            ),
        ));
    }
    // The AR indications: this device checks the station's ARs and holds its
    // ApplicationReady until PNIO_set_appl_state_ready.
    let services = Services::open(&instance, ServiceOptions::new(&name))
        .map_err(|e| attach_failure(cp, &instance, &e))?;
    let iobase = IoBaseDevice::with_services(services)
        .map_err(|e| fail(F, PNIO_ERR_CREATE_INSTANCE, format_args!("{e}")))?;
    // The manual's device is not reachable for PLCs before PNIO_device_start.
    client.control().set_mode(Mode::Offline).map_err(|e| {
        fail(
            F,
            PNIO_ERR_NO_FW_COMMUNICATION,
            format_args!("instance \"{instance}\" did not take the mode OFFLINE: {e}"),
        )
    })?;
    let gsdml = station.program.map(|p| p.gsdml);
    Device::register(
        cp,
        instance,
        cbf,
        req.high,
        req.ext_par & PNIO_CEP_PE_MODE_ENABLE != 0,
        gsdml,
        client,
        iobase,
        super::worker::spawn,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_ar_as_the_manual_says() {
        assert!(max_ar_ok(PNIO_CEP_MODE_CTRL, 1));
        assert!(max_ar_ok(PNIO_CEP_MODE_CTRL, 3));
        assert!(!max_ar_ok(PNIO_CEP_MODE_CTRL, 0));
        assert!(!max_ar_ok(PNIO_CEP_MODE_CTRL, 4));
        let by_type = PNIO_CEP_MODE_CTRL | PNIO_CEP_DEV_MAXAR_BY_TYPE;
        assert!(max_ar_ok(by_type, 0x111));
        assert!(!max_ar_ok(by_type, 0x110), "no RT AR");
        assert!(!max_ar_ok(by_type, 0x1001));
    }

    unsafe extern "C" fn stopped(_: u32, _: u32) {}

    #[test]
    fn every_mandatory_callback_is_named_when_missing() {
        let mut c = PNIO_CBF_FUNCTIONS::default();
        assert_eq!(missing_callbacks(&c).len(), 15);
        c.cbf_device_stopped = Some(stopped);
        assert!(!missing_callbacks(&c).contains(&"cbf_device_stopped"));
    }
}
