// SPDX-License-Identifier: MIT OR Apache-2.0
//! The stream decoder: the UART's bytes in, whole frames (or the errors between them) out.
//!
//! A UART has no frame boundaries of its own: the decoder finds them from the header. A
//! frame starts with a known ID, its LEN must be one the type allows, and its CRC must
//! match; then the next frame starts right after it.
//!
//! # Resynchronisation
//!
//! When a candidate frame fails — an unknown ID, a LEN the type cannot carry, a CRC error,
//! or a silence in the middle of it — the decoder drops **one byte** and tries the next byte
//! as a frame start, not the whole length the broken header claimed. Why: a broken header
//! says nothing trustworthy about where the next frame starts. A host that resets in the
//! middle of a frame, or a noise burst that turns a byte into a large LEN, would otherwise
//! swallow the good frames that follow; trying every byte finds the next good frame
//! wherever it starts. The cost is a small chance that bytes inside a damaged frame form a
//! frame that passes all three checks (about 2⁻¹⁶ per such candidate, the CRC's strength).
//!
//! The decoder reports the **first** failure after it lost the frame boundaries, and is
//! silent while it looks for the next good frame (counting the bytes it skips in
//! [`DecoderStats`]). So one burst of garbage costs one error, with its cause: the module
//! answers with error bit 4 for a CRC error and error bit 5 for an unknown ID or a LEN that
//! does not fit (reference §1.6), once, and the link keeps working.
//!
//! # Silence
//!
//! A candidate whose declared length has not arrived is waited for — but not for ever: a
//! few garbage bytes that look like a header with a large LEN would otherwise hold back the
//! host's next Request Status until hundreds of bytes had come. A host writes each frame in
//! one go, so a silence of [`Decoder::gap`] in the middle of a frame means the rest is not
//! coming: the candidate is dropped as [`StreamError::Truncated`] and the decoder resumes at
//! its next byte. The decoder takes the time as an argument (sans-IO); the caller asks
//! [`Decoder::poll_at`] when to call [`Decoder::poll`] again.
//!
//! # Bounded
//!
//! The decoder holds at most [`MAX_FRAME_LEN`] bytes: [`Decoder::push`] takes what fits and
//! says how many; [`Decoder::poll`] always makes progress on a full buffer, because every
//! candidate frame fits in it. [`Decoder::feed`] does both in a loop.

use std::time::{Duration, Instant};

use crate::frame::{CRC_LEN, Frame, FrameId, FrameRepr, MAX_FRAME_LEN};

/// The default silence after which a frame that has begun is given up.
///
/// The module's UART would use a few character times (Modbus RTU: 3.5). On Linux the bytes
/// come through a USB-UART and the kernel's tty layer, which deliver them in bursts up to
/// the adapter's latency timer apart (16 ms by default on FTDI chips), so a gap of that size
/// inside a frame is normal there. 50 ms is well above it and still far below any sensible
/// host timeout for an answer.
pub const DEFAULT_GAP: Duration = Duration::from_millis(50);

/// What broke the frame boundaries. The frame (or the bytes) is dropped; the decoder goes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, thiserror::Error)]
pub enum StreamError {
    /// A byte where a frame should start is no ID of the catalogue (error bit 5).
    #[error(
        "byte 0x{0:02X} where a frame should start is no frame ID: the host sent an unknown \
         frame or bytes between frames; the decoder skips to the next good frame"
    )]
    UnknownId(u8),
    /// The LEN is not one the frame type allows (error bit 5).
    #[error(
        "{id} with LEN {len}, but it carries {allowed}: the host built the frame wrong (or \
         the bytes are not a frame); the decoder skips to the next good frame",
        allowed = id.payload_len()
    )]
    BadLen {
        /// The frame type.
        id: FrameId,
        /// The LEN field.
        len: usize,
    },
    /// The CRC does not match (error bit 4).
    #[error(
        "{id} with a CRC error (computed 0x{computed:04X}, received 0x{received:04X}): bytes \
         were damaged on the line; check baud rate and parity (115200 8E1), wiring and ground"
    )]
    Crc {
        /// The frame type.
        id: FrameId,
        /// The CRC of the bytes received.
        computed: u16,
        /// The CRC field.
        received: u16,
    },
    /// The line went silent in the middle of a frame (counted as a CRC error, error bit 4:
    /// the frame did not arrive whole).
    #[error(
        "{id} stopped after {received} of its {needed} bytes and the line went silent: the \
         host stopped or reset in the middle of a frame"
    )]
    Truncated {
        /// The frame type.
        id: FrameId,
        /// Bytes the frame needs (so far as its header tells).
        needed: usize,
        /// Bytes that came before the silence.
        received: usize,
    },
}

/// Counters of what the decoder saw.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DecoderStats {
    /// Good frames handed out.
    pub frames: u64,
    /// Errors reported (one per loss of the frame boundaries).
    pub errors: u64,
    /// Bytes dropped while looking for a frame start.
    pub skipped_bytes: u64,
}

/// The stream decoder. See the [module docs](self) for how it finds frames.
#[derive(Clone, Debug)]
pub struct Decoder {
    /// Bytes received; those before `start` are done with.
    buf: Vec<u8>,
    start: usize,
    /// Bytes of the frame last handed out (from `start`), dropped at the next call: the
    /// frame borrows them until then.
    handed_out: usize,
    /// `buf[..gap_end]` was followed by a silence of at least `gap` (0: no silence known).
    gap_end: usize,
    /// Whether the last thing decoded was a good frame (or nothing yet): a failure then is
    /// reported; while resynchronising, failures are only counted.
    in_sync: bool,
    last_rx: Option<Instant>,
    gap: Option<Duration>,
    stats: DecoderStats,
}

impl Default for Decoder {
    fn default() -> Decoder {
        Decoder::new()
    }
}

impl Decoder {
    /// A decoder that gives up a frame after [`DEFAULT_GAP`] of silence.
    pub fn new() -> Decoder {
        Decoder::with_gap(Some(DEFAULT_GAP))
    }

    /// A decoder that gives up a frame after `gap` of silence, or never (`None`: a candidate
    /// frame is then only given up when the bytes after it show it broken).
    pub fn with_gap(gap: Option<Duration>) -> Decoder {
        Decoder {
            buf: Vec::with_capacity(MAX_FRAME_LEN),
            start: 0,
            handed_out: 0,
            gap_end: 0,
            in_sync: true,
            last_rx: None,
            gap,
            stats: DecoderStats::default(),
        }
    }

    /// The silence after which a begun frame is given up.
    pub fn gap(&self) -> Option<Duration> {
        self.gap
    }

    /// What the decoder saw so far.
    pub fn stats(&self) -> DecoderStats {
        self.stats
    }

    /// Bytes held that are not yet a frame (at most [`MAX_FRAME_LEN`]).
    pub fn buffered(&self) -> usize {
        self.buf.len() - self.start - self.handed_out
    }

    /// Forgets the bytes held, as after a reset of the link; the counters stay.
    pub fn clear(&mut self) {
        self.buf.clear();
        self.start = 0;
        self.handed_out = 0;
        self.gap_end = 0;
        self.in_sync = true;
    }

    /// Takes bytes received at `now`, as many as fit; returns how many it took. Call
    /// [`poll`](Self::poll) until it returns `None` before pushing the rest.
    pub fn push(&mut self, bytes: &[u8], now: Instant) -> usize {
        self.drop_handed_out();
        if self.start > 0 {
            self.buf.drain(..self.start);
            self.gap_end = self.gap_end.saturating_sub(self.start);
            self.start = 0;
        }
        self.note_silence(now);
        let n = bytes.len().min(MAX_FRAME_LEN - self.buf.len());
        if n > 0 {
            self.buf.extend_from_slice(&bytes[..n]);
            self.last_rx = Some(now);
        }
        n
    }

    /// The next frame, or the next error, from the bytes held at `now`; `None` when the
    /// rest needs more bytes (or more time, see [`poll_at`](Self::poll_at)).
    ///
    /// The frame borrows the decoder's buffer until the next call.
    pub fn poll(&mut self, now: Instant) -> Option<Result<FrameRepr<'_>, StreamError>> {
        self.drop_handed_out();
        self.note_silence(now);
        let (id, header, len) = loop {
            let rest = &self.buf[self.start..];
            let &raw = rest.first()?;
            let Some(id) = FrameId::from_u8(raw) else {
                match self.lose(StreamError::UnknownId(raw)) {
                    Some(e) => return Some(Err(e)),
                    None => continue,
                }
            };
            let header = id.len_width().header_len();
            let (needed, len) = if rest.len() < header {
                (header, None)
            } else {
                let len = Frame::new_unchecked(rest).payload_len();
                if !id.payload_len().contains(len) {
                    match self.lose(StreamError::BadLen { id, len }) {
                        Some(e) => return Some(Err(e)),
                        None => continue,
                    }
                }
                (header + len + CRC_LEN, Some(len))
            };
            let end = self.start + needed;
            if self.gap_end > self.start && end > self.gap_end {
                let received = self.gap_end - self.start;
                match self.lose(StreamError::Truncated {
                    id,
                    needed,
                    received,
                }) {
                    Some(e) => return Some(Err(e)),
                    None => continue,
                }
            }
            // Not all there yet: wait for more bytes (or for the silence that ends it).
            let len = len.filter(|_| end <= self.buf.len())?;
            let frame = Frame::new_unchecked(&rest[..needed]);
            let (computed, received) = (frame.computed_crc(), frame.crc());
            if computed != received {
                match self.lose(StreamError::Crc {
                    id,
                    computed,
                    received,
                }) {
                    Some(e) => return Some(Err(e)),
                    None => continue,
                }
            }
            break (id, header, len);
        };
        self.in_sync = true;
        self.stats.frames += 1;
        self.handed_out = header + len + CRC_LEN;
        let at = self.start + header;
        Some(Ok(FrameRepr {
            id,
            payload: &self.buf[at..at + len],
        }))
    }

    /// When to call [`poll`](Self::poll) next even if no byte comes: when the frame that
    /// has begun is given up. `None` while nothing is pending (or without a gap).
    pub fn poll_at(&self) -> Option<Instant> {
        if self.buffered() == 0 {
            return None;
        }
        Some(self.last_rx? + self.gap?)
    }

    /// Pushes all of `bytes` received at `now`, handing every frame and error to `f` as it
    /// is decoded.
    pub fn feed(
        &mut self,
        bytes: &[u8],
        now: Instant,
        mut f: impl FnMut(Result<FrameRepr<'_>, StreamError>),
    ) {
        let mut rest = bytes;
        loop {
            let n = self.push(rest, now);
            rest = &rest[n..];
            while let Some(item) = self.poll(now) {
                f(item);
            }
            // A drained decoder always has room (every candidate frame fits), so this ends;
            // the second test is a guard, not a case.
            if rest.is_empty() || (n == 0 && self.buffered() == MAX_FRAME_LEN) {
                break;
            }
        }
    }

    fn drop_handed_out(&mut self) {
        self.start += std::mem::take(&mut self.handed_out);
    }

    /// Marks the bytes held as followed by a silence if none came for `gap`.
    fn note_silence(&mut self, now: Instant) {
        if let (Some(gap), Some(last)) = (self.gap, self.last_rx)
            && now.saturating_duration_since(last) >= gap
        {
            self.gap_end = self.buf.len();
        }
    }

    /// Drops the byte at the candidate's start; the error to report if the boundaries were
    /// known until now.
    fn lose(&mut self, e: StreamError) -> Option<StreamError> {
        self.start += 1;
        self.stats.skipped_bytes += 1;
        if self.in_sync {
            self.in_sync = false;
            self.stats.errors += 1;
            Some(e)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests;
