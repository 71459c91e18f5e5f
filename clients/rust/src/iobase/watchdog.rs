// SPDX-License-Identifier: MIT OR Apache-2.0
//! The CP application watchdog of IO-Base (`PNIO_CP_set_appl_watchdog`,
//! `PNIO_CP_trigger_watchdog`, `PNIO_CBF_APPL_WATCHDOG`) as a rule without a thread: the
//! program registers a timeout per key (IO-Base: per CPIndex), monitoring starts at the
//! first trigger, and a registration whose trigger does not come within its timeout expires
//! once. From then on its triggers are refused until it is deregistered; the program's
//! handles on that key are to be stopped (what stopping means is the caller's: the C library
//! sends the outputs BAD and refuses every call but close).
//!
//! The caller owns the timer: it asks [`AppWatchdogs::expire`] at the deadline
//! [`AppWatchdogs::next_deadline`] gives (and again after each trigger that started
//! monitoring).

use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// Why a watchdog call is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum WatchdogError {
    /// A registration needs a timeout.
    #[error("the watchdog's timeout is 0: give one, or deregister")]
    ZeroTimeout,
    /// The key has a registration already.
    #[error("a watchdog is registered for {key} already: deregister it first")]
    Registered {
        /// The key (IO-Base: the CPIndex).
        key: u32,
    },
    /// The key has no registration.
    #[error("no watchdog is registered for {key}")]
    NotRegistered {
        /// The key.
        key: u32,
    },
    /// The watchdog expired: triggers are refused until it is deregistered.
    #[error(
        "the watchdog of {key} expired: stop what it watched, deregister it and register again"
    )]
    Expired {
        /// The key.
        key: u32,
    },
}

/// One registration and what the caller keeps with it (the C library: the callback).
#[derive(Clone, Copy, Debug)]
struct Registration<C> {
    timeout: Duration,
    with: C,
    /// The last trigger; `None` until the first.
    last: Option<Instant>,
    expired: bool,
}

impl<C> Registration<C> {
    /// When it expires, if it is armed and has not expired.
    fn deadline(&self) -> Option<Instant> {
        if self.expired {
            return None;
        }
        self.last.map(|l| l + self.timeout)
    }
}

/// The watchdogs of a program, by key.
#[derive(Clone, Debug)]
pub struct AppWatchdogs<C> {
    regs: BTreeMap<u32, Registration<C>>,
}

impl<C> Default for AppWatchdogs<C> {
    fn default() -> AppWatchdogs<C> {
        AppWatchdogs::new()
    }
}

impl<C> AppWatchdogs<C> {
    /// No watchdog.
    pub const fn new() -> AppWatchdogs<C> {
        AppWatchdogs {
            regs: BTreeMap::new(),
        }
    }

    /// Registers a watchdog of `timeout` for `key`, with `with` kept for its expiry. Not
    /// armed until the first [`trigger`](Self::trigger).
    pub fn register(&mut self, key: u32, timeout: Duration, with: C) -> Result<(), WatchdogError> {
        if timeout.is_zero() {
            return Err(WatchdogError::ZeroTimeout);
        }
        if self.regs.contains_key(&key) {
            return Err(WatchdogError::Registered { key });
        }
        self.regs.insert(
            key,
            Registration {
                timeout,
                with,
                last: None,
                expired: false,
            },
        );
        Ok(())
    }

    /// Removes `key`'s watchdog (expired or not); whether there was one.
    pub fn deregister(&mut self, key: u32) -> bool {
        self.regs.remove(&key).is_some()
    }

    /// The program's sign of life at `now`: `Ok(true)` when it armed the watchdog (the
    /// caller's timer is to look at the new deadline).
    pub fn trigger(&mut self, key: u32, now: Instant) -> Result<bool, WatchdogError> {
        match self.regs.get_mut(&key) {
            None => Err(WatchdogError::NotRegistered { key }),
            Some(r) if r.expired => Err(WatchdogError::Expired { key }),
            Some(r) => Ok(r.last.replace(now).is_none()),
        }
    }

    /// Whether no watchdog is registered.
    pub fn is_empty(&self) -> bool {
        self.regs.is_empty()
    }

    /// The nearest deadline of an armed watchdog.
    pub fn next_deadline(&self) -> Option<Instant> {
        self.regs.values().filter_map(Registration::deadline).min()
    }
}

impl<C: Clone> AppWatchdogs<C> {
    /// The watchdogs whose timeout is exceeded at `now` (each once), with what was kept
    /// for them.
    pub fn expire(&mut self, now: Instant) -> Vec<(u32, C)> {
        let mut fired = Vec::new();
        for (&key, r) in &mut self.regs {
            if r.deadline().is_some_and(|d| d < now) {
                r.expired = true;
                fired.push((key, r.with.clone()));
            }
        }
        fired
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn monitoring_starts_at_the_first_trigger_and_expires_once() {
        let t0 = Instant::now();
        let ms = Duration::from_millis;
        let mut w = AppWatchdogs::new();
        assert_eq!(w.register(1, ms(0), 'a'), Err(WatchdogError::ZeroTimeout));
        w.register(1, ms(100), 'a').unwrap();
        assert_eq!(
            w.register(1, ms(100), 'b'),
            Err(WatchdogError::Registered { key: 1 })
        );
        assert_eq!(
            w.next_deadline(),
            None,
            "not armed before the first trigger"
        );
        assert!(w.expire(t0 + ms(1000)).is_empty());
        assert_eq!(w.trigger(1, t0), Ok(true));
        assert_eq!(w.trigger(1, t0 + ms(50)), Ok(false));
        assert_eq!(w.next_deadline(), Some(t0 + ms(150)));
        assert!(
            w.expire(t0 + ms(150)).is_empty(),
            "expired only once exceeded"
        );
        assert_eq!(w.expire(t0 + ms(151)), [(1, 'a')]);
        assert!(w.expire(t0 + ms(500)).is_empty(), "once");
        assert_eq!(w.trigger(1, t0), Err(WatchdogError::Expired { key: 1 }));
        assert_eq!(w.next_deadline(), None);
        assert!(w.deregister(1));
        assert_eq!(
            w.trigger(1, t0),
            Err(WatchdogError::NotRegistered { key: 1 })
        );
        assert!(w.is_empty());
    }
}
