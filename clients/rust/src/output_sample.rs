// SPDX-License-Identifier: MIT OR Apache-2.0
//! A client's output sample, with where its payload lies noted once, when it is loaned.
//!
//! iceoryx2's thread-safe services look a slice sample's length up behind two mutexes each
//! time its payload is asked for. A busy client asks several times between STARTOP and its
//! OPDONE (clearing the flags, each submodule written, the sample named in the handshake
//! block); with the payload noted at the loan none of those takes a lock.

use crate::connection::Ipc;
use core::ptr::NonNull;
use iceoryx2::port::SendError;
use iceoryx2::sample_mut::SampleMut;
use procimg_shm_layout::OutputHeader;

/// An output sample loaned from the client's publisher, not yet sent.
#[derive(Debug)]
pub struct OutputSample {
    sample: SampleMut<Ipc, [u8], OutputHeader>,
    payload: NonNull<u8>,
    len: usize,
}

// SAFETY: `payload` points into the chunk `sample` owns, which moves with it; the sample
// itself may go to another thread (iceoryx2's thread-safe service), and the payload is only
// reached through `&self` / `&mut self` like the sample's own.
unsafe impl Send for OutputSample {}

impl OutputSample {
    /// Wraps a sample just loaned, noting where its payload lies.
    pub fn new(mut sample: SampleMut<Ipc, [u8], OutputHeader>) -> OutputSample {
        let payload = sample.payload_mut();
        let len = payload.len();
        let payload = NonNull::from(payload).cast::<u8>();
        OutputSample {
            sample,
            payload,
            len,
        }
    }

    /// The payload.
    pub fn payload(&self) -> &[u8] {
        // SAFETY: `payload` and `len` are the sample's payload as iceoryx2 gave it at the
        // loan; the chunk stays this sample's until it is sent or dropped, which takes `self`.
        unsafe { core::slice::from_raw_parts(self.payload.as_ptr(), self.len) }
    }

    /// The payload, writable.
    pub fn payload_mut(&mut self) -> &mut [u8] {
        // SAFETY: as in `payload`; `&mut self` makes this the only reference into it.
        unsafe { core::slice::from_raw_parts_mut(self.payload.as_ptr(), self.len) }
    }

    /// The sample's header, writable.
    pub fn header_mut(&mut self) -> &mut OutputHeader {
        self.sample.user_header_mut()
    }

    /// Sends the sample to the server. Returns how many readers it reached.
    pub fn send(self) -> Result<usize, SendError> {
        self.sample.send()
    }
}
