// SPDX-License-Identifier: MIT OR Apache-2.0
//! What the soak runs: two network namespaces joined by a veth pair, procimgd as IO controller
//! in the first, `pnio-interop-device` (the independent `pnio` stack) in the second, and the
//! soak's synchronous client beside them. Each can be killed and started again.

use crate::process::Running;
use anyhow::{Context as _, bail};
use procimg_netns::netns::TestNet;
use std::net::Ipv4Addr;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// The device's NameOfStation.
pub const STATION: &str = "pnio-iop";

/// The programs the soak starts, found beside it (`cargo build --release --bins` builds them
/// all).
pub struct Programs {
    procimgd: PathBuf,
    device: PathBuf,
    soak: PathBuf,
}

impl Programs {
    /// The programs beside this one.
    pub fn beside_me() -> anyhow::Result<Programs> {
        let soak = std::env::current_exe().context("finding procimg-soak's own path")?;
        let sibling = |name: &str| -> anyhow::Result<PathBuf> {
            let path = soak.with_file_name(name);
            if !path.is_file() {
                bail!(
                    "{name} is not built beside procimg-soak ({}): run cargo build --release --bins",
                    path.display()
                );
            }
            Ok(path)
        };
        Ok(Programs {
            procimgd: sibling("procimgd")?,
            device: sibling("pnio-interop-device")?,
            soak: soak.clone(),
        })
    }
}

/// How procimgd talks to the device.
pub struct Plan {
    /// procimgd's cycle and the send clock of both IOCRs.
    pub cycle: Duration,
    /// DataHoldFactor of both IOCRs.
    pub watchdog_factor: u32,
}

/// The namespaces, the configuration and the three processes.
pub struct Rig {
    // Processes before the namespaces they run in (fields drop in order).
    /// The synchronous client, while it runs.
    pub client: Option<Running>,
    /// procimgd, while it runs.
    pub procimgd: Option<Running>,
    /// The device, while it runs.
    pub device: Option<Running>,
    net: TestNet,
    device_ip: Ipv4Addr,
    programs: Programs,
    config: PathBuf,
    logs: PathBuf,
    /// procimgd's instance name.
    pub instance: String,
}

impl Rig {
    /// Makes the namespaces and writes procimgd's configuration into `out`.
    pub fn new(programs: Programs, out: &Path, plan: &Plan) -> anyhow::Result<Rig> {
        let net = TestNet::new("soak", true);
        let controller_ip = Ipv4Addr::new(10, 214, 0, 1);
        let device_ip = Ipv4Addr::new(10, 214, 0, 2);
        net.address(0, &format!("{controller_ip}/24"));
        net.address(1, &format!("{device_ip}/24"));
        let printed = Command::new(&programs.device)
            .args(["--name", STATION, "--ip", &device_ip.to_string()])
            .arg("--print-config")
            .output()
            .context("running pnio-interop-device --print-config")?;
        if !printed.status.success() {
            bail!(
                "pnio-interop-device --print-config failed: {}",
                String::from_utf8_lossy(&printed.stderr)
            );
        }
        let block = String::from_utf8_lossy(&printed.stdout).replacen(
            "[[device]]\n",
            &format!("[[device]]\nwatchdog_factor = {}\n", plan.watchdog_factor),
            1,
        );
        let instance = format!("soak{}", std::process::id());
        let toml = format!(
            "# procimgd as IO controller of pnio-interop-device (procimg-soak)\n\
             instance = \"{instance}\"\n\
             network = \"{}\"\n\
             cycle_time = \"{}us\"\n\n{block}",
            net.ifs[0],
            plan.cycle.as_micros()
        );
        let config = out.join("procimgd.toml");
        std::fs::write(&config, toml).with_context(|| format!("writing {}", config.display()))?;
        Ok(Rig {
            client: None,
            procimgd: None,
            device: None,
            net,
            device_ip,
            programs,
            config,
            logs: out.to_path_buf(),
            instance,
        })
    }

    /// The device's end of the veth pair and its namespace.
    pub fn device_side(&self) -> (&str, &str) {
        (&self.net.ns[1], &self.net.ifs[1])
    }

    /// Where the logs are.
    pub fn logs(&self) -> &Path {
        &self.logs
    }

    /// The MAC address of procimgd's end of the veth pair.
    pub fn procimgd_mac(&self) -> anyhow::Result<String> {
        let out = Command::new("ip")
            .args([
                "-n",
                &self.net.ns[0],
                "-o",
                "link",
                "show",
                &self.net.ifs[0],
            ])
            .output()
            .context("running ip (iproute2)")?;
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let mut words = text.split_whitespace();
        words
            .find(|w| *w == "link/ether")
            .and_then(|_| words.next())
            .map(str::to_string)
            .with_context(|| format!("no MAC address of {} in {text:?}", self.net.ifs[0]))
    }

    /// Starts procimgd in the controller's namespace (it re-attaches running clients itself).
    pub fn start_procimgd(&mut self) -> anyhow::Result<()> {
        let mut cmd = Command::new("ip");
        cmd.args(["netns", "exec", &self.net.ns[0]])
            .arg(&self.programs.procimgd)
            .arg("--config")
            .arg(&self.config)
            .arg("--quiet");
        let log = self.logs.join("procimgd.log");
        self.procimgd = Some(Running::spawn(cmd, &log).context("starting procimgd")?);
        Ok(())
    }

    /// Starts the device in its namespace and waits for its `READY`.
    pub fn start_device(&mut self) -> anyhow::Result<()> {
        let mut cmd = Command::new("ip");
        // `ip netns exec` execs the program in place, so the child's pid is the device's.
        cmd.args(["netns", "exec", &self.net.ns[1]])
            .arg(&self.programs.device)
            .args(["--iface", &self.net.ifs[1], "--name", STATION])
            .args(["--ip", &self.device_ip.to_string()])
            // It stands for hardware of its own: above procimgd's cycle thread (80).
            .args(["--rt-priority", "90", "--lock-memory"]);
        let log = self.logs.join("device.log");
        let device = Running::spawn(cmd, &log).context("starting pnio-interop-device")?;
        if device
            .wait_line(Duration::from_secs(10), |l| l == "READY", |_| {})
            .is_none()
        {
            bail!(
                "pnio-interop-device printed no READY in 10 s (see {})",
                log.display()
            );
        }
        self.device = Some(device);
        Ok(())
    }

    /// Starts the synchronous client (this program's `client` subcommand).
    pub fn start_client(&mut self) -> anyhow::Result<()> {
        let mut cmd = Command::new(&self.programs.soak);
        cmd.args(["client", "--instance", &self.instance, "--device", STATION]);
        let log = self.logs.join("client.log");
        self.client = Some(Running::spawn(cmd, &log).context("starting the soak client")?);
        Ok(())
    }
}
