// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller services through the real `procimgd --demo`, as a client program uses
//! them: record jobs with references, alarms with acknowledgement, device activation with
//! its confirmation and the DEV_FAILURE / DEV_RETURN it causes, and the diagnosis.

use procimg_client::{
    AlarmReport, ControlError, DeviceState, FailureCause, Notification, RecordError, RecordTarget,
    Refusal, ServiceOptions, Services,
};
use procimg_profinet::device::{SIM_ALARM_INDEX, SIM_ALARM_USI};
use procimg_profinet::wire::record::Im0;
use procimg_testkit::{Launch, Procimgd};
use std::time::{Duration, Instant};

const WAIT: Duration = Duration::from_secs(5);

fn device(s: &Services, name: &str) -> u32 {
    let devices = s.control().status().expect("status").devices;
    devices
        .iter()
        .position(|d| d.name == name)
        .unwrap_or_else(|| panic!("no device {name:?} in {devices:?}")) as u32
}

/// Waits for the first notification `pick` accepts; the others seen meanwhile are returned
/// too, in order.
fn wait_for<T>(
    s: &mut Services,
    what: &str,
    mut pick: impl FnMut(&Notification) -> Option<T>,
) -> (T, Vec<Notification>) {
    let until = Instant::now() + WAIT;
    let mut seen = Vec::new();
    while Instant::now() < until {
        if let Some(n) = s.next(Duration::from_millis(100)) {
            if let Some(t) = pick(&n) {
                return (t, seen);
            }
            seen.push(n);
        }
    }
    panic!("no {what} within {WAIT:?}; seen: {seen:?}");
}

#[test]
fn records_alarms_activation_and_diagnosis_reach_clients() {
    let server = Procimgd::demo("services");
    server.wait_devices_running(Duration::from_secs(10));
    let instance = server.instance.clone();
    let mut plc = Services::open(
        &instance,
        ServiceOptions::new("plc").acknowledge_alarms(true),
    )
    .expect("open the services");
    let mut observer =
        Services::open(&instance, ServiceOptions::new("observer")).expect("a second handle");
    let echo = device(&plc, "echo");
    let dio = device(&plc, "dio");

    // I&M0 of the echo device: its identity from the simulated device's description.
    let im0 = RecordTarget {
        device: echo,
        api: 0,
        slot: 0,
        subslot: 1,
        index: 0xAFF0,
    };
    let data = plc.read_record(im0, 4096, WAIT).expect("I&M0 read");
    let im0 = Im0::parse(&data).expect("an I&M0 block");
    assert_eq!(im0.vendor_id, 0x0493);
    assert_eq!(im0.order_id_str(), Some("PROCIMG-SIM"));

    // A record written is read back; the confirmation of an asynchronous job carries its
    // reference and reaches only the handle that asked.
    let user = RecordTarget {
        device: echo,
        api: 0,
        slot: 1,
        subslot: 1,
        index: 0x0010,
    };
    plc.write_record(user, &[1, 2, 3], WAIT)
        .expect("record write");
    plc.record_read(user, 16, 4711).expect("job taken");
    let (confirmation, _) = wait_for(&mut plc, "record confirmation", |n| match n {
        Notification::Record { confirmation, .. } => Some(confirmation.clone()),
        _ => None,
    });
    assert_eq!(confirmation.reference, 4711);
    assert!(confirmation.status.is_ok(), "{confirmation:?}");
    assert_eq!(confirmation.data, [1, 2, 3]);
    assert!(
        std::iter::from_fn(|| observer.try_next())
            .all(|n| !matches!(n, Notification::Record { .. })),
        "another handle's confirmation reached the observer"
    );

    // The longest record a job carries crosses in RPC fragments both ways.
    let long: Vec<u8> = (0..4096u32).map(|i| (i % 251) as u8).collect();
    let big = RecordTarget {
        index: 0x0011,
        ..user
    };
    plc.write_record(big, &long, WAIT)
        .expect("a 4096-byte record write");
    assert_eq!(plc.read_record(big, 4096, WAIT).expect("read back"), long);

    // A record the device does not have: the device's PNIORW status comes back.
    let missing = RecordTarget {
        index: 0x1234,
        ..user
    };
    match plc.read_record(missing, 16, WAIT) {
        Err(RecordError::Failed { status, .. }) => {
            assert_eq!((status.error_code, status.error_decode), (0xDE, 0x80));
        }
        other => panic!("a read of a missing record gave {other:?}"),
    }

    // An alarm goes to every handle; the device's AlarmAck waits for the handle that takes
    // part in acknowledgement.
    let trigger = RecordTarget {
        index: SIM_ALARM_INDEX,
        ..user
    };
    plc.write_record(trigger, &[0xab], WAIT)
        .expect("alarm trigger written");
    let (alarm, _) = wait_for(&mut plc, "alarm", |n| match n {
        Notification::Alarm(a) => Some(a.clone()),
        _ => None,
    });
    let check = |a: &AlarmReport| {
        assert_eq!(a.device, echo);
        assert_eq!((a.slot, a.subslot, a.alarm_type), (1, 1, 2));
        assert!(a.high_priority);
        assert_eq!(a.usi(), Some(SIM_ALARM_USI));
        assert_eq!(a.payload[2..], [0xab]);
    };
    check(&alarm);
    let (seen, _) = wait_for(&mut observer, "alarm at the observer", |n| match n {
        Notification::Alarm(a) => Some(a.clone()),
        _ => None,
    });
    assert_eq!(seen, alarm);
    let waiting = |s: &Services| -> Vec<(String, u32)> {
        let st = s.control().status().expect("status");
        st.subscribers
            .into_iter()
            .map(|x| (x.name, x.alarms_waiting))
            .collect()
    };
    assert!(
        waiting(&plc).contains(&("plc".into(), 1)),
        "{:?}",
        waiting(&plc)
    );
    assert!(waiting(&plc).contains(&("observer".into(), 0)));
    plc.acknowledge(&alarm).expect("acknowledged");
    assert!(waiting(&plc).contains(&("plc".into(), 0)));
    assert!(
        plc.acknowledge(&alarm).is_err(),
        "an alarm was acknowledged twice"
    );

    // Deactivation: confirmed to the asker; the end of data exchange is a DEV_FAILURE for
    // every handle; activation brings a DEV_RETURN.
    plc.activate(dio, false).expect("deactivation taken");
    let ((), seen) = wait_for(&mut plc, "deactivation confirmation", |n| match n {
        Notification::Activation {
            device, active, ok, ..
        } if *device == dio => {
            assert!(!active && *ok);
            Some(())
        }
        _ => None,
    });
    let failure = |n: &Notification| matches!(n, Notification::DeviceFailure { device, .. } if *device == dio);
    if !seen.iter().any(failure) {
        wait_for(&mut plc, "DEV_FAILURE", |n| failure(n).then_some(()));
    }
    wait_for(&mut observer, "DEV_FAILURE at the observer", |n| {
        failure(n).then_some(())
    });
    let diag = plc.diagnosis().expect("diagnosis");
    let d = &diag.devices[dio as usize];
    assert_eq!(
        (d.name.as_str(), d.state, d.active),
        ("dio", DeviceState::Deactivated, false)
    );
    assert_eq!(
        (d.cause, d.last_error.as_str()),
        (FailureCause::Deactivated, "deactivated by a client")
    );

    plc.activate(dio, true).expect("activation taken");
    wait_for(&mut plc, "DEV_RETURN", |n| {
        matches!(n, Notification::DeviceReturn { device, .. } if *device == dio).then_some(())
    });
    let diag = plc.diagnosis().expect("diagnosis");
    assert!(
        diag.devices
            .iter()
            .all(|d| d.state == DeviceState::Running && d.active && d.cause == FailureCause::None),
        "{diag:?}"
    );
    assert_eq!(observer.lost(), 0);
}

#[test]
fn requests_the_server_cannot_take_are_refused_with_reasons() {
    let server = Procimgd::demo("services-refused");
    server.wait_devices_running(Duration::from_secs(10));
    let mut s = Services::open(&server.instance, ServiceOptions::new("refused")).expect("open");
    let nowhere = RecordTarget {
        device: 99,
        api: 0,
        slot: 0,
        subslot: 1,
        index: 0xAFF0,
    };
    let e = s.read_record(nowhere, 16, WAIT).unwrap_err();
    assert!(e.to_string().contains("no device #99"), "{e}");
    let too_long = RecordTarget {
        device: 0,
        ..nowhere
    };
    let e = s.write_record(too_long, &vec![0; 5000], WAIT).unwrap_err();
    assert!(e.to_string().contains("5000 bytes"), "{e}");
    let e = s.activate(99, false).unwrap_err();
    assert!(e.to_string().contains("no device #99"), "{e}");
    // The IO device's station services, asked of an IO controller, say so.
    let e = s.hold_application_ready(true).unwrap_err();
    assert!(
        matches!(
            &e,
            ControlError::Refused(Refusal::WrongRole { role, .. }) if role == "controller"
        ),
        "{e}"
    );

    // In OFFLINE, activation is not allowed and record jobs find no connection.
    s.control()
        .set_mode(procimg_client::Mode::Offline)
        .expect("mode change taken");
    let until = Instant::now() + WAIT;
    while s.control().status().expect("status").mode != procimg_client::Mode::Offline {
        assert!(Instant::now() < until, "OFFLINE not reached");
        std::thread::sleep(Duration::from_millis(10));
    }
    let e = s.activate(0, true).unwrap_err();
    assert!(e.to_string().contains("OFFLINE"), "{e}");
    match s.read_record(too_long, 16, WAIT) {
        Err(RecordError::Failed { status, .. }) => {
            assert_eq!(
                (status.error_code, status.error_decode, status.error_code1),
                (0xC0, 0x80, 0xA3),
                "IO-Base's status for no connection"
            );
        }
        other => panic!("a read without connection gave {other:?}"),
    }
}

/// A simulated device with one 4-byte submodule each way, behaving as `sim`.
fn sim_device(name: &str, ip: &str, sim: &str) -> String {
    format!(
        "[[device]]\nname = \"{name}\"\nip = \"{ip}\"\nvendor_id = 0x0493\ndevice_id = 0x0001\n\
         sim = \"{sim}\"\nwatchdog_factor = 100\n[[device.submodule]]\nslot = 1\nsubslot = 1\n\
         module_ident = 0x20\nsubmodule_ident = 0x01\ninput_length = 4\noutput_length = 4\n"
    )
}

#[test]
fn a_device_absent_from_the_simulated_network_is_not_found_while_the_other_runs() {
    let config = format!(
        "network = \"sim\"\n{}{}",
        sim_device("here", "10.0.0.2", "echo"),
        sim_device("gone", "10.0.0.3", "absent")
    );
    let server = Launch::config("services-absent", &config)
        .until_cycling()
        .start();
    let s = Services::open(&server.instance, ServiceOptions::new("absent")).expect("open");
    let until = Instant::now() + 2 * WAIT;
    loop {
        let diag = s.diagnosis().expect("diagnosis");
        let (here, gone) = (&diag.devices[0], &diag.devices[1]);
        if here.state == DeviceState::Running && gone.cause == FailureCause::NotFound {
            // It failed and is looked for again, as a missing real device is.
            assert_eq!(gone.name, "gone");
            assert!(
                matches!(gone.state, DeviceState::Failed | DeviceState::Searching),
                "{gone:?}"
            );
            assert!(
                gone.last_error
                    .contains("no device named \"gone\" answered DCP Identify"),
                "{gone:?}"
            );
            break;
        }
        assert!(Instant::now() < until, "{diag:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}
