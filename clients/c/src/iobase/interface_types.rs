// SPDX-License-Identifier: MIT OR Apache-2.0
//! Rust mirrors of the C types of the controller's own interface in `pniousrx.h` (PN
//! Driver's `PNIO_interface_*`), with the C names; laid out as [`super::types`] says.
#![allow(non_camel_case_types, non_snake_case)]

pub use super::types::{
    PNIO_CBE_PRM_REMA_READ_IND, PNIO_CBE_PRM_SET_ADDR_CONF, PNIO_SET_IP_MODE,
    PNIO_SET_IP_NOS_MODE_TYPE, PNIO_SET_NOS_MODE,
};
use super::types::{PNIO_UINT8, PNIO_UINT16};

/// `PNIO_BOOL`: PN Driver's boolean (its `LSA_BOOL`, one byte).
pub type PNIO_BOOL = PNIO_UINT8;
/// `PNIO_FALSE`.
pub const PNIO_FALSE: PNIO_BOOL = 0;
/// `PNIO_TRUE`.
pub const PNIO_TRUE: PNIO_BOOL = 1;

/// `PNIO_IPv4`: an IP suite, bytes in dotted order.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PNIO_IPv4 {
    /// The address.
    pub IpAddress: [PNIO_UINT8; 4],
    /// The netmask.
    pub NetMask: [PNIO_UINT8; 4],
    /// The gateway (all zero: none).
    pub Gateway: [PNIO_UINT8; 4],
    /// Kept across a restart.
    pub Remanent: PNIO_BOOL,
}

/// `PNIO_NOS`: a NameOfStation, `Length` bytes of `Nos`.
#[repr(C, align(4))]
#[derive(Clone, Copy, Debug)]
pub struct PNIO_NOS {
    /// The name.
    pub Nos: [PNIO_UINT8; 256],
    /// Its length.
    pub Length: PNIO_UINT16,
    /// Kept across a restart.
    pub Remanent: PNIO_BOOL,
}
