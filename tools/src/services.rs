// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg record`, `procimg events`, `procimg device` and `procimg diag`: the controller
//! services from the command line.

use crate::io::parse_hex;
use crate::text::hex;
use anyhow::{Context, bail};
use clap::Subcommand;
use procimg_client::{
    ActivationError, Notification, PortRef, RecordTarget, ServiceOptions, Services, Tailoring,
    TailoringRefusal,
};
use procimg_profinet::wire::record::Im0;
use std::time::{Duration, Instant};

/// How long a record job may take before the command gives up.
pub(crate) const RECORD_TIMEOUT: Duration = Duration::from_secs(10);

#[derive(Subcommand)]
pub enum RecordCommand {
    /// Read a record and print it in hex (I&M0, index 0xAFF0, also decoded).
    Read {
        #[command(flatten)]
        at: RecordAt,
        /// The most bytes to read.
        #[arg(long, default_value_t = 4096)]
        max_len: u32,
    },
    /// Write a record.
    Write {
        #[command(flatten)]
        at: RecordAt,
        /// The record in hex, e.g. 01ff or "01 ff".
        data: String,
    },
}

/// Where a record is.
#[derive(clap::Args)]
pub struct RecordAt {
    /// The device's station name (as in `procimg status`).
    device: String,
    /// Slot.
    #[arg(long, default_value_t = 0)]
    slot: u16,
    /// Subslot (decimal or 0x hex).
    #[arg(long, default_value = "1", value_parser = parse_u16)]
    subslot: u16,
    /// Record index (decimal or 0x hex), e.g. 0xAFF0 for I&M0.
    #[arg(long, value_parser = parse_u16)]
    index: u16,
    /// API.
    #[arg(long, default_value_t = 0)]
    api: u32,
}

pub(crate) fn parse_u16(s: &str) -> Result<u16, String> {
    let r = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(hex) => u16::from_str_radix(hex, 16),
        None => s.parse(),
    };
    r.map_err(|e| format!("{s:?} is not a 16-bit number: {e}"))
}

pub(crate) fn open(instance: &str, name: &str, acknowledge: bool) -> anyhow::Result<Services> {
    Ok(Services::open(
        instance,
        ServiceOptions::new(name).acknowledge_alarms(acknowledge),
    )?)
}

/// The index of the device named `name`.
pub(crate) fn device_index(s: &Services, name: &str) -> anyhow::Result<u32> {
    let devices = s.control().status()?.devices;
    match devices.iter().position(|d| d.name == name) {
        Some(i) => Ok(i as u32),
        None => {
            let names: Vec<&str> = devices.iter().map(|d| d.name.as_str()).collect();
            bail!(
                "instance \"{}\" has no device {name:?}; it has: {}",
                s.control().instance(),
                names.join(", ")
            )
        }
    }
}

fn target(s: &Services, at: &RecordAt) -> anyhow::Result<RecordTarget> {
    Ok(RecordTarget {
        device: device_index(s, &at.device)?,
        api: at.api,
        slot: at.slot,
        subslot: at.subslot,
        index: at.index,
    })
}

/// `procimg record …`.
pub fn record(instance: &str, op: RecordCommand) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-record", false)?;
    match op {
        RecordCommand::Read { at, max_len } => {
            let t = target(&s, &at)?;
            let data = s
                .read_record(t, max_len, RECORD_TIMEOUT)
                .with_context(|| format!("reading record {:#06x} of {:?}", at.index, at.device))?;
            println!("{}", hex(&data));
            if at.index == 0xAFF0
                && let Ok(im) = Im0::parse(&data)
            {
                println!(
                    "I&M0: vendor {:#06x}, order id {:?}, serial {:?}, hardware {}, software {}",
                    im.vendor_id,
                    im.order_id_str().unwrap_or("?"),
                    im.serial_number_str().unwrap_or("?"),
                    im.hardware_revision,
                    im.software_revision
                );
            }
        }
        RecordCommand::Write { at, data } => {
            let t = target(&s, &at)?;
            let bytes = parse_hex(&data)?;
            s.write_record(t, &bytes, RECORD_TIMEOUT)
                .with_context(|| format!("writing record {:#06x} of {:?}", at.index, at.device))?;
            println!("written");
        }
    }
    Ok(())
}

/// `procimg events`: prints device events, alarms and confirmations (or the station's
/// events, in the device role) as they come.
pub fn events(
    instance: &str,
    json: bool,
    acknowledge: bool,
    count: Option<u64>,
    seconds: Option<f64>,
) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-events", acknowledge)?;
    let term = crate::interrupt::flag()?;
    let until = seconds.map(|x| Instant::now() + Duration::from_secs_f64(x));
    let mut seen = 0;
    while !term.load(std::sync::atomic::Ordering::Acquire)
        && count.is_none_or(|c| seen < c)
        && until.is_none_or(|u| Instant::now() < u)
    {
        let Some(n) = s.next(Duration::from_millis(200)) else {
            continue;
        };
        seen += 1;
        if json {
            println!("{}", serde_json::to_string(&n)?);
        } else {
            println!("{}", describe(&n));
        }
        if acknowledge && let Notification::Alarm(a) = &n {
            // An alarm older than the subscription is not waiting for us: nothing to do.
            let _ = s.acknowledge(a);
        }
    }
    Ok(())
}

fn describe(n: &Notification) -> String {
    match n {
        Notification::ServerStarted { generation } => {
            format!("server started (generation {generation:016x})")
        }
        Notification::DeviceState { name, state, .. } => format!("{name}: {state}"),
        Notification::DeviceFailure { name, reason, .. } => {
            format!("{name}: DEV_FAILURE: {reason}")
        }
        Notification::DeviceReturn { name, .. } => format!("{name}: DEV_RETURN"),
        Notification::ModuleDiff {
            name, submodules, ..
        } => {
            let list: Vec<String> = submodules
                .iter()
                .map(|d| format!("slot {} subslot {:#06x}: {}", d.slot, d.subslot, d.text))
                .collect();
            format!("{name}: modules differ: {}", list.join("; "))
        }
        Notification::Alarm(a) => format!(
            "alarm #{}: {}{}",
            a.id,
            a.text,
            if a.payload.is_empty() {
                String::new()
            } else {
                format!(" [{}]", hex(&a.payload))
            }
        ),
        Notification::Record { confirmation, .. } => {
            format!(
                "record {:#06x} done: {:?}",
                confirmation.target.index, confirmation.status
            )
        }
        Notification::Activation { device, active, .. } => format!(
            "device #{device} {}",
            if *active { "activated" } else { "deactivated" }
        ),
        Notification::ControllerSignal => {
            "the controller's station: DCP Signal (flash its LED)".to_owned()
        }
        Notification::PeConfirmation {
            command,
            answer,
            message,
            ..
        } => match answer {
            Some(a) => format!("PE {command:?}: {a:?}"),
            None => format!("PE {command:?} failed: {message}"),
        },
        Notification::StopRequest { reason } => {
            format!("stop request (CP_STOP_REQ): {reason}; programs are to close")
        }
        Notification::Restart { done, message, .. } => {
            if *done {
                format!("restart: {message}")
            } else {
                format!("restart given up: {message}")
            }
        }
        Notification::InterfaceAlarm(a) => format!(
            "the controller's interface: alarm #{}: {}{}",
            a.id,
            a.text,
            if a.payload.is_empty() {
                String::new()
            } else {
                format!(" [{}]", hex(&a.payload))
            }
        ),
        Notification::InterfaceRecord {
            subslot,
            index,
            status,
            data,
            ..
        } => format!(
            "the controller's interface: record {index:#06x} of subslot {subslot:#06x}: {} \
             bytes, {status:?}",
            data.len()
        ),
        Notification::ControllerAddress {
            name,
            ip,
            netmask,
            gateway,
            reply_to,
            refused,
            ..
        } => {
            let by = if reply_to.is_some() {
                "a program"
            } else {
                "DCP"
            };
            match refused {
                Some(why) => format!(
                    "the controller's station: {by}'s change refused: {}",
                    why.message
                ),
                None => format!(
                    "the controller's station: {by} set it to \"{name}\" at {ip} \
                     (netmask {netmask}, gateway {gateway})"
                ),
            }
        }
        Notification::Reconfigured {
            active, refused, ..
        } => match refused {
            Some(r) => format!("IO system tailoring refused: {}", refusal_text(r)),
            None if *active => "IO system tailored".to_owned(),
            None => "IO system deactivated".to_owned(),
        },
        Notification::StationAr {
            state,
            ar_uuid,
            controller_mac,
            controller_name,
        } => format!(
            "station: AR {ar_uuid} with PLC \"{controller_name}\" ({controller_mac}): {state}"
        ),
        Notification::StationArEnded {
            ar_uuid, reason, ..
        } => format!("station: AR {ar_uuid} ended: {reason}"),
        Notification::StationPlcRunning {
            running,
            station_problem,
            backup,
        } => format!(
            "station: the PLC is in {}",
            procimg_control::services::plc_state_text(*running, *station_problem, *backup)
        ),
        Notification::StationBlink => "station: DCP Signal (blink)".to_owned(),
        Notification::StationNeighbours {
            port,
            neighbours,
            alias_name,
        } => {
            let who: Vec<String> = neighbours
                .iter()
                .map(|n| match (&n.station, &n.port) {
                    (Some(s), Some(p)) => format!("\"{s}\" {p} ({})", n.mac),
                    _ => format!("chassis {} port {} ({})", n.chassis_id, n.port_id, n.mac),
                })
                .collect();
            let alias = alias_name
                .as_deref()
                .map(|a| format!(", alias {a:?}"))
                .unwrap_or_default();
            if who.is_empty() {
                format!("station: port-{port:03} has no neighbour{alias}")
            } else {
                format!(
                    "station: port-{port:03} neighbour {}{alias}",
                    who.join(", ")
                )
            }
        }
        Notification::StationIdentity {
            name,
            ip,
            netmask,
            gateway,
            permanent,
            factory_reset,
        } => format!(
            "station: {}\"{name}\" at {ip}/{netmask} via {gateway}{}",
            if *factory_reset {
                "reset to factory: "
            } else {
                ""
            },
            if *permanent { " (kept)" } else { "" }
        ),
        Notification::StationPlug {
            slot,
            subslot,
            plugged,
            module_ident,
            submodule_ident,
            alarm,
            ..
        } => format!(
            "station: slot {slot} subslot {subslot:#06x} {}{}",
            if *plugged {
                format!("plugged (module {module_ident:#010x}, submodule {submodule_ident:#010x})")
            } else {
                "pulled".to_owned()
            },
            if alarm.is_empty() {
                String::new()
            } else {
                format!(", {alarm} alarm to the PLC")
            }
        ),
        // Only the subscriber that took the records gets these, and `procimg events` takes
        // none.
        Notification::StationDcpSetCheck { check, .. } => format!(
            "station: DCP client {} sets name {:?}, address {:?}{} (check {})",
            check.from,
            check.name,
            check.ip_suite,
            if check.reset {
                ", reset to factory"
            } else {
                ""
            },
            check.job
        ),
        Notification::StationArCheck { check, .. } => format!(
            "station: PLC {} ({}) connects AR {} (check {})",
            check.controller_mac, check.controller_name, check.ar_uuid, check.job
        ),
        Notification::StationPlugParameterized { api, slot, subslot } => format!(
            "station: the PLC ended the parameters of API {api} slot {slot} subslot \
             {subslot:#06x} (plugged)"
        ),
        Notification::StationAlarmDone { tag, status, .. } => match status {
            Some(s) => format!("station: alarm {tag} acknowledged by the PLC, status {s:02x?}"),
            None => format!("station: alarm {tag} not acknowledged: the AR ended"),
        },
        Notification::StationRecord { job, .. } => format!(
            "station: record {:#06x} of slot {} subslot {:#06x} {} (job {})",
            job.index,
            job.slot,
            job.subslot,
            if job.write { "written" } else { "read" },
            job.job
        ),
    }
}

/// `procimg device activate|deactivate NAME`: waits for the confirmation.
pub fn activate(instance: &str, name: &str, active: bool) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-device", false)?;
    let device = device_index(&s, name)?;
    s.activate_confirmed(device, active, Duration::from_secs(5))
        .map_err(|e| match e {
            ActivationError::Refused { .. } => {
                anyhow::anyhow!("device {name:?} did not take the change")
            }
            other => other.into(),
        })?;
    println!(
        "{name} {}",
        if active { "activated" } else { "deactivated" }
    );
    Ok(())
}

/// Why a tailoring was refused, in words.
fn refusal_text(r: &TailoringRefusal) -> &str {
    match r {
        TailoringRefusal::Station { reason, .. } | TailoringRefusal::Port { reason, .. } => reason,
    }
}

/// One end of a `--link`: `NAME:SUBSLOT`, the subslot in hex (`0x8002`) or decimal.
fn port_of(s: &Services, end: &str) -> anyhow::Result<PortRef> {
    let (name, subslot) = end
        .rsplit_once(':')
        .ok_or_else(|| anyhow::anyhow!("{end:?} is not NAME:SUBSLOT (e.g. conveyor:0x8002)"))?;
    let subslot = match subslot.strip_prefix("0x") {
        Some(hex) => u16::from_str_radix(hex, 16),
        None => subslot.parse(),
    }
    .map_err(|_| anyhow::anyhow!("{subslot:?} in {end:?} is not a subslot (e.g. 0x8001)"))?;
    Ok(PortRef {
        device: device_index(s, name)?,
        slot: 0,
        subslot,
    })
}

/// `procimg device tailor [DEVICE…] [--link A:SUBSLOT=B:SUBSLOT…]` (with `what`) and
/// `procimg device deactivate-all` (without): waits for the confirmation.
pub fn tailor(instance: &str, what: Option<(&[String], &[String])>) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-tailor", false)?;
    let tailoring = match what {
        None => None,
        Some((present, links)) => {
            let devices = present
                .iter()
                .map(|n| device_index(&s, n))
                .collect::<anyhow::Result<Vec<_>>>()?;
            let links = links
                .iter()
                .map(|l| {
                    let (a, b) = l.split_once('=').ok_or_else(|| {
                        anyhow::anyhow!("--link {l:?} is not PORT=PORT (e.g. a:0x8002=b:0x8001)")
                    })?;
                    Ok([port_of(&s, a)?, port_of(&s, b)?])
                })
                .collect::<anyhow::Result<Vec<_>>>()?;
            Some(Tailoring { devices, links })
        }
    };
    s.reconfigure_io_system(tailoring)?;
    let until = Instant::now() + Duration::from_secs(5);
    while Instant::now() < until {
        if let Some(Notification::Reconfigured {
            active, refused, ..
        }) = s.next(Duration::from_millis(100))
        {
            if let Some(r) = refused {
                bail!("the tailoring was refused: {}", refusal_text(&r));
            }
            println!(
                "{}",
                if active {
                    "IO system tailored: the mandatory devices and those named come up"
                } else {
                    "every device deactivated"
                }
            );
            return Ok(());
        }
    }
    bail!("no confirmation from instance \"{instance}\" within 5 s")
}

/// `procimg diag`: the state of every device, or the station's diagnosis in the device role.
pub fn diag(instance: &str, json: bool) -> anyhow::Result<()> {
    let s = open(instance, "procimg-diag", false)?;
    if let Some(station) = s.control().status()?.station {
        return crate::station_diag::print(&station, json);
    }
    let d = s.diagnosis()?;
    if json {
        println!("{}", serde_json::to_string_pretty(&d)?);
        return Ok(());
    }
    for dev in &d.devices {
        print!(
            "#{} {:<24} {:<30} {} failures {}",
            dev.device,
            dev.name,
            dev.state,
            if dev.active { "active  " } else { "inactive" },
            dev.failures
        );
        if !dev.last_error.is_empty() {
            print!("  last error: {}", dev.last_error);
        }
        println!();
        for m in &dev.module_diff {
            println!(
                "    API {} slot {} subslot {:#06x}: {}",
                m.api, m.slot, m.subslot, m.text
            );
        }
    }
    Ok(())
}
