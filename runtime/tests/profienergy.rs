// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFIenergy commands through the real procimgd to the demo's simulated devices, which
//! answer as stations without energy-saving modes: every command's answer as the profile
//! gives it, a command to a submodule that is not there refused with the record job's
//! status, and the same through `procimg pe`.

use procimg_client::pe::{PeAnswer, PeCommand};
use procimg_client::{RecordError, RecordTarget, ServiceOptions, Services};
use procimg_testkit::Launch;

fn head(device: u32) -> RecordTarget {
    RecordTarget {
        device,
        api: 0,
        slot: 0,
        subslot: 1,
        index: 0x80a0,
    }
}

#[test]
fn pe_commands_reach_a_device_and_its_answers_come_back() {
    let server = Launch::demo("pe").until_cycling().start();
    let mut s = Services::open(&server.instance, ServiceOptions::new("pe")).expect("services");
    let echo = head(0);
    let identify = s.pe(echo, PeCommand::Identify).expect("PE_Identify");
    let PeAnswer::Identify { services } = identify else {
        panic!("{identify:?}");
    };
    assert!(
        services.contains(&0x01) && services.contains(&0x02),
        "{services:?}"
    );
    assert_eq!(
        s.pe(echo, PeCommand::ListModes).unwrap(),
        PeAnswer::ModeList { modes: vec![0xff] }
    );
    assert_eq!(
        s.pe(echo, PeCommand::StartPause { pause_ms: 5000 })
            .unwrap(),
        PeAnswer::Error { code: 0x06 }
    );
    assert_eq!(
        s.pe(echo, PeCommand::EndPause).unwrap(),
        PeAnswer::EndPause { time_to_operate: 0 }
    );
    let PeAnswer::PemStatus(status) = s.pe(echo, PeCommand::PemStatus).unwrap() else {
        panic!("PEM_Status");
    };
    assert_eq!((status.source, status.destination), (0xff, 0xff));
    let PeAnswer::MeasurementValues { values } = s
        .pe(echo, PeCommand::MeasurementValues { ids: vec![13, 14] })
        .unwrap()
    else {
        panic!("Get_Measurement_Values");
    };
    assert_eq!(values.len(), 2);
    assert!(
        values.iter().all(|v| v.status == 2),
        "not available: {values:?}"
    );

    // A submodule the device does not have: the write fails, with its status.
    let nowhere = RecordTarget { slot: 9, ..echo };
    match s.pe(nowhere, PeCommand::QueryVersion) {
        Err(RecordError::Failed { status, .. }) => {
            assert_eq!((status.error_code, status.error_code1), (0xdf, 0xb2))
        }
        other => panic!("a submodule that is not there: {other:?}"),
    }

    let out = std::process::Command::new(procimg_testkit::workspace_bin(
        "procimg",
        "PROCIMG_BIN",
        "procimg-tools",
    ))
    .args(["-i", &server.instance, "pe", "echo", "version"])
    .output()
    .expect("procimg pe");
    assert!(out.status.success(), "{out:?}");
    assert_eq!(
        String::from_utf8_lossy(&out.stdout).trim(),
        "PROFIenergy 1.1"
    );
}
