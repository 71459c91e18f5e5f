// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO data functions (`PNIO_data_read` and its kin) behind the C boundary: the manual's
//! parameter checks in its order, then procimg-client's access by logical address, inside
//! the STARTOP..OPDONE window when the controller is isochronous and a window is open.

use super::controller::{Controller, Io, lookup_io, wrong_handle};
use super::errors::fail;
use super::errors::*;
use super::io_failure::{self, IoContext, access_failure};
use super::sync::lock;
use super::types::*;
use procimg_client::access::{AccessError, Resolved, Space, resolve_read, resolve_write};
use procimg_client::{Client, Cycle, IoError, Ioxs};
use procimg_shm_layout::RT_CLASS_3;
use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

/// How long a write waits for room in the server's buffer for this client (it takes the
/// buffer's samples every cycle) before it gives up.
const DELIVERY_WAIT: Duration = Duration::from_millis(50);

/// The parameters of a read (`PNIO_data_read`, `PNIO_data_read_cache`,
/// `PNIO_output_data_read`), as C passed them.
pub(crate) struct ReadArgs {
    pub handle: u32,
    pub addr: *mut PNIO_ADDR,
    pub buf_len: u32,
    pub data_len: *mut PNIO_UINT32,
    pub buf: *mut PNIO_UINT8,
    /// `IOlocState` (reads of inputs).
    pub loc: PNIO_IOXS,
    /// `pIOlocState` (reads of outputs).
    pub loc_out: *mut PNIO_IOXS,
    pub rem: *mut PNIO_IOXS,
}

/// The parameters of a write (`PNIO_data_write`, `PNIO_data_write_cache`).
pub(crate) struct WriteArgs {
    pub handle: u32,
    pub addr: *mut PNIO_ADDR,
    pub buf_len: u32,
    pub buf: *mut PNIO_UINT8,
    pub loc: PNIO_IOXS,
    pub rem: *mut PNIO_IOXS,
}

/// Which read.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum ReadKind {
    /// `PNIO_data_read`.
    Direct,
    /// `PNIO_data_read_cache`.
    Cache,
    /// `PNIO_output_data_read`.
    Outputs,
}

/// Reads and checks `pAddr`: not NULL, the space `want`, a logical address.
///
/// # Safety
/// `p` is NULL or points to a readable `PNIO_ADDR`.
unsafe fn checked_addr(f: &str, p: *const PNIO_ADDR, want: PNIO_IO_TYPE) -> Result<PNIO_ADDR, u32> {
    if p.is_null() {
        return Err(fail(f, PNIO_ERR_PRM_ADD, "pAddr is NULL"));
    }
    // SAFETY: not NULL, readable by the caller's contract; unaligned reads are fine.
    let a = unsafe { p.read_unaligned() };
    if a.IODataType != want {
        let (needs, space) = if want == PNIO_IO_IN {
            ("PNIO_IO_IN", "inputs")
        } else {
            ("PNIO_IO_OUT", "outputs")
        };
        return Err(fail(
            f,
            PNIO_ERR_PRM_IO_TYPE,
            format_args!(
                "pAddr->IODataType is {}; this function accesses {space}: set {needs}",
                a.IODataType
            ),
        ));
    }
    if a.AddrType != PNIO_ADDR_LOG {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!(
                "pAddr->AddrType is {}; a controller addresses by logical address only \
                 (PNIO_ADDR_LOG)",
                a.AddrType
            ),
        ));
    }
    Ok(a)
}

fn io_failure(f: &str, ctl: &Controller, e: IoError) -> u32 {
    let ctx = IoContext {
        instance: &ctl.instance,
        owner: "the controller",
        reclaim: "close that client, then close the controller and open it again",
        fewer_writes: "write fewer times per cycle, or use PNIO_data_write_cache and one \
                       PNIO_data_write_cache_flush",
        delivery_wait: Some(DELIVERY_WAIT),
    };
    io_failure::io_failure(f, &ctx, e)
}

/// The client, or the code for a controller that lost it.
fn client<'a>(f: &str, ctl: &Controller, io: &'a mut Io) -> Result<&'a mut Client, u32> {
    io.client.as_mut().ok_or_else(|| {
        fail(
            f,
            PNIO_ERR_NO_CONNECTION,
            format_args!(
                "controller {} lost instance \"{}\" when it re-attached; close and open it again",
                ctl.handle, ctl.instance
            ),
        )
    })
}

/// Runs `op` on the client, again while the server's buffer for this client is full.
fn delivered<R>(
    client: &mut Client,
    mut op: impl FnMut(&mut Client) -> Result<R, IoError>,
) -> Result<R, IoError> {
    let until = Instant::now() + DELIVERY_WAIT;
    loop {
        match op(client) {
            Err(IoError::NotDelivered(_)) if Instant::now() < until => {
                std::thread::sleep(Duration::from_micros(200));
            }
            r => return r,
        }
    }
}

/// Runs `op` inside the open STARTOP window; `None` when none is open (or it is over).
fn in_window<R>(io: &mut Io, op: impl FnOnce(&mut Cycle<'_>) -> R) -> Option<R> {
    let client = io.client.as_mut()?;
    io.window.run(client, op)
}

/// Whether the device of submodule `s` exchanges data; sets `*rem` BAD when not.
///
/// # Safety
/// `rem` is a valid, writable pointer.
unsafe fn connected(f: &str, ctl: &Controller, s: usize, rem: *mut PNIO_IOXS) -> Result<(), u32> {
    let device = ctl.layout.submodules[s].device as usize;
    if ctl.mode() != PNIO_MODE_OFFLINE && ctl.device_up(device) {
        return Ok(());
    }
    // SAFETY: checked for NULL by the caller, writable by the C caller's contract.
    unsafe { rem.write_unaligned(PNIO_S_BAD) };
    Err(fail(
        f,
        PNIO_ERR_NO_CONNECTION,
        format_args!(
            "device \"{}\" is not in data exchange ({}); wait for its return alarm \
             (PNIO_ALARM_DEV_RETURN)",
            ctl.layout.device_name(device),
            if ctl.mode() == PNIO_MODE_OFFLINE {
                "the controller is OFFLINE"
            } else {
                "not connected or deactivated"
            }
        ),
    ))
}

/// The controller of `handle` for a data access, after checking the buffer is given: what
/// every data function checks first, in the IO-Base order.
fn controller_and_buffer(
    f: &str,
    handle: u32,
    buf_is_null: bool,
    buf_len: u32,
) -> Result<Arc<Controller>, u32> {
    let Some(ctl) = lookup_io(handle) else {
        return Err(wrong_handle(f, handle));
    };
    if buf_is_null || buf_len == 0 {
        return Err(fail(
            f,
            PNIO_ERR_PRM_BUF,
            format_args!("pBuffer is NULL or BufLen is 0 (BufLen {buf_len})"),
        ));
    }
    Ok(ctl)
}

/// The local status an `IOlocState` argument gives; anything but GOOD and BAD is refused.
fn local_state(f: &str, loc: PNIO_IOXS) -> Result<Ioxs, u32> {
    ioxs(loc).ok_or_else(|| {
        fail(
            f,
            PNIO_ERR_PRM_LOC_STATE,
            format_args!("IOlocState {loc} is neither PNIO_S_GOOD nor PNIO_S_BAD"),
        )
    })
}

/// `Ok` when the access resolved to a submodule whose device exchanges data ([`connected`]
/// writes `*rem`).
///
/// # Safety
/// `rem` is not NULL and writable.
unsafe fn reachable(
    f: &str,
    ctl: &Controller,
    resolved: Result<Resolved, AccessError>,
    rem: *mut PNIO_IOXS,
) -> Result<(), u32> {
    let r = resolved.map_err(|e| access_failure(f, e))?;
    // SAFETY: as the caller's contract says.
    unsafe { connected(f, ctl, r.submodule, rem) }
}

/// `PNIO_data_read`, `PNIO_data_read_cache`, `PNIO_output_data_read`.
///
/// # Safety
/// The pointers in `a` are NULL or valid for what the IO-Base prototypes say (`buf` for
/// `buf_len` bytes).
pub(crate) unsafe fn read(f: &str, kind: ReadKind, a: &ReadArgs) -> u32 {
    let ctl = match controller_and_buffer(f, a.handle, a.buf.is_null(), a.buf_len) {
        Ok(ctl) => ctl,
        Err(code) => return code,
    };
    let want = if kind == ReadKind::Outputs {
        PNIO_IO_OUT
    } else {
        PNIO_IO_IN
    };
    // SAFETY: forwarded from the caller's contract.
    let addr = match unsafe { checked_addr(f, a.addr, want) } {
        Ok(x) => x,
        Err(code) => return code,
    };
    let local = if kind == ReadKind::Outputs {
        if a.loc_out.is_null() {
            return fail(f, PNIO_ERR_PRM_LOC_STATE, "pIOlocState is NULL");
        }
        Ioxs::Good
    } else {
        match local_state(f, a.loc) {
            Ok(l) => l,
            Err(code) => return code,
        }
    };
    if a.data_len.is_null() {
        return fail(f, PNIO_ERR_PRM_LEN, "pDataLen is NULL");
    }
    if a.rem.is_null() {
        return fail(f, PNIO_ERR_PRM_RSTATE, "pIOremState is NULL");
    }
    let space = if kind == ReadKind::Outputs {
        Space::Output
    } else {
        Space::Input
    };
    let address = addr.addr();
    let resolved = resolve_read(
        &ctl.layout.submodules,
        space,
        address,
        a.buf_len as usize,
        ctl.slice,
    );
    let irt_data = is_irt(&ctl, &resolved);
    // SAFETY: `rem` checked for NULL above.
    if let Err(code) = unsafe { reachable(f, &ctl, resolved, a.rem) } {
        return code;
    }
    // SAFETY: not NULL, and the caller's buffer holds BufLen bytes.
    let buf = unsafe { std::slice::from_raw_parts_mut(a.buf, a.buf_len as usize) };
    let iso = ctl.isochronous.load(Ordering::Acquire);
    // The window's rules are IRT data's: an isochronous controller's RT data is read as any.
    let irt = iso && irt_data;
    let mut guard = lock(&ctl.io);
    let io = &mut *guard;
    let (res, warn) = if kind == ReadKind::Outputs {
        let client = match client(f, &ctl, io) {
            Ok(c) => c,
            Err(code) => return code,
        };
        match client.output_data_read(address, buf) {
            Ok(o) => {
                // SAFETY: checked for NULL above, writable by the caller's contract.
                unsafe { a.loc_out.write_unaligned(pnio_ioxs(o.local)) };
                (Ok((o.len, o.remote)), false)
            }
            Err(e) => (Err(e), false),
        }
    } else if let Some(res) = iso
        .then(|| in_window(io, |c| c.read(address, buf, local)))
        .flatten()
    {
        (res.map(|x| (x.len, x.remote)), false)
    } else {
        let client = match client(f, &ctl, io) {
            Ok(c) => c,
            Err(code) => return code,
        };
        // The cached path of an isochronous controller's IRT data is the direct one (the
        // manual).
        let res = if kind == ReadKind::Cache && !irt {
            match client.data_read_cache(address, buf, local) {
                Err(IoError::NoImage { .. }) => {
                    return fail(
                        f,
                        PNIO_ERR_NO_CONNECTION,
                        "the read cache is empty: call PNIO_data_read_cache_refresh first",
                    );
                }
                r => r,
            }
        } else {
            delivered(client, |c| c.data_read(address, buf, local))
        };
        (res.map(|x| (x.len, x.remote)), irt)
    };
    drop(guard);
    match res {
        Ok((len, remote)) => {
            // SAFETY: both checked for NULL above, writable by the caller's contract.
            unsafe {
                a.data_len.write_unaligned(len as u32);
                a.rem.write_unaligned(pnio_ioxs(remote));
            }
            if warn { irt_inconsistent(f) } else { PNIO_OK }
        }
        Err(e) => io_failure(f, &ctl, e),
    }
}

/// Whether an access resolved to IRT data (a submodule of RT class 3).
fn is_irt(ctl: &Controller, resolved: &Result<Resolved, AccessError>) -> bool {
    resolved.as_ref().is_ok_and(|r| {
        ctl.layout
            .submodules
            .get(r.submodule)
            .is_some_and(|e| e.rt_class == RT_CLASS_3)
    })
}

fn irt_inconsistent(f: &str) -> u32 {
    fail(
        f,
        PNIO_WARN_IRT_INCONSISTENT,
        "IRT data accessed outside the STARTOP..PNIO_CP_set_opdone window of this isochronous \
         controller: the data may belong to another cycle than the rest",
    )
}

/// `PNIO_data_write`, `PNIO_data_write_cache`.
///
/// # Safety
/// The pointers in `a` are NULL or valid for what the IO-Base prototypes say (`buf` for
/// `buf_len` bytes).
pub(crate) unsafe fn write(f: &str, cached: bool, a: &WriteArgs) -> u32 {
    let ctl = match controller_and_buffer(f, a.handle, a.buf.is_null(), a.buf_len) {
        Ok(ctl) => ctl,
        Err(code) => return code,
    };
    // SAFETY: forwarded from the caller's contract.
    let addr = match unsafe { checked_addr(f, a.addr, PNIO_IO_OUT) } {
        Ok(x) => x,
        Err(code) => return code,
    };
    let local = match local_state(f, a.loc) {
        Ok(l) => l,
        Err(code) => return code,
    };
    if a.rem.is_null() {
        return fail(f, PNIO_ERR_PRM_RSTATE, "pIOremState is NULL");
    }
    let address = addr.addr();
    let resolved = resolve_write(
        &ctl.layout.submodules,
        address,
        a.buf_len as usize,
        ctl.slice,
    );
    let irt_data = is_irt(&ctl, &resolved);
    // SAFETY: `rem` checked for NULL above.
    if let Err(code) = unsafe { reachable(f, &ctl, resolved, a.rem) } {
        return code;
    }
    // SAFETY: not NULL, and the caller's buffer holds BufLen bytes.
    let data = unsafe { std::slice::from_raw_parts(a.buf.cast_const(), a.buf_len as usize) };
    let iso = ctl.isochronous.load(Ordering::Acquire);
    let irt = iso && irt_data;
    let mut guard = lock(&ctl.io);
    let io = &mut *guard;
    let (res, warn) = if let Some(res) = iso
        .then(|| in_window(io, |c| c.write(address, data, local)))
        .flatten()
    {
        (res, false)
    } else {
        let client = match client(f, &ctl, io) {
            Ok(c) => c,
            Err(code) => return code,
        };
        let res = if cached && !irt {
            client.data_write_cache(address, data, local)
        } else {
            delivered(client, |c| c.data_write(address, data, local))
        };
        (res, irt)
    };
    drop(guard);
    match res {
        Ok(remote) => {
            // SAFETY: checked for NULL above, writable by the caller's contract.
            unsafe { a.rem.write_unaligned(pnio_ioxs(remote)) };
            if warn { irt_inconsistent(f) } else { PNIO_OK }
        }
        Err(e) => io_failure(f, &ctl, e),
    }
}

/// `PNIO_data_read_cache_refresh` (`flush` false) and `PNIO_data_write_cache_flush`.
pub(crate) fn cache(f: &str, handle: u32, flush: bool) -> u32 {
    let Some(ctl) = lookup_io(handle) else {
        return wrong_handle(f, handle);
    };
    // Refresh and flush move what the cached functions hold: for an isochronous controller
    // its RT data only (its IRT data goes the direct way).
    let mut io = lock(&ctl.io);
    let client = match client(f, &ctl, &mut io) {
        Ok(c) => c,
        Err(code) => return code,
    };
    let res = if flush {
        delivered(client, |c| c.data_write_cache_flush())
    } else {
        client.data_read_cache_refresh()
    };
    drop(io);
    match res {
        Ok(()) => PNIO_OK,
        Err(e) => io_failure(f, &ctl, e),
    }
}

/// `PNIO_CP_set_opdone`.
///
/// # Safety
/// `out` is NULL or points to a writable `PNIO_CYCLE_INFO`.
pub(crate) unsafe fn set_opdone(handle: u32, out: *mut PNIO_CYCLE_INFO) -> u32 {
    const F: &str = "PNIO_CP_set_opdone";
    let Some(ctl) = lookup_io(handle) else {
        return wrong_handle(F, handle);
    };
    let ctl: Arc<Controller> = ctl;
    if !ctl.isochronous.load(Ordering::Acquire) {
        return fail(
            F,
            PNIO_ERR_STARTOP_NOT_REGISTERED,
            "no PNIO_CP_CBE_STARTOP_IND callback is registered: the controller takes no part \
             in the cycle (register OPFAULT_IND, then STARTOP_IND with PNIO_CP_register_cbf)",
        );
    }
    let mut guard = lock(&ctl.io);
    let io = &mut *guard;
    if let Err(code) = client(F, &ctl, io) {
        return code;
    }
    let Some(c) = io.client.as_mut() else {
        return PNIO_ERR_INTERNAL;
    };
    let res = io.window.set_opdone(c);
    drop(guard);
    match res {
        Ok(info) => {
            if !out.is_null() {
                // SAFETY: not NULL, writable by the caller's contract.
                unsafe { out.write_unaligned(info) };
            }
            PNIO_OK
        }
        Err(code) => code,
    }
}
