// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy from an IO-Base controller program (`tests/c/iobase_pe.c`, strict warnings,
//! statically and dynamically linked) against the demo: the calls' refusals and every
//! command's confirmation.

use procimg_testkit::Launch;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use std::time::Duration;

#[test]
fn a_controller_program_sends_pe_commands_and_gets_their_answers() {
    let server = Launch::demo("cpe").until_cycling().start();
    for link in [Link::Static, Link::Shared] {
        let src = crate_dir().join("tests/c/iobase_pe.c");
        let program = scratch("iobase_pe").join(format!("pe-{link:?}").to_lowercase());
        compile(&[src], &program, link, sanitize_from_env());
        let o = run(&program, &[], &server.instance, Duration::from_secs(60));
        assert_success(&o, &format!("iobase_pe ({link:?})"));
        assert!(String::from_utf8_lossy(&o.stdout).contains("pe: all checks held"));
    }
}
