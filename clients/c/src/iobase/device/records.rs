// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PLC's record reads and writes of the program's submodules (`PNIO_CBF_REC_READ`,
//! `PNIO_CBF_REC_WRITE`), and which records the program answers.
//!
//! From `PNIO_device_start` to `PNIO_device_stop` the library takes the user records
//! (indices 0x0000–0x7FFF) of every submodule the program plugged, and of those it plugged
//! with I&M0 bits (`PNIO_sub_plug_ext_IM`, anything but `PNIO_PLUG_IM0_BITS_NOTHING`) the I&M
//! records 0xAFF0–0xAFF4 as well: procimgd hands each read or write of them to the library
//! thread, which calls the callback and answers with what it returns. The other records
//! (identification, diagnosis, ModuleDiff, I&M0FilterData, and I&M of the submodules
//! plugged without I&M bits) are procimgd's, as the stack's are on a CP.
//!
//! A read gives the callback a buffer of the length the PLC takes (`*pBufLen`), and sends
//! the first `*pBufLen` bytes the callback leaves there; a write gives it the PLC's data.
//! A `PNIO_ERR_STAT` with ErrCode1 other than 0 refuses the job with that ErrorCode1 and
//! ErrorCode2 (procimgd sets ErrorCode 0xDE or 0xDF and ErrorDecode PNIORW). The callback
//! has procimgd's record timeout (2 s) to return; later, the PLC got "resource busy".

use super::Pos;
use super::state::{Device, Life};
use crate::iobase::callbacks::invoke_device;
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use crate::iobase::types::{PNIO_ERR_STAT, PNIO_IO_IN, PNIO_IO_OUT};
use procimg_client::iobase::ArId;
use procimg_client::{RecordRefusal, StationRecordJob};
use std::collections::BTreeMap;

/// The submodules whose records the library took: with their I&M records or not.
pub(crate) type Taken = BTreeMap<Pos, bool>;

/// The most bytes a read callback gets to fill: a record read's data fits in one RPC
/// fragment's worth of what a PLC asks for.
const MAX_READ: u32 = 65_535;

/// Takes the records of the program's submodules while the device is started, and gives
/// back those it holds no more (pulled, or the device stopped).
pub(crate) fn follow(dev: &Device, taken: &mut Taken) {
    let wanted: Taken = {
        let c = lock(&dev.config);
        if c.life == Life::Started {
            c.subs.keys().map(|p| (*p, c.im.contains(p))).collect()
        } else {
            Taken::new()
        }
    };
    if wanted == *taken {
        return;
    }
    let services = dev.iobase.services();
    taken.retain(|p, _| {
        // A pulled submodule's records went back with it: a refusal says no more than that.
        wanted.contains_key(p) || {
            let _ = services.give_back_records(*p);
            false
        }
    });
    for (&p, &im) in &wanted {
        if taken.get(&p) == Some(&im) {
            continue;
        }
        let r = services.take_records_with(p, im, dev.pe);
        match r {
            Ok(()) => {
                taken.insert(p, im);
            }
            Err(e) => {
                fail(
                    "PNIO_device_start",
                    PNIO_ERR_NO_FW_COMMUNICATION,
                    format_args!(
                        "the records of API {} slot {} subslot {:#06x} stay procimgd's: {e}",
                        p.0, p.1, p.2
                    ),
                );
            }
        }
    }
}

/// A record job of procimgd: the callback, then the answer.
pub(crate) fn job(dev: &Device, ar: Option<ArId>, job: &StationRecordJob) {
    let (callback, mut data) = if job.write {
        (dev.cbf.cbf_rec_write, job.data.clone())
    } else {
        (
            dev.cbf.cbf_rec_read,
            vec![0u8; job.max_len.min(MAX_READ) as usize],
        )
    };
    let answer = match callback {
        Some(f) => call(dev, f, ar, job, &mut data).map(|len| {
            // A length above the buffer is the program's error: not more than it has.
            data.truncate(len.min(data.len() as u32) as usize);
            if job.write { Vec::new() } else { data }
        }),
        None => Err(RecordRefusal::new(RecordRefusal::INVALID_INDEX)),
    };
    let answer = answer.as_deref().map_err(|r| *r);
    if let Err(e) = dev.iobase.services().answer_record(job, answer) {
        fail(
            if job.write {
                "PNIO_CBF_REC_WRITE"
            } else {
                "PNIO_CBF_REC_READ"
            },
            PNIO_ERR_NO_FW_COMMUNICATION,
            format_args!(
                "record job {} ({:#06x} of slot {} subslot {:#06x}) not answered: {e}",
                job.job, job.index, job.slot, job.subslot
            ),
        );
    }
}

/// Calls `f` (`PNIO_CBF_REC_READ` or `_WRITE`, which have one type) for `job` with `data`
/// as the buffer: the length the program leaves, or the refusal its `PNIO_ERR_STAT` says.
fn call(
    dev: &Device,
    f: unsafe extern "C" fn(
        u32,
        u32,
        u16,
        u16,
        u32,
        *mut PNIO_DEV_ADDR,
        u32,
        *mut u32,
        *mut u8,
        *mut PNIO_ERR_STAT,
    ),
    ar: Option<ArId>,
    job: &StationRecordJob,
    data: &mut [u8],
) -> Result<u32, RecordRefusal> {
    let (number, key) = ar.map_or((0, 0), |a| (a.number, a.session_key));
    let sequence = {
        let mut c = lock(&dev.config);
        c.record_sequence = c.record_sequence.wrapping_add(1);
        c.record_sequence
    };
    let mut addr = PNIO_DEV_ADDR::geo(
        if job.write { PNIO_IO_OUT } else { PNIO_IO_IN },
        job.slot.into(),
        job.subslot.into(),
    );
    let mut state = PNIO_ERR_STAT::default();
    let mut len = data.len() as u32;
    let (pa, pl, pd, ps) = (
        &mut addr as *mut _,
        &mut len as *mut u32,
        data.as_mut_ptr(),
        &mut state as *mut _,
    );
    let index = u32::from(job.index);
    // SAFETY: a record callback the program gave PNIO_device_open, callable until
    // PNIO_device_close (which waits for this thread); the pointers are to locals that
    // outlive the call, the buffer holds `len` bytes, the most the program may use.
    invoke_device(|| unsafe {
        f(
            dev.handle, job.api, number, key, sequence, pa, index, pl, pd, ps,
        )
    });
    match refusal(&state, job.write) {
        Some(r) => Err(r),
        None => Ok(len),
    }
}

/// The refusal a callback's `PNIO_ERR_STAT` says, if it says one.
fn refusal(s: &PNIO_ERR_STAT, write: bool) -> Option<RecordRefusal> {
    let code1 = match s.ErrCode1 {
        0 if s.ErrCode == 0 => return None,
        // An error without ErrorCode1 is still one: "application read/write error".
        0 if write => RecordRefusal::WRITE_ERROR,
        0 => RecordRefusal::READ_ERROR,
        c => c,
    };
    Some(RecordRefusal {
        code1,
        code2: s.ErrCode2,
    })
}
