// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PNIO blocks of a Connect request and response (the bytes after the NDR header): each
//! block type alone, the whole request and response with their round trips, and the C_SDU
//! layout and IOCRBlockReqs a controller would build for the submodules a request expects.
#![no_main]

use libfuzzer_sys::fuzz_target;
use procimg_profinet::iocr_layout::IocrLayout;
use procimg_profinet::wire::common::blocks;
use procimg_profinet::wire::connect::{
    AlarmCrBlockReq, AlarmCrBlockRes, ArBlockReq, ArBlockRes, ArServerBlock, ConnectRequest,
    ConnectResponse, ExpectedSubmoduleBlockReq, IocrBlockReq, IocrBlockRes, ModuleDiffBlock,
    iocr_type,
};

/// parse → to_vec → parse gives the same block, of `buffer_len` bytes.
macro_rules! block_round_trip {
    ($data:expr, $($t:ty),+ $(,)?) => {$(
        if let Ok(b) = <$t>::parse($data) {
            let v = b.to_vec().expect(concat!("a parsed ", stringify!($t), " emits"));
            assert_eq!(v.len(), b.buffer_len());
            assert_eq!(<$t>::parse(&v), Ok(b));
        }
    )+};
}

fuzz_target!(|data: &[u8]| {
    // Every block type on its own, at the start of the input and at each block boundary.
    for block in blocks(data)
        .map_while(Result::ok)
        .map(|(_, b)| b)
        .chain([data])
    {
        block_round_trip!(
            block,
            ArBlockReq,
            IocrBlockReq,
            AlarmCrBlockReq,
            ExpectedSubmoduleBlockReq,
            ArBlockRes,
            IocrBlockRes,
            AlarmCrBlockRes,
            ArServerBlock,
        );
        if let Ok(d) = ModuleDiffBlock::parse(block) {
            for (_, _, _, state) in d.submodules() {
                let _ = (
                    state.is_usable(),
                    state.ar_info(),
                    state.ident_info(),
                    state.add_info(),
                );
            }
            let v = d.to_vec().expect("a parsed ModuleDiffBlock emits");
            assert_eq!(ModuleDiffBlock::parse(&v), Ok(d));
        }
    }
    if let Ok(req) = ConnectRequest::parse(data) {
        request(&req);
    }
    if let Ok(res) = ConnectResponse::parse(data) {
        response(data, &res);
    }
});

fn request(req: &ConnectRequest) {
    // Each parsed block has the length it had, so the request emits (in the S7's block
    // order, which may differ from the input's) and parses back.
    let v = req.to_vec().expect("a parsed request emits");
    assert_eq!(v.len(), req.buffer_len());
    assert_eq!(ConnectRequest::parse(&v).as_ref(), Ok(req));
    for cr in &req.iocrs {
        let _ = (cr.rt_class(), cr.period_ns());
    }
    // What a controller would ask for these submodules.
    let subs: Vec<_> = req.submodules().collect();
    let Ok(layout) = IocrLayout::new(&subs) else {
        return;
    };
    for (t, cr) in [
        (iocr_type::INPUT, &layout.input),
        (iocr_type::OUTPUT, &layout.output),
    ] {
        assert!(usize::from(cr.data_length) >= 40);
        let block = IocrBlockReq::from_layout(t, 1, 0x8000, cr, &subs)
            .expect("the layout's submodule indices are valid");
        assert_eq!(block.data_length, cr.data_length);
        // Fewer than 65536 entries of each kind per API fit a block.
        if let Ok(v) = block.to_vec() {
            assert_eq!(IocrBlockReq::parse(&v), Ok(block));
        }
    }
}

fn response(data: &[u8], res: &ConnectResponse) {
    match res.to_vec() {
        Ok(v) => {
            assert_eq!(v.len(), res.buffer_len());
            assert_eq!(ConnectResponse::parse(&v).as_ref(), Ok(res));
        }
        // Only an ARServerBlock near 64 KiB whose padding grows to the canonical length can
        // outgrow its BlockLength.
        Err(_) => assert!(data.len() > 0xfff0),
    }
    for cr in &res.iocrs {
        assert!(res.frame_id(cr.iocr_reference).is_some());
    }
}
