// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the cycle thread's PROFINET tests share: one device with 4 input bytes, its AR
//! started in an IO system over an in-process link, and the wire's end of that link.

use super::PnioIo;
use super::channel::{Channel, ToCycle};
use crate::config;
use crate::image::{Image, Tables};
use crate::io::CycleTime;
use procimg_nic::sim_link::{self, LinkEnd};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::wire::MacAddress;
use std::sync::Arc;

pub(super) const CONTROLLER: MacAddress = MacAddress([2, 0, 0, 0, 0, 1]);
pub(super) const DEVICE: MacAddress = MacAddress([2, 0, 0, 0, 0, 2]);
pub(super) const MS: u64 = 1_000_000;

/// The IO system with the device's exchange started, and what a test looks at.
pub(super) struct Rig {
    pub io: PnioIo,
    pub channel: Arc<Channel>,
    /// The device's end of the link: what it sends reaches the IO system.
    pub wire: LinkEnd,
    pub image: Image,
    /// The exchange as it was handed to the cycle.
    pub ar: CyclicAr,
}

/// A 1 ms cycle's time at cycle `k`.
pub(super) const fn at(k: u64) -> CycleTime {
    CycleTime {
        cycle: k,
        now_ns: k * MS,
    }
}

impl Rig {
    /// The device `io` (slot 1 with 4 input bytes) with `watchdog_factor`, its AR handed to
    /// the cycle (started at the next receive).
    pub(super) fn one_device(watchdog_factor: u16) -> Rig {
        Rig::of(&format!(
            r#"
            [[device]]
            name = "io"
            vendor_id = 1
            device_id = 1
            watchdog_factor = {watchdog_factor}
            [[device.submodule]]
            slot = 1
            subslot = 1
            module_ident = 1
            submodule_ident = 1
            input_length = 4
            "#
        ))
    }

    /// The first device of configuration `toml`, its AR handed to the cycle over an
    /// in-process link.
    pub(super) fn of(toml: &str) -> Rig {
        let config = config::parse(toml, "rig.toml").unwrap();
        let tables = Tables::from_config(&config).unwrap();
        let plan = &crate::roles::controller::plan_devices(&config).unwrap()[0];
        let ar = CyclicAr::new(plan, 1, CONTROLLER, DEVICE, plan.frame_ids);
        let (ours, wire) = sim_link::link(CONTROLLER, DEVICE);
        let channel = Arc::new(Channel::new());
        let io = PnioIo::new(
            Box::new(ours) as Box<dyn procimg_nic::Nic>,
            channel.clone(),
            std::iter::once(ar.submodules.clone()).collect(),
            config.cycle_ns,
        );
        assert!(
            channel
                .to_cycle
                .push(ToCycle::Start(Box::new(ar.clone())))
                .is_ok()
        );
        Rig {
            io,
            channel,
            wire,
            image: Image::new(&tables),
            ar,
        }
    }
}
