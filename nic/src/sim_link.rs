// SPDX-License-Identifier: MIT OR Apache-2.0
//! An in-process Ethernet link between two ends, for the simulated network and for tests:
//! what one end sends, the other receives. Bounded, lock-free, allocation-free per frame.

use crate::{MAX_FRAME, Nic, check_frame_len};
use crossbeam_queue::ArrayQueue;
use procimg_profinet::wire::MacAddress;
use std::sync::Arc;

/// Frames in flight per direction; more are dropped, as a real link drops under overload.
const DEPTH: usize = 256;

struct Slot {
    len: usize,
    data: [u8; MAX_FRAME],
}

/// One end of a simulated link.
pub struct LinkEnd {
    mac: MacAddress,
    tx: Arc<ArrayQueue<Box<Slot>>>,
    rx: Arc<ArrayQueue<Box<Slot>>>,
    /// Empty slots, returned after reading, so no frame allocates.
    free: Arc<ArrayQueue<Box<Slot>>>,
    /// Frames dropped because the link was full.
    pub dropped: u64,
}

/// A link between two ends with the given MAC addresses.
pub fn link(a: MacAddress, b: MacAddress) -> (LinkEnd, LinkEnd) {
    let ab = Arc::new(ArrayQueue::new(DEPTH));
    let ba = Arc::new(ArrayQueue::new(DEPTH));
    let free = Arc::new(ArrayQueue::new(2 * DEPTH));
    for _ in 0..2 * DEPTH {
        let _ = free.push(Box::new(Slot {
            len: 0,
            data: [0; MAX_FRAME],
        }));
    }
    (
        LinkEnd {
            mac: a,
            tx: ab.clone(),
            rx: ba.clone(),
            free: free.clone(),
            dropped: 0,
        },
        LinkEnd {
            mac: b,
            tx: ba,
            rx: ab,
            free,
            dropped: 0,
        },
    )
}

impl Nic for LinkEnd {
    fn mac(&self) -> MacAddress {
        self.mac
    }

    fn send(&mut self, frame: &[u8]) -> std::io::Result<()> {
        check_frame_len(frame)?;
        match self.free.pop() {
            Some(mut slot) => {
                slot.len = frame.len();
                slot.data[..frame.len()].copy_from_slice(frame);
                if let Err(slot) = self.tx.push(slot) {
                    self.dropped += 1;
                    let _ = self.free.push(slot);
                }
            }
            None => self.dropped += 1,
        }
        Ok(())
    }

    fn recv(&mut self, buf: &mut [u8]) -> std::io::Result<Option<usize>> {
        let Some(slot) = self.rx.pop() else {
            return Ok(None);
        };
        let n = slot.len.min(buf.len());
        buf[..n].copy_from_slice(&slot.data[..n]);
        let _ = self.free.push(slot);
        Ok(Some(n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_cross_the_link_both_ways() {
        let a = MacAddress([2, 0, 0, 0, 0, 1]);
        let b = MacAddress([2, 0, 0, 0, 0, 2]);
        let (mut x, mut y) = link(a, b);
        x.send(&[1, 2, 3]).unwrap();
        y.send(&[4; 60]).unwrap();
        let mut buf = [0u8; MAX_FRAME];
        assert_eq!(y.recv(&mut buf).unwrap(), Some(3));
        assert_eq!(&buf[..3], &[1, 2, 3]);
        assert_eq!(x.recv(&mut buf).unwrap(), Some(60));
        assert_eq!(x.recv(&mut buf).unwrap(), None);
        assert!(x.send(&[0; MAX_FRAME + 1]).is_err());
    }

    #[test]
    fn a_full_link_drops_instead_of_blocking() {
        let (mut x, _y) = link(MacAddress::default(), MacAddress::default());
        for _ in 0..DEPTH + 10 {
            x.send(&[0; 64]).unwrap();
        }
        assert_eq!(x.dropped, 10);
    }
}
