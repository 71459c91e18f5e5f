// SPDX-License-Identifier: MIT OR Apache-2.0
//! The configuration functions after the handle checks: APIs, modules and submodules, their
//! address and sequence checks, and the jobs they give the library thread.
//!
//! Codes where the manual leaves the choice: an API not added, a slot above MaxSlots, a
//! subslot outside 1..MaxSubslots, an address that is not geographical or a position the
//! station's configuration does not have answer `PNIO_ERR_PRM_ADD` (for a station its
//! program defines, outside slot 0: a submodule its GSDML file does not allow there); a submodule plugged
//! before its module, at a position the program plugged already, a pull of what the program
//! did not plug, a module plugged twice, an API added twice or removed while it has modules,
//! and plug or pull after start without `PNIO_CBF_PULL_PLUG_CONF` answer
//! `PNIO_ERR_SEQUENCE`. An AlarmType other than PLUG and PLUG_WRONG, or IM0_bits none of the
//! four, answer `PNIO_ERR_PRM_INVALIDARG` (procimgd picks the alarm by what the PLC expects,
//! and keeps I&M0FilterData itself).

use super::Pos;
use super::jobs::Job;
use super::state::{Config, Device, Life};
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use crate::iobase::types::PNIO_ADDR_GEO;
use procimg_client::{ControlError, Refusal, StationTreeEntry, TreeRecords};
use std::sync::MutexGuard;

/// The configuration when plug and pull are allowed now: before start, after stop, and after
/// start with `PNIO_CBF_PULL_PLUG_CONF`.
fn may_plug<'a>(f: &str, dev: &'a Device) -> Result<MutexGuard<'a, Config>, u32> {
    let c = lock(&dev.config);
    match c.life {
        Life::Opened | Life::Stopped => Ok(c),
        Life::Started if dev.cbf.cbf_pull_plug_conf.is_some() => Ok(c),
        Life::Started => Err(fail(
            f,
            PNIO_ERR_SEQUENCE,
            "after PNIO_device_start, plug and pull need PNIO_CBF_PULL_PLUG_CONF (given to \
             PNIO_device_open); without it stop the device, plug or pull, and start again",
        )),
        other => Err(fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "the device is {}: wait for PNIO_CBF_DEVICE_STOPPED",
                other.name()
            ),
        )),
    }
}

/// The configuration when APIs may be added or removed: not while started or stopping.
fn may_configure<'a>(f: &str, dev: &'a Device) -> Result<MutexGuard<'a, Config>, u32> {
    let c = lock(&dev.config);
    match c.life {
        Life::Opened | Life::Stopped => Ok(c),
        other => Err(fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "the device is {}: APIs are added and removed before PNIO_device_start or \
                 after PNIO_CBF_DEVICE_STOPPED",
                other.name()
            ),
        )),
    }
}

/// `PNIO_api_add` (`high` for `PNIO_api_add_ext`: the device's open_ext numbers).
pub(crate) fn api_add(f: &str, dev: &Device, api: u32, high: (u16, u16)) -> u32 {
    let mut c = match may_configure(f, dev) {
        Ok(c) => c,
        Err(code) => return code,
    };
    if c.apis.contains_key(&api) {
        return fail(
            f,
            PNIO_ERR_ALREADY_DONE,
            format_args!("API {api} is added already"),
        );
    }
    // A station its program defines takes the APIs its GSDML file has: its plugs say.
    if dev.gsdml.is_none() && !dev.positions().iter().any(|p| p.at.0 == api) {
        return fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!(
                "the station of instance \"{}\" has no submodule in API {api}",
                dev.instance
            ),
        );
    }
    if high.1 == 0 {
        return fail(f, PNIO_ERR_PRM_INVALIDARG, "MaxSubslots is 0");
    }
    c.apis.insert(api, high);
    PNIO_OK
}

/// `PNIO_api_remove`.
pub(crate) fn api_remove(f: &str, dev: &Device, api: u32) -> u32 {
    let mut c = match may_configure(f, dev) {
        Ok(c) => c,
        Err(code) => return code,
    };
    if !c.apis.contains_key(&api) {
        return fail(f, PNIO_ERR_PRM_ADD, format_args!("API {api} is not added"));
    }
    if c.modules.keys().any(|(a, _)| *a == api) {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("API {api} still has modules: pull them first (PNIO_mod_pull)"),
        );
    }
    c.apis.remove(&api);
    PNIO_OK
}

/// The slot, and with `sub` the subslot, of `addr` in `api`, checked against the added API
/// and the station's positions.
fn address(
    f: &str,
    dev: &Device,
    c: &Config,
    api: u32,
    addr: &PNIO_DEV_ADDR,
    sub: bool,
) -> Result<Pos, u32> {
    if addr.AddrType != PNIO_ADDR_GEO {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!("pAddr->AddrType {} is not PNIO_ADDR_GEO", addr.AddrType),
        ));
    }
    let Some(&(max_slots, max_subslots)) = c.apis.get(&api) else {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!("API {api} is not added (PNIO_api_add)"),
        ));
    };
    let g = addr.geo_addr();
    let slot = match u16::try_from(g.Slot) {
        Ok(s) if s <= max_slots => s,
        _ => {
            return Err(fail(
                f,
                PNIO_ERR_PRM_ADD,
                format_args!("slot {} is above API {api}'s MaxSlots {max_slots}", g.Slot),
            ));
        }
    };
    // Outside slot 0 a station its program defines has the positions the program plugs,
    // checked against its GSDML file (`tree_allows`), until it is defined at start.
    let open_tree = defines_tree(dev, c) && slot != 0;
    if !sub {
        if !open_tree
            && !dev
                .positions()
                .iter()
                .any(|p| (p.at.0, p.at.1) == (api, slot))
        {
            return Err(fail(
                f,
                PNIO_ERR_PRM_ADD,
                format_args!(
                    "the station of instance \"{}\" has no slot {slot} in API {api} (only its \
                     configured positions can be plugged)",
                    dev.instance
                ),
            ));
        }
        return Ok((api, slot, 0));
    }
    let subslot = match u16::try_from(g.Subslot) {
        Ok(s) if s >= 1 && s <= max_subslots => s,
        _ => {
            return Err(fail(
                f,
                PNIO_ERR_PRM_ADD,
                format_args!(
                    "subslot {:#x} is not in 1..MaxSubslots ({max_subslots:#x}) of API {api}",
                    g.Subslot
                ),
            ));
        }
    };
    if !open_tree && !dev.has_position((api, slot, subslot)) {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!(
                "the station of instance \"{}\" has no submodule at API {api} slot {slot} \
                 subslot {subslot:#06x} (only its configured positions can be plugged)",
                dev.instance
            ),
        ));
    }
    Ok((api, slot, subslot))
}

/// Whether the program's plugs outside slot 0 define the station now: it is one its program
/// defines, and the device is not started (after start its positions are the tree's).
pub(crate) fn defines_tree(dev: &Device, c: &Config) -> bool {
    dev.gsdml.is_some() && c.life != Life::Started
}

/// The program's tree after slot 0 as procimgd's station takes it: each submodule with its
/// module's ident number, its records the program's (with the I&M records when plugged with
/// I&M0 bits).
pub(crate) fn program_tree(c: &Config) -> Vec<StationTreeEntry> {
    c.subs
        .iter()
        .filter(|(at, _)| at.1 != 0)
        .filter_map(|(&(api, slot, subslot), &submodule_ident)| {
            Some(StationTreeEntry {
                api,
                slot,
                subslot,
                module_ident: *c.modules.get(&(api, slot))?,
                submodule_ident,
                records: if c.im.contains(&(api, slot, subslot)) {
                    TreeRecords::ProgramWithIm
                } else {
                    TreeRecords::Program
                },
            })
        })
        .collect()
}

/// Whether the station's GSDML file allows the program's tree with `module` and
/// `submodule` at `at` too (asked of procimgd, which names what is wrong).
fn tree_allows(f: &str, dev: &Device, at: Pos, module: u32, submodule: u32) -> Result<(), u32> {
    let mut tree = program_tree(&lock(&dev.config));
    tree.push(StationTreeEntry {
        api: at.0,
        slot: at.1,
        subslot: at.2,
        module_ident: module,
        submodule_ident: submodule,
        records: TreeRecords::Program,
    });
    let checked = dev.iobase.services().check_station_tree(&tree);
    checked.map_err(|e| match e {
        ControlError::Refused(Refusal::BadRequest { message }) => fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!(
                "instance \"{}\" does not take module {module:#010x} submodule \
                 {submodule:#010x} at API {} slot {} subslot {:#06x}: {message}",
                dev.instance, at.0, at.1, at.2
            ),
        ),
        e => fail(f, PNIO_ERR_NO_FW_COMMUNICATION, e),
    })
}

/// Counts the job as waiting for its confirmation and gives it to the library thread.
fn queue(f: &str, dev: &Device, mut c: MutexGuard<'_, Config>, job: Job) -> u32 {
    c.pending += 1;
    drop(c);
    match dev.send(job) {
        Ok(()) => PNIO_OK,
        Err(code) => {
            let mut c = lock(&dev.config);
            c.pending = c.pending.saturating_sub(1);
            fail(f, code, "the device's thread has ended")
        }
    }
}

/// The configuration, locked, and the position `addr` names in it: what every plug and pull
/// checks first ([`may_plug`], then [`address`]; `sub` as there).
fn config_at<'a>(
    f: &str,
    dev: &'a Device,
    api: u32,
    addr: &PNIO_DEV_ADDR,
    sub: bool,
) -> Result<(MutexGuard<'a, Config>, Pos), u32> {
    let c = may_plug(f, dev)?;
    let at = address(f, dev, &c, api, addr, sub)?;
    Ok((c, at))
}

/// `PNIO_mod_plug`.
pub(crate) fn mod_plug(f: &str, dev: &Device, api: u32, addr: PNIO_DEV_ADDR, ident: u32) -> u32 {
    let (mut c, (_, slot, _)) = match config_at(f, dev, api, &addr, false) {
        Ok(found) => found,
        Err(code) => return code,
    };
    if c.modules.contains_key(&(api, slot)) {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("a module is plugged in API {api} slot {slot} already: pull it first"),
        );
    }
    c.modules.insert((api, slot), ident);
    queue(
        f,
        dev,
        c,
        Job::Confirm {
            api,
            action: PNIO_MOD_PLUG,
            addr,
        },
    )
}

/// `PNIO_mod_pull`: the module's submodules come out of procimgd's station.
pub(crate) fn mod_pull(f: &str, dev: &Device, api: u32, addr: PNIO_DEV_ADDR) -> u32 {
    let (mut c, (_, slot, _)) = match config_at(f, dev, api, &addr, false) {
        Ok(found) => found,
        Err(code) => return code,
    };
    let Some(ident) = c.modules.remove(&(api, slot)) else {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("no module of the program is plugged in API {api} slot {slot}"),
        );
    };
    let subs: Vec<(Pos, u32)> = c
        .subs
        .iter()
        .filter(|(p, _)| (p.0, p.1) == (api, slot))
        .map(|(p, s)| (*p, *s))
        .collect();
    for (p, _) in &subs {
        c.subs.remove(p);
    }
    queue(
        f,
        dev,
        c,
        Job::Pull {
            api,
            at: subs,
            action: PNIO_MOD_PULL,
            module: Some(((api, slot), ident)),
            addr,
        },
    )
}

/// `PNIO_sub_plug`, `PNIO_sub_plug_ext` and `PNIO_sub_plug_ext_IM`.
pub(crate) fn sub_plug(
    f: &str,
    dev: &Device,
    api: u32,
    addr: PNIO_DEV_ADDR,
    ident: u32,
    alarm_type: u32,
    im0_bits: PNIO_PLUG_IM0_BITS,
) -> u32 {
    if alarm_type != PNIO_ALARM_TYPE_PLUG && alarm_type != PNIO_ALARM_TYPE_PLUG_WRONG {
        return fail(
            f,
            PNIO_ERR_PRM_INVALIDARG,
            format_args!(
                "AlarmType {alarm_type:#x} is neither PNIO_ALARM_TYPE_PLUG nor \
                 PNIO_ALARM_TYPE_PLUG_WRONG"
            ),
        );
    }
    if ![
        PNIO_PLUG_IM0_BITS_NOTHING,
        PNIO_PLUG_IM0_BITS_SUBMODULE,
        PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MODULE,
        PNIO_PLUG_IM0_BITS_SUBMODULE_REP_MOD_DEV,
    ]
    .contains(&im0_bits)
    {
        return fail(
            f,
            PNIO_ERR_PRM_INVALIDARG,
            format_args!("IM0_bits {im0_bits:#x} is none of the PNIO_PLUG_IM0_BITS_* values"),
        );
    }
    let (mut c, at) = match config_at(f, dev, api, &addr, true) {
        Ok(found) => found,
        Err(code) => return code,
    };
    let Some(&module) = c.modules.get(&(api, at.1)) else {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "no module is plugged in API {api} slot {}: PNIO_mod_plug first, then its \
                 submodules",
                at.1
            ),
        );
    };
    if c.subs.contains_key(&at) {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "the program plugged API {api} slot {} subslot {:#06x} already: pull it first",
                at.1, at.2
            ),
        );
    }
    if at.1 != 0 && defines_tree(dev, &c) {
        // Asked without the configuration locked: the library thread takes it meanwhile.
        drop(c);
        if let Err(code) = tree_allows(f, dev, at, module, ident) {
            return code;
        }
        c = match config_at(f, dev, api, &addr, true) {
            Ok((c, _)) => c,
            Err(code) => return code,
        };
        if c.subs.contains_key(&at) || c.modules.get(&(api, at.1)) != Some(&module) {
            return fail(
                f,
                PNIO_ERR_SEQUENCE,
                "the program's configuration changed during the call: plug again",
            );
        }
    }
    c.subs.insert(at, ident);
    if im0_bits == PNIO_PLUG_IM0_BITS_NOTHING {
        c.im.remove(&at);
    } else {
        c.im.insert(at);
    }
    queue(
        f,
        dev,
        c,
        Job::Plug {
            api,
            at,
            idents: (module, ident),
            addr,
        },
    )
}

/// `PNIO_sub_pull`.
pub(crate) fn sub_pull(f: &str, dev: &Device, api: u32, addr: PNIO_DEV_ADDR) -> u32 {
    let (mut c, at) = match config_at(f, dev, api, &addr, true) {
        Ok(found) => found,
        Err(code) => return code,
    };
    let Some(ident) = c.subs.remove(&at) else {
        return fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!(
                "the program has no submodule plugged at API {api} slot {} subslot {:#06x}",
                at.1, at.2
            ),
        );
    };
    queue(
        f,
        dev,
        c,
        Job::Pull {
            api,
            at: vec![(at, ident)],
            action: PNIO_SUB_PULL,
            module: None,
            addr,
        },
    )
}
