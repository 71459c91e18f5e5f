// SPDX-License-Identifier: MIT OR Apache-2.0
//! The shared-memory layout of a procimg process image.
//!
//! `procimgd` publishes three kinds of shared-memory samples through iceoryx2, all described
//! by the `#[repr(C)]` types of this crate; the Rust client and the C header
//! (`include/procimg_shm.h`, generated from this source) read them in place:
//!
//! * the **layout** sample (one per server generation, kept as history): a [`LayoutHeader`]
//!   followed by the [`DeviceEntry`] and [`SubmoduleEntry`] tables;
//! * one **input image** sample per cycle: an [`ImageHeader`] (with this cycle's
//!   [`CycleInfo`]) as iceoryx2 user header, and a payload holding the input data, one
//!   [`SubmoduleStatus`] per submodule and a mirror of the outputs as last sent (in the
//!   controller role, each device's output frame as last sent, [`MirrorArea`]);
//! * **output** samples from clients: an [`OutputHeader`] and a payload holding the output
//!   data and one [`ClientSubmoduleStatus`] per submodule.
//!
//! [`ImageLayout`] computes where each region lies, the same way on every side. Nothing here
//! does I/O; all offsets are in bytes from the start of a payload.
#![no_std]
#![deny(unsafe_code)]

// Always: texts for people (`SubmoduleDesc::address_text`) are built without the control
// protocol too, as the configuration crate uses the layout's plain types alone.
extern crate alloc;

/// The newest image's cycle info beside its word (the busy path): not in the C header.
///
/// cbindgen:ignore
pub mod cycle_record;
pub mod events;
/// The futex words of the handshake: used through the client library, not in the C header.
///
/// cbindgen:ignore
pub mod handshake;
#[cfg(feature = "std")]
#[allow(unsafe_code)]
pub mod handshake_map;
mod hash;
mod image_layout;
mod line;
#[cfg(feature = "std")]
pub mod maps;
#[cfg(feature = "std")]
#[allow(unsafe_code)]
pub mod os;
/// The busy path's hold marks on input images: used through the client library, not in the
/// C header.
///
/// cbindgen:ignore
pub mod pins;
/// The busy path's places of output samples: used through the client library, not in the C
/// header.
///
/// cbindgen:ignore
pub mod posts;
/// Samples named by their place in a segment (the busy path): not in the C header.
///
/// cbindgen:ignore
pub mod segment;
#[cfg(feature = "std")]
pub mod share;
mod table_codec;
mod types;

pub use hash::layout_hash;
pub use image_layout::{ImageLayout, LayoutError, MAX_SUBMODULE_DATA_LEN, MirrorArea};
pub use table_codec::{decode_device, decode_submodule, encode_tables};
pub use types::*;
