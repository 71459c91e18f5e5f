// SPDX-License-Identifier: MIT OR Apache-2.0
//! A faulty network between the devices and the controller, for tests that lose, corrupt or
//! repeat what the devices send ([`World::intercept`](super::World::intercept)).

use procimg_profinet::wire::rt::FrameIdClass;

/// The kind of a message a device sends toward the controller.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A UDP datagram.
    Datagram,
    /// An acyclic frame (DCP, alarm) or one without a FrameID.
    Acyclic,
    /// A cyclic (RT) frame.
    Cyclic,
}

impl Kind {
    /// The kind of an Ethernet frame, tagged or not, by its FrameID.
    pub fn of_frame(frame: &[u8]) -> Kind {
        let at = if frame.get(12..14) == Some(&[0x81, 0x00]) {
            16
        } else {
            12
        };
        let id = frame
            .get(at + 2..at + 4)
            .map_or(0, |b| u16::from_be_bytes([b[0], b[1]]));
        if FrameIdClass::of(id).is_cyclic() {
            Kind::Cyclic
        } else {
            Kind::Acyclic
        }
    }
}

/// A message a device sends toward the controller, handed to an [`Interceptor`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Intercepted {
    /// The sending device.
    pub device: usize,
    /// What it is.
    pub kind: Kind,
    /// The frame, or the datagram's payload.
    pub bytes: Vec<u8>,
}

/// A faulty network between the devices and the controller: given each message a device
/// sends toward the controller, it returns what arrives instead (nothing: dropped; changed
/// bytes: corrupted; two: repeated).
pub type Interceptor = Box<dyn FnMut(Intercepted) -> Vec<Vec<u8>>>;
