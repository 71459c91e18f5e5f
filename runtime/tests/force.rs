// SPDX-License-Identifier: MIT OR Apache-2.0
//! The force table against the real procimgd and its simulated devices: forced outputs reach
//! the device over what a client writes and stay after the forcing process is gone; forced
//! inputs are what clients read; unforcing gives the process back; a restart forgets them.

use procimg_client::{AttachOptions, Client, ControlError, ControlHandle, Ioxs, Refusal, Space};
use procimg_testkit::Procimgd;
use std::time::{Duration, Instant};

/// How long a value may take through the cycle, the simulated device and back, on a loaded
/// machine.
const ROUND_TRIP: Duration = Duration::from_secs(5);

/// Waits until `read` gives `want`, or fails naming what was last read.
fn await_bytes(what: &str, want: &[u8], mut read: impl FnMut() -> Vec<u8>) {
    let until = Instant::now() + ROUND_TRIP;
    loop {
        let got = read();
        if got == want {
            return;
        }
        assert!(
            Instant::now() < until,
            "{what}: wanted {want:02x?}, still {got:02x?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

fn inputs(c: &mut Client, address: u32, len: usize) -> Vec<u8> {
    let mut buf = vec![0; len];
    c.data_read(address, &mut buf, Ioxs::Good).unwrap();
    buf
}

fn outputs(c: &mut Client, address: u32, len: usize) -> (Vec<u8>, Ioxs) {
    let mut buf = vec![0; len];
    let r = c.output_data_read(address, &mut buf).unwrap();
    (buf, r.local)
}

#[test]
fn forced_outputs_win_over_the_owner_and_outlive_the_forcing_process() {
    let server = Procimgd::demo("force-q");
    let mut owner = Client::attach(&server.instance, AttachOptions::asynchronous("owner")).unwrap();
    let echo = owner.layout().find("echo", 1, 1).unwrap();
    owner.claim(&[echo]).unwrap();
    let written = [0x11; 16];
    owner.data_write(0, &written, Ioxs::Good).unwrap();
    await_bytes("the owner's echo", &written, || inputs(&mut owner, 0, 16));

    // Forced from a handle that is gone right after: the force stays in the server.
    let forced: Vec<u8> = (1..=16).collect();
    ControlHandle::open(&server.instance, "forcer")
        .unwrap()
        .force(Space::Output, 0, &forced)
        .unwrap();
    await_bytes("the forced echo", &forced, || inputs(&mut owner, 0, 16));
    // The owner writes on; the device still gets the forced values.
    owner.data_write(0, &[0x22; 16], Ioxs::Good).unwrap();
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(outputs(&mut owner, 0, 16), (forced.clone(), Ioxs::Good));

    let st = server.status();
    assert_eq!(st.forces.len(), 1, "{:?}", st.forces);
    let f = &st.forces[0];
    assert_eq!(
        (f.space, f.address, &f.data[..]),
        (Space::Output, 0, &forced[..])
    );
    assert_eq!((f.device.as_str(), f.slot, f.subslot), ("echo", 1, 1));

    // With nobody owning the outputs, forced ones still go out valid.
    drop(owner);
    let mut reader = Client::attach(&server.instance, AttachOptions::asynchronous("r")).unwrap();
    let until = Instant::now() + ROUND_TRIP;
    while server.status().clients.iter().any(|c| c.name == "owner") {
        assert!(Instant::now() < until, "the owner was not reaped");
        std::thread::sleep(Duration::from_millis(20));
    }
    std::thread::sleep(Duration::from_millis(20));
    assert_eq!(outputs(&mut reader, 0, 16), (forced.clone(), Ioxs::Good));

    // Unforced: the process is the program's again.
    let control = ControlHandle::open(&server.instance, "unforcer").unwrap();
    control.unforce(Space::Output, 0, None).unwrap();
    let mut owner =
        Client::attach(&server.instance, AttachOptions::asynchronous("owner2")).unwrap();
    owner.claim(&[echo]).unwrap();
    owner.data_write(0, &[0x33; 16], Ioxs::Good).unwrap();
    await_bytes("the new owner's echo", &[0x33; 16], || {
        inputs(&mut owner, 0, 16)
    });
    assert!(server.status().forces.is_empty());
}

#[test]
fn forced_inputs_are_what_clients_read_and_a_restart_forgets_them() {
    let mut server = Procimgd::demo("force-i");
    let control = ControlHandle::open(&server.instance, "forcer").unwrap();
    let mut c = Client::attach(&server.instance, AttachOptions::asynchronous("reader")).unwrap();
    let counter = c.layout().find("counter", 1, 1).unwrap();
    let at = c.layout().submodules[counter].input_address;
    control
        .force(Space::Input, at, &[0xde, 0xad, 0xbe, 0xef])
        .unwrap();
    await_bytes("the forced counter", &[0xde, 0xad, 0xbe, 0xef], || {
        inputs(&mut c, at, 4)
    });
    // A part of a submodule: the other bytes keep counting.
    control.unforce(Space::Input, at, Some(2)).unwrap();
    let st = server.status();
    assert_eq!(st.forces.len(), 1);
    assert_eq!(
        (st.forces[0].address, &st.forces[0].data[..]),
        (at + 2, &[0xbe, 0xef][..])
    );
    drop(c);
    drop(control);

    server.kill();
    server.restart();
    assert!(
        server.status().forces.is_empty(),
        "a new server starts without forces"
    );
    let mut c = Client::attach(&server.instance, AttachOptions::asynchronous("reader")).unwrap();
    let first = inputs(&mut c, at, 4);
    let until = Instant::now() + ROUND_TRIP;
    while inputs(&mut c, at, 4) == first {
        assert!(
            Instant::now() < until,
            "the counter stands still at {first:02x?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn forces_outside_a_submodule_are_refused_with_the_reason() {
    let server = Procimgd::demo("force-refused");
    let control = ControlHandle::open(&server.instance, "forcer").unwrap();
    let refusal = |r: Result<(), ControlError>| match r {
        Err(ControlError::Refused(r)) => r,
        other => panic!("not refused: {other:?}"),
    };
    assert_eq!(
        refusal(control.force(Space::Output, 1, &[0; 16])),
        Refusal::PastSubmoduleEnd {
            space: Space::Output,
            address: 1,
            length: 16,
            room: 15
        }
    );
    assert_eq!(
        refusal(control.force(Space::Output, 9999, &[0])),
        Refusal::NoSuchAddress {
            space: Space::Output,
            address: 9999
        }
    );
    // The echo device's DAP has a diagnostic address, and no data to force there.
    let diag = Client::attach(&server.instance, AttachOptions::asynchronous("t"))
        .unwrap()
        .layout()
        .submodules[0]
        .diagnostic_address()
        .expect("the DAP has a diagnostic address");
    let r = refusal(control.force(Space::Input, diag, &[0]));
    assert!(r.to_string().contains("procimg layout"), "{r}");
    assert!(server.status().forces.is_empty());
    // Unforcing all when nothing is forced is fine.
    control.unforce_all().unwrap();
}
