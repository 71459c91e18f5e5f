// SPDX-License-Identifier: MIT OR Apache-2.0
//! A restart of the server under way: a reset (the configuration it runs) or a download (a
//! new one), as IO-Base's CP service functions and `procimg config load` ask for it.
//!
//! The new configuration is checked as procimgd checks its file at start, for this machine,
//! before anything else happens; the instance name stays the running one (its programs find
//! it under that name). Then the attached programs are asked to stop
//! ([`Notification::StopRequest`], IO-Base's CP_STOP_REQ) and the restart waits for them to
//! detach, up to [`RESTART_WAIT_MS`]: once none is attached it takes effect (the running
//! generation ends as at a stop, outputs safe first, and a new one starts with the
//! configuration); if one is still attached then, it is given up, or with
//! [`RestartClients::Force`] it takes effect anyway. A configuration downloaded to a
//! procimgd started with `-c FILE` is written to FILE (into a file beside it, then renamed
//! over it), so that it is also the one of the next start.

use procimg_config::{Config, InterfaceCheck};
use procimg_control::services::{Notification, RESTART_WAIT_MS};
use procimg_control::{Refusal, RestartClients};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Where procimgd's configuration came from, for checking and keeping a new one.
#[derive(Clone, Debug)]
pub struct ConfigSource {
    /// The file (`-c FILE`); `None` for the demo or standard input.
    pub path: Option<PathBuf>,
    /// The instance procimgd serves (`--instance` or the first configuration's).
    pub instance: String,
    /// The network interface `--adapter` chose, over the configuration's.
    pub adapter: Option<String>,
    /// The network procimgd started on: a downloaded PN Driver configuration (TIA Portal's
    /// XML), which names no interface, runs on it.
    pub network: procimg_config::Network,
}

impl ConfigSource {
    /// Checks `text` as a configuration for this machine and makes it the running
    /// instance's; why not, with the line and key. With it comes the text to keep: `text`,
    /// or for a PN Driver configuration its import on procimgd's network, so that the file
    /// starts procimgd again as it runs.
    pub fn check(
        &self,
        text: &str,
        interface: InterfaceCheck<'_>,
    ) -> Result<(Config, String), String> {
        let mut origin = match &self.path {
            Some(p) => format!("{} (downloaded)", p.display()),
            None => "the downloaded configuration".to_owned(),
        };
        let dir = self
            .path
            .as_deref()
            .and_then(Path::parent)
            .map(Path::to_path_buf)
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let mut keep = text.to_owned();
        if procimg_config::pn_driver::is_xml(text) {
            let network = self.adapter.clone().or(match &self.network {
                procimg_config::Network::Interface(name) => Some(name.clone()),
                procimg_config::Network::Sim => None,
            });
            keep = procimg_config::pn_driver::import(text, &origin, network.as_deref())
                .map_err(|e| e.to_string())?;
            origin.push_str(" (imported)");
        }
        let mut config = procimg_config::parse_for_machine(&keep, &origin, &dir, interface)
            .map_err(|e| e.to_string())?;
        config.instance.clone_from(&self.instance);
        if let Some(a) = &self.adapter
            && config.network != procimg_config::Network::Sim
        {
            config.network = procimg_config::Network::Interface(a.clone());
        }
        Ok((config, keep))
    }

    /// Keeps `text` as the configuration of the next start: written over the file procimgd
    /// started with, through a file beside it. `Ok(false)` when there is no file.
    pub fn keep(&self, text: &str) -> std::io::Result<bool> {
        let Some(path) = &self.path else {
            return Ok(false);
        };
        let mut tmp = path.clone().into_os_string();
        tmp.push(".new");
        let tmp = PathBuf::from(tmp);
        {
            use std::io::Write;
            let mut f = std::fs::File::create(&tmp)?;
            f.write_all(text.as_bytes())?;
            f.sync_all()?;
        }
        std::fs::rename(&tmp, path)?;
        Ok(true)
    }
}

/// What the running generation is to become.
#[derive(Debug)]
pub enum Restart {
    /// Start anew with the configuration it runs.
    Same,
    /// Start with this configuration (and keep its text).
    With(Box<Config>, String),
}

/// A restart waiting for the programs to detach.
#[derive(Debug)]
pub struct PendingRestart {
    reply_to: u64,
    what: Option<Restart>,
    clients: RestartClients,
    deadline: Instant,
}

/// What a pending restart comes to now.
#[derive(Debug)]
pub enum RestartStep {
    /// Still waiting.
    Waiting,
    /// Take effect: end the generation.
    Now(Restart),
    /// Given up (a program stayed).
    GivenUp,
}

impl PendingRestart {
    /// A restart for `reply_to`: `what`, with `attached` the programs attached now.
    /// Refused at once if `clients` says so and some are; otherwise they are asked to stop
    /// (`notices` gets the request).
    pub fn begin(
        reply_to: u64,
        what: Restart,
        clients: RestartClients,
        attached: &[String],
        notify: &mut dyn FnMut(&Notification),
    ) -> Result<PendingRestart, Refusal> {
        if clients == RestartClients::Refuse && !attached.is_empty() {
            return Err(Refusal::ClientsAttached {
                clients: attached.to_vec(),
            });
        }
        if !attached.is_empty() {
            let reason = match what {
                Restart::Same => "the server restarts (reset)",
                Restart::With(..) => "a new configuration was downloaded",
            };
            tracing::info!(
                "{reason}: asking {} to stop (CP_STOP_REQ)",
                attached.join(", ")
            );
            notify(&Notification::StopRequest {
                reason: reason.to_owned(),
            });
        }
        Ok(PendingRestart {
            reply_to,
            what: Some(what),
            clients,
            deadline: Instant::now() + Duration::from_millis(RESTART_WAIT_MS),
        })
    }

    /// Who asked.
    pub fn reply_to(&self) -> u64 {
        self.reply_to
    }

    /// Where it stands with `attached` the programs attached now, at `now`.
    pub fn step(&mut self, attached: &[String], now: Instant) -> RestartStep {
        let waited_out = now >= self.deadline;
        if attached.is_empty() || (waited_out && self.clients == RestartClients::Force) {
            return match self.what.take() {
                Some(r) => RestartStep::Now(r),
                None => RestartStep::Waiting,
            };
        }
        if waited_out {
            return RestartStep::GivenUp;
        }
        RestartStep::Waiting
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn begin(clients: RestartClients, attached: &[&str]) -> Result<PendingRestart, Refusal> {
        let attached: Vec<String> = attached.iter().map(|s| s.to_string()).collect();
        let mut told = Vec::new();
        let r = PendingRestart::begin(1, Restart::Same, clients, &attached, &mut |n| {
            told.push(n.clone())
        });
        assert_eq!(
            told.len(),
            usize::from(r.is_ok() && !attached.is_empty()),
            "{told:?}"
        );
        r
    }

    #[test]
    fn a_safe_restart_waits_for_nobody() {
        assert!(matches!(
            begin(RestartClients::Refuse, &["plc"]),
            Err(Refusal::ClientsAttached { .. })
        ));
        let mut r = begin(RestartClients::Refuse, &[]).unwrap();
        assert!(matches!(
            r.step(&[], Instant::now()),
            RestartStep::Now(Restart::Same)
        ));
    }

    #[test]
    fn programs_asked_to_stop_are_waited_for_then_given_up_unless_forced() {
        let plc = vec!["plc".to_owned()];
        let now = Instant::now();
        let late = now + Duration::from_millis(RESTART_WAIT_MS + 1);
        let mut asked = begin(RestartClients::Ask, &["plc"]).unwrap();
        assert!(matches!(asked.step(&plc, now), RestartStep::Waiting));
        assert!(matches!(asked.step(&plc, late), RestartStep::GivenUp));
        let mut closed = begin(RestartClients::Ask, &["plc"]).unwrap();
        assert!(matches!(closed.step(&[], now), RestartStep::Now(_)));
        let mut forced = begin(RestartClients::Force, &["plc"]).unwrap();
        assert!(matches!(forced.step(&plc, now), RestartStep::Waiting));
        assert!(matches!(forced.step(&plc, late), RestartStep::Now(_)));
    }

    #[test]
    fn a_downloaded_configuration_is_the_running_instances_and_kept_in_its_file() {
        let dir = std::env::temp_dir().join(format!("procimg-restart-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("plant.toml");
        std::fs::write(&path, "instance = \"line\"\n").unwrap();
        let source = ConfigSource {
            path: Some(path.clone()),
            instance: "line".into(),
            adapter: None,
            network: procimg_config::Network::Interface("eth7".into()),
        };
        let any = |_: &str| Ok(());
        let (c, kept) = source
            .check("instance = \"other\"\ncycle_time = \"2ms\"\n", &any)
            .unwrap();
        assert_eq!(kept, "instance = \"other\"\ncycle_time = \"2ms\"\n");
        assert_eq!((c.instance.as_str(), c.cycle_ns), ("line", 2_000_000));
        let bad = source.check("cycle_time = \"3us\"\n", &any).unwrap_err();
        assert!(bad.contains("cycle_time") && bad.contains(":1:"), "{bad}");
        // TIA Portal's PN Driver configuration runs on procimgd's network, and its import is
        // what is kept.
        let (c, kept) = source.check(pn_driver_xml(), &any).unwrap();
        assert_eq!(c.network, procimg_config::Network::Interface("eth7".into()));
        assert_eq!(c.devices[0].name, "pc-device");
        assert!(
            kept.starts_with("# procimgd's configuration, imported")
                && kept.contains("network = \"eth7\"")
        );
        assert!(source.keep("cycle_time = \"2ms\"\n").unwrap());
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "cycle_time = \"2ms\"\n"
        );
        std::fs::remove_dir_all(&dir).unwrap();
        let no_file = ConfigSource {
            path: None,
            ..source
        };
        assert!(!no_file.keep("").unwrap());
    }

    /// The veth station's PN Driver configuration (the configuration crate's test data).
    fn pn_driver_xml() -> &'static str {
        include_str!("../../../config/tests/data/pn-driver/pc-device.xml")
    }
}
