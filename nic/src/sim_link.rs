// SPDX-License-Identifier: MIT OR Apache-2.0
//! An in-process Ethernet link between two ends, for the simulated network and for tests:
//! what one end sends, the other receives. Bounded, lock-free, allocation-free per frame.

use crate::{MAX_FRAME, Nic, RecvError, SendError, check_frame_len};
use crossbeam_queue::ArrayQueue;
use procimg_profinet::wire::MacAddress;
use std::sync::Arc;

/// The ends' name in messages: the simulated network is `network = "sim"` in procimgd's
/// configuration.
const NAME: &str = "sim";

/// Frames in flight per direction by default; more are dropped, as a real link drops under
/// overload.
pub const DEPTH: usize = 256;

struct Slot {
    len: usize,
    data: [u8; MAX_FRAME],
}

/// One end of a simulated link.
pub struct LinkEnd {
    name: Arc<str>,
    mac: MacAddress,
    tx: Arc<ArrayQueue<Box<Slot>>>,
    rx: Arc<ArrayQueue<Box<Slot>>>,
    /// Empty slots, returned after reading, so no frame allocates.
    free: Arc<ArrayQueue<Box<Slot>>>,
    /// Frames dropped because the link was full.
    pub dropped: u64,
}

/// A link between two ends with the given MAC addresses, [`DEPTH`] frames deep.
pub fn link(a: MacAddress, b: MacAddress) -> (LinkEnd, LinkEnd) {
    link_with_depth(a, b, DEPTH)
}

/// A link `depth` frames deep per direction (at least 1): a network whose cycle carries
/// more frames than [`DEPTH`] needs room for a cycle's frames and the next, or it drops
/// whenever one end is late.
pub fn link_with_depth(a: MacAddress, b: MacAddress, depth: usize) -> (LinkEnd, LinkEnd) {
    let depth = depth.max(1);
    let ab = Arc::new(ArrayQueue::new(depth));
    let ba = Arc::new(ArrayQueue::new(depth));
    let free = Arc::new(ArrayQueue::new(2 * depth));
    let name: Arc<str> = NAME.into();
    for _ in 0..2 * depth {
        let _ = free.push(Box::new(Slot {
            len: 0,
            data: [0; MAX_FRAME],
        }));
    }
    (
        LinkEnd {
            name: name.clone(),
            mac: a,
            tx: ab.clone(),
            rx: ba.clone(),
            free: free.clone(),
            dropped: 0,
        },
        LinkEnd {
            name,
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

    fn send(&mut self, frame: &[u8]) -> Result<(), SendError> {
        check_frame_len(&self.name, frame)?;
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

    fn receive(&mut self, f: &mut dyn FnMut(&[u8])) -> Result<bool, RecvError> {
        let Some(slot) = self.rx.pop() else {
            return Ok(false);
        };
        // `send` stored at most MAX_FRAME bytes: the slot holds the whole frame.
        f(&slot.data[..slot.len.min(MAX_FRAME)]);
        let _ = self.free.push(slot);
        Ok(true)
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
        let mut got = Vec::new();
        assert!(y.receive(&mut |f| got = f.to_vec()).unwrap());
        assert_eq!(got, [1, 2, 3]);
        assert!(x.receive(&mut |f| got = f.to_vec()).unwrap());
        assert_eq!(got, [4; 60]);
        assert!(!x.receive(&mut |_| panic!("no frame was sent")).unwrap());
        let e = x.send(&[0; MAX_FRAME + 1]).unwrap_err();
        assert!(matches!(e, SendError::TooLong { len: 1519, .. }), "{e}");
        assert!(e.to_string().contains("\"sim\""), "{e}");
    }

    #[test]
    fn a_full_link_drops_instead_of_blocking() {
        let (mut x, _y) = link(MacAddress::default(), MacAddress::default());
        for _ in 0..DEPTH + 10 {
            x.send(&[0; 64]).unwrap();
        }
        assert_eq!(x.dropped, 10);
    }

    #[test]
    fn a_deeper_link_holds_more_frames_and_each_direction_its_own() {
        let (mut x, mut y) = link_with_depth(MacAddress::default(), MacAddress::default(), 1000);
        for _ in 0..1000 {
            x.send(&[1; 64]).unwrap();
            y.send(&[2; 64]).unwrap();
        }
        assert_eq!((x.dropped, y.dropped), (0, 0));
        x.send(&[1; 64]).unwrap();
        assert_eq!(x.dropped, 1);
        let mut got = 0;
        while y
            .receive(&mut |f| got += usize::from(f == [1; 64]))
            .unwrap()
        {}
        assert_eq!(got, 1000);
    }
}
