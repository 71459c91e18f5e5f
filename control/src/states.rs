// SPDX-License-Identifier: MIT OR Apache-2.0
//! The states that cross the control protocol: a device's state (IO controller role) and the
//! station's AR state (IO device role).
//!
//! They travel as the same words as ever (`"running"`, `"data"`, …: `procimg status --json`
//! and the scripts that read it depend on them), but every program matches on the enums, so a
//! renamed state fails to compile instead of reading as an unknown one. A state this program
//! does not know (from a newer server) reads as `Unknown` instead of failing the whole message.

use core::fmt;
use serde::{Deserialize, Serialize};

/// Where an IO device of the controller role is in its life.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DeviceState {
    /// Not wanted: the controller is OFFLINE.
    #[default]
    Offline,
    /// Deactivated by a client.
    Deactivated,
    /// Looked for by name (DCP Identify).
    Searching,
    /// Found by name, its IP address being set (DCP Set).
    SettingIp,
    /// Connect sent.
    Connecting,
    /// Its parameter records being written.
    Parameterizing,
    /// PrmEnd done; its ApplicationReady awaited.
    WaitingForApplicationReady,
    /// In data exchange.
    Running,
    /// Something failed; it is tried again after a back-off.
    Failed,
    /// A state this program does not know (from a newer server).
    #[serde(other)]
    Unknown,
}

impl DeviceState {
    /// Every state, in the order an enumeration numbers them (OPC UA's, from 0).
    pub const ALL: [DeviceState; 10] = [
        DeviceState::Offline,
        DeviceState::Deactivated,
        DeviceState::Searching,
        DeviceState::SettingIp,
        DeviceState::Connecting,
        DeviceState::Parameterizing,
        DeviceState::WaitingForApplicationReady,
        DeviceState::Running,
        DeviceState::Failed,
        DeviceState::Unknown,
    ];

    /// Its word in the protocol, the status report and messages.
    pub const fn as_str(self) -> &'static str {
        match self {
            DeviceState::Offline => "offline",
            DeviceState::Deactivated => "deactivated",
            DeviceState::Searching => "searching",
            DeviceState::SettingIp => "setting-ip",
            DeviceState::Connecting => "connecting",
            DeviceState::Parameterizing => "parameterizing",
            DeviceState::WaitingForApplicationReady => "waiting-for-application-ready",
            DeviceState::Running => "running",
            DeviceState::Failed => "failed",
            DeviceState::Unknown => "unknown",
        }
    }
}

impl fmt::Display for DeviceState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// Where the AR of a station (IO device role) with a PLC stands. A station without an AR has
/// none to report (`Option<ArState>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ArState {
    /// A PLC's Connect was accepted: a new AR, parameters may be written.
    Connected,
    /// The PLC's PrmEnd came (IO-Base END_OF_PARAM).
    Parameterized,
    /// The station's ApplicationReady went out; the PLC's confirmation is awaited.
    WaitingForApplicationReadyConfirm,
    /// The PLC confirmed it (IO-Base IN_DATA): data exchange.
    Data,
    /// A state this program does not know (from a newer server).
    #[serde(other)]
    Unknown,
}

impl ArState {
    /// Every state, in the order an enumeration numbers them (OPC UA's, from 1: 0 is no
    /// AR).
    pub const ALL: [ArState; 5] = [
        ArState::Connected,
        ArState::Parameterized,
        ArState::WaitingForApplicationReadyConfirm,
        ArState::Data,
        ArState::Unknown,
    ];

    /// Its word in the protocol, the status report and messages.
    pub const fn as_str(self) -> &'static str {
        match self {
            ArState::Connected => "connected",
            ArState::Parameterized => "parameterized",
            ArState::WaitingForApplicationReadyConfirm => "waiting-for-application-ready-confirm",
            ArState::Data => "data",
            ArState::Unknown => "unknown",
        }
    }
}

impl fmt::Display for ArState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DeviceReport;
    use crate::{decode, encode};

    const DEVICE_STATES: [(DeviceState, &str); 9] = [
        (DeviceState::Offline, "offline"),
        (DeviceState::Deactivated, "deactivated"),
        (DeviceState::Searching, "searching"),
        (DeviceState::SettingIp, "setting-ip"),
        (DeviceState::Connecting, "connecting"),
        (DeviceState::Parameterizing, "parameterizing"),
        (
            DeviceState::WaitingForApplicationReady,
            "waiting-for-application-ready",
        ),
        (DeviceState::Running, "running"),
        (DeviceState::Failed, "failed"),
    ];

    const AR_STATES: [(ArState, &str); 4] = [
        (ArState::Connected, "connected"),
        (ArState::Parameterized, "parameterized"),
        (
            ArState::WaitingForApplicationReadyConfirm,
            "waiting-for-application-ready-confirm",
        ),
        (ArState::Data, "data"),
    ];

    fn json(s: &impl Serialize) -> String {
        String::from_utf8(encode(s)).unwrap()
    }

    fn word_json(word: &str) -> String {
        format!("\"{word}\"")
    }

    #[test]
    fn device_states_keep_their_wire_names_both_ways() {
        for (state, word) in DEVICE_STATES {
            assert_eq!(json(&state), word_json(word));
            assert_eq!(decode::<DeviceState>(word_json(word).as_bytes()), Ok(state));
            assert_eq!(state.to_string(), word);
        }
    }

    #[test]
    fn ar_states_keep_their_wire_names_both_ways() {
        for (state, word) in AR_STATES {
            assert_eq!(json(&state), word_json(word));
            assert_eq!(decode::<ArState>(word_json(word).as_bytes()), Ok(state));
            assert_eq!(state.to_string(), word);
        }
    }

    #[test]
    fn the_enumerations_number_every_state_once() {
        // Every known state and Unknown, each once.
        let devices: Vec<DeviceState> = DEVICE_STATES.iter().map(|(s, _)| *s).collect();
        for (i, s) in DeviceState::ALL.iter().enumerate() {
            assert!(devices.contains(s) || *s == DeviceState::Unknown, "{s}");
            assert_eq!(DeviceState::ALL.iter().position(|x| x == s), Some(i));
        }
        assert_eq!(DeviceState::ALL.len(), DEVICE_STATES.len() + 1);
        let ars: Vec<ArState> = AR_STATES.iter().map(|(s, _)| *s).collect();
        for (i, s) in ArState::ALL.iter().enumerate() {
            assert!(ars.contains(s) || *s == ArState::Unknown, "{s}");
            assert_eq!(ArState::ALL.iter().position(|x| x == s), Some(i));
        }
        assert_eq!(ArState::ALL.len(), AR_STATES.len() + 1);
    }

    #[test]
    fn a_state_from_a_newer_server_reads_as_unknown() {
        let newer = word_json("hibernating");
        assert_eq!(
            decode::<DeviceState>(newer.as_bytes()),
            Ok(DeviceState::Unknown)
        );
        assert_eq!(decode::<ArState>(newer.as_bytes()), Ok(ArState::Unknown));
    }

    #[test]
    fn a_report_with_a_newer_state_still_reads() {
        let r: DeviceReport = decode(br#"{"name":"dio","state":"hibernating"}"#).unwrap();
        assert_eq!(r.state, DeviceState::Unknown);
    }
}
