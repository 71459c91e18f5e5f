// SPDX-License-Identifier: MIT OR Apache-2.0
//! Plugging and pulling submodules while the device runs (IO-Base's `PNIO_sub_plug` and
//! `PNIO_sub_pull`, GOAL's and GS20-PN's add and remove item), and the return of a
//! submodule.
//!
//! The device's positions are the ones it was set up with ([`DeviceSetup::submodules`](super::DeviceSetup)):
//! a pull empties one, a plug fills an empty one again, with the configured data lengths
//! and the ident numbers of whatever is plugged. What the controller learns depends on the
//! AR:
//!
//! - without an AR, nothing: the next Connect's ModuleDiffBlock and the identification
//!   records show the tree as it is;
//! - between the Connect and data exchange, plug and pull are refused
//!   ([`PlugError::ArStartingUp`], IO-Base's `PNIO_AR_REASON_PULLPLUG`): the controller is
//!   parameterizing what it saw in the Connect response;
//! - in data exchange, for a submodule the AR expects, an alarm on the low-priority channel:
//!   - pull: a Pull alarm, and the submodule's IOPS and IOCS turn BAD at once;
//!   - plug of the expected submodule: a Plug alarm, then the re-parameterization
//!     sub-cycle: the controller acknowledges, writes the submodule's parameter records and
//!     sends a PlugPrmEnd (0x0111) with the alarm's sequence number; the device answers it
//!     and sends its PlugApplicationReady (0x0113), and when the controller confirms, the
//!     submodule exchanges data with GOOD status again;
//!   - plug of something else: a Plug Wrong Submodule alarm; the submodule stays BAD (the
//!     controller parameterizes nothing it did not engineer);
//!   - return: a Return of Submodule alarm for a proper submodule whose data was BAD for a
//!     while (its provider went away and came back); the controller does not parameterize.
//!
//! Alarms and IOxS follow the AR's expectations; a submodule the AR does not expect changes
//! only the device's identification records.
//!
//! [`Plugging`] keeps what is plugged where and answers what is plugged
//! ([`Device::plugging`]); the device's plug, pull and return add what the AR and the
//! diagnosis make of a change, since they need those parts too.

use super::ar::IOXS_BAD;
use super::diagnosis::SubslotAddr;
use super::rpc::ClientCall;
use super::{
    APP_READY_DELAY_NS, APP_READY_HOLD_TIMEOUT_NS, Application, ArState, Device, DeviceAction,
    PluggedSubmodule,
};
use crate::wire::alarm::{AlarmNotification, AlarmSpecifier, AlarmType, Priority};
use crate::wire::control::ControlBlock;

/// Why a plug, pull or return was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum PlugError {
    /// The device was not set up with a submodule at this position.
    #[error(
        "no submodule is configured at {0}: only configured positions can be plugged; add \
         it to the configuration (its ident numbers and IO lengths) and restart"
    )]
    NotConfigured(SubslotAddr),
    /// Something is plugged there already.
    #[error("a submodule is plugged at {0} already: pull it first")]
    AlreadyPlugged(SubslotAddr),
    /// Nothing is plugged there.
    #[error("no submodule is plugged at {0}: plug it first")]
    NotPlugged(SubslotAddr),
    /// The AR is between its Connect and data exchange.
    #[error(
        "the PLC's AR is starting up (between its Connect and data exchange), when plug and \
         pull are not allowed: try again once the AR is in data exchange"
    )]
    ArStartingUp,
}

/// What is plugged where: the positions the device was set up with and, per position, what
/// is plugged there now. The pure side of plugging and pulling; the [`Device`] adds what
/// the AR and the diagnosis make of it.
#[derive(Clone, Debug)]
pub struct Plugging {
    /// Every position the device was set up with, in that order: what
    /// [`Device::plug_submodule`] may plug, and the order of the exchange's submodule table.
    table: Vec<PluggedSubmodule>,
    /// Per entry of `table`: the (module, submodule) ident numbers plugged there, or `None`
    /// when pulled.
    idents: Vec<Option<(u32, u32)>>,
    /// The submodules plugged now: `table` less the pulled ones, with the ident numbers
    /// they were plugged with.
    plugged: Vec<PluggedSubmodule>,
    /// Plugged submodules whose parameters the controller ended (PlugPrmEnd) since
    /// [`Device::take_plug_parameterized`] was last called.
    parameterized: Vec<SubslotAddr>,
}

impl Plugging {
    /// Every one of `submodules` plugged, at the positions they name.
    pub(super) fn new(submodules: Vec<PluggedSubmodule>) -> Plugging {
        Plugging {
            idents: submodules
                .iter()
                .map(|s| Some((s.module_ident, s.submodule_ident)))
                .collect(),
            table: submodules.clone(),
            plugged: submodules,
            parameterized: Vec::new(),
        }
    }

    /// Whether a submodule is plugged at `at` (a configured position not pulled).
    pub fn is_plugged(&self, at: SubslotAddr) -> bool {
        self.real_submodule(at).is_some()
    }

    /// The (module, submodule) ident numbers of what is plugged at `at`, if anything.
    pub fn real_submodule(&self, at: SubslotAddr) -> Option<(u32, u32)> {
        self.plugged
            .iter()
            .find(|s| s.addr() == at)
            .map(|s| (s.module_ident, s.submodule_ident))
    }

    /// The submodules plugged now, in the order the device was set up with, with the ident
    /// numbers they were plugged with: the real tree.
    pub fn plugged(&self) -> &[PluggedSubmodule] {
        &self.plugged
    }

    /// Every position the device was set up with, plugged or not, in that order (with the
    /// ident numbers it was set up with).
    pub fn configured(&self) -> &[PluggedSubmodule] {
        &self.table
    }

    /// The index of (`api`, `slot`, `subslot`) in the exchange's submodule table (the
    /// configured positions' order), if it is configured.
    pub(super) fn table_index(&self, api: u32, slot: u16, subslot: u16) -> Option<usize> {
        self.table
            .iter()
            .position(|s| (s.api, s.slot, s.subslot) == (api, slot, subslot))
    }

    /// The index of position `at` in the device's table.
    fn position(&self, at: SubslotAddr) -> Result<usize, PlugError> {
        self.table
            .iter()
            .position(|s| s.addr() == at)
            .ok_or(PlugError::NotConfigured(at))
    }

    /// The (module, submodule) ident numbers plugged at the configured position `at`.
    pub(super) fn idents_at(&self, at: SubslotAddr) -> Result<(u32, u32), PlugError> {
        self.idents[self.position(at)?].ok_or(PlugError::NotPlugged(at))
    }

    /// Puts `idents` (or nothing) at position `at`, which must hold nothing (or something);
    /// refused when `ar_starting_up` (an AR between its Connect and data exchange). Returns
    /// the configured submodule at that position.
    pub(super) fn replug(
        &mut self,
        at: SubslotAddr,
        idents: Option<(u32, u32)>,
        ar_starting_up: bool,
    ) -> Result<PluggedSubmodule, PlugError> {
        let i = self.position(at)?;
        match (self.idents[i], idents) {
            (None, None) => return Err(PlugError::NotPlugged(at)),
            (Some(_), Some(_)) => return Err(PlugError::AlreadyPlugged(at)),
            _ => {}
        }
        if ar_starting_up {
            return Err(PlugError::ArStartingUp);
        }
        self.idents[i] = idents;
        self.refresh_plugged();
        Ok(self.table[i])
    }

    /// Rebuilds the list of plugged submodules from the table.
    fn refresh_plugged(&mut self) {
        self.plugged = self
            .table
            .iter()
            .zip(&self.idents)
            .filter_map(|(s, p)| {
                p.map(|(module_ident, submodule_ident)| PluggedSubmodule {
                    module_ident,
                    submodule_ident,
                    ..*s
                })
            })
            .collect();
    }

    /// The ModuleIdentNumber of what is plugged in (`api`, `slot`): the module, if a
    /// submodule of it remains plugged; 0 otherwise.
    pub(super) fn module_in_slot(&self, api: u32, slot: u16) -> u32 {
        self.plugged
            .iter()
            .find(|r| (r.api, r.slot) == (api, slot))
            .map_or(0, |r| r.module_ident)
    }

    /// Notes that the controller ended the parameters of the plugged submodule at `at`.
    pub(super) fn parameterized(&mut self, at: SubslotAddr) {
        self.parameterized.push(at);
    }

    /// The submodules noted by [`parameterized`](Self::parameterized) since the last call.
    pub(super) fn take_parameterized(&mut self) -> Vec<SubslotAddr> {
        std::mem::take(&mut self.parameterized)
    }
}

impl<A: Application> Device<A> {
    /// What is plugged where.
    pub fn plugging(&self) -> &Plugging {
        &self.plugging
    }

    /// Pulls the submodule at `at`; its pending diagnosis goes with it. Returns the alarm
    /// that announced it (a Pull alarm to the AR in data exchange that expects it), if any.
    pub fn pull_submodule(
        &mut self,
        at: SubslotAddr,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<Option<AlarmType>, PlugError> {
        self.plugging.replug(at, None, self.ar_starting_up())?;
        // Its diagnosis ends with it; the Pull alarm says so.
        let _ = self.diagnosis.clear(at);
        let Some(ar) = self.ar.current.as_mut().filter(|a| a.in_data()) else {
            return Ok(None);
        };
        let Some(s) = ar.submodules.iter_mut().find(|s| s.expected.addr() == at) else {
            return Ok(None);
        };
        if s.proper {
            ar.exchange_generation = ar.exchange_generation.wrapping_add(1);
        }
        s.proper = false;
        s.plugging = None;
        s.outputs_valid = false;
        s.controller_iocs = IOXS_BAD;
        ar.plug_ready.retain(|(p, _, _)| *p != at);
        if ar.plug_call.as_ref().is_some_and(|(_, p)| *p == at) {
            ar.plug_call = None;
        }
        // What is plugged there now: the module, if other submodules of its slot remain.
        let module = self.plugging.module_in_slot(at.api, at.slot);
        Ok(self.send_plug_alarm(at, AlarmType::Pull, (module, 0), now_ns, out))
    }

    /// Plugs a submodule with these ident numbers at the configured position `at` (with its
    /// configured data lengths). Returns the alarm that announced it to the AR in data
    /// exchange that expects a submodule there, if any: Plug when it is the expected one
    /// (the re-parameterization sub-cycle follows), Plug Wrong Submodule otherwise.
    pub fn plug_submodule(
        &mut self,
        at: SubslotAddr,
        module_ident: u32,
        submodule_ident: u32,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<Option<AlarmType>, PlugError> {
        let idents = Some((module_ident, submodule_ident));
        let real = self.plugging.replug(at, idents, self.ar_starting_up())?;
        let Some(ar) = self.ar.current.as_mut().filter(|a| a.in_data()) else {
            return Ok(None);
        };
        let sequence = ar.alarms.sequence;
        let Some(s) = ar.submodules.iter_mut().find(|s| s.expected.addr() == at) else {
            return Ok(None);
        };
        let e = s.expected;
        let proper = (e.module_ident, e.submodule_ident) == (module_ident, submodule_ident)
            && (e.input_length, e.output_length) == (real.input_length, real.output_length);
        let alarm = if proper {
            // Exchanges data again at the end of the sub-cycle this alarm starts.
            s.plugging = Some(sequence);
            AlarmType::Plug
        } else {
            AlarmType::PlugWrongSubmodule
        };
        Ok(self.send_plug_alarm(at, alarm, (module_ident, submodule_ident), now_ns, out))
    }

    /// Announces that the proper submodule at `at` provides valid data again (a Return of
    /// Submodule alarm to the AR in data exchange). Returns the alarm, if one went out.
    pub fn return_submodule(
        &mut self,
        at: SubslotAddr,
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Result<Option<AlarmType>, PlugError> {
        let idents = self.plugging.idents_at(at)?;
        let owned = self
            .ar
            .current
            .as_ref()
            .filter(|a| a.in_data())
            .is_some_and(|a| a.owned().any(|o| o == at));
        if !owned {
            return Ok(None);
        }
        // The application is ready for it now.
        if let Some(ar) = self.ar.current.as_mut() {
            ar.app_ready_pending.retain(|p| *p != at);
        }
        Ok(self.send_plug_alarm(at, AlarmType::ReturnOfSubmodule, idents, now_ns, out))
    }

    /// A PlugPrmEnd from the controller for the AR in data exchange: the end of a plugged
    /// submodule's parameters. `Err` with the PNIO ErrorCode1/ErrorCode2 pair when no
    /// submodule waits for it.
    pub(super) fn plug_prm_end(&mut self, c: &ControlBlock, now_ns: u64) -> Result<(), u8> {
        let Some(ar) = self.ar.current.as_mut().filter(|a| a.in_data()) else {
            return Err(super::connect::CMDEV_STATE_CONFLICT);
        };
        let Some(s) = ar
            .submodules
            .iter_mut()
            .find(|s| s.plugging == Some(c.alarm_sequence_number))
        else {
            return Err(super::connect::CMDEV_STATE_CONFLICT);
        };
        s.plugging = None;
        let at = s.expected.addr();
        // Held like the AR's ApplicationReady: the application releases it once it took the
        // submodule's parameters, at the latest after the hold timeout.
        let delay = if self.ar.hold_app_ready {
            APP_READY_HOLD_TIMEOUT_NS
        } else {
            APP_READY_DELAY_NS
        };
        ar.plug_ready
            .push_back((at, c.alarm_sequence_number, now_ns.saturating_add(delay)));
        self.plugging.parameterized(at);
        Ok(())
    }

    /// The plugged submodules whose parameters the controller ended (PlugPrmEnd) since the
    /// last call: each one's PlugApplicationReady waits for
    /// [`release_application_ready`](Self::release_application_ready) while the application
    /// holds the ApplicationReady ([`hold_application_ready`](Self::hold_application_ready)).
    pub fn take_plug_parameterized(&mut self) -> Vec<SubslotAddr> {
        self.plugging.take_parameterized()
    }

    /// Sends the next due PlugApplicationReady and retransmits the outstanding one.
    pub(super) fn run_plug_ready(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        let Some(ar) = self.ar.current.as_ref() else {
            return;
        };
        if ar.plug_call.is_none() && ar.plug_ready.front().is_some_and(|r| now_ns >= r.2) {
            let activity = self.new_activity();
            let Some(ar) = self.ar.current.as_mut() else {
                return;
            };
            let Some((at, sequence, _)) = ar.plug_ready.pop_front() else {
                return;
            };
            let call = ClientCall::control(
                ControlBlock::plug_application_ready(ar.ar_uuid, ar.session_key, sequence),
                &[],
                ar.initiator_object,
                activity,
                ar.controller,
            );
            if let Some(mut call) = call {
                call.transmit(now_ns, out);
                ar.plug_call = Some((call, at));
            }
        }
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        if let Some((call, _)) = ar.plug_call.as_mut()
            && !call.poll(now_ns, out)
        {
            // Unanswered: the controller lost the submodule; it stays BAD until it is
            // pulled and plugged again.
            ar.plug_call = None;
        }
    }

    /// A response that may answer the outstanding PlugApplicationReady: `true` if it did.
    pub(super) fn plug_ready_pdu(
        &mut self,
        h: &crate::wire::rpc::Header,
        body: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> bool {
        let Some(ar) = self.ar.current.as_mut() else {
            return false;
        };
        let Some((call, at)) = ar.plug_call.as_mut() else {
            return false;
        };
        let at = *at;
        match call.on_pdu(h, body, now_ns, out) {
            super::rpc::CallOutcome::Confirmed => {
                ar.plug_call = None;
                if let Some(s) = ar.submodules.iter_mut().find(|s| s.expected.addr() == at) {
                    s.proper = true;
                    ar.exchange_generation = ar.exchange_generation.wrapping_add(1);
                }
                true
            }
            super::rpc::CallOutcome::Failed => {
                ar.plug_call = None;
                true
            }
            super::rpc::CallOutcome::Pending => true,
            super::rpc::CallOutcome::NotOurs => false,
        }
    }

    /// Whether an AR is between its Connect and data exchange, when plug and pull are
    /// refused.
    fn ar_starting_up(&self) -> bool {
        self.ar
            .current
            .as_ref()
            .is_some_and(|ar| !matches!(ar.state, ArState::Idle | ArState::Data))
    }

    /// Sends a plug, pull or return alarm for `at` to the AR in data exchange, with the
    /// (module, submodule) ident numbers of what is plugged there.
    fn send_plug_alarm(
        &mut self,
        at: SubslotAddr,
        alarm_type: AlarmType,
        (module_ident, submodule_ident): (u32, u32),
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) -> Option<AlarmType> {
        let diagnosis = &self.diagnosis;
        let ar = self.ar.current.as_ref().filter(|a| a.in_data())?;
        let ar_fault = ar.owned().any(|o| diagnosis.has_fault_at(o));
        let n = AlarmNotification {
            priority: Priority::Low,
            alarm_type,
            api: at.api,
            slot: at.slot,
            subslot: at.subslot,
            module_ident,
            submodule_ident,
            specifier: AlarmSpecifier {
                submodule_diagnosis: diagnosis.has_fault_at(at),
                ar_diagnosis: ar_fault,
                ..AlarmSpecifier::default()
            },
            maintenance: None,
            item: None,
        };
        self.send_alarm(n, now_ns, out);
        Some(alarm_type)
    }
}
