// SPDX-License-Identifier: MIT OR Apache-2.0
//! The soak's services client, on a thread of its own (iceoryx2 ports stay on the thread that
//! made them): it reads a record when asked, acknowledges the device's alarms and passes them
//! on. It lives through every restart of procimgd as a user's program would: its handle
//! announces itself again to a new server by itself; only when a request finds no server at
//! all does it open a new handle.

use procimg_client::{Notification, RecordError, RecordTarget, ServiceOptions, Services};
use std::sync::mpsc;
use std::time::Duration;

/// How long a record job may take before it counts as lost.
pub const RECORD_TIMEOUT: Duration = Duration::from_secs(5);

/// What the monitor is asked to do.
enum Command {
    /// Read the record and answer on the channel.
    ReadRecord(RecordTarget, mpsc::Sender<RecordOutcome>),
}

/// How a record job ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RecordOutcome {
    /// The device's data came back.
    Answered,
    /// An error came back (from the device or procimgd): not lost, but not expected in the
    /// steady state the soak asks in.
    Refused(String),
    /// Nothing came back within [`RECORD_TIMEOUT`].
    Lost,
    /// No services handle could be opened.
    NoServer(String),
}

/// An alarm the monitor received (and acknowledged).
#[derive(Clone, Debug)]
pub struct AlarmSeen {
    /// AlarmType.
    pub alarm_type: u16,
    /// Slot.
    pub slot: u16,
}

/// The handle on the monitor thread.
pub struct Monitor {
    commands: mpsc::Sender<Command>,
    /// The alarms, as they come.
    pub alarms: mpsc::Receiver<AlarmSeen>,
}

impl Monitor {
    /// Starts the monitor of `instance`.
    pub fn start(instance: &str) -> Monitor {
        let (commands, rx) = mpsc::channel();
        let (alarms_tx, alarms) = mpsc::channel();
        let instance = instance.to_string();
        std::thread::Builder::new()
            .name("soak-monitor".into())
            .spawn(move || serve(&instance, &rx, &alarms_tx))
            .expect("starting the monitor thread");
        Monitor { commands, alarms }
    }

    /// Reads a record through procimgd and says how it ended.
    pub fn read_record(&self, target: RecordTarget) -> RecordOutcome {
        let (tx, rx) = mpsc::channel();
        if self.commands.send(Command::ReadRecord(target, tx)).is_err() {
            return RecordOutcome::NoServer("the monitor thread ended".into());
        }
        rx.recv()
            .unwrap_or_else(|_| RecordOutcome::NoServer("the monitor thread ended".into()))
    }
}

fn open(instance: &str) -> Result<Services, String> {
    Services::open(
        instance,
        ServiceOptions::new("soak-monitor").acknowledge_alarms(true),
    )
    .map_err(|e| e.to_string())
}

fn serve(instance: &str, commands: &mpsc::Receiver<Command>, alarms: &mpsc::Sender<AlarmSeen>) {
    let mut services: Option<Services> = None;
    loop {
        match commands.recv_timeout(Duration::from_millis(20)) {
            Ok(Command::ReadRecord(target, reply)) => {
                if services.is_none() {
                    services = open(instance).ok();
                }
                let outcome = match services.as_mut() {
                    None => RecordOutcome::NoServer(
                        open(instance).err().unwrap_or_else(|| "opened late".into()),
                    ),
                    Some(s) => match s.read_record(target, 4096, RECORD_TIMEOUT) {
                        Ok(_) => RecordOutcome::Answered,
                        Err(RecordError::Timeout(_)) => RecordOutcome::Lost,
                        Err(RecordError::Failed { message, .. }) => RecordOutcome::Refused(message),
                        Err(RecordError::Control(e)) => {
                            services = None;
                            RecordOutcome::NoServer(e.to_string())
                        }
                    },
                };
                let _ = reply.send(outcome);
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => return,
        }
        if services.is_none() {
            services = open(instance).ok();
        }
        let Some(s) = services.as_mut() else { continue };
        while let Some(n) = s.try_next() {
            if let Notification::Alarm(alarm) = n {
                let _ = s.acknowledge(&alarm);
                let _ = alarms.send(AlarmSeen {
                    alarm_type: alarm.alarm_type,
                    slot: alarm.slot,
                });
            }
        }
    }
}
