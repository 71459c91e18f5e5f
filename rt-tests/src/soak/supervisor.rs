// SPDX-License-Identifier: MIT OR Apache-2.0
//! The soak itself: brings everything up, then until the time is over asks for a record every
//! second and makes the device raise or clear a diagnosis every few seconds (each must reach
//! the services client), and at random moments kills the client, the device or procimgd and
//! measures how long until all works again. One thing at a time: no fault falls into a
//! probe, so every record or alarm that does not arrive is lost, not interrupted.

use crate::baseline::Baseline;
use crate::capture::Capture;
use crate::monitor::{Monitor, RecordOutcome};
use crate::process::Running;
use crate::rig::{Plan, Programs, Rig};
use crate::tally::Tally;
use anyhow::{Context as _, bail};
use procimg_client::{ControlHandle, DeviceState, RecordTarget, StatusReport};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What the soak is asked to do.
pub struct Settings {
    /// How long.
    pub duration: Duration,
    /// procimgd's cycle.
    pub cycle: Duration,
    /// DataHoldFactor of the IOCRs.
    pub watchdog_factor: u32,
    /// Mean time between faults.
    pub mean_gap: Duration,
    /// Seed of the schedule.
    pub seed: u64,
    /// Logs and results.
    pub out: PathBuf,
    /// Whether tshark checks the frames.
    pub capture: bool,
}

/// How long the soak waits for something to work again before it counts a failed recovery.
const RECOVERY_TIMEOUT: Duration = Duration::from_secs(30);
/// How long a diagnosis alarm may take to reach the services client.
const ALARM_TIMEOUT: Duration = Duration::from_secs(5);
/// How often the device raises or clears its diagnosis.
const ALARM_PERIOD: Duration = Duration::from_secs(5);
/// How often a record is read.
const RECORD_PERIOD: Duration = Duration::from_secs(1);
/// The device's input submodule: where its diagnosis is.
const DIAGNOSIS_SLOT: u16 = 1;
/// I&M0 of the device's DAP.
const IM0: RecordTarget = RecordTarget {
    device: 0,
    api: 0,
    slot: 0,
    subslot: 1,
    index: 0xAFF0,
};

/// A fault the schedule picks.
#[derive(Clone, Copy, Debug)]
enum Fault {
    Client,
    Device,
    Procimgd { sigkill: bool },
}

/// The random schedule (xorshift64*: repeatable from the seed).
struct Schedule {
    state: u64,
    mean_gap: Duration,
}

impl Schedule {
    fn new(seed: u64, mean_gap: Duration) -> Schedule {
        Schedule {
            state: seed.max(1),
            mean_gap,
        }
    }

    fn next(&mut self) -> u64 {
        self.state ^= self.state >> 12;
        self.state ^= self.state << 25;
        self.state ^= self.state >> 27;
        self.state.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Between half and one and a half of the mean gap.
    fn gap(&mut self) -> Duration {
        let fraction = (self.next() % 1001) as f64 / 1000.0;
        self.mean_gap.mul_f64(0.5 + fraction)
    }

    /// Client and device twice as often as procimgd.
    fn fault(&mut self) -> Fault {
        match self.next() % 10 {
            0..4 => Fault::Client,
            4..8 => Fault::Device,
            8 => Fault::Procimgd { sigkill: true },
            _ => Fault::Procimgd { sigkill: false },
        }
    }
}

/// The soak's state.
struct Soak {
    rig: Rig,
    monitor: Option<Monitor>,
    control: Option<ControlHandle>,
    tally: Tally,
    /// The last status of the running procimgd.
    life: Option<StatusReport>,
    /// The last `COUNT` of the running client.
    client_life: Counts,
    /// Whether the running client has had an answer since it (re-)attached.
    client_echoed: bool,
    /// AlarmAcks the running device counted.
    device_acked: u64,
    /// AlarmAcks of the devices before it.
    device_acked_before: u64,
    /// Ctrl-C.
    interrupted: Arc<AtomicBool>,
}

/// Runs the soak.
pub fn run(settings: &Settings) -> anyhow::Result<Tally> {
    let interrupted = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, interrupted.clone())
            .context("installing a signal handler")?;
    }
    let plan = Plan {
        cycle: settings.cycle,
        watchdog_factor: settings.watchdog_factor,
    };
    let rig = Rig::new(Programs::beside_me()?, &settings.out, &plan)?;
    let mut capture = if settings.capture {
        let (ns, iface) = rig.device_side();
        Some(Capture::start(
            ns,
            iface,
            &rig.procimgd_mac()?,
            &settings.out,
        )?)
    } else {
        None
    };
    let baseline = Baseline::start(
        settings.cycle,
        settings.duration + Duration::from_secs(600),
        &settings.out,
    )?;
    let mut soak = Soak {
        rig,
        monitor: None,
        control: None,
        tally: Tally {
            seed: settings.seed,
            cycle_us: settings.cycle.as_micros() as u64,
            ..Tally::default()
        },
        life: None,
        client_life: Counts::default(),
        client_echoed: false,
        device_acked: 0,
        device_acked_before: 0,
        interrupted: interrupted.clone(),
    };
    soak.bring_up()?;
    soak.monitor = Some(Monitor::start(&soak.rig.instance));

    let mut schedule = Schedule::new(settings.seed, settings.mean_gap);
    let started = Instant::now();
    let deadline = started + settings.duration;
    let mut next_fault = started + schedule.gap();
    let mut next_alarm = started + ALARM_PERIOD;
    let mut next_check = started + Duration::from_secs(60);
    while Instant::now() < deadline && !interrupted.load(Ordering::Relaxed) {
        soak.pump();
        let now = Instant::now();
        if now >= next_fault {
            let fault = schedule.fault();
            soak.inflict(fault)?;
            next_fault = Instant::now() + schedule.gap();
            continue;
        }
        if now >= next_check {
            if let Some(c) = capture.as_mut() {
                c.check_finished()?;
            }
            next_check = Instant::now() + Duration::from_secs(60);
            continue;
        }
        if soak.device_running() {
            if now >= next_alarm {
                soak.probe_alarm();
                next_alarm = Instant::now() + ALARM_PERIOD;
            } else {
                soak.probe_record();
            }
        }
        let wake = (Instant::now() + RECORD_PERIOD)
            .min(next_fault)
            .min(next_alarm)
            .min(deadline);
        std::thread::sleep(wake.saturating_duration_since(Instant::now()));
    }
    soak.tally.seconds = started.elapsed().as_secs_f64();
    soak.shut_down();
    if let Some(c) = capture {
        soak.tally.frames = Some(c.finish()?.into());
    }
    if let Some(b) = baseline {
        soak.tally.cyclictest = Some(b.finish()?);
    }
    Ok(soak.tally)
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1000.0
}

impl Soak {
    /// Device, procimgd and client, until the client has its first answer.
    fn bring_up(&mut self) -> anyhow::Result<()> {
        self.rig.start_device()?;
        self.rig.start_procimgd()?;
        if self
            .wait(RECOVERY_TIMEOUT * 2, Soak::device_running)
            .is_none()
        {
            bail!(
                "procimgd did not bring the device to data exchange in {:?}: see the logs in {}",
                RECOVERY_TIMEOUT * 2,
                self.rig.logs().display()
            );
        }
        self.client_echoed = false;
        self.rig.start_client()?;
        if self.wait(RECOVERY_TIMEOUT, |s| s.client_echoed).is_none() {
            bail!(
                "the client had no answer from the device in {RECOVERY_TIMEOUT:?}: see {}",
                self.rig.logs().display()
            );
        }
        Ok(())
    }

    /// procimgd's status (and the control handle opened again when it went away).
    fn status(&mut self) -> Option<StatusReport> {
        if self.control.is_none() {
            self.control = ControlHandle::open(&self.rig.instance, "soak-status").ok();
        }
        match self.control.as_ref()?.status() {
            Ok(s) => {
                if self.life.as_ref().is_none_or(|l| l.pid == s.pid) {
                    self.life = Some(s.clone());
                }
                Some(s)
            }
            Err(_) => {
                self.control = None;
                None
            }
        }
    }

    fn device_running(&mut self) -> bool {
        self.status().is_some_and(|s| {
            s.devices
                .first()
                .is_some_and(|d| d.state == DeviceState::Running)
        })
    }

    /// Polls `done` every 10 ms for up to `timeout`; how long it took.
    fn wait(
        &mut self,
        timeout: Duration,
        mut done: impl FnMut(&mut Soak) -> bool,
    ) -> Option<Duration> {
        let start = Instant::now();
        loop {
            self.pump();
            if done(self) {
                return Some(start.elapsed());
            }
            if start.elapsed() >= timeout || self.interrupted.load(Ordering::Relaxed) {
                return None;
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Takes what the client and the device printed.
    fn pump(&mut self) {
        if let Some(c) = &self.rig.client {
            for line in c.take_lines() {
                match line.as_str() {
                    "ECHO" => self.client_echoed = true,
                    "REATTACHED" => self.client_echoed = false,
                    l => {
                        if let Some(counts) = l.strip_prefix("COUNT ") {
                            self.client_life = parse_counts(counts);
                        }
                    }
                }
            }
        }
        if let Some(d) = &self.rig.device {
            for line in d.take_lines() {
                if let Some(n) = line.strip_prefix("ALARMS acked ")
                    && let Ok(n) = n.parse()
                {
                    self.device_acked = n;
                }
            }
        }
    }

    /// Adds the ended procimgd's figures.
    fn close_procimgd(&mut self) {
        if let Some(s) = self.life.take() {
            let t = &mut self.tally;
            t.cycles += s.cycle_count;
            t.overruns += s.overruns;
            t.opfaults += s.opfaults;
            t.watchdog_expiries += s.network.watchdog_expiries;
            t.malformed_received += s.network.malformed + s.network.malformed_datagrams;
            t.rt_heap_allocations += s.rt_heap_allocations;
        }
        self.control = None;
    }

    /// Adds the ended client's figures.
    fn close_client(&mut self) {
        let c = std::mem::take(&mut self.client_life);
        self.tally.client_cycles += c.cycles;
        self.tally.data_errors += c.wrong;
        self.tally.stale_echoes += c.stale;
        self.tally.oldest_echo = self.tally.oldest_echo.max(c.oldest);
    }

    fn stop(slot: &mut Option<Running>, signal: i32) {
        if let Some(mut p) = slot.take() {
            p.stop(signal, Duration::from_secs(10));
        }
    }

    /// One fault, and the wait until everything works again.
    fn inflict(&mut self, fault: Fault) -> anyhow::Result<()> {
        eprintln!("procimg-soak: {fault:?}");
        match fault {
            Fault::Client => {
                self.tally.kills.client += 1;
                self.pump();
                Soak::stop(&mut self.rig.client, libc::SIGKILL);
                self.close_client();
                self.client_echoed = false;
                self.rig.start_client()?;
                match self.wait(RECOVERY_TIMEOUT, |s| s.client_echoed) {
                    Some(d) => self.tally.reconnect_ms.client.push(ms(d)),
                    None => return self.recovery_failed("the new client had no answer"),
                }
            }
            Fault::Device => {
                self.tally.kills.device += 1;
                self.pump();
                Soak::stop(&mut self.rig.device, libc::SIGKILL);
                self.device_acked_before += std::mem::take(&mut self.device_acked);
                // procimgd notices first (its watchdog), then the device comes back.
                let _ = self.wait(RECOVERY_TIMEOUT, |s| !s.device_running());
                self.rig.start_device()?;
                let since = self.rig.device.as_ref().map(|d| d.started);
                match self.wait(RECOVERY_TIMEOUT, Soak::device_running) {
                    Some(_) => {
                        let d = since.map_or(Duration::ZERO, |s| s.elapsed());
                        self.tally.reconnect_ms.device.push(ms(d));
                    }
                    None => return self.recovery_failed("the device did not come back"),
                }
            }
            Fault::Procimgd { sigkill } => {
                if sigkill {
                    self.tally.kills.procimgd_killed += 1;
                } else {
                    self.tally.kills.procimgd_terminated += 1;
                }
                self.status();
                let signal = if sigkill {
                    libc::SIGKILL
                } else {
                    libc::SIGTERM
                };
                Soak::stop(&mut self.rig.procimgd, signal);
                self.close_procimgd();
                self.rig.start_procimgd()?;
                let since = self
                    .rig
                    .procimgd
                    .as_ref()
                    .map_or_else(Instant::now, |p| p.started);
                self.client_echoed = false;
                if self.wait(RECOVERY_TIMEOUT, Soak::device_running).is_none() {
                    return self.recovery_failed("procimgd did not bring the device back");
                }
                self.tally.reconnect_ms.procimgd.push(ms(since.elapsed()));
                if self.wait(RECOVERY_TIMEOUT, |s| s.client_echoed).is_none() {
                    return self.recovery_failed("the client did not come back to procimgd");
                }
                self.tally
                    .reconnect_ms
                    .client_after_procimgd
                    .push(ms(since.elapsed()));
            }
        }
        Ok(())
    }

    /// Counts a failed recovery and starts everything again.
    fn recovery_failed(&mut self, what: &str) -> anyhow::Result<()> {
        self.tally.recoveries_failed += 1;
        eprintln!(
            "procimg-soak: {what} within {RECOVERY_TIMEOUT:?}; starting everything again \
             (logs in {})",
            self.rig.logs().display()
        );
        self.status();
        Soak::stop(&mut self.rig.client, libc::SIGKILL);
        self.close_client();
        Soak::stop(&mut self.rig.procimgd, libc::SIGTERM);
        self.close_procimgd();
        Soak::stop(&mut self.rig.device, libc::SIGTERM);
        self.device_acked_before += std::mem::take(&mut self.device_acked);
        self.bring_up()
    }

    /// One record read through procimgd.
    fn probe_record(&mut self) {
        let Some(m) = &self.monitor else { return };
        let outcome = m.read_record(IM0);
        let r = &mut self.tally.records;
        r.asked += 1;
        match outcome {
            RecordOutcome::Answered => r.answered += 1,
            RecordOutcome::Refused(why) | RecordOutcome::NoServer(why) => {
                r.refused += 1;
                eprintln!("procimg-soak: record read refused: {why}");
            }
            RecordOutcome::Lost => {
                r.lost += 1;
                eprintln!("procimg-soak: record read lost (no answer in 5 s)");
            }
        }
    }

    /// The device raises or clears its diagnosis; its alarm must reach the services client.
    fn probe_alarm(&mut self) {
        let Some(m) = &self.monitor else { return };
        let Some(device) = &self.rig.device else {
            return;
        };
        while m.alarms.try_recv().is_ok() {}
        procimg_netns::signal::send(device.pid(), libc::SIGUSR1);
        self.tally.alarms.raised += 1;
        let until = Instant::now() + ALARM_TIMEOUT;
        let mut delivered = false;
        while let Some(left) = until.checked_duration_since(Instant::now()) {
            match m.alarms.recv_timeout(left) {
                Ok(a) if a.slot == DIAGNOSIS_SLOT && matches!(a.alarm_type, 0x0001 | 0x000C) => {
                    delivered = true;
                    break;
                }
                Ok(_) => {}
                Err(_) => break,
            }
        }
        if delivered {
            self.tally.alarms.delivered += 1;
        } else {
            self.tally.alarms.lost += 1;
            eprintln!("procimg-soak: diagnosis alarm lost (not delivered in {ALARM_TIMEOUT:?})");
        }
    }

    /// Stops everything in order and adds the last figures.
    fn shut_down(&mut self) {
        self.pump();
        self.status();
        Soak::stop(&mut self.rig.client, libc::SIGKILL);
        self.close_client();
        Soak::stop(&mut self.rig.procimgd, libc::SIGTERM);
        self.close_procimgd();
        // The AlarmAck of the last alarm may still be on its way to the device's counter.
        let _ = self.wait(Duration::from_secs(1), |s| {
            s.device_acked_before + s.device_acked >= s.tally.alarms.delivered
        });
        Soak::stop(&mut self.rig.device, libc::SIGTERM);
        self.tally.alarms.acked_at_device = self.device_acked_before + self.device_acked;
    }
}

/// What the client counted: `cycles=N opfaults=N wrong=N stale=N oldest=N`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Counts {
    cycles: u64,
    wrong: u64,
    stale: u64,
    oldest: u64,
}

fn parse_counts(text: &str) -> Counts {
    let mut c = Counts::default();
    for field in text.split_whitespace() {
        let Some((key, value)) = field.split_once('=') else {
            continue;
        };
        let Ok(v) = value.parse() else { continue };
        match key {
            "cycles" => c.cycles = v,
            "wrong" => c.wrong = v,
            "stale" => c.stale = v,
            "oldest" => c.oldest = v,
            _ => {}
        }
    }
    c
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clients_counts_are_read_by_name() {
        let c = parse_counts("cycles=10 opfaults=2 wrong=0 stale=3 oldest=70");
        assert_eq!(
            c,
            Counts {
                cycles: 10,
                wrong: 0,
                stale: 3,
                oldest: 70
            }
        );
    }

    #[test]
    fn the_schedule_repeats_from_its_seed() {
        let mut a = Schedule::new(7, Duration::from_secs(20));
        let mut b = Schedule::new(7, Duration::from_secs(20));
        for _ in 0..100 {
            let gap = a.gap();
            assert_eq!(gap, b.gap());
            assert!(gap >= Duration::from_secs(10) && gap <= Duration::from_secs(30));
            assert_eq!(format!("{:?}", a.fault()), format!("{:?}", b.fault()));
        }
    }
}
