// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device states the acyclic thread publishes for the control side: one atomic per
//! device, so that a status request never waits for the controller.

use procimg_profinet::controller::DeviceState;
use std::sync::atomic::{AtomicU8, Ordering};

/// Every state, in the order of their stored index.
const STATES: [DeviceState; 9] = [
    DeviceState::Offline,
    DeviceState::Deactivated,
    DeviceState::Searching,
    DeviceState::SettingIp,
    DeviceState::Connecting,
    DeviceState::Parameterizing,
    DeviceState::WaitingForApplicationReady,
    DeviceState::Running,
    DeviceState::Failed,
];

/// The state of every device.
pub struct DeviceStates {
    states: Box<[AtomicU8]>,
}

impl DeviceStates {
    /// `n` devices, all offline.
    pub fn new(n: usize) -> DeviceStates {
        DeviceStates {
            states: (0..n).map(|_| AtomicU8::new(0)).collect(),
        }
    }

    pub(super) fn set(&self, d: usize, s: DeviceState) {
        if let (Some(a), Some(i)) = (self.states.get(d), STATES.iter().position(|&x| x == s)) {
            // At most 9 states: the index fits.
            a.store(i as u8, Ordering::Release);
        }
    }

    /// The state of device `d`.
    pub fn get(&self, d: usize) -> Option<DeviceState> {
        let i = self.states.get(d)?.load(Ordering::Acquire) as usize;
        STATES.get(i).copied()
    }

    /// Number of devices.
    pub fn len(&self) -> usize {
        self.states.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// Whether no device has a connection (each is offline or deactivated).
    pub fn all_released(&self) -> bool {
        (0..self.len()).all(|d| {
            matches!(
                self.get(d),
                Some(DeviceState::Offline | DeviceState::Deactivated)
            )
        })
    }
}
