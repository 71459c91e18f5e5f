// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's AR slot: the one AR it holds at a time, and what it keeps across ARs (how
//! the last one ended, how many were aborted, the input frames produced, the activity
//! counter of its client calls, whether it takes Connects, the application's hold on the
//! ApplicationReady). [`Device::ar`](super::Device::ar) gives the read-only view: the AR's
//! state and identity, its submodules' IO data, its alarm sequence and the counters.

use super::access_ar::AccessAr;
use super::ar::{Ar, ArSubmodule};
use super::log_book::{LogBook, detail};
use super::{ArState, DeviceAction};
use crate::cyclic::VerdictCounts;
use crate::wire::rta_pdu::{AbortCode, ErrRta};
use crate::wire::{MacAddress, PnioStatus, Uuid};

/// The device's AR, if it holds one, and what it keeps across ARs.
pub struct ArSlot {
    /// The AR, from its Connect to its end.
    pub(super) current: Option<Ar>,
    /// An engineering tool's device access AR, beside it.
    pub(super) access: Option<AccessAr>,
    /// What happened to the ARs.
    pub(super) log: LogBook,
    /// The device's clock at its last input (frame, datagram, poll): the log book's time.
    pub(super) now_ns: u64,
    /// Input CR frames produced since the device was made.
    pub(super) frames_produced: u64,
    /// The counter behind the activity UUIDs of the device's client calls.
    activities: u32,
    last_abort: Option<AbortCode>,
    /// ARs that ended other than by Release.
    aborted_ars: u64,
    /// Whether a Connect may make an AR (see [`Device::set_accepting`](super::Device::set_accepting)).
    pub(super) accepting: bool,
    /// Whether the ApplicationReady waits for
    /// [`Device::release_application_ready`](super::Device::release_application_ready).
    pub(super) hold_app_ready: bool,
    /// ApplicationReadys that went out because the application did not release them.
    pub(super) app_ready_hold_timeouts: u64,
}

impl Default for ArSlot {
    fn default() -> ArSlot {
        ArSlot {
            current: None,
            access: None,
            log: LogBook::default(),
            now_ns: 0,
            frames_produced: 0,
            activities: 0,
            last_abort: None,
            aborted_ars: 0,
            accepting: true,
            hold_app_ready: false,
            app_ready_hold_timeouts: 0,
        }
    }
}

impl ArSlot {
    /// Where the AR stands.
    pub fn state(&self) -> ArState {
        self.current.as_ref().map_or(ArState::Idle, |a| a.state)
    }

    /// The ARUUID of the current AR.
    pub fn ar_uuid(&self) -> Option<Uuid> {
        self.current.as_ref().map(|a| a.ar_uuid)
    }

    /// The MAC address of the controller of the current AR.
    pub fn controller_mac(&self) -> Option<MacAddress> {
        self.current.as_ref().map(Ar::controller_mac)
    }

    /// The NameOfStation of the controller of the current AR (its Connect's
    /// CMInitiatorStationName).
    pub fn controller_name(&self) -> Option<&str> {
        self.current.as_ref().map(|a| a.controller_name.as_str())
    }

    /// How many ARs ended other than by Release (aborted by either side).
    pub fn aborted_ars(&self) -> u64 {
        self.aborted_ars
    }

    /// Why the last AR ended other than by Release, if one did.
    pub fn last_abort(&self) -> Option<AbortCode> {
        self.last_abort
    }

    /// How the AR's consumer has judged the controller's output frames so far; `None`
    /// without an AR. Zero while the cycle thread runs the exchange (handed over).
    pub fn consumer_verdicts(&self) -> Option<VerdictCounts> {
        self.current.as_ref().map(|ar| ar.consumer.counts())
    }

    /// Input CR frames produced since the device was made.
    pub fn frames_produced(&self) -> u64 {
        self.frames_produced
    }

    /// Whether the AR's ApplicationReady waits for the application now.
    pub fn application_ready_held(&self) -> bool {
        self.current
            .as_ref()
            .is_some_and(|a| a.app_ready_held.is_some())
    }

    /// ApplicationReadys that went out because the application did not release them in time.
    pub fn app_ready_hold_timeouts(&self) -> u64 {
        self.app_ready_hold_timeouts
    }

    fn ar_submodule(&self, api: u32, slot: u16, subslot: u16) -> Option<&ArSubmodule> {
        self.current.as_ref()?.submodules.iter().find(|s| {
            let e = &s.expected;
            (e.api, e.slot, e.subslot) == (api, slot, subslot)
        })
    }

    /// The outputs a submodule of the AR last received and whether they are valid (the
    /// controller in RUN, their IOPS GOOD, the submodule the expected one).
    pub fn outputs(&self, api: u32, slot: u16, subslot: u16) -> Option<(&[u8], bool)> {
        self.ar_submodule(api, slot, subslot)
            .map(|s| (&s.outputs[..], s.outputs_valid))
    }

    /// The inputs a submodule of the AR last produced.
    pub fn inputs(&self, api: u32, slot: u16, subslot: u16) -> Option<&[u8]> {
        self.ar_submodule(api, slot, subslot).map(|s| &s.inputs[..])
    }

    /// The controller's IOCS for a submodule's inputs, from its last output frame.
    pub fn controller_iocs(&self, api: u32, slot: u16, subslot: u16) -> Option<u8> {
        self.ar_submodule(api, slot, subslot)
            .map(|s| s.controller_iocs)
    }

    /// The AlarmSequenceNumber the next alarm to the AR gets; `None` without an AR.
    pub fn next_alarm_sequence(&self) -> Option<u16> {
        self.current.as_ref().map(|a| a.alarms.sequence)
    }

    /// A new activity UUID for a client call: version 1 layout with the device's MAC as the
    /// node and a counter as the time, so it is unique per device and call without a random
    /// source.
    pub(super) fn new_activity(&mut self, mac: MacAddress) -> Uuid {
        self.activities = self.activities.wrapping_add(1);
        let m = mac.0;
        Uuid::from_fields(
            self.activities,
            0,
            0x1000,
            [0x80, 0x00, m[0], m[1], m[2], m[3], m[4], m[5]],
        )
    }

    /// Ends the AR from the device's side: ERR-RTA from `mac` to the controller.
    pub(super) fn abort(&mut self, code: AbortCode, mac: MacAddress, out: &mut Vec<DeviceAction>) {
        if let Some(mut ar) = self.current.take() {
            ar.alarms.abort(code, mac, out);
            self.last_abort = Some(code);
            self.aborted_ars += 1;
            self.note_abort(ar.ar_uuid, code);
        }
    }

    fn note_abort(&mut self, ar_uuid: Uuid, code: AbortCode) {
        let status = ErrRta::abort(code).status;
        self.log
            .note(self.now_ns, ar_uuid, status, detail::AR_ABORTED);
    }

    /// Notes in the log book what happened to `ar_uuid` (OK, or the refusal `status`).
    pub(super) fn note(&mut self, ar_uuid: Uuid, status: PnioStatus, what: u32) {
        self.log.note(self.now_ns, ar_uuid, status, what);
    }

    /// The device access AR, if a tool holds one.
    pub fn access(&self) -> Option<&AccessAr> {
        self.access.as_ref()
    }

    /// The log book.
    pub fn log_book(&self) -> &LogBook {
        &self.log
    }

    /// The AR ended without a further ERR-RTA from the device (the controller aborted it,
    /// or the alarm channel already sent one).
    pub(super) fn end(&mut self, code: AbortCode) {
        if let Some(ar) = self.current.take() {
            self.last_abort = Some(code);
            self.aborted_ars += 1;
            self.note_abort(ar.ar_uuid, code);
        }
    }
}
