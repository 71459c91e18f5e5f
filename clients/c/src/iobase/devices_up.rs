// SPDX-License-Identifier: MIT OR Apache-2.0
//! Which devices of an open controller are in data exchange (for `PNIO_ERR_NO_CONNECTION`):
//! the server's status report when the controller opens, then its notifications, which the
//! services worker applies before it calls the program back (DEV_FAILURE, DEV_RETURN), so
//! the data functions and the callbacks agree. The worker subscribes before the status is
//! read, and one lock orders the two: a notification the worker applies after the status
//! is newer than it, one applied before is older, so an older state never overwrites a
//! newer one. Reads take no lock.

use super::sync::lock;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// Per device of the layout: in data exchange.
pub(crate) struct DevicesUp {
    up: Vec<AtomicBool>,
    order: Mutex<()>,
}

impl DevicesUp {
    /// `n` devices, none in data exchange.
    pub(crate) fn new(n: usize) -> DevicesUp {
        DevicesUp {
            up: (0..n).map(|_| AtomicBool::new(false)).collect(),
            order: Mutex::new(()),
        }
    }

    /// Device `d` is (`true`) or is not in data exchange, as a notification says.
    pub(crate) fn set(&self, d: usize, up: bool) {
        let _order = lock(&self.order);
        if let Some(u) = self.up.get(d) {
            u.store(up, Ordering::Relaxed);
        }
    }

    /// Every device is (`true`) or is not in data exchange: a new server.
    pub(crate) fn set_all(&self, up: bool) {
        let _order = lock(&self.order);
        self.up.iter().for_each(|u| u.store(up, Ordering::Relaxed));
    }

    /// Takes the server's status (`status` reads it: per device, in data exchange; `None`
    /// when it could not be read, which changes nothing).
    pub(crate) fn take_status(&self, status: impl FnOnce() -> Option<Vec<bool>>) {
        let _order = lock(&self.order);
        if let Some(up) = status() {
            for (u, up) in self.up.iter().zip(up) {
                u.store(up, Ordering::Relaxed);
            }
        }
    }

    /// Whether device `d` is in data exchange (a device the layout does not have is not the
    /// concern of this check: the address check refuses it).
    pub(crate) fn get(&self, d: usize) -> bool {
        self.up.get(d).is_none_or(|u| u.load(Ordering::Relaxed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notifications_and_the_status_set_what_the_data_functions_read() {
        let d = DevicesUp::new(2);
        assert!(
            !d.get(0) && !d.get(1),
            "none in data exchange before the server said so"
        );
        d.take_status(|| Some(vec![true, false]));
        assert!(d.get(0) && !d.get(1));
        d.take_status(|| None);
        assert!(d.get(0), "a status that could not be read changes nothing");
        d.set(1, true);
        d.set(0, false);
        assert!(!d.get(0) && d.get(1));
        d.set_all(false);
        assert!(!d.get(0) && !d.get(1));
        assert!(d.get(7), "not this check's concern");
    }
}
