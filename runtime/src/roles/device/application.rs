// SPDX-License-Identifier: MIT OR Apache-2.0
//! The clients' say in the PLC's AR (GOAL's NEW_AR, record and END_OF_PARAM callbacks,
//! IO-Base's `PNIO_CBF_AR_CHECK_IND`, `PNIO_CBF_REC_READ/WRITE`, `PNIO_CBF_PRM_END_IND` and
//! `PNIO_set_appl_state_ready`; GOAL's STATION_NAME_VERIFY and NET_IP_SET_VERIFY), as the
//! control side keeps it: who checks new ARs and DCP's changes, which
//! subscriber took which submodule's records, the checks and record jobs waiting for their
//! answers, and who holds the ApplicationReady.
//!
//! The defaults when nobody answers: a new AR nobody checks, or whose check is not answered
//! within [`AR_CHECK_TIMEOUT_MS`], is accepted; a DCP Set likewise is carried out (after
//! [`DCP_SET_CHECK_TIMEOUT_MS`]); the station answers the records nobody took
//! itself
//! (its configured parameter records, "invalid index" otherwise); a job its taker leaves
//! unanswered ends after [`STATION_RECORD_TIMEOUT_MS`] with "resource busy" to the PLC; a
//! held ApplicationReady goes out after [`APP_READY_HOLD_TIMEOUT_MS`] (both in the engine).
//! What a subscriber took or held ends with it (unsubscribed, or its process gone).

use procimg_control::Refusal;
use procimg_control::services::{
    APP_READY_HOLD_TIMEOUT_MS, AR_CHECK_TIMEOUT_MS, DCP_SET_CHECK_TIMEOUT_MS,
    STATION_RECORD_TIMEOUT_MS,
};
use procimg_profinet::device::SubslotAddr;
use std::collections::{BTreeMap, BTreeSet};
use std::time::{Duration, Instant};

/// Which of the station's own records of a submodule a client takes besides its user
/// records.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Taken {
    /// I&M0–I&M4 (0xAFF0–0xAFF4).
    pub im: bool,
    /// PROFIenergy's record 0x80A0.
    pub pe: bool,
}

/// What the engine is to do after a change of the clients' say.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// Give the records of a submodule to a client (`true`, with the station's own records
    /// `Taken` names) or answer them again.
    Records(SubslotAddr, bool, Taken),
    /// Hold the ApplicationReady after each PrmEnd, or not.
    Hold(bool),
    /// Let a held ApplicationReady go out.
    Release,
    /// Answer a job that has no taker any more: "resource busy".
    Busy(u64),
    /// Have new ARs checked by a client, or not.
    Check(bool),
    /// Accept an AR whose checker is gone.
    Accept(u64),
    /// Have DCP's changes checked by a client, or not.
    VerifyDcp(bool),
    /// Allow a DCP Set whose checker is gone.
    AllowDcp(u64),
}

/// What one subscriber said that lasts beyond one AR: the station's program says it once,
/// and it holds in each station the program defines (see `program.rs`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Standing {
    /// It checks new ARs.
    pub checks_ars: bool,
    /// It checks DCP's changes.
    pub verifies_dcp: bool,
    /// It holds the ApplicationReady.
    pub holds: bool,
    /// The submodules whose records it took, with (`true`) or without their I&M records.
    pub records: BTreeMap<SubslotAddr, Taken>,
}

/// How long a job is remembered after it was given out: its timeout in the engine and a
/// margin, so that a late answer is refused as stale here already.
const JOB_MEMORY: Duration = Duration::from_millis(STATION_RECORD_TIMEOUT_MS + 1000);

/// The clients' say in the AR.
#[derive(Debug, Default)]
pub struct ApplicationSay {
    /// The station's submodules.
    submodules: BTreeSet<SubslotAddr>,
    /// Who took the records of a submodule.
    owners: BTreeMap<SubslotAddr, u64>,
    /// The submodules whose I&M records went with them.
    taken: BTreeMap<SubslotAddr, Taken>,
    /// Jobs given out: to whom, and when.
    jobs: BTreeMap<u64, (u64, Instant)>,
    /// Subscribers that hold the ApplicationReady.
    holders: BTreeSet<u64>,
    /// Holders that applied the parameters since the last PrmEnd.
    ready: BTreeSet<u64>,
    /// Who checks new ARs, and the checks given out.
    ars: Checker,
    /// Who checks DCP's changes, and the checks given out.
    dcp: Checker,
}

/// One subscriber that checks something, and the checks it was given: to whom, and when.
#[derive(Debug, Default)]
struct Checker {
    by: Option<u64>,
    given: BTreeMap<u64, (u64, Instant)>,
}

impl Checker {
    /// `subscriber` checks (or stops): `Ok(Some(on))` when that changes, `Err(holder)` when
    /// another one checks.
    fn take(&mut self, subscriber: u64, on: bool) -> Result<Option<bool>, u64> {
        match (self.by, on) {
            (Some(c), true) if c != subscriber => Err(c),
            (Some(_), true) => Ok(None),
            (None, true) => {
                self.by = Some(subscriber);
                Ok(Some(true))
            }
            (Some(c), false) if c == subscriber => {
                self.by = None;
                Ok(Some(false))
            }
            (_, false) => Ok(None),
        }
    }

    /// Check `job`: the subscriber it goes to, if one checks.
    fn give(&mut self, job: u64, now: Instant) -> Option<u64> {
        self.given
            .retain(|_, (_, t)| now.duration_since(*t) < JOB_MEMORY);
        let c = self.by?;
        self.given.insert(job, (c, now));
        Some(c)
    }

    /// Whether `subscriber` may answer `job` (it is then answered).
    fn answer(&mut self, subscriber: u64, job: u64) -> bool {
        let mine = self.given.get(&job).is_some_and(|(c, _)| *c == subscriber);
        if mine {
            self.given.remove(&job);
        }
        mine
    }

    /// `subscriber` is gone: whether it was the checker, and its open checks.
    fn forget(&mut self, subscriber: u64) -> (bool, Vec<u64>) {
        let was = self.by == Some(subscriber);
        if was {
            self.by = None;
        }
        let open = self
            .given
            .iter()
            .filter(|(_, (c, _))| *c == subscriber)
            .map(|(j, _)| *j)
            .collect();
        self.given.retain(|_, (c, _)| *c != subscriber);
        (was, open)
    }
}

impl ApplicationSay {
    /// The say over a station with `submodules`.
    pub fn new(submodules: impl IntoIterator<Item = SubslotAddr>) -> ApplicationSay {
        ApplicationSay {
            submodules: submodules.into_iter().collect(),
            ..ApplicationSay::default()
        }
    }

    /// `subscriber` takes (`own`; with the I&M records if `im`) or gives back the records of
    /// `at`; `name` names a subscriber for the refusal.
    pub fn own(
        &mut self,
        subscriber: u64,
        at: SubslotAddr,
        own: bool,
        taken: Taken,
        name: &dyn Fn(u64) -> String,
    ) -> Result<Option<Order>, Refusal> {
        if !self.submodules.contains(&at) {
            return Err(Refusal::NoSuchStationSubmodule {
                api: at.api,
                slot: at.slot,
                subslot: at.subslot,
            });
        }
        match (self.owners.get(&at).copied(), own) {
            (Some(o), true) if o != subscriber => Err(Refusal::RecordsTaken {
                api: at.api,
                slot: at.slot,
                subslot: at.subslot,
                by: name(o),
            }),
            // Taken (again): with or without the station's own records, as said now.
            (_, true) => {
                self.owners.insert(at, subscriber);
                self.taken.insert(at, taken);
                Ok(Some(Order::Records(at, true, taken)))
            }
            (Some(o), false) if o == subscriber => {
                self.owners.remove(&at);
                self.taken.remove(&at);
                Ok(Some(Order::Records(at, false, Taken::default())))
            }
            (_, false) => Ok(None),
        }
    }

    /// A job of the engine: the subscriber it goes to, or the order to answer it when nobody
    /// took its submodule's records (any more).
    pub fn job(&mut self, job: u64, at: SubslotAddr, now: Instant) -> Result<u64, Order> {
        self.jobs
            .retain(|_, (_, t)| now.duration_since(*t) < JOB_MEMORY);
        match self.owners.get(&at) {
            Some(&o) => {
                self.jobs.insert(job, (o, now));
                Ok(o)
            }
            None => Err(Order::Busy(job)),
        }
    }

    /// `subscriber` answers `job`: it must be the one the job went to.
    pub fn answer(&mut self, subscriber: u64, job: u64) -> Result<(), Refusal> {
        match self.jobs.get(&job) {
            Some((o, _)) if *o == subscriber => {
                self.jobs.remove(&job);
                Ok(())
            }
            _ => Err(Refusal::StaleRecordJob { job }),
        }
    }

    /// `subscriber` checks new ARs (or stops); `name` names a subscriber for the refusal.
    pub fn check(
        &mut self,
        subscriber: u64,
        check: bool,
        name: &dyn Fn(u64) -> String,
    ) -> Result<Option<Order>, Refusal> {
        self.ars
            .take(subscriber, check)
            .map(|c| c.map(Order::Check))
            .map_err(|c| Refusal::ArChecksTaken { by: name(c) })
    }

    /// An AR check of the engine: the subscriber it goes to, or the order to accept it when
    /// nobody checks (any more).
    pub fn ar_check(&mut self, job: u64, now: Instant) -> Result<u64, Order> {
        self.ars.give(job, now).ok_or(Order::Accept(job))
    }

    /// `subscriber` answers AR check `job`: it must be the one the check went to.
    pub fn answer_check(&mut self, subscriber: u64, job: u64) -> Result<(), Refusal> {
        if self.ars.answer(subscriber, job) {
            Ok(())
        } else {
            Err(Refusal::StaleArCheck { job })
        }
    }

    /// `subscriber` checks DCP's changes of the station (or stops).
    pub fn verify_dcp(
        &mut self,
        subscriber: u64,
        verify: bool,
        name: &dyn Fn(u64) -> String,
    ) -> Result<Option<Order>, Refusal> {
        self.dcp
            .take(subscriber, verify)
            .map(|c| c.map(Order::VerifyDcp))
            .map_err(|c| Refusal::DcpChecksTaken { by: name(c) })
    }

    /// A DCP Set check of the engine: the subscriber it goes to, or the order to allow it.
    pub fn dcp_check(&mut self, job: u64, now: Instant) -> Result<u64, Order> {
        self.dcp.give(job, now).ok_or(Order::AllowDcp(job))
    }

    /// `subscriber` answers DCP Set check `job`.
    pub fn answer_dcp(&mut self, subscriber: u64, job: u64) -> Result<(), Refusal> {
        if self.dcp.answer(subscriber, job) {
            Ok(())
        } else {
            Err(Refusal::StaleDcpCheck { job })
        }
    }

    /// `subscriber` holds the ApplicationReady (or not).
    pub fn hold(&mut self, subscriber: u64, hold: bool) -> Vec<Order> {
        let before = !self.holders.is_empty();
        if hold {
            self.holders.insert(subscriber);
        } else {
            self.holders.remove(&subscriber);
            self.ready.remove(&subscriber);
        }
        self.after_holders_changed(before)
    }

    /// The PLC's PrmEnd: every holder is to say again that its parameters are applied.
    pub fn parameters_ended(&mut self) {
        self.ready.clear();
    }

    /// `subscriber` applied the parameters: the ApplicationReady goes once every holder did.
    pub fn ready(&mut self, subscriber: u64) -> Option<Order> {
        if !self.holders.contains(&subscriber) {
            return None;
        }
        self.ready.insert(subscriber);
        self.all_ready().then_some(Order::Release)
    }

    /// `subscriber` is gone: what it took comes back, its hold ends.
    pub fn forget(&mut self, subscriber: u64) -> Vec<Order> {
        let mut orders: Vec<Order> = self
            .owners
            .iter()
            .filter(|(_, o)| **o == subscriber)
            .map(|(at, _)| Order::Records(*at, false, Taken::default()))
            .collect();
        self.owners.retain(|_, o| *o != subscriber);
        self.taken.retain(|at, _| self.owners.contains_key(at));
        self.jobs.retain(|_, (o, _)| *o != subscriber);
        // Its open checks are decided as without a checker: the AR accepted, the Set allowed.
        let (was, open) = self.ars.forget(subscriber);
        if was {
            orders.push(Order::Check(false));
        }
        orders.extend(open.into_iter().map(Order::Accept));
        let (was, open) = self.dcp.forget(subscriber);
        if was {
            orders.push(Order::VerifyDcp(false));
        }
        orders.extend(open.into_iter().map(Order::AllowDcp));
        let before = !self.holders.is_empty();
        self.holders.remove(&subscriber);
        self.ready.remove(&subscriber);
        orders.extend(self.after_holders_changed(before));
        orders
    }

    /// What `subscriber` has said that lasts beyond one AR.
    pub fn standing(&self, subscriber: u64) -> Standing {
        Standing {
            checks_ars: self.ars.by == Some(subscriber),
            verifies_dcp: self.dcp.by == Some(subscriber),
            holds: self.holders.contains(&subscriber),
            records: self
                .owners
                .iter()
                .filter(|(_, o)| **o == subscriber)
                .map(|(at, _)| (*at, self.taken.get(at).copied().unwrap_or_default()))
                .collect(),
        }
    }

    /// `subscriber` says again what `standing` holds, as far as this station has the
    /// submodules; the orders for the engine.
    pub fn resume(&mut self, subscriber: u64, standing: &Standing) -> Vec<Order> {
        let nobody = |_: u64| String::new();
        let mut orders = Vec::new();
        for (&at, &taken) in &standing.records {
            if let Ok(Some(o)) = self.own(subscriber, at, true, taken, &nobody) {
                orders.push(o);
            }
        }
        if standing.checks_ars
            && let Ok(Some(o)) = self.check(subscriber, true, &nobody)
        {
            orders.push(o);
        }
        if standing.verifies_dcp
            && let Ok(Some(o)) = self.verify_dcp(subscriber, true, &nobody)
        {
            orders.push(o);
        }
        if standing.holds {
            orders.extend(self.hold(subscriber, true));
        }
        orders
    }

    fn all_ready(&self) -> bool {
        self.holders.is_subset(&self.ready)
    }

    /// The orders after a holder came or went: hold on or off; a held ApplicationReady
    /// goes when the holders left are ready.
    fn after_holders_changed(&self, held_before: bool) -> Vec<Order> {
        let held = !self.holders.is_empty();
        let mut orders = Vec::new();
        if held != held_before {
            orders.push(Order::Hold(held));
        }
        if held_before && self.all_ready() {
            orders.push(Order::Release);
        }
        orders
    }
}

/// The engine's and the clients' timeouts agree.
const _: () = {
    assert!(
        procimg_profinet::device::RECORD_ANSWER_TIMEOUT_NS == STATION_RECORD_TIMEOUT_MS * 1_000_000
    );
    assert!(
        procimg_profinet::device::APP_READY_HOLD_TIMEOUT_NS
            == APP_READY_HOLD_TIMEOUT_MS * 1_000_000
    );
    assert!(procimg_profinet::device::AR_CHECK_TIMEOUT_NS == AR_CHECK_TIMEOUT_MS * 1_000_000);
    assert!(
        procimg_profinet::device::DCP_SET_CHECK_TIMEOUT_NS == DCP_SET_CHECK_TIMEOUT_MS * 1_000_000
    );
};

#[cfg(test)]
mod tests {
    use super::*;

    const SLOT1: SubslotAddr = SubslotAddr::new(0, 1, 1);

    fn say() -> ApplicationSay {
        ApplicationSay::new([SubslotAddr::new(0, 0, 1), SLOT1])
    }

    #[test]
    fn one_subscriber_takes_a_submodules_records_and_its_jobs() {
        let mut s = say();
        let name: &dyn Fn(u64) -> String = &|id| format!("client {id}");
        assert_eq!(
            s.own(1, SLOT1, true, Taken::default(), name),
            Ok(Some(Order::Records(SLOT1, true, Taken::default())))
        );
        assert_eq!(
            s.own(
                1,
                SLOT1,
                true,
                Taken {
                    im: true,
                    pe: false
                },
                name
            ),
            Ok(Some(Order::Records(
                SLOT1,
                true,
                Taken {
                    im: true,
                    pe: false
                }
            )))
        );
        assert_eq!(
            s.own(2, SLOT1, true, Taken::default(), name),
            Err(Refusal::RecordsTaken {
                api: 0,
                slot: 1,
                subslot: 1,
                by: "client 1".into()
            })
        );
        assert!(matches!(
            s.own(1, SubslotAddr::new(0, 9, 1), true, Taken::default(), name),
            Err(Refusal::NoSuchStationSubmodule { slot: 9, .. })
        ));
        let now = Instant::now();
        assert_eq!(s.job(7, SLOT1, now), Ok(1));
        assert_eq!(
            s.job(8, SubslotAddr::new(0, 0, 1), now),
            Err(Order::Busy(8))
        );
        assert_eq!(s.answer(2, 7), Err(Refusal::StaleRecordJob { job: 7 }));
        assert_eq!(s.answer(1, 7), Ok(()));
        assert_eq!(s.answer(1, 7), Err(Refusal::StaleRecordJob { job: 7 }));
        // Gone: its records come back, its jobs are stale.
        assert_eq!(s.job(9, SLOT1, now), Ok(1));
        assert_eq!(
            s.forget(1),
            [Order::Records(SLOT1, false, Taken::default())]
        );
        assert_eq!(s.answer(1, 9), Err(Refusal::StaleRecordJob { job: 9 }));
        assert_eq!(
            s.own(2, SLOT1, true, Taken::default(), name),
            Ok(Some(Order::Records(SLOT1, true, Taken::default())))
        );
    }

    #[test]
    fn old_jobs_are_forgotten() {
        let mut s = say();
        s.own(1, SLOT1, true, Taken::default(), &|_| String::new())
            .unwrap();
        let then = Instant::now();
        assert_eq!(s.job(1, SLOT1, then), Ok(1));
        assert_eq!(s.job(2, SLOT1, then + JOB_MEMORY), Ok(1));
        assert_eq!(s.answer(1, 1), Err(Refusal::StaleRecordJob { job: 1 }));
        assert_eq!(s.answer(1, 2), Ok(()));
    }

    #[test]
    fn one_subscriber_checks_new_ars_and_its_checks_are_accepted_when_it_goes() {
        let mut s = say();
        let name: &dyn Fn(u64) -> String = &|id| format!("client {id}");
        let now = Instant::now();
        assert_eq!(s.ar_check(1, now), Err(Order::Accept(1)), "nobody checks");
        assert_eq!(s.check(1, true, name), Ok(Some(Order::Check(true))));
        assert_eq!(
            s.check(2, true, name),
            Err(Refusal::ArChecksTaken {
                by: "client 1".into()
            })
        );
        assert_eq!(s.ar_check(2, now), Ok(1));
        assert_eq!(s.answer_check(2, 2), Err(Refusal::StaleArCheck { job: 2 }));
        assert_eq!(s.answer_check(1, 2), Ok(()));
        assert_eq!(s.answer_check(1, 2), Err(Refusal::StaleArCheck { job: 2 }));
        assert_eq!(s.ar_check(3, now), Ok(1));
        assert_eq!(s.forget(1), [Order::Check(false), Order::Accept(3)]);
        assert_eq!(s.check(2, true, name), Ok(Some(Order::Check(true))));
    }

    #[test]
    fn one_subscriber_checks_dcps_changes_and_its_checks_are_allowed_when_it_goes() {
        let mut s = say();
        let name: &dyn Fn(u64) -> String = &|id| format!("client {id}");
        let now = Instant::now();
        assert_eq!(s.dcp_check(1, now), Err(Order::AllowDcp(1)));
        assert_eq!(
            s.verify_dcp(1, true, name),
            Ok(Some(Order::VerifyDcp(true)))
        );
        assert_eq!(
            s.verify_dcp(2, true, name),
            Err(Refusal::DcpChecksTaken {
                by: "client 1".into()
            })
        );
        assert_eq!(s.dcp_check(2, now), Ok(1));
        assert_eq!(s.answer_dcp(2, 2), Err(Refusal::StaleDcpCheck { job: 2 }));
        assert_eq!(s.answer_dcp(1, 2), Ok(()));
        assert_eq!(s.dcp_check(3, now), Ok(1));
        assert_eq!(s.forget(1), [Order::VerifyDcp(false), Order::AllowDcp(3)]);
    }

    #[test]
    fn the_application_ready_goes_when_every_holder_is_ready() {
        let mut s = say();
        assert_eq!(s.hold(1, true), [Order::Hold(true)]);
        assert_eq!(s.hold(2, true), []);
        s.parameters_ended();
        assert_eq!(s.ready(3), None, "not a holder");
        assert_eq!(s.ready(1), None);
        assert_eq!(s.ready(2), Some(Order::Release));
        // The next PrmEnd: both say it again; one goes away meanwhile.
        s.parameters_ended();
        assert_eq!(s.ready(2), None);
        assert_eq!(s.forget(1), [Order::Release]);
        assert_eq!(s.hold(2, false), [Order::Hold(false), Order::Release]);
    }
    #[test]
    fn what_a_subscriber_said_is_said_again_in_another_station() {
        let mut old = say();
        let none = |_: u64| String::new();
        old.own(
            7,
            SLOT1,
            true,
            Taken {
                im: true,
                pe: false,
            },
            &none,
        )
        .unwrap();
        old.check(7, true, &none).unwrap();
        old.hold(7, true);
        old.check(8, false, &none).unwrap();
        let standing = old.standing(7);
        assert!(standing.checks_ars && standing.holds && !standing.verifies_dcp);
        assert_eq!(
            standing.records.get(&SLOT1),
            Some(&Taken {
                im: true,
                pe: false
            })
        );
        assert_eq!(old.standing(8), Standing::default());

        // A station with slot 1 subslot 1 and another submodule, and one without slot 1.
        let mut new = ApplicationSay::new([SLOT1, SubslotAddr::new(0, 2, 1)]);
        let orders = new.resume(7, &standing);
        assert!(orders.contains(&Order::Records(
            SLOT1,
            true,
            Taken {
                im: true,
                pe: false
            }
        )));
        assert!(orders.contains(&Order::Check(true)));
        assert!(orders.contains(&Order::Hold(true)));
        assert_eq!(new.standing(7), standing);
        let mut other = ApplicationSay::new([SubslotAddr::new(0, 2, 1)]);
        let orders = other.resume(7, &standing);
        assert!(!orders.iter().any(|o| matches!(o, Order::Records(..))));
        assert!(other.standing(7).records.is_empty());
    }
}
