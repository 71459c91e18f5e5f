// SPDX-License-Identifier: MIT OR Apache-2.0
//! Logical addresses of the IO-Base services: from a `PNIO_ADDR` to the device, API, slot and
//! subslot a record job or an activation goes to, and back from a device or submodule to the
//! address an alarm or a confirmation names.
//!
//! A record job names "a module by one of its logical addresses"; any address inside the
//! submodule's range in the space that `IODataType` selects is taken, as `PNIO_device_activate`
//! takes any address of the device. A submodule without IO data (the DAP in slot 0, the
//! interface, the ports) is named by its diagnostic address, an input address of length 0,
//! as the manual has it: record jobs on it take `PNIO_IO_IN`.

use crate::iobase::types::{PNIO_ADDR, PNIO_ADDR_LOG, PNIO_IO_IN, PNIO_IO_OUT};
use procimg_client::access::{self, Space};
use procimg_client::{Layout, RecordTarget};
use procimg_shm_layout::{NO_ADDRESS, SubmoduleEntry};

/// Where an address leads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Resolved {
    /// Device index in the layout.
    pub device: u32,
    /// Submodule index in the layout.
    pub submodule: usize,
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
}

impl Resolved {
    /// The record `index` of this submodule.
    pub fn record(&self, index: u16) -> RecordTarget {
        RecordTarget {
            device: self.device,
            api: self.api,
            slot: self.slot,
            subslot: self.subslot,
            index,
        }
    }
}

/// The space an `IODataType` selects, if it is one.
pub(crate) fn space(io: u32) -> Option<Space> {
    match io {
        PNIO_IO_IN => Some(Space::Input),
        PNIO_IO_OUT => Some(Space::Output),
        _ => None,
    }
}

/// Resolves a logical address; `None` for another address type, an unknown space, or an
/// address no submodule has (IO-Base `PNIO_ERR_PRM_ADD`).
pub(crate) fn resolve(layout: &Layout, addr: &PNIO_ADDR) -> Option<Resolved> {
    if addr.AddrType != PNIO_ADDR_LOG {
        return None;
    }
    let space = space(addr.IODataType)?;
    let submodule = access::find_module(&layout.submodules, space, addr.addr())?;
    let e = &layout.submodules[submodule];
    Some(Resolved {
        device: u32::from(e.device),
        submodule,
        api: e.api,
        slot: e.slot,
        subslot: e.subslot,
    })
}

/// The address in words, for error texts ("I 20", "Q 3", or what is wrong with it).
pub(crate) fn describe(addr: &PNIO_ADDR) -> String {
    if addr.AddrType != PNIO_ADDR_LOG {
        return format!(
            "an address of type {} (the controller takes only PNIO_ADDR_LOG)",
            addr.AddrType
        );
    }
    match space(addr.IODataType) {
        Some(s) => format!("{s} {}", addr.addr()),
        None => format!(
            "address {} with IODataType {} (neither PNIO_IO_IN nor PNIO_IO_OUT)",
            addr.addr(),
            addr.IODataType
        ),
    }
}

/// The first address of a submodule: its inputs, else its outputs, else its diagnostic
/// address.
fn submodule_address(e: &SubmoduleEntry) -> Option<PNIO_ADDR> {
    if e.input_length > 0 && e.input_address != NO_ADDRESS {
        Some(PNIO_ADDR::logical(PNIO_IO_IN, e.input_address))
    } else if e.output_length > 0 && e.output_address != NO_ADDRESS {
        Some(PNIO_ADDR::logical(PNIO_IO_OUT, e.output_address))
    } else {
        e.diagnostic_address()
            .map(|a| PNIO_ADDR::logical(PNIO_IO_IN, a))
    }
}

/// The address that stands for device `device` (station failure and return, the manual's
/// "base (diagnostic) address" of the device): the diagnostic address of its device access
/// point (the data-less submodule in slot 0 with the lowest subslot); for a device
/// configured without its DAP, its lowest input address, else its lowest output address.
/// A device with none of these is named by `PNIO_IO_IN` and 0xFFFFFFFF.
pub(crate) fn device_address(layout: &Layout, device: u32) -> PNIO_ADDR {
    let subs = || {
        layout
            .submodules_of(device as usize)
            .filter_map(|s| layout.submodules.get(s))
    };
    let dap = subs()
        .filter(|e| e.slot == 0)
        .filter_map(|e| e.diagnostic_address().map(|a| (e.subslot, a)))
        .min();
    if let Some((_, a)) = dap {
        return PNIO_ADDR::logical(PNIO_IO_IN, a);
    }
    let lowest_in = subs()
        .filter(|e| e.input_length > 0 && e.input_address != NO_ADDRESS)
        .map(|e| e.input_address)
        .min();
    let lowest_out = subs()
        .filter(|e| e.output_length > 0 && e.output_address != NO_ADDRESS)
        .map(|e| e.output_address)
        .min();
    match (lowest_in, lowest_out) {
        (Some(a), _) => PNIO_ADDR::logical(PNIO_IO_IN, a),
        (None, Some(a)) => PNIO_ADDR::logical(PNIO_IO_OUT, a),
        (None, None) => PNIO_ADDR::logical(PNIO_IO_IN, NO_ADDRESS),
    }
}

/// The address of the module an alarm comes from: the submodule's own address (its
/// diagnostic address if it has no IO data); for a submodule the layout does not have, the
/// first address of another submodule in the same slot; failing that, the device's
/// address.
pub(crate) fn module_address(
    layout: &Layout,
    device: u32,
    api: u32,
    slot: u16,
    subslot: u16,
) -> PNIO_ADDR {
    let subs: Vec<&SubmoduleEntry> = layout
        .submodules_of(device as usize)
        .filter_map(|s| layout.submodules.get(s))
        .collect();
    let own = subs
        .iter()
        .find(|e| e.api == api && e.slot == slot && e.subslot == subslot)
        .and_then(|e| submodule_address(e));
    let same_slot = || {
        subs.iter()
            .filter(|e| e.api == api && e.slot == slot)
            .find_map(|e| submodule_address(e))
    };
    own.or_else(same_slot)
        .unwrap_or_else(|| device_address(layout, device))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::iobase::types::PNIO_ADDR_GEO;
    use procimg_shm_layout::{DeviceEntry, LayoutHeader, STATION_NAME_LEN};

    fn device(name: &str, first: u32, count: u32) -> DeviceEntry {
        let mut station_name = [0u8; STATION_NAME_LEN];
        station_name[..name.len()].copy_from_slice(name.as_bytes());
        DeviceEntry {
            station_name,
            vendor_id: 0x0493,
            device_id: 1,
            instance: 1,
            reduction_ratio: 1,
            ip_address: [192, 168, 0, 11],
            first_submodule: first,
            submodule_count: count,
            watchdog_factor: 3,
            reserved: 0,
        }
    }

    fn sub(
        device: u16,
        slot: u16,
        input: Option<(u32, u16)>,
        output: Option<(u32, u16)>,
    ) -> SubmoduleEntry {
        let mut e = SubmoduleEntry::EMPTY;
        e.device = device;
        e.slot = slot;
        e.subslot = 1;
        e.module_ident = 0x20 + u32::from(slot);
        e.submodule_ident = 1;
        if let Some((a, l)) = input {
            e.input_address = a;
            e.input_length = l;
        }
        if let Some((a, l)) = output {
            e.output_address = a;
            e.output_length = l;
        }
        e
    }

    /// The demo's IO system: echo (I 0..15, Q 0..15, IRT data), counter (I 16..19), dio
    /// (I 20..21, Q 16..17), each with a data-less DAP in slot 0 (diagnostic addresses I 22,
    /// 23, 24).
    pub(crate) fn demo_layout() -> Layout {
        let mut echo = sub(0, 1, Some((0, 16)), Some((0, 16)));
        echo.rt_class = procimg_shm_layout::RT_CLASS_3;
        Layout {
            header: LayoutHeader {
                cycle_ns: 1_000_000,
                device_count: 3,
                submodule_count: 7,
                ..LayoutHeader::default()
            },
            devices: vec![
                device("echo", 0, 2),
                device("counter", 2, 2),
                device("dio", 4, 3),
            ],
            submodules: vec![
                sub(0, 0, Some((22, 0)), None),
                echo,
                sub(1, 0, Some((23, 0)), None),
                sub(1, 1, Some((16, 4)), None),
                sub(2, 0, Some((24, 0)), None),
                sub(2, 1, Some((20, 2)), None),
                sub(2, 2, None, Some((16, 2))),
            ],
        }
    }

    #[test]
    fn any_address_inside_a_submodule_resolves_in_the_space_iodatatype_says() {
        let l = demo_layout();
        let r = resolve(&l, &PNIO_ADDR::logical(PNIO_IO_IN, 21)).expect("I 21");
        assert_eq!((r.device, r.slot, r.subslot, r.submodule), (2, 1, 1, 5));
        let r = resolve(&l, &PNIO_ADDR::logical(PNIO_IO_OUT, 17)).expect("Q 17");
        assert_eq!((r.device, r.slot), (2, 2));
        let r = resolve(&l, &PNIO_ADDR::logical(PNIO_IO_OUT, 15)).expect("Q 15");
        assert_eq!((r.device, r.slot), (0, 1));
        assert_eq!(r.record(0xAFF0).index, 0xAFF0);
    }

    #[test]
    fn gaps_other_spaces_and_address_types_do_not_resolve() {
        let l = demo_layout();
        assert_eq!(resolve(&l, &PNIO_ADDR::logical(PNIO_IO_IN, 25)), None);
        assert_eq!(resolve(&l, &PNIO_ADDR::logical(PNIO_IO_OUT, 18)), None);
        // A diagnostic address is an input address.
        assert_eq!(resolve(&l, &PNIO_ADDR::logical(PNIO_IO_OUT, 22)), None);
        assert_eq!(resolve(&l, &PNIO_ADDR::logical(2, 0)), None);
        let mut geo = PNIO_ADDR::logical(PNIO_IO_IN, 0);
        geo.AddrType = PNIO_ADDR_GEO;
        assert_eq!(resolve(&l, &geo), None);
        assert!(describe(&geo).contains("PNIO_ADDR_LOG"));
        assert_eq!(describe(&PNIO_ADDR::logical(PNIO_IO_OUT, 7)), "Q 7");
    }

    #[test]
    fn a_dataless_submodule_resolves_by_its_diagnostic_address() {
        let l = demo_layout();
        let r = resolve(&l, &PNIO_ADDR::logical(PNIO_IO_IN, 23)).expect("I 23");
        assert_eq!((r.device, r.slot, r.subslot, r.submodule), (1, 0, 1, 2));
    }

    #[test]
    fn devices_are_named_by_their_dap_and_modules_by_their_first_address() {
        let l = demo_layout();
        let a = device_address(&l, 2);
        assert_eq!((a.IODataType, a.addr()), (PNIO_IO_IN, 24));
        let a = device_address(&l, 1);
        assert_eq!((a.IODataType, a.addr()), (PNIO_IO_IN, 23));
        // The output module of dio, and its data-less DAP.
        let a = module_address(&l, 2, 0, 2, 1);
        assert_eq!((a.IODataType, a.addr()), (PNIO_IO_OUT, 16));
        let a = module_address(&l, 2, 0, 0, 1);
        assert_eq!((a.IODataType, a.addr()), (PNIO_IO_IN, 24));
        // A submodule the layout does not have: another one in its slot names it.
        let a = module_address(&l, 2, 0, 1, 2);
        assert_eq!((a.IODataType, a.addr()), (PNIO_IO_IN, 20));
        // A device configured without its DAP: its lowest input address.
        let mut l = l;
        l.submodules[4].input_address = NO_ADDRESS;
        let a = device_address(&l, 2);
        assert_eq!((a.IODataType, a.addr()), (PNIO_IO_IN, 20));
        // A device index the layout does not have.
        let a = device_address(&l, 9);
        assert_eq!(a.addr(), NO_ADDRESS);
    }
}
