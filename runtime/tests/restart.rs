// SPDX-License-Identifier: MIT OR Apache-2.0
//! A running procimgd restarted by a program: a new configuration (a download) checked
//! first, the programs attached asked to stop and waited for, then the server anew with it,
//! kept in its configuration file; a reset with the configuration it runs, SAFE refused while
//! a program is attached; the type of station set for the next start; a program that does
//! not close makes the restart give up, changing nothing.

use procimg_client::{
    AttachOptions, Client, ControlError, Notification, Refusal, RestartClients, RestartError,
    ServiceOptions, Services,
};
use procimg_config::DEMO_TOML;
use procimg_testkit::Launch;
use std::time::{Duration, Instant};

const WAIT: Duration = Duration::from_secs(40);

/// Waits for the stop request among `services`' notifications.
fn stop_request(services: &mut Services) -> String {
    let until = Instant::now() + Duration::from_secs(10);
    while Instant::now() < until {
        if let Some(Notification::StopRequest { reason }) =
            services.next(Duration::from_millis(100))
        {
            return reason;
        }
    }
    panic!("no stop request within 10 s");
}

#[test]
fn a_download_asks_the_programs_to_stop_then_takes_effect_and_is_kept() {
    let server = Launch::config("rsd", DEMO_TOML).until_cycling().start();
    let first = server.status().generation;
    let mut admin =
        Services::open(&server.instance, ServiceOptions::new("rs-admin")).expect("services");

    // A configuration that does not check changes nothing.
    match admin.restart_and_wait(
        Some("cycle_time = \"3us\"\n".into()),
        RestartClients::Ask,
        WAIT,
    ) {
        Err(RestartError::Control(ControlError::Refused(Refusal::BadConfiguration {
            message,
        }))) => {
            assert!(message.contains("cycle_time"), "{message}")
        }
        other => panic!("a bad configuration: {other:?}"),
    }

    // A program attached: a SAFE reset is refused; a download asks it to stop.
    let program = Client::attach(&server.instance, AttachOptions::asynchronous("plc"))
        .expect("a program attaches");
    match admin.restart_and_wait(None, RestartClients::Refuse, WAIT) {
        Err(RestartError::Control(ControlError::Refused(Refusal::ClientsAttached { clients }))) => {
            assert!(clients[0].contains("plc"), "{clients:?}")
        }
        other => panic!("a SAFE reset with a program attached: {other:?}"),
    }
    let mut watcher =
        Services::open(&server.instance, ServiceOptions::new("rs-plc")).expect("services");
    let new = DEMO_TOML.replace("cycle_time = \"1ms\"", "cycle_time = \"2ms\"");
    assert_ne!(new, DEMO_TOML, "the demo sets its cycle time");
    let downloader = std::thread::spawn({
        let instance = server.instance.clone();
        let new = new.clone();
        move || {
            let mut s = Services::open(&instance, ServiceOptions::new("rs-download")).unwrap();
            s.restart_and_wait(Some(new), RestartClients::Ask, WAIT)
        }
    });
    let reason = stop_request(&mut watcher);
    assert!(reason.contains("configuration"), "{reason}");
    drop(program);
    let message = downloader
        .join()
        .unwrap()
        .expect("the download takes effect");
    assert!(message.contains("configuration file"), "{message}");
    let now = server.status();
    assert_ne!(now.generation, first, "a new server");
    assert_eq!(now.cycle_ns, 2_000_000);
    assert_eq!(now.instance, server.instance);
    assert_eq!(
        std::fs::read_to_string(server.config_path()).unwrap(),
        new,
        "the file holds the new configuration"
    );

    // The type of station, from the next start on: a reset.
    admin
        .set_type_of_station("procimg line 4")
        .expect("type of station");
    let before = server.status().controller.unwrap().type_of_station;
    assert_eq!(before, "procimg controller");
    admin
        .restart_and_wait(None, RestartClients::Refuse, WAIT)
        .expect("a SAFE reset with no program attached");
    let after = server.status();
    assert_eq!(after.controller.unwrap().type_of_station, "procimg line 4");
    assert_eq!(after.cycle_ns, 2_000_000, "a reset keeps the configuration");
}

#[test]
fn a_program_that_stays_makes_the_restart_give_up() {
    let server = Launch::demo("rsg").until_cycling().start();
    let first = server.status().generation;
    let _program = Client::attach(&server.instance, AttachOptions::asynchronous("stubborn"))
        .expect("a program attaches");
    let mut admin =
        Services::open(&server.instance, ServiceOptions::new("rs-admin")).expect("services");
    match admin.restart_and_wait(None, RestartClients::Ask, WAIT) {
        Err(RestartError::GivenUp(why)) => assert!(why.contains("stubborn"), "{why}"),
        other => panic!("a program that stays: {other:?}"),
    }
    assert_eq!(server.status().generation, first, "nothing changed");
}

#[test]
fn sighup_takes_the_configuration_file_into_use() {
    let server = Launch::config("rsh", DEMO_TOML).until_cycling().start();
    let first = server.status().generation;
    let new = DEMO_TOML.replace("cycle_time = \"1ms\"", "cycle_time = \"2ms\"");
    std::fs::write(server.config_path(), &new).unwrap();
    let hup = std::process::Command::new("kill")
        .args(["-HUP", &server.pid().to_string()])
        .status()
        .expect("kill -HUP");
    assert!(hup.success());
    let until = Instant::now() + WAIT;
    loop {
        let now = server.status();
        if now.generation != first {
            assert_eq!(now.cycle_ns, 2_000_000, "the file's configuration runs");
            break;
        }
        assert!(Instant::now() < until, "no restart after SIGHUP");
        std::thread::sleep(Duration::from_millis(100));
    }
}
