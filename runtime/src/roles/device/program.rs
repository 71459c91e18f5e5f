// SPDX-License-Identifier: MIT OR Apache-2.0
//! A station its program defines (`[station] gsdml`, no `[[station.submodule]]`): who its
//! program is, and the station procimgd is to run next. It outlives a generation: the
//! control side of each generation asks it, procimgd's main loop runs the next generation
//! from what it holds (docs/ARCHITECTURE.md, "A station its program defines").

use super::application::{Standing, Taken};
use crate::config::StationConfig;
use crate::image::Tables;
use crate::roles::subscribers::Subscriber;
use procimg_config::{PlannedSubmodule, define_station, with_identity};
use procimg_control::{DefinedIdentity, StationTreeEntry, TreeRecords};
use procimg_profinet::device::SubslotAddr;
use std::collections::HashSet;
use std::sync::{Arc, Mutex, PoisonError};

/// The program that defined the station.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Definer {
    /// Its subscriber id.
    pub subscriber: u64,
    /// The subscriber as it announced itself (name, pid, iceoryx2 node).
    pub who: Subscriber,
}

/// A station and its image tables, made when its tree was checked.
#[derive(Clone, Debug)]
pub struct Generation {
    /// The station.
    pub station: StationConfig,
    /// Its image tables.
    pub tables: Tables,
}

/// What procimgd runs after this generation.
#[derive(Clone, Debug)]
pub enum Next {
    /// The station with the program's tree, on the wire.
    Defined(Box<Generation>),
    /// The station without its program: the device access point only, off the wire.
    Waiting,
}

/// Why a definition is refused.
#[derive(Debug, PartialEq, Eq, thiserror::Error)]
pub enum DefineError {
    /// Another program defined the station.
    #[error(
        "the station is defined by {0} already; one program defines it: end that one first \
         (its close, or its process's end, takes the station off the wire)"
    )]
    Taken(String),
    /// The station has an AR.
    #[error(
        "an AR with the PLC runs: the tree is defined before a PLC connects; end the \
         station's program (its close) to take the station off the wire, then define it again"
    )]
    ArRuns,
    /// The tree does not fit the GSDML file, or the station no process image.
    #[error("{0}")]
    Tree(String),
}

/// The station's program and the generation to come.
pub struct StationProgram {
    /// The station as configured (identity and device access point, no tree), with its
    /// tables.
    waiting: Generation,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    definer: Option<Definer>,
    /// What the definer said that holds in the station it defined.
    standing: Standing,
    next: Option<Next>,
}

impl StationProgram {
    /// The program state of `station`, if its program defines it (`[station] gsdml`), whose
    /// image has `tables` while it waits.
    pub fn of(station: &StationConfig, tables: &Tables) -> Option<Arc<StationProgram>> {
        station.program.as_ref()?;
        Some(Arc::new(StationProgram {
            waiting: Generation {
                station: station.clone(),
                tables: tables.clone(),
            },
            state: Mutex::new(State::default()),
        }))
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The station without a program, as configured, with its tables.
    pub fn waiting(&self) -> &Generation {
        &self.waiting
    }

    /// The program that defined the current station, if one did.
    pub fn definer(&self) -> Option<Definer> {
        self.lock().definer.clone()
    }

    /// The station `tree` defines, with `identity`'s name, address and serial number where
    /// it gives them, and its tables: refused when the identity is not one a station can
    /// have, the GSDML file does not allow the tree, or the station would have no process
    /// image.
    pub fn plan(
        &self,
        tree: &[StationTreeEntry],
        identity: &DefinedIdentity,
    ) -> Result<Generation, DefineError> {
        let planned: Vec<PlannedSubmodule> = tree
            .iter()
            .map(|e| PlannedSubmodule {
                api: e.api,
                slot: e.slot,
                subslot: e.subslot,
                module_ident: e.module_ident,
                submodule_ident: e.submodule_ident,
            })
            .collect();
        let Some(file) = &self.waiting.station.program else {
            return Err(DefineError::Tree(
                "the station is not one its program defines".into(),
            ));
        };
        let base = with_identity(
            &self.waiting.station,
            identity.name.as_deref(),
            identity
                .ip
                .map(|[ip, mask, gw]| (ip.into(), mask.into(), gw.into())),
            identity.serial_number.as_deref(),
        )
        .map_err(|e| DefineError::Tree(format!("the station's identity: {e}")))?;
        let station = define_station(&base, &file.file, &file.file.daps[file.dap_index], &planned)
            .map_err(|e| DefineError::Tree(e.to_string()))?;
        // Made now, so that a station without an image is refused rather than found out
        // when the current generation has ended.
        let tables = Tables::of_station(&station)
            .map_err(|e| DefineError::Tree(format!("the station's process image: {e}")))?;
        Ok(Generation { station, tables })
    }

    /// Subscriber `subscriber` (`who`) defines the station as `tree` with the parts of
    /// `identity` it gives, having said `standing` so far: refused when another program defined it, while an AR runs
    /// (`ar_runs`), or when the GSDML file does not allow the tree; once accepted the next
    /// generation runs it, with `standing` and the records the tree gives the program
    /// taken from its start.
    pub fn define(
        &self,
        subscriber: u64,
        who: &Subscriber,
        tree: &[StationTreeEntry],
        identity: &DefinedIdentity,
        ar_runs: bool,
        mut standing: Standing,
    ) -> Result<(), DefineError> {
        let mut state = self.lock();
        if let Some(d) = &state.definer
            && d.subscriber != subscriber
        {
            return Err(DefineError::Taken(d.who.to_string()));
        }
        if ar_runs {
            return Err(DefineError::ArRuns);
        }
        let next = self.plan(tree, identity)?;
        for e in tree {
            let at = SubslotAddr::new(e.api, e.slot, e.subslot);
            match e.records {
                TreeRecords::Station => {}
                TreeRecords::Program => {
                    standing.records.insert(at, Taken::default());
                }
                TreeRecords::ProgramWithIm => {
                    standing.records.insert(
                        at,
                        Taken {
                            im: true,
                            pe: false,
                        },
                    );
                }
            }
        }
        state.definer = Some(Definer {
            subscriber,
            who: who.clone(),
        });
        state.standing = standing;
        state.next = Some(Next::Defined(Box::new(next)));
        Ok(())
    }

    /// The program that defined the current station and what it said that holds there.
    pub fn carried(&self) -> Option<(Definer, Standing)> {
        let state = self.lock();
        let d = state.definer.clone()?;
        Some((d, state.standing.clone()))
    }

    /// Subscriber `subscriber`'s program ends: if it defined the station, the next
    /// generation waits for a program. Whether it had.
    pub fn release(&self, subscriber: u64) -> bool {
        let mut state = self.lock();
        if state
            .definer
            .as_ref()
            .is_none_or(|d| d.subscriber != subscriber)
        {
            return false;
        }
        state.definer = None;
        state.standing = Standing::default();
        state.next = Some(Next::Waiting);
        true
    }

    /// When the defining program's process is gone (`alive`: the live iceoryx2 node ids),
    /// the next generation waits for a program; the program, if it was so.
    pub fn reap(&self, alive: &HashSet<String>) -> Option<Definer> {
        let mut state = self.lock();
        let gone = state
            .definer
            .as_ref()
            .is_some_and(|d| !alive.contains(&d.who.node_id));
        if !gone {
            return None;
        }
        state.next = Some(Next::Waiting);
        state.standing = Standing::default();
        state.definer.take()
    }

    /// The generation to run next, if one was asked for.
    pub fn take_next(&self) -> Option<Next> {
        self.lock().next.take()
    }
}
