// SPDX-License-Identifier: MIT OR Apache-2.0
//! The structs of `pniousrd.h`, mirrored as the [module above](super) says.

#![allow(non_camel_case_types, non_snake_case)]

use super::*;
use crate::iobase::types::{PNIO_ADDR_GEO, PNIO_ADDR_TYPE, PNIO_IO_TYPE};
use crate::iobase::types::{PNIO_UINT8, PNIO_UINT16, PNIO_UINT32};
use core::ffi::c_void;

/// The geographical address of `PNIO_DEV_ADDR::u` (an unnamed struct in C).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_DEV_ADDR_Geo {
    /// Reserved.
    pub RESERVED1: [PNIO_UINT32; 2],
    /// Slot.
    pub Slot: PNIO_UINT32,
    /// Subslot.
    pub Subslot: PNIO_UINT32,
    /// Reserved.
    pub RESERVED2: [PNIO_UINT32; 1],
}

/// `PNIO_DEV_ADDR::u`.
#[repr(C)]
#[derive(Clone, Copy)]
pub union PNIO_DEV_ADDR_u {
    /// Reserved.
    pub RESERVED: PNIO_UINT32,
    /// The geographical address.
    pub Geo: PNIO_DEV_ADDR_Geo,
}

/// `PNIO_DEV_ADDR`: a device address, always geographical.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct PNIO_DEV_ADDR {
    /// `PNIO_ADDR_GEO`.
    pub AddrType: PNIO_ADDR_TYPE,
    /// `PNIO_IO_IN` or `PNIO_IO_OUT`.
    pub IODataType: PNIO_IO_TYPE,
    /// The slot and subslot.
    pub u: PNIO_DEV_ADDR_u,
}

impl PNIO_DEV_ADDR {
    /// The geographical address of slot and subslot, for data of `IODataType`.
    pub fn geo(IODataType: PNIO_IO_TYPE, Slot: u32, Subslot: u32) -> PNIO_DEV_ADDR {
        PNIO_DEV_ADDR {
            AddrType: PNIO_ADDR_GEO,
            IODataType,
            u: PNIO_DEV_ADDR_u {
                Geo: PNIO_DEV_ADDR_Geo {
                    Slot,
                    Subslot,
                    ..PNIO_DEV_ADDR_Geo::default()
                },
            },
        }
    }

    /// The geographical address (`u.Geo`).
    pub fn geo_addr(&self) -> PNIO_DEV_ADDR_Geo {
        // SAFETY: every bit pattern is a valid `PNIO_DEV_ADDR_Geo`, and `Geo` spans the whole
        // union, all of it initialised (built by `geo` or read from C memory of its size).
        unsafe { self.u.Geo }
    }
}

impl core::fmt::Debug for PNIO_DEV_ADDR {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let geo = self.geo_addr();
        f.debug_struct("PNIO_DEV_ADDR")
            .field("AddrType", &self.AddrType)
            .field("IODataType", &self.IODataType)
            .field("Slot", &geo.Slot)
            .field("Subslot", &geo.Subslot)
            .finish()
    }
}

/// `PNIO_ANNOTATION`: what the PLC's engineering shows of the device.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_ANNOTATION {
    /// ProductFamily, NUL-terminated.
    pub deviceType: [PNIO_UINT8; MAX_DEVICE_TYPE_LENGTH as usize + 1],
    /// OrderNumber, NUL-terminated.
    pub orderId: [PNIO_UINT8; MAX_ORDER_ID_LENGTH as usize + 1],
    /// HardwareRelease.
    pub hwRevision: PNIO_UINT16,
    /// The prefix of SoftwareRelease (`'V'` of "V1.2.3").
    pub swRevisionPrefix: PNIO_UINT8,
    /// The first number of SoftwareRelease.
    pub swRevision1: PNIO_UINT16,
    /// The second.
    pub swRevision2: PNIO_UINT16,
    /// The third.
    pub swRevision3: PNIO_UINT16,
}

/// `PNIO_UUID_TYPE`: a UUID, passed by value.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_UUID_TYPE {
    /// time_low.
    pub TimeLow: PNIO_UINT32,
    /// time_mid.
    pub TimeMid: PNIO_UINT16,
    /// time_hi_and_version.
    pub TimeHiAndVersion: PNIO_UINT16,
    /// clock_seq_hi_and_reserved.
    pub ClockSeqHiAndReserved: PNIO_UINT8,
    /// clock_seq_low.
    pub ClockSeqLow: PNIO_UINT8,
    /// node.
    pub Node: [PNIO_UINT8; 6],
}

/// `PNIO_IOCS_TYPE`: a submodule in an IOCR.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IOCS_TYPE {
    /// Slot.
    pub SlotNum: PNIO_UINT32,
    /// Subslot.
    pub SubslotNum: PNIO_UINT32,
    /// Reserved.
    pub reserved: PNIO_UINT32,
}

/// `PNIO_IOCR_TYPE`: one input or output frame of an AR.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_IOCR_TYPE {
    /// SendClock × 31.25 µs × ReductioFactor.
    pub CycleTime: PNIO_UINT32,
    /// `PNIO_IOCR_TYPE_*`.
    pub Direction: PNIO_IOCR_TYPE_ENUM,
    /// `PNIO_IOCR_PROP_*`.
    pub IOCRProperties: PNIO_IOCR_PROP_ENUM,
    /// Send clock in 31.25 µs units.
    pub SendClock: PNIO_UINT32,
    /// Sent every ReductioFactor send clocks.
    pub ReductioFactor: PNIO_UINT32,
    /// Phase.
    pub Phase: PNIO_UINT32,
    /// Elements of `pIoCsList`.
    pub NumOfIoCs: PNIO_UINT32,
    /// The submodules in this frame.
    pub pIoCsList: *mut PNIO_IOCS_TYPE,
    /// Reserved.
    pub reserved: [PNIO_UINT32; 3],
}

/// `PNIO_SUBMOD_TYPE`: a submodule of an AR.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_SUBMOD_TYPE {
    /// Slot.
    pub SlotNum: PNIO_UINT32,
    /// Subslot.
    pub SubSlotNum: PNIO_UINT32,
    /// `PNIO_SUB_PROP_TYPE_*` under `PNIO_SUB_PROP_TYPE_MASK`.
    pub SubMProperties: PNIO_UINT32,
    /// SubmoduleIdentNumber.
    pub SubMIdent: PNIO_UINT32,
    /// Input data bytes (the device sends).
    pub InDatLen: PNIO_UINT32,
    /// Bytes of the device's IOPS of the inputs.
    pub InIopsLen: PNIO_UINT32,
    /// Bytes of the PLC's IOCS of the inputs.
    pub InIocsLen: PNIO_UINT32,
    /// Output data bytes (the device receives).
    pub OutDatLen: PNIO_UINT32,
    /// Bytes of the PLC's IOPS of the outputs.
    pub OutIopsLen: PNIO_UINT32,
    /// Bytes of the device's IOCS of the outputs.
    pub OutIocsLen: PNIO_UINT32,
    /// Reserved.
    pub reserved: [PNIO_UINT32; 8],
}

/// `PNIO_MODULE_TYPE`: a module of an AR. C also names `Api` as the manual does, `API`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_MODULE_TYPE {
    /// API.
    pub Api: PNIO_UINT32,
    /// Slot.
    pub SlotNum: PNIO_UINT32,
    /// Elements of `pSubList`.
    pub NumOfSubmod: PNIO_UINT32,
    /// Reserved, 0.
    pub ModProperties: PNIO_UINT32,
    /// ModuleIdentNumber.
    pub ModIdent: PNIO_UINT32,
    /// Its submodules.
    pub pSubList: *mut PNIO_SUBMOD_TYPE,
}

/// `PNIO_AR_TYPE`: an AR. C also names `pNextAr` as the manual does, `pReserved`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_AR_TYPE {
    /// Don't care.
    pub pNextAr: *mut c_void,
    /// The AR's number.
    pub ArNumber: PNIO_UINT16,
    /// Grows with every AR.
    pub SessionKey: PNIO_UINT16,
    /// Elements of `pIoCrList`.
    pub NumOfIocr: PNIO_UINT32,
    /// Its IOCRs.
    pub pIoCrList: *mut PNIO_IOCR_TYPE,
    /// Elements of `pModList`.
    pub NumOfMod: PNIO_UINT32,
    /// Its modules.
    pub pModList: *mut PNIO_MODULE_TYPE,
}

/// `PNIO_LIST_ENTRY_TYPE`: a link of a doubly linked list; a head whose `Flink` is NULL or
/// the head itself is an empty list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_LIST_ENTRY_TYPE {
    /// Next.
    pub Flink: *mut PNIO_LIST_ENTRY_TYPE,
    /// Previous.
    pub Blink: *mut PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_LIST_TYPE`: the submodules that are not ready.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_LIST_TYPE {
    /// Of `PNIO_APPL_READY_AP_TYPE`.
    pub ap_list: PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_AP_TYPE`: an API of that list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_AP_TYPE {
    /// The list entry (first: a pointer to it is one to the element).
    pub link: PNIO_LIST_ENTRY_TYPE,
    /// API.
    pub api: PNIO_UINT32,
    /// Of `PNIO_APPL_READY_MODULE_TYPE`.
    pub module_list: PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_MODULE_TYPE`: a slot of that list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_MODULE_TYPE {
    /// The list entry.
    pub link: PNIO_LIST_ENTRY_TYPE,
    /// Slot.
    pub slot_nr: PNIO_UINT16,
    /// Of `PNIO_APPL_READY_SUBMODULE_TYPE`.
    pub submodule_list: PNIO_LIST_ENTRY_TYPE,
}

/// `PNIO_APPL_READY_SUBMODULE_TYPE`: a subslot of that list.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_APPL_READY_SUBMODULE_TYPE {
    /// The list entry.
    pub link: PNIO_LIST_ENTRY_TYPE,
    /// Subslot.
    pub subslot_nr: PNIO_UINT16,
}

/// `PNIO_BLOCK_HEADER`: the header of an I&M record, a plain struct of 6 bytes (not
/// `ATTR_PACKED`, so that the records keep their wire layout).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_BLOCK_HEADER {
    /// 0x0020 + n for I&Mn.
    pub BlockType: PNIO_UINT16,
    /// Bytes after BlockType and BlockLength.
    pub BlockLength: PNIO_UINT16,
    /// 1.
    pub BlockVersionHigh: PNIO_UINT8,
    /// 0.
    pub BlockVersionLow: PNIO_UINT8,
}

/// `PNIO_IM0_TYPE`: I&M0 (record 0xAFF0); 16-bit fields big-endian.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IM0_TYPE {
    /// BlockType 0x0020.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// VendorID, high byte.
    pub VendorIDHigh: PNIO_UINT8,
    /// VendorID, low byte.
    pub VendorIDLow: PNIO_UINT8,
    /// Order number, blank-padded.
    pub OrderID: [PNIO_UINT8; 20],
    /// Serial number, blank-padded.
    pub IM_Serial_Number: [PNIO_UINT8; 16],
    /// Hardware revision.
    pub IM_Hardware_Revision: PNIO_UINT16,
    /// Prefix, functional, bug fix, internal.
    pub IM_Software_Revision: [PNIO_UINT8; 4],
    /// Revision counter (after 0xFFFF comes 1).
    pub IM_Revision_Counter: PNIO_UINT16,
    /// Profile (0xF600: generic device).
    pub IM_Profile_ID: PNIO_UINT16,
    /// Profile specific type.
    pub IM_Profile_Specific_Type: PNIO_UINT16,
    /// 1.
    pub IM_Version_Major: PNIO_UINT8,
    /// 1.
    pub IM_Version_Minor: PNIO_UINT8,
    /// Bit n: I&Mn supported.
    pub IM_Supported: PNIO_UINT16,
}

/// `PNIO_IM1_TYPE`: I&M1 (record 0xAFF1).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_IM1_TYPE {
    /// BlockType 0x0021.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// Tag function.
    pub IM_Tag_Function: [PNIO_UINT8; 32],
    /// Tag location.
    pub IM_Tag_Location: [PNIO_UINT8; 22],
}

/// `PNIO_IM2_TYPE`: I&M2 (record 0xAFF2).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IM2_TYPE {
    /// BlockType 0x0022.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// "YYYY-MM-DD hh:mm".
    pub IM_Date: [PNIO_UINT8; 16],
}

/// `PNIO_IM3_TYPE`: I&M3 (record 0xAFF3).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_IM3_TYPE {
    /// BlockType 0x0023.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// Descriptor.
    pub IM_Descriptor: [PNIO_UINT8; 54],
}

/// `PNIO_IM4_TYPE`: I&M4 (record 0xAFF4).
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PNIO_IM4_TYPE {
    /// BlockType 0x0024.
    pub BlockHeader: PNIO_BLOCK_HEADER,
    /// Signature.
    pub IM_Signature: [PNIO_UINT8; 54],
}
