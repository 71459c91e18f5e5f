// SPDX-License-Identifier: MIT OR Apache-2.0
//! Control blocks (PrmEnd, ApplicationReady, Release, PrmBegin and their answers) and what
//! may follow them in a Control call (an ApplicationReady carries a ModuleDiffBlock).
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::wire::common::blocks;
use procimg_profinet::wire::connect::ModuleDiffBlock;
use procimg_profinet::wire::control::{BLOCK_LEN, ControlBlock, Packet};

fuzz_target!(|data: &[u8]| {
    if let Ok(p) = Packet::new_checked(data) {
        let _ = (p.header(), p.reserved(), p.ar_uuid(), p.session_key());
        let _ = (p.alarm_sequence_number(), p.control_command());
        let _ = p.control_block_properties();
    }
    let Ok(c) = ControlBlock::parse(data) else {
        return;
    };
    let _ = c.to_string();
    // Every field is kept but the reserved one, which emits as 0.
    let bytes = c.to_bytes();
    assert_eq!(bytes.len(), c.buffer_len());
    assert_eq!(&bytes[..6], &data[..6]);
    assert_eq!(&bytes[8..], &data[8..BLOCK_LEN]);
    assert_eq!(ControlBlock::parse(&bytes), Ok(c));
    assert!(c.is_request() != c.is_response());
    // A request's Done response answers it, and no other block does unless equal in what
    // `answers` compares.
    if let Some(res) = ControlBlock::done_response_for(&c) {
        assert!(c.is_request());
        assert!(res.answers(&c));
        assert!(res.is_response() && res.is_done());
        assert_eq!(ControlBlock::parse(&res.to_bytes()), Ok(res));
    } else {
        assert!(c.is_response());
    }
    // What follows the control block.
    for (_, block) in blocks(&data[BLOCK_LEN..]).map_while(Result::ok) {
        if let Ok(d) = ModuleDiffBlock::parse(block) {
            let v = d.to_vec().expect("a parsed ModuleDiffBlock emits");
            assert_eq!(ModuleDiffBlock::parse(&v), Ok(d));
        }
    }
});
