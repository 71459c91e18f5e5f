// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the controller asks of one device, worked out once from the configuration: the
//! submodules in wire order, the C_SDU layout of both IO CRs, the expected-submodule blocks,
//! the timing of the CRs and the parameter records. Each connect attempt then only fills in
//! the AR's identity (ARUUID, session key).

pub use crate::cyclic::CrTiming;
use crate::iocr_layout::{IocrLayout, SubmoduleIo, TooLarge};
use crate::wire::connect::{
    ALARM_CR_TYPE, AR_TYPE_IOC_SINGLE, AlarmCrBlockReq, ArBlockReq, ConnectRequest, ExpectedModule,
    ExpectedSubmodule, ExpectedSubmoduleBlockReq, IocrBlockReq, LT_PROFINET, TAG_HEADER_PRIO_5,
    TAG_HEADER_PRIO_6, UDP_RT_PORT_NONE, ar_properties, iocr_type,
};
use crate::wire::rt::TIME_UNIT_NS;
use crate::wire::{MacAddress, Uuid};
use std::net::Ipv4Addr;

/// The largest SendClockFactor for RT class 1/2 (4 ms).
const MAX_SEND_CLOCK_FACTOR: u64 = 128;
/// The largest ReductionRatio for RT class 1/2.
const MAX_REDUCTION_RATIO: u64 = 512;

/// Why a device cannot be planned.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlanError {
    /// The cycle time is no send clock times a power of two.
    #[error(
        "device {device:?}: a cycle time of {cycle_ns} ns is not a PROFINET send clock \
         (31.25 µs × 1..=128) times a power of two; choose a cycle time such as 1ms, 2ms or 4ms"
    )]
    CycleTime {
        /// Station name.
        device: String,
        /// Cycle time.
        cycle_ns: u64,
    },
    /// The reduction ratio goes beyond 512 send clocks.
    #[error(
        "device {device:?}: reduction_ratio {reduction_ratio} at this cycle time means a \
         ReductionRatio of {wire} send clocks, over the 512 PROFINET allows; lower it"
    )]
    ReductionRatio {
        /// Station name.
        device: String,
        /// Configured ratio.
        reduction_ratio: u16,
        /// Resulting wire value.
        wire: u64,
    },
    /// The IO data does not fit one frame.
    // Not a `source`: the message already holds it, and error chains would repeat it.
    #[error("device {device:?}: {problem}")]
    TooLarge {
        /// Station name.
        device: String,
        /// Which CR and how much.
        problem: TooLarge,
    },
}

/// The send clock and base reduction for a cycle time: the cycle is SCF × 2^k send clock
/// units with SCF ≤ 128, as RT class 1/2 requires.
fn send_clock(cycle_ns: u64) -> Option<(u64, u64)> {
    if cycle_ns == 0 || !cycle_ns.is_multiple_of(TIME_UNIT_NS) {
        return None;
    }
    let (mut scf, mut rr) = (cycle_ns / TIME_UNIT_NS, 1u64);
    while scf > MAX_SEND_CLOCK_FACTOR {
        if !scf.is_multiple_of(2) {
            return None;
        }
        scf /= 2;
        rr *= 2;
    }
    Some((scf, rr))
}

/// What the controller is to do with one device: its identity and its submodules, as the
/// configuration says (procimgd translates its TOML into this).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DeviceSpec {
    /// NameOfStation.
    pub name: String,
    /// The IP address to give it, if any.
    pub ip: Option<Ipv4Addr>,
    /// Vendor ID.
    pub vendor_id: u16,
    /// Device ID.
    pub device_id: u16,
    /// Instance.
    pub instance: u16,
    /// Frames every this many controller cycles (a power of two, 1 to 512).
    pub reduction_ratio: u16,
    /// Frame periods without data before the device counts as failed (3 to 255).
    pub watchdog_factor: u16,
    /// Its submodules, in configuration order.
    pub submodules: Vec<SubmoduleSpec>,
    /// Optional: it stays deactivated until the IO system is tailored with it
    /// ([`Controller::reconfigure`](super::Controller::reconfigure)).
    pub optional: bool,
    /// Its ports (subslots of slot 0) whose neighbour tailoring names (programmable peers).
    pub programmable_ports: Vec<u16>,
}

impl DeviceSpec {
    /// Its submodules' IO lengths, and where their data and status go in the two CRs: the
    /// layout its ARs exchange, and procimgd lays out its image's output frames by.
    pub fn iocr_layout(&self) -> (Vec<SubmoduleIo>, Result<IocrLayout, TooLarge>) {
        DeviceSpec::iocr_layout_of(&self.submodules)
    }

    /// The IO lengths of `submodules`, and the layout of the ARs a controller that plans a
    /// device with them sets up (procimgd's, and an S7-1500's: see [`IocrLayout`]).
    pub fn iocr_layout_of(
        submodules: &[SubmoduleSpec],
    ) -> (Vec<SubmoduleIo>, Result<IocrLayout, TooLarge>) {
        let submodules: Vec<SubmoduleIo> = submodules
            .iter()
            .map(|s| SubmoduleIo {
                api: s.api,
                slot: s.slot,
                subslot: s.subslot,
                input_length: s.input_length,
                output_length: s.output_length,
            })
            .collect();
        let layout = IocrLayout::new(&submodules);
        (submodules, layout)
    }
}

/// One submodule of a [`DeviceSpec`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SubmoduleSpec {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Module ident number.
    pub module_ident: u32,
    /// Submodule ident number.
    pub submodule_ident: u32,
    /// Input bytes.
    pub input_length: u16,
    /// Output bytes.
    pub output_length: u16,
    /// Parameter records written before PrmEnd: (index, data), in order.
    pub records: Vec<(u16, Vec<u8>)>,
}

impl SubmoduleSpec {
    /// The submodule a device plugs where the controller expects this one: the same place,
    /// ident numbers and lengths.
    pub const fn plugged(&self) -> crate::device::PluggedSubmodule {
        crate::device::PluggedSubmodule {
            api: self.api,
            slot: self.slot,
            subslot: self.subslot,
            module_ident: self.module_ident,
            submodule_ident: self.submodule_ident,
            input_length: self.input_length,
            output_length: self.output_length,
        }
    }
}

/// A parameter record to write before PrmEnd.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlannedRecord {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Index.
    pub index: u16,
    /// Data.
    pub data: Vec<u8>,
}

/// Everything fixed about one device's AR.
#[derive(Clone, Debug)]
pub struct DevicePlan {
    /// Index of the device in the configuration (and the device table).
    pub device: usize,
    /// NameOfStation.
    pub name: String,
    /// The IP address to give it, if configured.
    pub ip: Option<Ipv4Addr>,
    /// Vendor ID.
    pub vendor_id: u16,
    /// Device ID.
    pub device_id: u16,
    /// Instance.
    pub instance: u16,
    /// Index of its first submodule in the submodule table; its submodules follow in
    /// configuration order.
    pub first_submodule: usize,
    /// Its submodules in configuration order (index i is table entry `first_submodule + i`).
    pub submodules: Vec<SubmoduleIo>,
    /// The C_SDU layouts.
    pub layout: IocrLayout,
    /// The expected configuration, one block per slot as the S7 sends it.
    pub expected: Vec<ExpectedSubmoduleBlockReq>,
    /// Timing of both CRs.
    pub timing: CrTiming,
    /// Parameter records, in configuration order.
    pub records: Vec<PlannedRecord>,
    /// The FrameIDs proposed for the input and output CR.
    pub frame_ids: (u16, u16),
    /// Optional ([`DeviceSpec::optional`]).
    pub optional: bool,
    /// Ports with a programmable peer ([`DeviceSpec::programmable_ports`]).
    pub programmable_ports: Vec<u16>,
}

/// Properties of the controller itself that go into every Connect.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ControllerIdentity {
    /// The MAC address of the interface (source of RT frames).
    pub mac: MacAddress,
    /// The controller's IP address (the device sends ApplicationReady there).
    pub ip: Ipv4Addr,
    /// The controller's NameOfStation.
    pub station_name: String,
    /// Vendor ID of the controller, in its CMInitiatorObjectUUID.
    pub vendor_id: u16,
    /// Device ID of the controller.
    pub device_id: u16,
    /// Instance of the controller.
    pub instance: u16,
}

impl ControllerIdentity {
    /// The CMInitiatorObjectUUID: `DEA00000-6C97-11D1-8271-<instance><device><vendor>`.
    pub const fn object_uuid(&self) -> Uuid {
        crate::wire::rpc::object_uuid(self.instance, self.device_id, self.vendor_id)
    }
}

impl DevicePlan {
    /// Plans every device of `devices` at controller cycle `cycle_ns`; their submodules
    /// follow one another in the submodule table.
    pub fn all(devices: &[DeviceSpec], cycle_ns: u64) -> Result<Vec<DevicePlan>, PlanError> {
        let mut first = 0;
        let mut plans = Vec::with_capacity(devices.len());
        for (d, dev) in devices.iter().enumerate() {
            plans.push(DevicePlan::new(d, first, dev, cycle_ns)?);
            first += dev.submodules.len();
        }
        Ok(plans)
    }

    /// Plans device `device` (configuration index) whose submodules start at table index
    /// `first_submodule`.
    pub fn new(
        device: usize,
        first_submodule: usize,
        dev: &DeviceSpec,
        cycle_ns: u64,
    ) -> Result<DevicePlan, PlanError> {
        let (scf, base_rr) = send_clock(cycle_ns).ok_or_else(|| PlanError::CycleTime {
            device: dev.name.clone(),
            cycle_ns,
        })?;
        let rr = base_rr * u64::from(dev.reduction_ratio.max(1));
        if rr > MAX_REDUCTION_RATIO {
            return Err(PlanError::ReductionRatio {
                device: dev.name.clone(),
                reduction_ratio: dev.reduction_ratio,
                wire: rr,
            });
        }
        let (submodules, layout) = dev.iocr_layout();
        let layout = layout.map_err(|problem| PlanError::TooLarge {
            device: dev.name.clone(),
            problem,
        })?;
        // One block per (API, slot), slots ascending, submodules ascending: the S7's order.
        let mut order: Vec<usize> = (0..dev.submodules.len()).collect();
        order.sort_by_key(|&i| {
            let s = &dev.submodules[i];
            (s.api, s.slot, s.subslot)
        });
        let mut expected: Vec<ExpectedSubmoduleBlockReq> = Vec::new();
        for i in order {
            let s = &dev.submodules[i];
            let sub = ExpectedSubmodule::with_io(
                s.subslot,
                s.submodule_ident,
                s.input_length,
                s.output_length,
            );
            match expected.last_mut().and_then(|b| b.modules.last_mut()) {
                Some(m) if m.api == s.api && m.slot == s.slot => m.submodules.push(sub),
                _ => expected.push(ExpectedSubmoduleBlockReq {
                    modules: vec![ExpectedModule {
                        api: s.api,
                        slot: s.slot,
                        module_ident: s.module_ident,
                        properties: 0,
                        submodules: vec![sub],
                    }],
                }),
            }
        }
        let records = dev
            .submodules
            .iter()
            .flat_map(|s| {
                s.records.iter().map(|(index, data)| PlannedRecord {
                    api: s.api,
                    slot: s.slot,
                    subslot: s.subslot,
                    index: *index,
                    data: data.clone(),
                })
            })
            .collect();
        // Distinct per device so that frames can be told apart even by FrameID alone; only
        // the low bits of the index matter (the mask keeps the FrameIDs in RT class 2).
        let base = 0x8000u16.wrapping_add((device as u16).wrapping_mul(2) & 0x3ffe);
        Ok(DevicePlan {
            device,
            name: dev.name.clone(),
            ip: dev.ip,
            vendor_id: dev.vendor_id,
            device_id: dev.device_id,
            instance: dev.instance,
            first_submodule,
            submodules,
            layout,
            expected,
            timing: CrTiming {
                // At most 128 and 512 (send_clock and the check above), so the casts keep
                // every bit.
                send_clock_factor: scf as u16,
                reduction_ratio: rr as u16,
                every_cycles: u32::from(dev.reduction_ratio.max(1)),
                data_hold_factor: dev.watchdog_factor,
            },
            records,
            frame_ids: (base, base + 1),
            optional: dev.optional,
            programmable_ports: dev.programmable_ports.clone(),
        })
    }

    /// The controller's LocalAlarmReference for the device: its index modulo 2^16 (not a
    /// length; it only has to tell the controller's ARs apart).
    pub const fn alarm_reference(&self) -> u16 {
        self.device as u16
    }

    /// Whether the plan expects a submodule at (API, slot, subslot).
    pub fn has_submodule(&self, api: u32, slot: u16, subslot: u16) -> bool {
        self.submodules
            .iter()
            .any(|s| (s.api, s.slot, s.subslot) == (api, slot, subslot))
    }

    /// The RPC object UUID of the device.
    pub const fn object_uuid(&self) -> Uuid {
        crate::wire::rpc::object_uuid(self.instance, self.device_id, self.vendor_id)
    }

    /// The Connect request of one attempt, with the choices an S7-1500 makes: a single
    /// IOC AR with advanced startup, an activity timeout of 20 s, RT class 2 frames with
    /// priority 6, the alarm CR with a 100 ms RTA timeout and 3 retries.
    pub fn connect_request(
        &self,
        controller: &ControllerIdentity,
        ar_uuid: Uuid,
        session_key: u16,
    ) -> ConnectRequest {
        let mut crs = Vec::with_capacity(2);
        for (t, r, frame_id, layout) in [
            (iocr_type::INPUT, 1, self.frame_ids.0, &self.layout.input),
            (iocr_type::OUTPUT, 2, self.frame_ids.1, &self.layout.output),
        ] {
            // The layout was made from these submodules, so every index is in range.
            if let Ok(mut cr) = IocrBlockReq::from_layout(t, r, frame_id, layout, &self.submodules)
            {
                cr.send_clock_factor = self.timing.send_clock_factor;
                cr.reduction_ratio = self.timing.reduction_ratio;
                cr.watchdog_factor = self.timing.data_hold_factor;
                cr.data_hold_factor = self.timing.data_hold_factor;
                crs.push(cr);
            }
        }
        ConnectRequest {
            ar: ArBlockReq {
                ar_type: AR_TYPE_IOC_SINGLE,
                ar_uuid,
                session_key,
                initiator_mac: controller.mac,
                initiator_object_uuid: controller.object_uuid(),
                ar_properties: ar_properties::ADVANCED,
                activity_timeout_factor: 200,
                udp_rt_port: UDP_RT_PORT_NONE,
                station_name: controller.station_name.clone(),
            },
            iocrs: crs,
            alarm_cr: AlarmCrBlockReq {
                alarm_cr_type: ALARM_CR_TYPE,
                lt: LT_PROFINET,
                properties: 0,
                rta_timeout_factor: 1,
                rta_retries: 3,
                local_alarm_reference: self.alarm_reference(),
                max_alarm_data_length: 256,
                tag_header_high: TAG_HEADER_PRIO_6,
                tag_header_low: TAG_HEADER_PRIO_5,
            },
            expected: self.expected.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn send_clock_splits_long_cycles_into_a_power_of_two() {
        assert_eq!(send_clock(1_000_000), Some((32, 1)));
        assert_eq!(send_clock(31_250), Some((1, 1)));
        assert_eq!(send_clock(4_000_000), Some((128, 1)));
        assert_eq!(send_clock(32_000_000), Some((128, 8)));
        assert_eq!(send_clock(8_000_000), Some((128, 2)));
        assert_eq!(send_clock(0), None);
        assert_eq!(send_clock(1_000), None);
    }
}
