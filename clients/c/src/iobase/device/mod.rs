// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO device side of the IO-Base API (`pniousrd.h`): management (`PNIO_device_open`,
//! `_close`, `_start`, `_stop`), configuration (`PNIO_api_add`, `_remove`,
//! `PNIO_mod_plug`, `_pull`, `PNIO_sub_plug`, `_ext`, `_ext_IM`, `PNIO_sub_pull`) and AR
//! control (`PNIO_set_appl_state_ready`, `PNIO_device_ar_abort`, the AR callbacks) and the
//! IO data (`PNIO_initiate_data_write`, `_read` and their `_ext`, with `PNIO_CBF_DATA_WRITE`
//! and `PNIO_CBF_DATA_READ`), records, diagnosis and alarms over procimgd's device role.
//!
//! * `open`: the checks of `PNIO_device_open`'s parameters, and attaching to the station;
//! * `state`: an open device, its lifecycle and the program's configuration, and the table of
//!   handles;
//! * `config`: the address and sequence checks of the configuration functions;
//! * `jobs`: what the program's calls give the library thread, and the thread's handle;
//! * `worker`: the library thread that carries plugs, pulls, start, stop and AR aborts out
//!   on procimgd and calls `PNIO_CBF_PULL_PLUG_CONF` and `PNIO_CBF_DEVICE_STOPPED`, and
//!   between them hands the station's notifications to `ar`;
//! * `station`: a plug or pull on procimgd's station, and the IO-Base codes of its
//!   refusals;
//! * `data`: the IO data functions (the callbacks on the caller's thread, the IOxS they
//!   return sent), and the claims of the program's I data from start to stop;
//! * `isochronous`: `PNIO_CP_register_cbf` and `PNIO_CP_set_opdone` with a device handle,
//!   and the thread that delivers STARTOP_IND, OPFAULT_IND and NEWCYCLE_IND (the window
//!   and the registration rules are `crate::iobase::isochronous`'s, the thread's loop
//!   `crate::iobase::cycle_thread`'s, both shared with the controller);
//! * `ar`: the AR indications (`AR_CHECK_IND`, `CHECK_IND`, `AR_INFO_IND`, `PRM_END_IND`,
//!   `AR_INDATA_IND`, `APDU_STATUS_IND`, `AR_ABORT_IND`, `AR_OFFLINE_IND`), the LED's
//!   (`START_LED_FLASH`, `STOP_LED_FLASH`) and `CP_STOP_REQ`, as C callbacks of the
//!   [`DeviceCallbacks`](procimg_client::iobase::DeviceCallbacks) that the device's
//!   [`IoBaseDevice`](procimg_client::iobase::IoBaseDevice) calls;
//! * `records`: the records the library takes from start to stop, and `PNIO_CBF_REC_READ`
//!   and `PNIO_CBF_REC_WRITE` for procimgd's record jobs;
//! * `diag`: the checks of the diagnosis functions (the DiagTags are the
//!   `IoBaseDevice`'s);
//! * `alarms`: the program's alarms and their `PNIO_CBF_REQ_DONE`;
//! * `held`: what an open device keeps for `alarms` and `isochronous`.
//!
//! The IO-Base semantics that are not about C (ArNumber and SessionKey, the order of the
//! indications, the ApplicationReady, DiagTags, the LED's three seconds) are the Rust
//! client's [`procimg_client::iobase`], which a Rust device program uses without this
//! library.
//!
//! # Lifecycle
//!
//! `PNIO_device_open` attaches to the procimgd instance that CpIndex names (as for the
//! controller: `PROCIMG_CP<n>`, else `PROCIMG_INSTANCE`, else `procimg`), which must be in the
//! device role with the VendorID and DeviceID given (its configuration's, or its GSDML
//! file's), and takes the server to OFFLINE: the
//! station takes no AR until `PNIO_device_start`, which takes it to OPERATE. From open to
//! close the device checks the station's ARs and holds its ApplicationReady, so that the
//! AR callbacks come in the manual's order and `PNIO_set_appl_state_ready` sends it (see
//! `ar`). `PNIO_device_stop` takes it to OFFLINE again (the PLC's AR ends with an abort:
//! `AR_OFFLINE_IND`, or `AR_ABORT_IND` before data exchange) and confirms with
//! `PNIO_CBF_DEVICE_STOPPED` on the library thread. `PNIO_device_close` leaves
//! the server as it is (OFFLINE after a stop). Open → (api_add, plug) → start → stop → (pull,
//! api_remove) → close; every call out of this order answers `PNIO_ERR_SEQUENCE`, as does
//! every call from inside a callback but the IO data, diagnosis, alarm and state ones (which
//! go to procimgd directly, not through the library thread).
//!
//! The CP application watchdog (`crate::iobase::watchdog`) stops a device on expiry: every
//! call answers `PNIO_ERR_NO_FW_COMMUNICATION` but `PNIO_device_close`, which then also
//! takes a started device OFFLINE.
//!
//! # A station its program defines
//!
//! When procimgd's configuration names only the station's GSDML file (`[station] gsdml`, no
//! submodules), the program's plugs outside slot 0 are its station: each submodule plug is
//! checked at once against the file by procimgd (a module or submodule ident the file lacks,
//! or a slot or subslot it does not allow: `PNIO_ERR_PRM_ADD`, the text naming the ident
//! and the file) and confirmed without changing procimgd's station, which waits off the
//! wire with its device access point. `PNIO_device_start` defines the station with the
//! program's tree (each submodule's records the program's, with its I&M records when
//! plugged with I&M0 bits): procimgd runs the station anew with the lengths the file gives,
//! the device's client follows the new layout, and the PLC may connect at once; the
//! device's AR checks and its hold of the ApplicationReady are in place from the station's
//! first moment. A start after a stop defines the station again only when the program's
//! tree changed. After start, plug and pull work on the positions of the defined tree, as
//! for a configured station. `PNIO_device_close` (or the program's end) ends the station:
//! its AR ends with an abort and it waits off the wire for the next program.
//!
//! # Plugging
//!
//! procimgd's station has the positions its configuration gives, each with its IO lengths.
//! The program's plugs must lie at those positions (any other: `PNIO_ERR_PRM_ADD`); their
//! IO lengths are the configured ones. `PNIO_mod_plug` only records the slot's
//! ModuleIdentNumber (procimgd plugs submodules, each with its module's ident number); each
//! submodule plug is carried out on procimgd on the library thread, then confirmed:
//!
//! * an empty position is plugged with the program's ident numbers;
//! * a position where procimgd has a submodule with the same ident numbers is taken as the
//!   program's as it is (no pull, no alarm);
//! * a position where procimgd has a submodule with other ident numbers is pulled and
//!   plugged with the program's.
//!
//! What procimgd has at a position is, as far as the library knows, what its configuration
//! says, or what this library plugged or pulled there since open; a plug or pull by another
//! client of the instance meanwhile is not seen.
//!
//! `PNIO_device_start` pulls every position of the station outside slot 0 that the program
//! has not plugged, so that the PLC sees the program's tree; slot 0 (the DAP, its interface
//! and ports) stays as procimgd has it unless the program plugs there. Pulls
//! (`PNIO_sub_pull`, `PNIO_mod_pull`) take the program's submodules out of procimgd's
//! station. After start, plug and pull need `PNIO_CBF_PULL_PLUG_CONF` (without it:
//! `PNIO_ERR_SEQUENCE`) and reach the PLC as Pull, Plug or Plug Wrong alarms; between the
//! PLC's Connect and data exchange procimgd refuses them, and the confirmation carries
//! `PNIO_ERR_SEQUENCE`.
//!
//! # IO data
//!
//! The device's client of procimgd is asynchronous: the program exchanges data when it likes
//! and procimgd's cycle never waits for it. With `PNIO_CP_CBE_STARTOP_IND` registered
//! (before start) it is synchronous instead, as an isochronous controller's: STARTOP_IND
//! every cycle on a library thread, the data functions inside it act on that cycle, and
//! `PNIO_CP_set_opdone` hands the I data over (see `isochronous`). From start to stop the client claims the I data
//! of the program's submodules (and of each one plugged after start, released at each pull),
//! so that the PLC gets them with the IOPS the program returns; before the first write they
//! go with IOPS BAD. `PNIO_initiate_data_write(_ext)` calls `PNIO_CBF_DATA_WRITE` on the
//! caller's thread for each of the program's submodules with I data (the PLC's IOCS of the I
//! data sent before as `IOremState`, the buffer starting as last sent) and sends all of them
//! with their IOPS in one sample; `PNIO_initiate_data_read(_ext)` calls
//! `PNIO_CBF_DATA_READ` for each with Q data, with the newest image's Q data and the PLC's
//! IOPS, and sends the IOCS returned. The plain calls visit RT data; `_ext` selects by
//! `pAddr` (NULL, a slot with subslot 0, or one submodule; one the program has not plugged:
//! `PNIO_ERR_PRM_ADD`) and `AccessType` (`ALL_WITH_LOCK` and `IRT_WITH_LOCK`, unsupported as
//! in IO-Base, and unknown values: `PNIO_ERR_PRM_ACCESS_TYPE`). Before start they answer
//! `PNIO_ERR_SEQUENCE`; with no AR whose `PRM_END_IND` was given (the manual writes the
//! first I data after it, before `PNIO_set_appl_state_ready`), or nothing selected,
//! `PNIO_WARN_NO_SUBMODULES`. They may be called inside callbacks.
//! The buffers are copies, not the shared memory itself (see `data` for why).

/// API, slot, subslot.
pub(crate) type Pos = (u32, u16, u16);

use crate::iobase::errors::{PNIO_ERR_SEQUENCE, PNIO_ERR_SESSION, fail};
use procimg_client::iobase::SessionError;

/// The code of a call naming an AR that is not the current one: an ArNumber this device
/// never gave is out of sequence; an ended AR's, or the current one's with another
/// SessionKey, a session error.
pub(crate) fn session_failure(f: &str, e: SessionError) -> u32 {
    let code = match e {
        SessionError::NeverGiven { .. } => PNIO_ERR_SEQUENCE,
        SessionError::WrongSessionKey { .. } | SessionError::Ended { .. } => PNIO_ERR_SESSION,
    };
    fail(f, code, e)
}

pub(crate) mod alarms;
pub(crate) mod ar;
pub(crate) mod config;
pub(crate) mod data;
pub(crate) mod diag;
pub(crate) mod held;
pub(crate) mod isochronous;
pub(crate) mod jobs;
pub(crate) mod open;
pub(crate) mod ready_list;
pub(crate) mod records;
pub(crate) mod state;
pub(crate) mod station;
pub(crate) mod worker;
