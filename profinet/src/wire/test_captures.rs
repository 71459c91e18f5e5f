// SPDX-License-Identifier: MIT OR Apache-2.0
//! The captured CM frames the wire tests check against, read from the capture files in
//! `tests/fixtures/captures` so that each frame's bytes are kept once.

use crate::test_fixtures::capture;

/// Bytes in front of a captured RPC PDU: 14 Ethernet + 20 IPv4 + 8 UDP.
const RPC_PDU_OFFSET: usize = 42;
/// Where the PNIO blocks of a captured RPC frame start: after the 80-byte RPC header and the
/// 20-byte NDR header.
const BLOCKS_OFFSET: usize = RPC_PDU_OFFSET + 80 + 20;
/// Offset of the NDR ActualCount (the last field of the NDR header).
const ACTUAL_COUNT: core::ops::Range<usize> = BLOCKS_OFFSET - 4..BLOCKS_OFFSET;

/// The RPC PDU of a captured Ethernet/IPv4/UDP frame, e.g. `rpc_pdu("cm/prmend_req")`.
pub(crate) fn rpc_pdu(name: &str) -> Vec<u8> {
    capture(name)[RPC_PDU_OFFSET..].to_vec()
}

/// The PNIO blocks of a captured RPC frame, checked against the NDR ActualCount (read in the
/// frame's DREP order).
pub(crate) fn capture_blocks(name: &str) -> Vec<u8> {
    let frame = capture(name);
    // DREP is the fifth byte of the RPC header; its high nibble 1 means little-endian.
    let little_endian = frame[RPC_PDU_OFFSET + 4] & 0xf0 == 0x10;
    let count: [u8; 4] = frame[ACTUAL_COUNT].try_into().unwrap();
    let count = if little_endian {
        u32::from_le_bytes(count)
    } else {
        u32::from_be_bytes(count)
    };
    let blocks = frame[BLOCKS_OFFSET..].to_vec();
    assert_eq!(blocks.len(), count as usize, "{name}: NDR ActualCount");
    blocks
}
