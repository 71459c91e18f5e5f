// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's IO data: `PNIO_initiate_data_write(_ext)` and `PNIO_initiate_data_read(_ext)`
//! after their handle checks, and the claims of the program's I data.
//!
//! The device's client of procimgd (attached at open, asynchronous: the program calls the
//! `initiate_*` functions when it likes, as the manual says it need not follow the bus
//! cycle, and a synchronous client would hold up procimgd's cycle between two of its calls)
//! reads the newest image and writes without the STARTOP/OPDONE handshake. While the device
//! is started the client claims the I data of the program's submodules (start, and each plug
//! after it), so that the PLC gets them with the program's IOPS; it releases them at stop
//! and at each pull.
//!
//! One call walks the program's submodules that have data in its direction (I data for a
//! write: what the PLC reads; Q data for a read: what the PLC wrote), selected by `pAddr`
//! (NULL: all; subslot 0: the slot's; else that one, in any API) and by RT class
//! (`PNIO_ACCESS_*`), and calls the program's callback for each on the caller's thread. There
//! is something to visit only while an AR is up and its `PRM_END_IND` was given (else
//! `PNIO_WARN_NO_SUBMODULES`): the manual's steps 14 and 15 write the I data the PLC gets
//! with the ApplicationReady and read the Q data before `PNIO_set_appl_state_ready`. The
//! program's submodules are the station's tree from start on, so they are taken as the
//! AR's.
//!
//! Not zero-copy: the callbacks get a buffer of the library's, copied from or into the
//! image. The Q data of the newest image is mapped read-only while `PNIO_CBF_DATA_READ`'s
//! buffer is writable; and the client stays unlocked while callbacks run, because a callback
//! may call `initiate_*` again and the library thread needs the client for plugs and pulls
//! meanwhile. A write gathers every callback's I data and IOPS and sends them in one sample,
//! applied whole in one cycle; the IOCS a read's callback returns reaches the PLC in the next
//! cycle. What a callback returns other than `PNIO_S_GOOD` counts as `PNIO_S_BAD`.

use super::Pos;
use super::state::{Device, Life};
use crate::iobase::callbacks::invoke_device;
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::io_failure::{self, IoContext};
use crate::iobase::sync::lock;
use crate::iobase::types::{
    PNIO_ADDR_GEO, PNIO_IO_IN, PNIO_IO_OUT, PNIO_IOXS, PNIO_S_BAD, ioxs, pnio_ioxs,
};
use procimg_client::{Client, IoError, Ioxs};
use procimg_shm_layout::{NO_ADDRESS, RT_CLASS_3};
use std::time::Duration;

/// Which data the call visits, by RT class (`PNIO_ACCESS_ENUM`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Classes {
    /// RT and IRT.
    All,
    /// RT only (the plain calls).
    Rt,
    /// IRT only.
    Irt,
}

impl Classes {
    /// The classes `AccessType` selects, or the code for one the manual marks unsupported
    /// or does not have.
    pub(crate) fn of(f: &str, access: PNIO_ACCESS_ENUM) -> Result<Classes, u32> {
        match access {
            PNIO_ACCESS_ALL_WITHOUT_LOCK => Ok(Classes::All),
            PNIO_ACCESS_RT_WITH_LOCK | PNIO_ACCESS_RT_WITHOUT_LOCK => Ok(Classes::Rt),
            PNIO_ACCESS_IRT_WITHOUT_LOCK => Ok(Classes::Irt),
            PNIO_ACCESS_ALL_WITH_LOCK | PNIO_ACCESS_IRT_WITH_LOCK => Err(fail(
                f,
                PNIO_ERR_PRM_ACCESS_TYPE,
                format_args!("AccessType {access} is not supported (as in IO-Base)"),
            )),
            _ => Err(fail(
                f,
                PNIO_ERR_PRM_ACCESS_TYPE,
                format_args!("AccessType {access} is not a PNIO_ACCESS_ENUM value"),
            )),
        }
    }

    fn has(self, rt_class: u8) -> bool {
        match self {
            Classes::All => true,
            Classes::Rt => rt_class != RT_CLASS_3,
            Classes::Irt => rt_class == RT_CLASS_3,
        }
    }
}

/// The direction of a call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Direction {
    /// `initiate_data_write`: the I data, `PNIO_CBF_DATA_WRITE`.
    Write,
    /// `initiate_data_read`: the Q data, `PNIO_CBF_DATA_READ`.
    Read,
}

/// The local status a program's callback returned: a callback's answer cannot be refused,
/// so anything but GOOD goes out as BAD.
fn returned_ioxs(v: PNIO_IOXS) -> Ioxs {
    ioxs(v).unwrap_or(Ioxs::Bad)
}

/// The layout indexes of the submodules at `mine` with I data the client can claim.
fn claimable(client: &Client, mine: &[Pos]) -> Vec<usize> {
    client
        .layout()
        .submodules
        .iter()
        .enumerate()
        .filter(|(_, e)| e.output_length > 0 && e.output_address != NO_ADDRESS)
        .filter(|(_, e)| mine.contains(&(e.api, e.slot, e.subslot)))
        .map(|(i, _)| i)
        .collect()
}

/// Claims the I data of the program's submodules at `mine` that the client does not hold
/// yet.
pub(crate) fn claim(client: &mut Client, mine: &[Pos]) -> Result<(), String> {
    let want: Vec<usize> = claimable(client, mine)
        .into_iter()
        .filter(|&s| !client.holds(s))
        .collect();
    if want.is_empty() {
        return Ok(());
    }
    client
        .claim(&want)
        .map_err(|e| format!("cannot claim the program's I data: {e}"))
}

/// Releases what the client holds: everything, or the submodule at `at`.
pub(crate) fn release(client: &mut Client, at: Option<Pos>) {
    let held: Vec<usize> = (0..client.layout().submodules.len())
        .filter(|&s| client.holds(s) && at.is_none_or(|a| a == position(client, s)))
        .collect();
    if !held.is_empty() {
        // A server that is gone holds nothing any more.
        let _ = client.release(&held);
    }
}

/// The position of the layout's submodule `s`.
fn position(client: &Client, s: usize) -> Pos {
    let e = &client.layout().submodules[s];
    (e.api, e.slot, e.subslot)
}

/// How long `PNIO_set_appl_state_ready` waits for procimgd to apply the I data written
/// before it: a few cycles are plenty.
const APPLIED_WAIT: Duration = Duration::from_millis(500);

/// Before the ApplicationReady goes: the I data the program wrote (its steps 14 and 15)
/// is what procimgd's frames carry, so that the PLC gets it, IOPS included, with the
/// ApplicationReady and not a cycle after. Inside an isochronous device's STARTOP window the
/// data goes out with `PNIO_CP_set_opdone`, later: no wait then.
pub(crate) fn before_application_ready(dev: &Device) {
    if lock(&dev.iso.window).is_open() {
        return;
    }
    let applied = lock(&dev.client).wait_outputs_applied(APPLIED_WAIT);
    if let Ok(false) = applied {
        fail(
            "PNIO_set_appl_state_ready",
            PNIO_OK,
            format_args!(
                "instance \"{}\" did not apply the I data written before within {} ms: the \
                 ApplicationReady goes all the same",
                dev.instance,
                APPLIED_WAIT.as_millis()
            ),
        );
    }
}

/// One submodule a call visits.
struct Visit {
    slot: u16,
    subslot: u16,
    address: u32,
    buf: Vec<u8>,
    remote: Ioxs,
    local: PNIO_IOXS,
}

fn io_failure(f: &str, dev: &Device, e: IoError) -> u32 {
    let ctx = IoContext {
        instance: &dev.instance,
        owner: "the device",
        reclaim: "close that client, then stop the device and start it again \
                  (PNIO_device_stop, PNIO_device_start: start claims the I data)",
        fewer_writes: "call PNIO_initiate_data_write and PNIO_initiate_data_read less often: \
                       the server takes this device's samples once per cycle",
        // The device's writes do not wait for room.
        delivery_wait: None,
    };
    io_failure::io_failure(f, &ctx, e)
}

/// `PNIO_initiate_data_write(_ext)` and `PNIO_initiate_data_read(_ext)` after the handle
/// check: `addr` is the `pAddr` read (None for NULL).
pub(crate) fn initiate(
    f: &str,
    dev: &Device,
    addr: Option<PNIO_DEV_ADDR>,
    classes: Classes,
    dir: Direction,
) -> u32 {
    let filter = match addr {
        None => None,
        Some(a) if a.AddrType != PNIO_ADDR_GEO => {
            return fail(
                f,
                PNIO_ERR_PRM_ADD,
                format_args!(
                    "pAddr->AddrType is {}; device addresses are geographical \
                     (PNIO_ADDR_GEO)",
                    a.AddrType
                ),
            );
        }
        Some(a) => {
            // SAFETY: every field of the union's variants is an integer.
            let g = unsafe { a.u.Geo };
            Some((g.Slot, g.Subslot))
        }
    };
    let life = lock(&dev.config).life;
    if life == Life::Opened {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            "the device is not started: call PNIO_device_start, then exchange data after \
             PNIO_CBF_AR_INDATA_IND",
        );
    }
    let mine: Vec<Pos> = lock(&dev.config).subs.keys().copied().collect();
    let chosen: Vec<usize> = {
        let client = lock(&dev.client);
        (0..client.layout().submodules.len())
            .filter(|&i| mine.contains(&position(&client, i)))
            .filter(|&i| {
                let (_, slot, subslot) = position(&client, i);
                filter.is_none_or(|(s, ss)| {
                    s == u32::from(slot) && (ss == 0 || ss == u32::from(subslot))
                })
            })
            .collect()
    };
    if let Some((slot, subslot)) = filter
        && chosen.is_empty()
    {
        return fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!("the program has plugged no submodule at slot {slot} subslot {subslot}"),
        );
    }
    // From PRM_END_IND on (the manual's steps 14 and 15, before the ApplicationReady).
    let in_ar = dev.iobase.ar_takes_data();
    if !in_ar {
        return PNIO_WARN_NO_SUBMODULES;
    }
    let mut visits = Vec::new();
    {
        let mut client = lock(&dev.client);
        let entries = client.layout().submodules.clone();
        for i in chosen {
            // The layout changes only at start, before any AR: a submodule gone is skipped.
            let Some(&e) = entries.get(i) else {
                continue;
            };
            let (len, address) = match dir {
                Direction::Write => (e.output_length, e.output_address),
                Direction::Read => (e.input_length, e.input_address),
            };
            if len == 0 || address == NO_ADDRESS || !classes.has(e.rt_class) {
                continue;
            }
            let mut buf = vec![0u8; len as usize];
            let remote = match dir {
                // The I data as last sent, with the PLC's IOCS of it.
                Direction::Write => match client.output_data_read(address, &mut buf) {
                    Ok(r) => r.remote,
                    Err(e) => return io_failure(f, dev, e),
                },
                Direction::Read => match client.newest_input(i) {
                    Ok(Some(q)) => {
                        let n = buf.len().min(q.len());
                        buf[..n].copy_from_slice(&q[..n]);
                        match client.newest_status(i) {
                            Ok(st) => st.map_or(Ioxs::Bad, |st| st.input_remote),
                            Err(e) => return io_failure(f, dev, e),
                        }
                    }
                    Ok(None) => continue,
                    Err(e) => return io_failure(f, dev, e),
                },
            };
            let (_, slot, subslot) = (e.api, e.slot, e.subslot);
            visits.push(Visit {
                slot,
                subslot,
                address,
                buf,
                remote,
                local: PNIO_S_BAD,
            });
        }
    }
    if visits.is_empty() {
        return PNIO_WARN_NO_SUBMODULES;
    }
    for v in &mut visits {
        let io_type = match dir {
            Direction::Write => PNIO_IO_IN,
            Direction::Read => PNIO_IO_OUT,
        };
        let mut a = PNIO_DEV_ADDR::geo(io_type, u32::from(v.slot), u32::from(v.subslot));
        let pa: *mut PNIO_DEV_ADDR = &mut a;
        let len = v.buf.len() as u32;
        let pb = v.buf.as_mut_ptr();
        let rem = pnio_ioxs(v.remote);
        let mut local = PNIO_S_BAD;
        match dir {
            Direction::Write => {
                if let Some(cb) = dev.cbf.cbf_data_write {
                    // SAFETY: the program's PNIO_CBF_DATA_WRITE, callable until close; `pa`
                    // and `pb` (BufLen bytes) are valid for the call.
                    invoke_device(|| local = unsafe { cb(dev.handle, pa, len, pb, rem) });
                }
            }
            Direction::Read => {
                if let Some(cb) = dev.cbf.cbf_data_read {
                    // SAFETY: the program's PNIO_CBF_DATA_READ, callable until close; `pa`
                    // and `pb` (BufLen bytes) are valid for the call.
                    invoke_device(|| local = unsafe { cb(dev.handle, pa, len, pb, rem) });
                }
            }
        }
        v.local = local;
    }
    let mut client = lock(&dev.client);
    match dir {
        Direction::Write => {
            // Inside an isochronous device's STARTOP window the I data goes out with
            // PNIO_CP_set_opdone.
            let windowed = lock(&dev.iso.window).run(&mut client, |c| {
                visits.iter().try_for_each(|v| {
                    c.write(v.address, &v.buf, returned_ioxs(v.local))
                        .map(|_| ())
                })
            });
            let sent = windowed.unwrap_or_else(|| {
                visits
                    .iter()
                    .try_for_each(|v| {
                        client
                            .data_write_cache(v.address, &v.buf, returned_ioxs(v.local))
                            .map(|_| ())
                    })
                    .and_then(|()| client.data_write_cache_flush())
            });
            if let Err(e) = sent {
                return io_failure(f, dev, e);
            }
        }
        Direction::Read => {
            for v in &visits {
                // Reads again only to hand the IOCS over; sent when it changed.
                let mut scratch = vec![0u8; v.buf.len()];
                if let Err(e) = client.data_read(v.address, &mut scratch, returned_ioxs(v.local)) {
                    return io_failure(f, dev, e);
                }
            }
        }
    }
    PNIO_OK
}
