// SPDX-License-Identifier: MIT OR Apache-2.0
//! Tailoring the IO system from C: `tests/c/iobase_tailoring.c`, built with strict warnings
//! against `pniousrx.h`, linked static and shared (with ASan and UBSan when
//! `PROCIMG_C_SANITIZE=1`), against a procimgd with one mandatory device and two optional
//! ones, one of them absent from the simulated network: PNIO_iosystem_reconfig's refusals
//! at the call and in PNIO_CBE_IOSYSTEM_RECONFIG, a tailoring that brings up the optional
//! device present and not the absent one, and DEACT.

use procimg_testkit::Launch;
use procimg_testkit::c::{
    Link, assert_success, compile, crate_dir, run, sanitize_from_env, scratch,
};
use std::time::Duration;

/// A simulated device: its access point, interface and two ports (diagnostic addresses
/// `diag`, `diag + 1`, `diag + 2`), 4 bytes each way at `io`; port 2 always, port 1 when
/// optional, with a programmable peer.
fn device(name: &str, ip: &str, sim: &str, optional: bool, io: u32, diag: u32) -> String {
    let mut t = format!(
        "[[device]]\nname = \"{name}\"\nip = \"{ip}\"\nvendor_id = 0x0493\ndevice_id = 1\n\
         sim = \"{sim}\"\nwatchdog_factor = 100\noptional = {optional}\n\
         [[device.submodule]]\nslot = 0\nsubslot = 1\nmodule_ident = 1\nsubmodule_ident = 1\n"
    );
    for (k, subslot) in [0x8000u32, 0x8001, 0x8002].into_iter().enumerate() {
        t += &format!(
            "[[device.submodule]]\nslot = 0\nsubslot = {subslot:#x}\nmodule_ident = 1\n\
             submodule_ident = {subslot:#x}\ndiagnostic_address = {}\n",
            diag + k as u32
        );
    }
    t += &format!(
        "[[device.submodule]]\nslot = 1\nsubslot = 1\nmodule_ident = 0x20\nsubmodule_ident = 1\n\
         input_length = 4\noutput_length = 4\ninput_address = {io}\noutput_address = {io}\n\
         [[device.topology]]\nsubslot = 0x8002\nprogrammable = true\n"
    );
    t += if optional {
        "[[device.topology]]\nsubslot = 0x8001\nprogrammable = true\n"
    } else {
        "[[device.topology]]\nsubslot = 0x8001\nstation = \"plc\"\nport = \"port-001\"\n"
    };
    t
}

#[test]
fn tailoring_from_c() {
    let config = format!(
        "network = \"sim\"\n{}{}{}",
        device("mandatory", "10.0.0.2", "echo", false, 0, 100),
        device("opt-present", "10.0.0.3", "echo", true, 4, 110),
        device("opt-absent", "10.0.0.4", "absent", true, 8, 120)
    );
    for link in [Link::Static, Link::Shared] {
        // Until it cycles: the optional devices wait for the program's tailoring.
        let server = Launch::config(&format!("tailor-{link:?}").to_lowercase(), &config)
            .until_cycling()
            .start();
        let src = crate_dir().join("tests/c/iobase_tailoring.c");
        let program = scratch("iobase_tailoring").join(format!("{link:?}").to_lowercase());
        compile(&[src], &program, link, sanitize_from_env());
        let o = run(&program, &[], &server.instance, Duration::from_secs(120));
        assert_success(&o, &format!("iobase_tailoring ({link:?})"));
        assert!(
            String::from_utf8_lossy(&o.stdout).contains("tailoring: all checks held"),
            "{}",
            String::from_utf8_lossy(&o.stdout)
        );
    }
}
