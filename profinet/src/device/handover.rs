// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cyclic exchange handed over to a cycle thread, for a device whose IO data lives in a
//! process image rather than in its [`Application`](super::Application).
//!
//! By default the engine produces the input CR and consumes the output CR itself (the
//! demo's simulated devices). After [`Device::hand_over_cyclic`] it leaves both to the
//! caller's cycle, which runs every `cycle_ns`: when an AR's parameterization ends (PrmEnd)
//! the engine hands out the AR's [`CyclicAr`] in [`DeviceAction::StartCyclic`], mapped onto
//! the device's submodules in the order they were set up, and when the AR ends,
//! [`DeviceAction::StopCyclic`]. When a submodule of the running AR is pulled, or a plugged
//! one finished its plug sub-cycle, the exchange is handed out again under a new epoch
//! (without a stop: it replaces the running one), so that the cycle exchanges exactly the
//! submodules that are plugged and proper. The cycle reports back the first valid output frame
//! ([`Device::cyclic_started`]) and the data hold watchdog running out
//! ([`Device::cyclic_expired`], which ends the AR as the device's own watchdog would).
//!
//! A Connect whose IO CR period is not a whole multiple of the cycle is refused: the cycle
//! could not keep the CR's timing.

use super::ar::Ar;
use super::{Application, ArState, Device, DeviceAction};
use crate::cyclic::CyclicAr;
use crate::wire::Uuid;
use crate::wire::rta_pdu::AbortCode;

/// What was handed over.
#[derive(Clone, Copy, Debug)]
pub(super) struct Handover {
    /// The period of the caller's cycle.
    pub(super) cycle_ns: u64,
    /// The AR whose exchange runs (its ARUUID and session key), its epoch, and the AR's
    /// [`exchange_generation`](Ar::exchange_generation) it was made from.
    running: Option<(Uuid, u16, u32, u32)>,
    /// Epochs handed out so far.
    epochs: u32,
}

impl Handover {
    pub(super) fn new(cycle_ns: u64) -> Handover {
        Handover {
            cycle_ns: cycle_ns.max(1),
            running: None,
            epochs: 0,
        }
    }

    /// Whether a CR with this period can run on the cycle.
    pub(super) fn fits(&self, period_ns: u64) -> bool {
        period_ns >= self.cycle_ns && period_ns.is_multiple_of(self.cycle_ns)
    }
}

impl<A: Application> Device<A> {
    /// From now on the caller's cycle, running every `cycle_ns`, exchanges the cyclic data
    /// (see the module docs). Call it before the first Connect.
    pub fn hand_over_cyclic(&mut self, cycle_ns: u64) {
        self.handover = Some(Handover::new(cycle_ns));
    }

    /// Whether the cyclic exchange is the caller's.
    pub fn cyclic_handed_over(&self) -> bool {
        self.handover.is_some()
    }

    /// The cycle took the first valid output frame of exchange `epoch`.
    pub fn cyclic_started(&mut self, epoch: u32, _now_ns: u64) -> bool {
        self.running_epoch() == Some(epoch)
    }

    /// The data hold watchdog of exchange `epoch` ran out on the cycle: the AR ends, with
    /// an ERR-RTA to the controller, as the device's own watchdog would end it.
    pub fn cyclic_expired(&mut self, epoch: u32, now_ns: u64, out: &mut Vec<DeviceAction>) {
        if self.running_epoch() == Some(epoch) {
            self.abort_ar(AbortCode::ConsumerDhtExpired, out);
            self.sync_handover(now_ns, out);
        }
    }

    fn running_epoch(&self) -> Option<u32> {
        self.handover.and_then(|h| h.running).map(|(_, _, e, _)| e)
    }

    /// Hands out or takes back the exchange after whatever changed the AR: a stop when the
    /// AR it belongs to is gone, a start when an AR finished its parameterization.
    pub(super) fn sync_handover(&mut self, _now_ns: u64, out: &mut Vec<DeviceAction>) {
        let Some(mut h) = self.handover else {
            return;
        };
        let current = self.ar.current.as_ref().map(|a| (a.ar_uuid, a.session_key));
        if let Some((uuid, key, epoch, _)) = h.running
            && current != Some((uuid, key))
        {
            out.push(DeviceAction::StopCyclic { epoch });
            h.running = None;
        }
        let generation = h.running.map(|(_, _, _, g)| g);
        if let Some(ar) = self
            .ar
            .current
            .as_ref()
            .filter(|a| a.state != ArState::Connected)
            && generation != Some(ar.exchange_generation)
        {
            h.epochs = h.epochs.wrapping_add(1);
            let exchange = self.exchange(ar, h.epochs, h.cycle_ns);
            out.push(DeviceAction::StartCyclic(Box::new(exchange)));
            h.running = Some((ar.ar_uuid, ar.session_key, h.epochs, ar.exchange_generation));
        }
        self.handover = Some(h);
    }

    /// `ar`'s exchange over the plugged submodules' order.
    fn exchange(&self, ar: &Ar, epoch: u32, cycle_ns: u64) -> CyclicAr {
        let (consumed, produced) =
            ar.cr_maps(|e| self.plugging.table_index(e.api, e.slot, e.subslot));
        let mut timing = ar.timing;
        timing.every_cycles = u32::try_from(timing.period_ns() / cycle_ns.max(1))
            .unwrap_or(u32::MAX)
            .max(1);
        CyclicAr::from_maps(
            0,
            epoch,
            (self.station.id.mac, ar.controller_mac()),
            consumed,
            produced,
            timing,
            0..self.plugging.configured().len(),
        )
    }
}
