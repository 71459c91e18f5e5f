// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg io watch`: a line whenever the bytes at an address, their provider and consumer
//! status (IOPS, IOCS), a force on them or the state of their device change — with the wall
//! time and the cycle number, as text or (`--json`) one JSON object per line.
//!
//! The bytes and the status come from the newest image, looked at every few milliseconds;
//! the device's state from the server's notifications (a device's state in the controller
//! role, the PLC's AR in the device role), and from its status report, which is also read
//! once a second for the forces.

use crate::text::hex;
use procimg_client::access::resolve_read;
use procimg_client::{
    ArState, Client, DeviceState, Ioxs, Notification, ServiceOptions, Services, Space, StatusReport,
};
use serde_json::json;
use std::fmt;
use std::time::{Duration, Instant, SystemTime};

/// What `procimg io watch` was asked.
pub struct Watch {
    /// Logical address.
    pub address: u32,
    /// Bytes to show (default: to the end of the submodule).
    pub length: Option<usize>,
    /// The output (Q) space.
    pub output: bool,
    /// Stop after this many lines.
    pub count: Option<u64>,
    /// JSON lines.
    pub json: bool,
}

/// How often the image is looked at.
const LOOK_EVERY: Duration = Duration::from_millis(2);
/// How often the status report is read (forces; the state, should a notification be lost).
const STATUS_EVERY: Duration = Duration::from_secs(1);

/// Everything a line shows but the time and the cycle.
#[derive(Clone, Debug, PartialEq, Eq)]
struct Seen {
    data: Vec<u8>,
    iops: Ioxs,
    iocs: Ioxs,
    forced: bool,
    state: Watched,
}

/// The state a line shows: of the device (controller role) or of the PLC's AR (device role).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Watched {
    /// Neither the status report nor a notification told it yet.
    NotKnown,
    /// The device's state (controller role).
    Device(DeviceState),
    /// The PLC's AR's state (device role).
    Ar(ArState),
    /// The device role without an AR.
    NoAr,
}

impl Watched {
    /// Its word in a JSON line: none while it is not known.
    fn json_word(self) -> String {
        match self {
            Watched::NotKnown => String::new(),
            known => known.to_string(),
        }
    }
}

impl fmt::Display for Watched {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Watched::NotKnown => f.write_str("?"),
            Watched::Device(s) => s.fmt(f),
            Watched::Ar(s) => s.fmt(f),
            Watched::NoAr => f.write_str("no AR"),
        }
    }
}

/// Watches until `count` lines (or forever).
pub fn watch(client: &mut Client, w: &Watch) -> anyhow::Result<()> {
    let space = if w.output {
        Space::Output
    } else {
        Space::Input
    };
    let at = resolve_read(
        &client.layout().submodules,
        space,
        w.address,
        usize::MAX,
        true,
    )?;
    let entry = client.layout().submodules[at.submodule];
    let device = entry.device;
    let device_name = client.layout().device_name(device as usize).to_owned();
    let length = w.length.unwrap_or(at.data_len).min(at.data_len);
    // In the device role a line says which of the PLC's data it shows.
    let label = if client.is_device() {
        format!("{device_name} ({})", crate::text::space_words(true, space))
    } else {
        device_name.clone()
    };
    // Without the notification service the status report keeps the state, once a second.
    let mut services =
        Services::open(client.instance(), ServiceOptions::new("procimg io watch")).ok();
    let mut status = client.control().status().ok();
    let mut state = status
        .as_ref()
        .map_or(Watched::NotKnown, |s| state_of(s, device));
    let mut status_at = Instant::now();
    let mut last: Option<Seen> = None;
    let mut lines = 0;
    let mut buf = vec![0u8; length];
    loop {
        if status_at.elapsed() >= STATUS_EVERY {
            status = client.control().status().ok();
            if services.is_none()
                && let Some(s) = &status
            {
                state = state_of(s, device);
            }
            status_at = Instant::now();
        }
        while let Some(n) = services.as_mut().and_then(Services::try_next) {
            if let Some(s) = state_change(&n, device) {
                state = s;
            }
        }
        let n = if w.output {
            client.output_data_read(w.address, &mut buf)?.len
        } else {
            client.data_read(w.address, &mut buf, Ioxs::Good)?.len
        };
        let (iops, iocs) = match client.newest_status(at.submodule)? {
            Some(x) if w.output => (x.output_local, x.output_remote),
            Some(x) => (x.input_remote, x.input_local),
            None => (Ioxs::Bad, Ioxs::Bad),
        };
        let now = Seen {
            data: buf[..n.min(length)].to_vec(),
            iops,
            iocs,
            forced: status.as_ref().is_some_and(|s| {
                s.forces_in(space, w.address, length as u32)
                    .next()
                    .is_some()
            }),
            state,
        };
        if last.as_ref() != Some(&now) {
            let cycle = client.cycle_info().map_or(0, |c| c.cycle_number);
            let time = humantime::format_rfc3339_millis(SystemTime::now()).to_string();
            if w.json {
                println!("{}", line_json(&time, cycle, w, &device_name, &now));
            } else {
                println!("{}", line_text(&time, cycle, &label, &now));
            }
            last = Some(now);
            lines += 1;
            if w.count.is_some_and(|c| lines >= c) {
                return Ok(());
            }
        }
        std::thread::sleep(LOOK_EVERY);
    }
}

/// The state of device `device` in `status`: the device's (controller role) or the PLC's
/// AR (device role).
fn state_of(status: &StatusReport, device: u16) -> Watched {
    if let Some(station) = &status.station {
        return station
            .ar
            .as_ref()
            .map_or(Watched::NoAr, |a| Watched::Ar(a.state));
    }
    status
        .devices
        .get(usize::from(device))
        .map_or(Watched::NotKnown, |d| Watched::Device(d.state))
}

/// The new state of device `device` that notification `n` tells, if it tells one.
fn state_change(n: &Notification, device: u16) -> Option<Watched> {
    match n {
        Notification::DeviceState {
            device: d, state, ..
        } if *d == u32::from(device) => Some(Watched::Device(*state)),
        Notification::StationAr { state, .. } => Some(Watched::Ar(*state)),
        Notification::StationArEnded { .. } => Some(Watched::NoAr),
        _ => None,
    }
}

fn ioxs_name(x: Ioxs) -> &'static str {
    match x {
        Ioxs::Good => "GOOD",
        Ioxs::Bad => "BAD",
    }
}

fn line_text(time: &str, cycle: u64, device: &str, s: &Seen) -> String {
    format!(
        "{time}  cycle {cycle:>9}  {}  IOPS {} IOCS {}  {device}: {}{}",
        hex(&s.data),
        ioxs_name(s.iops),
        ioxs_name(s.iocs),
        s.state,
        if s.forced { "  FORCED" } else { "" }
    )
}

fn line_json(time: &str, cycle: u64, w: &Watch, device: &str, s: &Seen) -> serde_json::Value {
    json!({
        "time": time,
        "cycle": cycle,
        "space": if w.output { "output" } else { "input" },
        "address": w.address,
        "data": hex(&s.data).replace(' ', ""),
        "iops": ioxs_name(s.iops),
        "iocs": ioxs_name(s.iocs),
        "device": device,
        "state": s.state.json_word(),
        "forced": s.forced,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_says_data_status_state_and_force() {
        let s = Seen {
            data: vec![1, 0xab],
            iops: Ioxs::Good,
            iocs: Ioxs::Bad,
            forced: true,
            state: Watched::Ar(ArState::Data),
        };
        let t = line_text("2026-11-27T00:00:00.000Z", 42, "dev1", &s);
        for part in [
            "cycle        42",
            "IOPS GOOD IOCS BAD",
            "dev1: data",
            "FORCED",
        ] {
            assert!(t.contains(part), "{part:?} in {t:?}");
        }
        let w = Watch {
            address: 4,
            length: None,
            output: false,
            count: None,
            json: true,
        };
        let j = line_json("t", 42, &w, "dev1", &s);
        assert_eq!(j["cycle"], 42);
        assert_eq!(j["iocs"], "BAD");
        assert_eq!(j["space"], "input");
        assert_eq!(j["forced"], true);
        assert!(j["data"].as_str().unwrap().eq_ignore_ascii_case("01ab"));
        assert_eq!(j["state"], "data");
    }

    #[test]
    fn a_state_not_known_yet_is_a_question_mark_in_text_and_empty_in_json() {
        let s = Seen {
            data: vec![0],
            iops: Ioxs::Good,
            iocs: Ioxs::Good,
            forced: false,
            state: Watched::NotKnown,
        };
        assert!(line_text("t", 1, "dev1", &s).ends_with("dev1: ?"));
        let w = Watch {
            address: 0,
            length: None,
            output: false,
            count: None,
            json: true,
        };
        assert_eq!(line_json("t", 1, &w, "dev1", &s)["state"], "");
    }
}
