// SPDX-License-Identifier: MIT OR Apache-2.0
//! The image's way through the input samples, cycle after cycle: the sample an image is
//! built in is bound right after the last publication (the clients' outputs go straight
//! into it; the link loaned it ahead, at the end of the cycle before), the inputs join it
//! at the cycle's start, and it is published whole. The one
//! place that binds the image to samples, so the contract of [`Image::bind_inputs`] and
//! [`Image::bind_outputs`] is kept here and nowhere else.

use super::link::ClientLink;
use crate::image::Image;
use core::ptr::NonNull;
use procimg_shm_layout::ImageHeader;

/// Which sample the image is being built in.
#[derive(Debug, Default)]
pub struct Publication {
    /// Loaned at the end of the last cycle, the outputs bound to it.
    next: Option<NonNull<u8>>,
    /// The sample of this cycle's image, from [`Publication::begin`] on.
    current: Option<NonNull<u8>>,
}

impl Publication {
    /// Nothing loaned yet.
    pub fn new() -> Publication {
        Publication::default()
    }

    /// Binds the image's inputs to the sample this cycle publishes: the one loaned after the
    /// last publication, or a new one (the outputs carried into it) if that loan failed.
    /// Without any, the image is built in its own payload and nothing will be published.
    pub fn begin(&mut self, ports: &mut impl ClientLink, image: &mut Image) {
        let sample = match self.next.take() {
            Some(sample) => Some(sample),
            None => {
                let sample = ports.loan_image(image.payload_len());
                #[allow(unsafe_code)]
                // SAFETY: as below.
                unsafe {
                    image.bind_outputs(sample)
                };
                sample
            }
        };
        // SAFETY: `loan_image` promises what `bind_inputs` requires: the sample is the
        // engine's until it is published, then unchanged until the next one is (the
        // publisher's history of one holds it), and its inputs are carried over before that;
        // the outputs are bound to the same sample.
        #[allow(unsafe_code)]
        unsafe {
            image.bind_inputs(sample)
        };
        self.current = sample;
    }

    /// Completes and publishes the image with `header`, which the link stamps with the time
    /// the image was complete ([`ClientLink::publish`]; with `send_later` iceoryx2's send
    /// waits for [`ClientLink::send_named`]). Whether it was published; if not, the image
    /// keeps what it had in its own payload. The outputs are bound to a sample again at
    /// [`Publication::loan_next`].
    pub fn finish(
        &mut self,
        ports: &mut impl ClientLink,
        image: &mut Image,
        header: &mut ImageHeader,
        send_later: bool,
    ) -> bool {
        image.publish_into();
        let published = self.current.take().is_some() && ports.publish(header, send_later);
        if !published {
            image.keep_unpublished();
        }
        published
    }

    /// Loans the next sample (the one the link loaned ahead, if any), which the outputs are
    /// bound to from now on: after [`Publication::finish`], before any output is set.
    /// (Apart from `finish`, so that STARTOP need not wait for it.)
    pub fn loan_next(&mut self, ports: &mut impl ClientLink, image: &mut Image) {
        let next = ports.loan_image(image.payload_len());
        // SAFETY: as for `bind_inputs` in `begin`; the inputs are bound to it in the next
        // cycle's `begin`.
        #[allow(unsafe_code)]
        unsafe {
            image.bind_outputs(next)
        };
        self.next = next;
    }
}
