// SPDX-License-Identifier: MIT OR Apache-2.0
//! The isochronous handshake that controllers and devices share: the rules of
//! `PNIO_CP_register_cbf`, the open STARTOP..`PNIO_CP_set_opdone` window of a synchronous
//! client, and the delivery of the `PNIO_CP_CBE_*` callbacks (from the thread of
//! `super::cycle_thread`, one loop for both).
//!
//! The registration rules are those of IO-Base's library, checked in its order: `Cbf` NULL
//! (`PNIO_ERR_PRM_CALLBACK`), an unknown type (`PNIO_ERR_PRM_TYPE`), NEWCYCLE after STARTOP
//! (`PNIO_ERR_NEWCYCLE_SEQUENCE_REG`: NEWCYCLE comes first), a type registered already
//! (`PNIO_ERR_ALLREADY_DONE`), STARTOP before OPFAULT (`PNIO_ERR_OPFAULT_NOT_REG`).

use super::callbacks::{CallbackTable, invoke_cp};
use super::errors::*;
use super::types::*;
use procimg_client::{Client, Cycle, CycleInfo, DetachedCycle, Ioxs, now_ns};

/// The name of the registration function, for error texts.
pub(crate) const REGISTER: &str = "PNIO_CP_register_cbf";
/// The name of the OPDONE function, for error texts.
pub(crate) const OPDONE: &str = "PNIO_CP_set_opdone";

/// Checks what a registration passes: a callback, and a type of `PNIO_CP_CBE_TYPE`.
pub(crate) fn check_args(t: PNIO_CP_CBE_TYPE, cbf: PNIO_CP_CBF) -> Result<(), u32> {
    if cbf.is_none() {
        return Err(fail(REGISTER, PNIO_ERR_PRM_CALLBACK, "Cbf is NULL"));
    }
    if !matches!(
        t,
        PNIO_CP_CBE_STARTOP_IND | PNIO_CP_CBE_OPFAULT_IND | PNIO_CP_CBE_NEWCYCLE_IND
    ) {
        return Err(fail(
            REGISTER,
            PNIO_ERR_PRM_TYPE,
            format_args!(
                "CbeType {t} is none of PNIO_CP_CBE_STARTOP_IND, _OPFAULT_IND, _NEWCYCLE_IND"
            ),
        ));
    }
    Ok(())
}

/// Stores a registration in `table` if the order rules allow it.
pub(crate) fn store(
    table: &CallbackTable,
    t: PNIO_CP_CBE_TYPE,
    cbf: PNIO_CP_CBF,
) -> Result<(), u32> {
    let startop = table.get_cp(PNIO_CP_CBE_STARTOP_IND).is_some();
    if t == PNIO_CP_CBE_NEWCYCLE_IND && startop {
        return Err(fail(
            REGISTER,
            PNIO_ERR_NEWCYCLE_SEQUENCE_REG,
            "register PNIO_CP_CBE_NEWCYCLE_IND before PNIO_CP_CBE_STARTOP_IND",
        ));
    }
    if table.get_cp(t).is_some() {
        return Err(fail(
            REGISTER,
            PNIO_ERR_ALLREADY_DONE,
            format_args!("a callback for CbeType {t} is registered already"),
        ));
    }
    if t == PNIO_CP_CBE_STARTOP_IND && table.get_cp(PNIO_CP_CBE_OPFAULT_IND).is_none() {
        return Err(fail(
            REGISTER,
            PNIO_ERR_OPFAULT_NOT_REG,
            "register PNIO_CP_CBE_OPFAULT_IND before PNIO_CP_CBE_STARTOP_IND",
        ));
    }
    if !table.set_cp_once(t, cbf) {
        return Err(fail(
            REGISTER,
            PNIO_ERR_ALLREADY_DONE,
            format_args!("a callback for CbeType {t} is registered already"),
        ));
    }
    Ok(())
}

/// Whether a registration of `t` changes how the client attaches (STARTOP: synchronous,
/// NEWCYCLE: with NEWCYCLE events); OPFAULT needs nothing of the server.
pub(crate) fn needs_reattach(t: PNIO_CP_CBE_TYPE) -> bool {
    t != PNIO_CP_CBE_OPFAULT_IND
}

/// Calls the isochronous callback of `t` in `table`, if one is registered.
pub(crate) fn report(
    table: &CallbackTable,
    t: PNIO_CP_CBE_TYPE,
    cp_index: u32,
    handle: u32,
    info: PNIO_CYCLE_INFO,
) {
    let cbf = table.get_cp(t);
    if cbf.is_none() {
        return;
    }
    let mut prm = PNIO_CP_CBE_PRM::new(t, cp_index, handle, info);
    invoke_cp(cbf, &mut prm);
}

/// The STARTOP..OPDONE window of a synchronous client, held apart from the client because
/// the program's calls come from several threads.
#[derive(Default)]
pub(crate) struct Window {
    open: Option<DetachedCycle>,
    /// The window was found over (the next cycle had begun) before its OPDONE: that
    /// OPDONE is late, not out of sequence.
    expired: bool,
}

impl Window {
    /// Takes the next cycle's STARTOP if the client has one; a window not closed by then is
    /// over (its outputs were not sent: OPFAULT).
    pub(crate) fn take_startop(&mut self, client: &mut Client) -> Option<CycleInfo> {
        let cycle = client.wait_startop(std::time::Duration::ZERO).ok()?;
        let info = cycle.info();
        self.open = Some(cycle.detach());
        self.expired = false;
        Some(info)
    }

    /// Ends an open window without OPDONE (the client is replaced): its
    /// `PNIO_CP_set_opdone` is answered as a late one, not refused.
    pub(crate) fn end(&mut self) {
        self.expired = self.open.take().is_some();
    }

    /// Whether a window is open.
    pub(crate) fn is_open(&self) -> bool {
        self.open.is_some()
    }

    /// Runs `op` inside the open window; `None` when none is open (or it is over).
    pub(crate) fn run<R>(
        &mut self,
        client: &mut Client,
        op: impl FnOnce(&mut Cycle<'_>) -> R,
    ) -> Option<R> {
        let w = self.open.take()?;
        let Some(mut cycle) = w.resume(client) else {
            self.expired = true;
            return None;
        };
        let r = op(&mut cycle);
        self.open = Some(cycle.detach());
        Some(r)
    }

    /// `PNIO_CP_set_opdone` on this window: the outputs written in it go out. A late one
    /// (the window is over) answers `PNIO_OK` (OPFAULT_IND tells the program); one without
    /// a window `PNIO_ERR_SEQUENCE`.
    pub(crate) fn set_opdone(&mut self, client: &mut Client) -> Result<PNIO_CYCLE_INFO, u32> {
        let late = || cycle_info(&client_info(client), now_ns());
        let Some(window) = self.open.take() else {
            if std::mem::take(&mut self.expired) {
                return Ok(late());
            }
            return Err(fail(
                OPDONE,
                PNIO_ERR_SEQUENCE,
                "no cycle is open: PNIO_CP_set_opdone was called already in this cycle, or \
                 before the first PNIO_CP_CBE_STARTOP_IND",
            ));
        };
        match window.resume(client) {
            Some(cycle) => cycle
                .set_opdone()
                .map(|info| cycle_info(&info, info.clock_ns))
                .map_err(|e| {
                    fail(
                        OPDONE,
                        PNIO_ERR_NO_FW_COMMUNICATION,
                        format_args!("the outputs of this cycle could not be handed over: {e}"),
                    )
                }),
            // Too late: the next cycle is there.
            None => Ok(cycle_info(&client_info(client), now_ns())),
        }
    }

    /// Ends the open window (if any) with every output the client holds marked BAD, and
    /// OPDONE: what the watchdog's expiry leaves the consumers.
    pub(crate) fn finish_bad(&mut self, client: &mut Client) {
        let held = held_outputs(client);
        let done = self.run(client, |c| {
            for &s in &held {
                let _ = c.set_output_status(s, Ioxs::Bad);
            }
        });
        if done.is_some() {
            let _ = self.set_opdone(client);
        }
    }
}

fn client_info(client: &Client) -> CycleInfo {
    client.cycle_info().unwrap_or_default()
}

/// The submodules with outputs (a device's I data) that the client holds.
fn held_outputs(client: &Client) -> Vec<usize> {
    (0..client.layout().submodules.len())
        .filter(|&s| client.holds(s) && client.layout().submodules[s].output_length > 0)
        .collect()
}

/// Sends every output the client holds again with IOPS BAD, outside a cycle window (an
/// asynchronous client, or a synchronous one between its windows).
pub(crate) fn outputs_bad(client: &mut Client) {
    for s in held_outputs(client) {
        let e = client.layout().submodules[s];
        let mut buf = vec![0u8; e.output_length as usize];
        if client.output_data_read(e.output_address, &mut buf).is_ok() {
            let _ = client.data_write_cache(e.output_address, &buf, Ioxs::Bad);
        }
    }
    let _ = client.data_write_cache_flush();
}

/// IO-Base's cycle info for the cycle `info`, as of `now` (`CLOCK_MONOTONIC` ns).
pub(crate) fn cycle_info(info: &CycleInfo, now: u64) -> PNIO_CYCLE_INFO {
    PNIO_CYCLE_INFO {
        CycleCount: info.cycle_count & 0xFFFF,
        // 10 ns ticks of a free-running 32-bit counter: wrapping is its nature.
        ClockCount: (now / 10) as u32,
        CountSinceCycleStart: (now.saturating_sub(info.cycle_start_ns) / 10)
            .min(u64::from(u32::MAX)) as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycle_info_in_the_manuals_units() {
        let info = CycleInfo {
            cycle_number: 5,
            cycle_start_ns: 1_000_000,
            clock_ns: 0,
            since_cycle_start_ns: 0,
            cycle_count: 0x1_0020,
            reserved: 0,
        };
        let c = cycle_info(&info, 1_000_000 + 123_450);
        assert_eq!(c.CycleCount, 0x20, "16 bits of 31.25 µs units");
        assert_eq!(c.CountSinceCycleStart, 12_345, "10 ns units");
        assert_eq!(c.ClockCount, (1_123_450u64 / 10) as u32);
        // The free-running 32-bit 10 ns counter wraps.
        let late = cycle_info(&info, 50_000_000_000);
        assert_eq!(late.ClockCount, (5_000_000_000u64 % (1 << 32)) as u32);
    }

    unsafe extern "C" fn cb(_: *mut PNIO_CP_CBE_PRM) {}

    #[test]
    fn the_order_rules_of_io_base() {
        let t = CallbackTable::new();
        assert_eq!(
            check_args(PNIO_CP_CBE_STARTOP_IND, None),
            Err(PNIO_ERR_PRM_CALLBACK)
        );
        assert_eq!(check_args(9, Some(cb)), Err(PNIO_ERR_PRM_TYPE));
        assert_eq!(
            store(&t, PNIO_CP_CBE_STARTOP_IND, Some(cb)),
            Err(PNIO_ERR_OPFAULT_NOT_REG)
        );
        assert_eq!(store(&t, PNIO_CP_CBE_OPFAULT_IND, Some(cb)), Ok(()));
        assert_eq!(
            store(&t, PNIO_CP_CBE_OPFAULT_IND, Some(cb)),
            Err(PNIO_ERR_ALLREADY_DONE)
        );
        assert_eq!(store(&t, PNIO_CP_CBE_STARTOP_IND, Some(cb)), Ok(()));
        assert_eq!(
            store(&t, PNIO_CP_CBE_NEWCYCLE_IND, Some(cb)),
            Err(PNIO_ERR_NEWCYCLE_SEQUENCE_REG)
        );
        let t = CallbackTable::new();
        assert_eq!(store(&t, PNIO_CP_CBE_NEWCYCLE_IND, Some(cb)), Ok(()));
        assert_eq!(
            store(&t, PNIO_CP_CBE_NEWCYCLE_IND, Some(cb)),
            Err(PNIO_ERR_ALLREADY_DONE)
        );
    }
}
