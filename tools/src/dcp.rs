// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg dcp`: find PROFINET devices on a network and give them a name or an address.

use anyhow::{Context, bail};
use clap::Subcommand;
use procimg_nic::af_packet::{AfPacket, OpenError};
use procimg_nic::{Nic, RecvError};
use procimg_profinet::dcp_client::{Identify, Set};
use procimg_profinet::wire::MacAddress;
use std::net::Ipv4Addr;
use std::time::{Duration, Instant};

#[derive(Subcommand)]
pub enum DcpCommand {
    /// List the devices that answer an Identify (all, or the one with --name).
    Scan {
        /// Only the device with this NameOfStation.
        #[arg(long)]
        name: Option<String>,
        /// How long to collect answers, in ms (devices spread their answers over this).
        #[arg(long, default_value_t = 1280)]
        wait_ms: u64,
    },
    /// Give the device with MAC address MAC a NameOfStation.
    SetName {
        /// The device's MAC address (aa:bb:cc:dd:ee:ff).
        #[arg(value_parser = parse_mac)]
        mac: MacAddress,
        /// The name.
        name: String,
        /// Store it permanently (default: until the device restarts).
        #[arg(long)]
        permanent: bool,
    },
    /// Give the device with MAC address MAC an IPv4 address.
    SetIp {
        /// The device's MAC address.
        #[arg(value_parser = parse_mac)]
        mac: MacAddress,
        /// Address.
        ip: Ipv4Addr,
        /// Netmask.
        mask: Ipv4Addr,
        /// Gateway (default: none, written as the address itself).
        gateway: Option<Ipv4Addr>,
        /// Store it permanently.
        #[arg(long)]
        permanent: bool,
    },
    /// Reset the device's communication parameters to factory: no name, no IP address (it
    /// ends the device's connection to its PLC).
    Reset {
        /// The device's MAC address.
        #[arg(value_parser = parse_mac)]
        mac: MacAddress,
    },
    /// Flash the device's LED so you can find it in the cabinet.
    Blink {
        /// The device's MAC address.
        #[arg(value_parser = parse_mac)]
        mac: MacAddress,
    },
}

fn parse_mac(s: &str) -> Result<MacAddress, String> {
    let parts: Vec<&str> = s.split([':', '-']).collect();
    let bytes: Vec<u8> = parts
        .iter()
        .filter_map(|p| u8::from_str_radix(p, 16).ok())
        .collect();
    match (parts.len(), <[u8; 6]>::try_from(bytes)) {
        (6, Ok(b)) => Ok(MacAddress(b)),
        _ => Err(format!("{s:?} is not a MAC address like 02:00:00:00:00:01")),
    }
}

fn xid() -> u32 {
    let t = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    (t.subsec_nanos() ^ std::process::id()) | 1
}

fn ip_str(b: [u8; 4]) -> String {
    Ipv4Addr::from(b).to_string()
}

/// The value parser of `--instance` on a subcommand that works on the network itself
/// (`dcp`, `capture`): the option is hidden there, and given anyway it is refused with the
/// reason, rather than taken and ignored.
pub fn no_instance(
    command: &'static str,
) -> impl Fn(&str) -> Result<String, String> + Clone + Send + Sync + 'static {
    move |_| {
        Err(format!(
            "`procimg {command}` works on the network interface given with --iface, not \
             through a procimgd, so it takes no --instance; leave it out"
        ))
    }
}

/// Why `--iface` could not be opened, and what to do, in the words of the command line.
pub fn iface_error(error: OpenError) -> anyhow::Error {
    let iface = match &error {
        OpenError::NoSuchInterface { name, .. }
        | OpenError::Down { name }
        | OpenError::NoMac { name }
        | OpenError::NotPermitted { name }
        | OpenError::Io { name, .. } => name.clone(),
    };
    let advice = match &error {
        OpenError::NoSuchInterface { available, .. } => {
            return anyhow::anyhow!(
                "--iface {iface}: there is no such network interface on this machine; its \
                 interfaces are {available}: give one of them with --iface"
            );
        }
        OpenError::Down { .. } => String::new(),
        OpenError::NoMac { .. } => "; give an Ethernet interface with --iface".to_owned(),
        OpenError::NotPermitted { .. } => {
            let exe = std::env::current_exe()
                .map(|p| p.display().to_string())
                .unwrap_or_else(|_| "procimg".to_owned());
            format!(
                "; run procimg as root, or grant it the capability (sudo setcap \
                 cap_net_raw+ep {exe})"
            )
        }
        OpenError::Io { .. } => String::new(),
    };
    anyhow::anyhow!("--iface {iface}: {error}{advice}")
}

pub fn run(iface: &str, op: DcpCommand) -> anyhow::Result<()> {
    let mut nic = AfPacket::open(iface, Duration::from_millis(10)).map_err(iface_error)?;
    let me = nic.mac();
    match op {
        DcpCommand::Scan { name, wait_ms } => {
            let mut id = Identify::new(xid());
            // Response delay factor in 10 ms units: devices spread their answers over it.
            let rdf = (wait_ms / 10).clamp(1, 6400) as u16;
            nic.send(&id.request(me, name.as_deref(), rdf)?)?;
            let until = Instant::now() + Duration::from_millis(wait_ms + 100);
            while Instant::now() < until {
                receive(&mut nic, &mut |frame| {
                    id.on_frame(frame);
                })?;
            }
            if id.devices().is_empty() {
                bail!(
                    "no device answered on {iface}{}",
                    name.map(|n| format!(" to the name \"{n}\""))
                        .unwrap_or_default()
                );
            }
            println!(
                "{:<18} {:<24} {:<16} {:<16} {:<11} vendor",
                "MAC", "name", "IP", "mask", "id"
            );
            for d in id.devices() {
                let (ip, mask) =
                    d.ip.map_or(("-".into(), "-".into()), |(i, m, _)| (ip_str(i), ip_str(m)));
                let ids =
                    d.id.map_or("-".into(), |(v, dev)| format!("{v:04x}:{dev:04x}"));
                println!(
                    "{:<18} {:<24} {:<16} {:<16} {:<11} {}",
                    d.mac.to_string(),
                    d.name.as_deref().unwrap_or("-"),
                    ip,
                    mask,
                    ids,
                    d.vendor.as_deref().unwrap_or("-")
                );
            }
            Ok(())
        }
        DcpCommand::SetName {
            mac,
            name,
            permanent,
        } => set(&mut nic, Set::name(xid(), mac, &name, permanent)),
        DcpCommand::SetIp {
            mac,
            ip,
            mask,
            gateway,
            permanent,
        } => set(
            &mut nic,
            Set::ip(
                xid(),
                mac,
                ip.octets(),
                mask.octets(),
                gateway.unwrap_or(ip).octets(),
                permanent,
            ),
        ),
        DcpCommand::Reset { mac } => set(&mut nic, Set::reset_to_factory(xid(), mac)),
        DcpCommand::Blink { mac } => set(&mut nic, Set::signal(xid(), mac)),
    }
}

/// Sends a Set and waits for the answer: 1 s, three tries.
fn set(nic: &mut AfPacket, request: Set) -> anyhow::Result<()> {
    let frame = request.request(nic.mac())?;
    for _ in 0..3 {
        nic.send(&frame).context("sending the DCP request")?;
        let until = Instant::now() + Duration::from_secs(1);
        while Instant::now() < until {
            let mut outcome = None;
            receive(nic, &mut |frame| outcome = request.on_frame(frame))?;
            if let Some(outcome) = outcome {
                println!("{outcome}");
                return match outcome {
                    procimg_profinet::dcp_client::SetOutcome::Done => Ok(()),
                    other => bail!("{other}"),
                };
            }
        }
    }
    bail!("the device did not answer in 3 s: check the MAC address and that it is on this network")
}

/// Receives a frame into `f`, if one comes within the interface's timeout. A frame too long
/// for any PROFINET station is not the answer waited for: it is skipped, with a warning.
fn receive(nic: &mut AfPacket, f: &mut dyn FnMut(&[u8])) -> anyhow::Result<()> {
    match nic.receive(f) {
        Ok(_) => Ok(()),
        Err(e @ RecvError::TooLong { .. }) => {
            eprintln!("warning: {e}");
            Ok(())
        }
        Err(e) => Err(e.into()),
    }
}
