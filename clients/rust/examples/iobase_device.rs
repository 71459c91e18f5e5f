// SPDX-License-Identifier: MIT OR Apache-2.0
//! An IO-Base style device program in Rust, without the C library: the AR callbacks in the
//! manual's order (`AR_CHECK_IND`, `AR_INFO_IND`, `PRM_END_IND`, `AR_INDATA_IND`,
//! `APDU_STATUS_IND`, `AR_OFFLINE_IND` / `AR_ABORT_IND`) with their ArNumber and
//! SessionKey, the program's ApplicationReady after `PRM_END_IND`, a diagnosis by DiagTag,
//! and an abort of an AR, through [`procimg_client::iobase`].
//!
//! Like `PNIO_device_open` and `PNIO_device_start`, it takes the station OFFLINE, claims
//! the I data, and takes it to OPERATE: the PLC's next AR is the program's first. Every
//! cycle it echoes each submodule's Q data (what the PLC wrote) into its I data (what the
//! PLC reads). Once an AR is in data exchange it reports a wire break on slot 1 under
//! DiagTag 7 and clears it; after `--hold` cycles it aborts the AR, and the PLC connects
//! again with the next ArNumber, until `--ars` ARs were in data exchange. It shows two
//! refusals of the manual's rules: a second ApplicationReady for one AR, and a call naming
//! an AR that has ended.
//!
//! Run against `procimgd --demo-device`, whose PLC writes each submodule's I data plus one
//! into its Q data:
//!   cargo run --example iobase_device -- --ars 2

use anyhow::{Context, bail};
use clap::Parser;
use procimg_client::iobase::{
    ApduStatus, ArEndReason, ArId, DeviceCallbacks, DiagTagKind, IoBaseDevice, channel_entry,
    channel_properties,
};
use procimg_client::{AttachOptions, Client, Ioxs, Mode, StationArCheckJob};
use std::time::{Duration, Instant};

#[derive(Parser)]
struct Args {
    /// Instance to attach to.
    #[arg(long, env = "PROCIMG_INSTANCE", default_value = "procimg")]
    instance: String,
    /// ARs to see in data exchange before the program ends.
    #[arg(long, default_value_t = 2)]
    ars: u16,
    /// Cycles each AR stays in data exchange before the program aborts it (the last one
    /// ends with the program).
    #[arg(long, default_value_t = 300)]
    hold: u64,
    /// The longest the program runs, in seconds.
    #[arg(long, default_value_t = 60)]
    timeout: u64,
}

/// Where the diagnosis goes: API 0, slot 1, subslot 1.
const SLOT1: (u32, u16, u16) = (0, 1, 1);
/// The program's DiagTag of the wire break.
const WIRE_BREAK_TAG: u16 = 7;

/// What the callbacks leave for the program's loop: the manual allows little inside a
/// callback, so the program acts after it.
#[derive(Default)]
struct Program {
    /// `PRM_END_IND` of the AR came: the ApplicationReady is due.
    prm_end: Option<ArId>,
    /// The AR in data exchange.
    in_data: Option<ArId>,
    /// ARs that were in data exchange.
    ars_in_data: u16,
    /// The last AR that ended.
    ended: Option<ArId>,
}

impl DeviceCallbacks for Program {
    fn ar_check(&mut self, ar: ArId, check: &StationArCheckJob) {
        println!(
            "AR_CHECK_IND ar {} session key {} from PLC \"{}\" ({} submodules expected)",
            ar.number,
            ar.session_key,
            check.controller_name,
            check.expected.len()
        );
    }

    fn ar_info(&mut self, ar: ArId, check: &StationArCheckJob) {
        let i: u32 = check
            .expected
            .iter()
            .map(|e| u32::from(e.input_length))
            .sum();
        let q: u32 = check
            .expected
            .iter()
            .map(|e| u32::from(e.output_length))
            .sum();
        let crs: Vec<String> = check
            .crs
            .iter()
            .map(|cr| {
                format!(
                    "{} CR frame {:#06x} RT class {} every {} µs",
                    if cr.input { "input" } else { "output" },
                    cr.frame_id,
                    cr.rt_class,
                    cr.period_us()
                )
            })
            .collect();
        println!(
            "AR_INFO_IND ar {}: {i} bytes I, {q} bytes Q; {}",
            ar.number,
            crs.join(", ")
        );
    }

    fn prm_end(&mut self, ar: ArId, submodule: Option<(u32, u16, u16)>) {
        println!("PRM_END_IND ar {} {submodule:?}", ar.number);
        self.prm_end = Some(ar);
    }

    fn in_data(&mut self, ar: ArId) {
        println!("AR_INDATA_IND ar {}", ar.number);
        self.in_data = Some(ar);
        self.ars_in_data += 1;
    }

    fn apdu_status(&mut self, ar: ArId, status: ApduStatus) {
        let state = if status.running { "RUN" } else { "STOP" };
        let problem = if status.station_problem {
            ", station problem"
        } else {
            ""
        };
        let backup = if status.backup { ", backup" } else { "" };
        println!("APDU_STATUS_IND ar {} {state}{problem}{backup}", ar.number);
    }

    fn ar_abort(&mut self, ar: ArId, reason: ArEndReason) {
        println!(
            "AR_ABORT_IND ar {} reason {}",
            ar.number,
            reason.iobase_code()
        );
        self.end(ar);
    }

    fn ar_offline(&mut self, ar: ArId, reason: ArEndReason) {
        println!(
            "AR_OFFLINE_IND ar {} reason {}",
            ar.number,
            reason.iobase_code()
        );
        self.end(ar);
    }
}

impl Program {
    fn end(&mut self, ar: ArId) {
        self.ended = Some(ar);
        if self.in_data == Some(ar) {
            self.in_data = None;
        }
        if self.prm_end == Some(ar) {
            self.prm_end = None;
        }
    }
}

fn main() {
    if let Err(e) = run(Args::parse()) {
        eprintln!("iobase_device: {e:#}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    let mut client = Client::attach(&args.instance, AttachOptions::synchronous("iobase_device"))
        .context("attaching")?;
    // On a controller's instance this and the claim say so (NotDevice).
    let device = IoBaseDevice::open(&args.instance, "iobase_device").context("opening")?;
    // PNIO_device_open: no PLC until the program is set up; PNIO_device_start: PLCs may come.
    device.set_mode(Mode::Offline).context("OFFLINE")?;
    let mine = client.claim_i_data().context("claiming the I data")?;
    device.set_mode(Mode::Operate).context("OPERATE")?;
    println!("providing the I data of {} submodules", mine.len());

    let wire_break = channel_entry(0, channel_properties(1, 1, 1), 6, None);
    let mut program = Program::default();
    let (mut cycles, mut echoed) = (0u64, 0u64);
    let mut in_data_since: Option<u64> = None;
    let mut q = Vec::new();
    let until = Instant::now() + Duration::from_secs(args.timeout);
    loop {
        if Instant::now() > until {
            bail!(
                "{} of {} ARs in data exchange after {} s",
                program.ars_in_data,
                args.ars,
                args.timeout
            );
        }
        // The cycle: Q into I, the same bytes the PLC wrote.
        if let Ok(mut cycle) = client.wait_startop(Duration::from_millis(100)) {
            let mut all_good = !mine.is_empty();
            for &s in &mine {
                q.clear();
                q.extend_from_slice(cycle.q_data(s)?);
                all_good &= q.is_empty() || cycle.q_status(s)? == Ioxs::Good;
                let i = cycle.i_data_mut(s)?;
                let n = i.len().min(q.len());
                i[..n].copy_from_slice(&q[..n]);
            }
            cycle.set_opdone()?;
            cycles += 1;
            echoed += u64::from(all_good && program.in_data.is_some());
        }
        // Between cycles: the callbacks, then what they asked for.
        device.poll(&mut program);
        if let Some(ar) = program.prm_end.take() {
            device
                .application_ready(ar, &[])
                .context("the ApplicationReady")?;
            println!("application ready for ar {}", ar.number);
            if let Err(e) = device.application_ready(ar, &[]) {
                println!("a second application ready is refused: {e}");
            }
        }
        let Some(ar) = program.in_data else {
            in_data_since = None;
            continue;
        };
        let since = *in_data_since.get_or_insert(cycles);
        if cycles == since + args.hold / 3 {
            device
                .add_diagnosis(
                    SLOT1,
                    WIRE_BREAK_TAG,
                    DiagTagKind::Channel,
                    wire_break.clone(),
                )
                .context("the diagnosis")?;
            println!("wire break on slot 1 under DiagTag {WIRE_BREAK_TAG}");
        } else if cycles == since + 2 * args.hold / 3 {
            device
                .remove_diagnosis(SLOT1, WIRE_BREAK_TAG, DiagTagKind::Channel)
                .context("clearing the diagnosis")?;
            println!("DiagTag {WIRE_BREAK_TAG} removed");
        } else if cycles >= since + args.hold {
            if program.ars_in_data >= args.ars {
                break;
            }
            println!("aborting ar {}", ar.number);
            device.abort(ar, &mut program).context("aborting the AR")?;
            if let Err(e) = device.check(ar) {
                println!("ar {} named again is refused: {e}", ar.number);
            }
        }
    }
    device.close();
    println!(
        "ARs in data exchange {}  cycles {cycles}  Q echoed in data exchange {echoed}  last \
         ended {:?}",
        program.ars_in_data,
        program.ended.map(|a| a.number)
    );
    Ok(())
}
