// SPDX-License-Identifier: MIT OR Apache-2.0
//! The notification service, published by the control side: every role publishes its events, alarms
//! and confirmations through it, one JSON [`Notification`] per sample, and wakes the
//! subscribers.

use crate::shm::Ipc;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::prelude::EventId;
use procimg_control as control;
use procimg_control::services::{EVENT_NOTIFICATIONS, Notification};

/// Publishes notifications to the subscribers.
pub struct Notices {
    publisher: Publisher<Ipc, [u8], ()>,
    notifier: Notifier<Ipc>,
    lost: u64,
}

impl Notices {
    /// Notices on `publisher`, waking subscribers through `notifier`.
    pub fn new(publisher: Publisher<Ipc, [u8], ()>, notifier: Notifier<Ipc>) -> Notices {
        Notices {
            publisher,
            notifier,
            lost: 0,
        }
    }

    /// Publishes `n` and wakes the subscribers; counts it as lost when shared memory has no
    /// room for it.
    pub fn publish(&mut self, n: &Notification) {
        let bytes = control::encode(n);
        let sent = self
            .publisher
            .loan_slice_uninit(bytes.len())
            .ok()
            .and_then(|s| s.write_from_slice(&bytes).send().ok());
        if sent.is_none() {
            self.lost += 1;
            return;
        }
        let _ = self
            .notifier
            .notify_with_custom_event_id(EventId::new(EVENT_NOTIFICATIONS));
    }

    /// Notifications that could not be published (no shared memory for them).
    pub fn lost(&self) -> u64 {
        self.lost
    }
}
