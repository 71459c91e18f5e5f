// SPDX-License-Identifier: MIT OR Apache-2.0
//! procimgd started as a program's own stack (`procimg_client::iobase::Stack`, under PN
//! Driver's `SERV_CP_startup`): it serves the configuration handed over, refuses a bad one
//! with procimgd's reason, does not start twice for one instance, and stops when shut down.

use procimg_client::iobase::{Stack, StackStart, StackStartError, instance_serves};
use procimg_client::{AttachOptions, Client};
use procimg_testkit::{procimgd_bin, unique_instance};
use std::sync::{Arc, Mutex};

/// The demo configuration, as `procimgd --print-demo-config` prints it.
fn demo_config() -> Vec<u8> {
    let out = std::process::Command::new(procimgd_bin())
        .arg("--print-demo-config")
        .output()
        .expect("run procimgd --print-demo-config");
    assert!(out.status.success());
    out.stdout
}

fn start<'a>(config: &'a [u8], instance: &'a str) -> StackStart<'a> {
    StackStart {
        program: Some(procimgd_bin()),
        ..StackStart::new(config, instance)
    }
}

#[test]
fn a_stack_serves_its_configuration_until_it_is_shut_down() {
    let instance = unique_instance("stack");
    let config = demo_config();
    let lines = Arc::new(Mutex::new(Vec::<String>::new()));
    let kept = lines.clone();
    let stack = Stack::start(StackStart {
        log: Some(Box::new(move |l: &str| {
            kept.lock().unwrap().push(l.to_string())
        })),
        ..start(&config, &instance)
    })
    .expect("the demo configuration starts");
    assert_eq!(stack.instance(), instance);
    let client =
        Client::attach(&instance, AttachOptions::asynchronous("stack-test")).expect("attach");
    assert!(
        client.layout().device("echo").is_some(),
        "the demo's devices"
    );
    drop(client);

    // One instance, one stack.
    let again = Stack::start(start(&config, &instance));
    assert!(
        matches!(again, Err(StackStartError::AlreadyRunning { .. })),
        "{again:?}"
    );

    let status = stack.shutdown().expect("a clean stop");
    assert!(status.success());
    assert!(!instance_serves(&instance));
    let lines = lines.lock().unwrap();
    assert!(
        lines
            .iter()
            .any(|l| l.contains(&format!("instance \"{instance}\" cycling"))),
        "procimgd's log reached the program: {lines:?}"
    );
    assert!(
        lines.iter().any(|l| l.contains("standard input closed")),
        "shut down by closing its standard input: {lines:?}"
    );
}

#[test]
fn a_configuration_procimgd_cannot_use_is_refused_with_its_line_and_key() {
    let instance = unique_instance("stack-bad");
    let config = b"cycle_time = \"1ms\"\ncycle_thread = 3\n\0ignored after the NUL";
    let err = Stack::start(start(config, &instance)).expect_err("a bad configuration");
    let StackStartError::Configuration { reason } = &err else {
        panic!("not a configuration error: {err:?}");
    };
    assert!(
        reason.contains("standard input:2") && reason.contains("cycle_thread"),
        "{reason}"
    );
    assert!(!instance_serves(&instance));
}

#[test]
fn a_missing_procimgd_is_named_with_what_to_do() {
    let instance = unique_instance("stack-none");
    let err = Stack::start(StackStart {
        program: Some("/nonexistent/procimgd".into()),
        ..StackStart::new(b"", &instance)
    })
    .expect_err("no such program");
    let text = err.to_string();
    assert!(
        text.contains("/nonexistent/procimgd") && text.contains("PROCIMGD"),
        "{text}"
    );
}
