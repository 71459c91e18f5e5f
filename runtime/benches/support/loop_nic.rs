// SPDX-License-Identifier: MIT OR Apache-2.0
//! A network interface that plays every device's side of the cyclic exchange: each round of
//! `receive` calls hands out one fresh input frame per device (then "nothing more"), and
//! `send` takes the output frames and only counts them.
//!
//! Handing a frame out copies it into the interface's own receive buffer first, as the
//! kernel's `recv` does for the real interface: that copy is part of what the PROFINET
//! receive figures include.

use procimg_nic::{MAX_FRAME, Nic, RecvError, SendError};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::ethernet::{self, ETHERTYPE_PROFINET, VlanTag};
use procimg_profinet::wire::rt::{self, data_status};
use procimg_shm_layout::IOXS_GOOD;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// The controller's MAC address in the benchmarks.
pub const OWN_MAC: MacAddress = MacAddress([0x02, 0x00, 0x00, 0x00, 0xff, 0xfe]);

/// What the interface saw, shared with the benchmark.
#[derive(Default)]
pub struct NicCounters {
    /// Output frames sent.
    pub sent_frames: AtomicU64,
    /// Bytes of the output frames sent.
    pub sent_bytes: AtomicU64,
}

struct InputFrame {
    bytes: Vec<u8>,
    /// Offset of the CycleCounter.
    counter_at: usize,
}

/// The devices' side of the cyclic exchange.
pub struct LoopNic {
    frames: Vec<InputFrame>,
    next: usize,
    counter: u16,
    counters: Arc<NicCounters>,
    /// The frame being received, as the AF_PACKET backend has it.
    rx: Box<[u8; MAX_FRAME]>,
}

impl LoopNic {
    /// One input frame per AR, laid out as the AR expects it: every data object GOOD, every
    /// consumer status GOOD, DataStatus OPERATE.
    pub fn new(ars: &[CyclicAr], counters: Arc<NicCounters>) -> LoopNic {
        let frames = ars
            .iter()
            .map(|ar| {
                let eth = ethernet::Repr {
                    dst: OWN_MAC,
                    src: ar.peer,
                    vlan: Some(VlanTag::RT),
                    ethertype: ETHERTYPE_PROFINET,
                };
                let rt = rt::Repr {
                    frame_id: ar.input.frame_id,
                    data_length: ar.input.data_length,
                    cycle_counter: 0,
                    data_status: data_status::OPERATE,
                    transfer_status: 0,
                };
                let at = eth.buffer_len();
                let mut bytes = vec![0u8; at + rt.buffer_len()];
                eth.emit(&mut bytes).expect("sized for the header");
                let mut packet = rt::Packet::new_unchecked(&mut bytes[at..], rt.data_length);
                rt.emit(&mut packet).expect("sized for the frame");
                let data = packet.data_mut();
                for o in &ar.input.objects {
                    data[o.data..o.data + o.len].fill(o.submodule as u8);
                    data[o.iops] = IOXS_GOOD;
                }
                for c in &ar.input.iocs {
                    data[c.offset] = IOXS_GOOD;
                }
                InputFrame {
                    bytes,
                    // FrameID, C_SDU, then the CycleCounter.
                    counter_at: at + 2 + ar.input.data_length,
                }
            })
            .collect();
        LoopNic {
            frames,
            next: 0,
            counter: 0,
            counters,
            rx: Box::new([0; MAX_FRAME]),
        }
    }
}

impl Nic for LoopNic {
    fn mac(&self) -> MacAddress {
        OWN_MAC
    }

    fn send(&mut self, frame: &[u8]) -> Result<(), SendError> {
        self.counters.sent_frames.fetch_add(1, Ordering::Relaxed);
        self.counters
            .sent_bytes
            .fetch_add(frame.len() as u64, Ordering::Relaxed);
        std::hint::black_box(frame);
        Ok(())
    }

    fn receive(&mut self, f: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError> {
        let Some(frame) = self.frames.get_mut(self.next) else {
            // End of this cycle's frames; the next call starts the next cycle's.
            self.next = 0;
            self.counter = self.counter.wrapping_add(32);
            return Ok(false);
        };
        self.next += 1;
        frame.bytes[frame.counter_at..frame.counter_at + 2]
            .copy_from_slice(&self.counter.to_be_bytes());
        // The frames are built for the ARs of the benchmarks, far below MAX_FRAME.
        let rx = &mut self.rx[..frame.bytes.len()];
        rx.copy_from_slice(&frame.bytes);
        f(rx);
        Ok(true)
    }
}
