// SPDX-License-Identifier: MIT OR Apache-2.0
//! A device program for procimgd's IO device role: it owns the I data of every submodule
//! and, every cycle, echoes each submodule's Q data (what the PLC wrote) into its I data
//! (what the PLC reads); I bytes beyond the Q data count the cycles. Half-way it raises a
//! channel diagnosis on slot 1 (a wire break on channel 0, which the PLC gets as an alarm and
//! in its diagnosis records), and clears it three quarters in. Between cycles it prints the
//! station's notifications (the PLC's AR coming up or ending, its RUN/STOP, DCP) and
//! answers the PLC's reads and writes of slot 1's parameter record 1 (4 bytes), which it
//! takes: a write of 4 bytes is its new value, a read gives it back, anything else is
//! refused with the PNIORW error a device gives. It prints what it saw.
//!
//! Run against `procimgd --demo-device`, whose PLC writes each submodule's I data plus one
//! into its Q data, so that the values climb by one every round trip:
//!   cargo run --release --example device_app -- --cycles 5000
//! Against `procimgd --demo-device-program` (a station its program defines) it first defines
//! the station itself: the demo's modules, which the station's GSDML file describes.

use anyhow::{Context, bail};
use clap::Parser;
use procimg_client::{
    ArState, AttachOptions, Client, DiagnosisDirection, DiagnosisEntry, Event, Ioxs, Notification,
    RecordRefusal, ServiceOptions, Services, StationRecordJob, StationTreeEntry, TreeRecords,
};
use std::time::Duration;

#[derive(Parser)]
struct Args {
    /// Instance to attach to.
    #[arg(long, default_value = "procimg")]
    instance: String,
    /// Cycles to run (0: until the server goes away).
    #[arg(long, default_value_t = 5_000)]
    cycles: u64,
    /// SCHED_FIFO priority of the loop (0: stay at normal priority).
    #[arg(long, default_value_t = 70)]
    priority: u8,
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("device_app: {e:#}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    if args.priority > 0
        && let Err(e) = procimg_client::realtime::make_current_thread_realtime(args.priority)
    {
        eprintln!(
            "warning: cannot run SCHED_FIFO at priority {} ({e}); OPDONE may miss the \
             deadline under load",
            args.priority
        );
    }
    // The station's events from now on; where the AR stands already is in the status.
    let mut station = match Services::open(&args.instance, ServiceOptions::new("device_app")) {
        Ok(s) => Some(s),
        Err(e) => {
            eprintln!("warning: no station notifications ({e}); running without them");
            None
        }
    };
    if let Some(s) = station.as_mut() {
        define_if_waiting(s)?;
    }
    let mut client = Client::attach(&args.instance, AttachOptions::synchronous("device_app"))
        .context("attaching")?;
    if !client.is_device() {
        bail!(
            "instance \"{}\" is an IO controller; run this against a procimgd with \
             role = \"device\" (e.g. procimgd --demo-device)",
            args.instance
        );
    }
    let mine = client.claim_i_data().context("claiming the I data")?;
    println!(
        "device_app: providing the I data of {} submodules of instance \"{}\"",
        mine.len(),
        args.instance
    );
    // Slot 1's records are this program's to answer from now on.
    if let Some(s) = station.as_ref() {
        match s.take_records(PARAMETER_AT) {
            Ok(()) => println!("device_app: answering the PLC's records of slot 1"),
            Err(e) => eprintln!("warning: slot 1's records stay the station's ({e})"),
        }
    }
    let mut parameter = Parameter::default();
    if let Some(ar) = client
        .control()
        .status()
        .ok()
        .and_then(|s| s.station)
        .and_then(|s| s.ar)
        && let Some(line) = describe(&Notification::StationAr {
            state: ar.state,
            ar_uuid: ar.ar_uuid,
            controller_mac: ar.controller_mac,
            controller_name: ar.controller_name,
        })
    {
        println!("device_app: {line}");
    }
    // Wire break (ChannelErrorType 6) on input channel 0 of slot 1.
    let wire_break = DiagnosisEntry {
        channel: 0,
        error_type: 6,
        direction: DiagnosisDirection::Input,
        data_type: 1,
        ..DiagnosisEntry::default()
    };
    let (raise_at, clear_at) = match args.cycles {
        0 => (5_000, 10_000),
        n => (n / 2, n * 3 / 4),
    };
    let (mut done, mut q_good, mut opfaults) = (0u64, 0u64, 0u64);
    let mut q = Vec::new();
    while args.cycles == 0 || done < args.cycles {
        let mut cycle = match client.wait_startop(Duration::from_secs(5)) {
            Ok(c) => c,
            Err(e) if args.cycles == 0 => {
                println!("device_app: {e}; stopping");
                break;
            }
            Err(e) => return Err(e).context("waiting for STARTOP"),
        };
        let k = cycle.number();
        let mut all_good = true;
        for &s in &mine {
            q.clear();
            q.extend_from_slice(cycle.q_data(s)?);
            all_good &= q.is_empty() || cycle.q_status(s)? == Ioxs::Good;
            let count = (k as u32).to_be_bytes();
            for (j, b) in cycle.i_data_mut(s)?.iter_mut().enumerate() {
                *b = q.get(j).copied().unwrap_or(count[j % 4]);
            }
        }
        q_good += u64::from(all_good);
        cycle.set_opdone()?;
        opfaults += client
            .events()
            .iter()
            .filter(|e| matches!(e, Event::OpFault { .. }))
            .count() as u64;
        done += 1;
        // Between cycles, without waiting: what the station reported.
        while let Some(n) = station.as_mut().and_then(Services::try_next) {
            if let Notification::StationRecord { job, .. } = &n {
                let answer = parameter.answer(job);
                if let Some(s) = station.as_ref()
                    && let Err(e) = s.answer_record(job, answer.as_deref().map_err(|e| *e))
                {
                    eprintln!("warning: record job {} not answered: {e}", job.job);
                }
            } else if let Some(line) = describe(&n) {
                println!("device_app: {line}");
            }
        }
        // Between cycles: a control request takes longer than a cycle's work.
        if done == raise_at {
            client
                .add_diagnosis((0, 1, 1), wire_break.clone())
                .context("raising the diagnosis")?;
            println!("device_app: wire break on channel 0 of slot 1 reported to the PLC");
        } else if done == clear_at {
            client
                .remove_diagnosis((0, 1, 1), wire_break.clone())
                .context("clearing the diagnosis")?;
            println!("device_app: the wire break is gone");
        }
    }
    println!(
        "device_app: cycles {done}  with every Q GOOD {q_good}  OPFAULTs {opfaults}  \
         parameter records answered {}",
        parameter.answered
    );
    Ok(())
}

/// The station this program defines when procimgd leaves the tree to its program
/// (`[station] gsdml`, `procimgd --demo-device-program`): slot, module and submodule ident
/// numbers, as the demo station's GSDML file describes them (module 0x10: 8 bytes each way
/// and parameter record 1; module 0x20: 4 bytes of inputs).
const TREE: [(u16, u32, u32); 2] = [(1, 0x10, 0x1), (2, 0x20, 0x1)];

/// Defines the station as [`TREE`] when it waits for its program, and waits until procimgd
/// runs it (a new generation, which the station's notifications announce; the client then
/// attaches to its layout). Slot 1's records are this program's from the station's first
/// moment: the PLC's records that come at once wait in the notifications.
fn define_if_waiting(services: &mut Services) -> anyhow::Result<()> {
    let status = services
        .control()
        .status()
        .context("asking for the status")?;
    let waits = status
        .station
        .and_then(|s| s.program)
        .is_some_and(|p| p.defined_by.is_none());
    if !waits {
        return Ok(());
    }
    let tree: Vec<StationTreeEntry> = TREE
        .iter()
        .map(|&(slot, module_ident, submodule_ident)| StationTreeEntry {
            api: 0,
            slot,
            subslot: 1,
            module_ident,
            submodule_ident,
            records: if (0, slot, 1) == PARAMETER_AT {
                TreeRecords::Program
            } else {
                TreeRecords::Station
            },
        })
        .collect();
    let before = services.generation();
    services
        .define_station(&tree)
        .context("defining the station")?;
    let until = std::time::Instant::now() + Duration::from_secs(10);
    // What comes before the new generation's start is the old station's.
    while services.generation() == before {
        if std::time::Instant::now() >= until {
            bail!("procimgd did not run the defined station within 10 s");
        }
        let _ = services.next(Duration::from_millis(100));
    }
    println!("device_app: defined the station: {} modules", TREE.len());
    Ok(())
}

/// Where the program's parameter record is: API 0, slot 1, subslot 1.
const PARAMETER_AT: (u32, u16, u16) = (0, 1, 1);
/// Its index.
const PARAMETER_INDEX: u16 = 1;

/// The parameter record the program keeps: 4 bytes, as the station's GSDML declares it.
#[derive(Default)]
struct Parameter {
    value: [u8; 4],
    answered: u64,
}

impl Parameter {
    /// The answer to the PLC's read or write `job`.
    fn answer(&mut self, job: &StationRecordJob) -> Result<Vec<u8>, RecordRefusal> {
        self.answered += 1;
        match (job.write, job.index) {
            (true, PARAMETER_INDEX) => match <[u8; 4]>::try_from(job.data.as_slice()) {
                Ok(v) => {
                    self.value = v;
                    println!(
                        "device_app: the PLC set parameter record {PARAMETER_INDEX} of slot 1 \
                         to {}",
                        u32::from_be_bytes(v)
                    );
                    Ok(Vec::new())
                }
                Err(_) => Err(RecordRefusal::new(RecordRefusal::WRITE_LENGTH_ERROR)),
            },
            (false, PARAMETER_INDEX) => Ok(self.value.to_vec()),
            _ => Err(RecordRefusal::new(RecordRefusal::INVALID_INDEX)),
        }
    }
}

/// A station notification in words (`None` for the controller's, which a device does not get).
fn describe(n: &Notification) -> Option<String> {
    Some(match n {
        Notification::StationAr {
            state: ArState::Data,
            ar_uuid,
            ..
        } => format!("AR {ar_uuid} is in data exchange"),
        Notification::StationAr { state, ar_uuid, .. } => format!("AR {ar_uuid} is {state}"),
        Notification::StationArEnded {
            ar_uuid, reason, ..
        } => format!("AR {ar_uuid} ended: {reason}"),
        Notification::StationPlcRunning { running, .. } => {
            format!("the PLC is in {}", if *running { "RUN" } else { "STOP" })
        }
        Notification::StationBlink => "DCP Signal: this station is asked to blink".to_owned(),
        Notification::StationIdentity { name, ip, .. } => {
            format!("the station is now \"{name}\" at {ip}")
        }
        _ => return None,
    })
}
