// SPDX-License-Identifier: MIT OR Apache-2.0
//! The CP service functions (`servusrx.h`, chapter 8) against a procimgd started with a
//! configuration file, by two C programs (`tests/c/cp_services.c`, strict warnings): one
//! holds a controller open and closes it when PNIO_CBE_CP_STOP_REQ comes; the other sets the
//! type of station, is refused what a CP refuses, and downloads a configuration, which the
//! first is asked to stop for. The new configuration runs and is the file's; the type of
//! station set is the new procimgd's.

use procimg_testkit::c::{Link, compile, crate_dir, run_with_env, sanitize_from_env, scratch};
use procimg_testkit::{Launch, procimgd_bin};
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::Duration;

/// The demo's configuration, as `procimgd --print-demo-config` prints it.
fn demo_config() -> String {
    let out = Command::new(procimgd_bin())
        .arg("--print-demo-config")
        .output()
        .expect("run procimgd --print-demo-config");
    assert!(out.status.success());
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn a_download_asks_the_running_program_to_stop_and_takes_effect() {
    let demo = demo_config();
    let server = Launch::config("cps", &demo).until_cycling().start();
    let src = crate_dir().join("tests/c/cp_services.c");
    let program = scratch("cp_services").join("cp_services");
    compile(&[src], &program, Link::Shared, sanitize_from_env());
    let new = demo.replace("cycle_time = \"1ms\"", "cycle_time = \"2ms\"");
    let new_file = scratch("cp_services").join(format!("{}.toml", server.instance));
    std::fs::write(&new_file, &new).unwrap();

    let mut holder = Command::new(&program)
        .arg("hold")
        .env_remove("LD_LIBRARY_PATH")
        .env("PROCIMG_INSTANCE", &server.instance)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the holding program");
    let mut out = BufReader::new(holder.stdout.take().expect("its output"));
    let mut line = String::new();
    out.read_line(&mut line).expect("its first line");
    assert_eq!(line.trim(), "ready");

    let o = run_with_env(
        &program,
        &["service"],
        &server.instance,
        &[("PROCIMG_TEST_CONFIG", new_file.as_os_str())],
        Duration::from_secs(60),
    );
    let said =
        String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success() && said.contains("cp: all checks held"),
        "{said}"
    );
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut out, &mut rest).unwrap();
    let status = holder.wait().unwrap();
    assert!(
        status.success() && rest.contains("closed"),
        "{status:?} {rest}"
    );

    let now = server.status();
    assert_eq!(now.cycle_ns, 2_000_000, "the downloaded configuration runs");
    assert_eq!(std::fs::read_to_string(server.config_path()).unwrap(), new);
}
