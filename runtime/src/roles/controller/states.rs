// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device states the acyclic thread publishes for the control side: one atomic per
//! device, so that a status request never waits for the controller; and how the control
//! protocol names each of them.

use procimg_control as control;
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

    /// The state of device `d` as clients are told it (offline if there is no such device).
    pub fn reported(&self, d: usize) -> control::DeviceState {
        self.get(d).map_or(control::DeviceState::Offline, reported)
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

/// The protocol crate's device state as clients are told it: the one place the two enums
/// meet, so a state added on either side fails to compile here until it is given a name.
pub fn reported(state: DeviceState) -> control::DeviceState {
    match state {
        DeviceState::Offline => control::DeviceState::Offline,
        DeviceState::Deactivated => control::DeviceState::Deactivated,
        DeviceState::Searching => control::DeviceState::Searching,
        DeviceState::SettingIp => control::DeviceState::SettingIp,
        DeviceState::Connecting => control::DeviceState::Connecting,
        DeviceState::Parameterizing => control::DeviceState::Parameterizing,
        DeviceState::WaitingForApplicationReady => control::DeviceState::WaitingForApplicationReady,
        DeviceState::Running => control::DeviceState::Running,
        DeviceState::Failed => control::DeviceState::Failed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_device_state_keeps_its_place_and_is_told_as_a_known_state() {
        let states = DeviceStates::new(STATES.len());
        for (d, &state) in STATES.iter().enumerate() {
            states.set(d, state);
            assert_eq!(states.get(d), Some(state));
            assert_eq!(states.reported(d), reported(state));
            assert_ne!(reported(state), control::DeviceState::Unknown);
        }
        assert_eq!(states.reported(STATES.len()), control::DeviceState::Offline);
    }
}
