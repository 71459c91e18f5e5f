// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station making itself seen: an engineering tool's DCP Signal asks it to flash for
//! three seconds ("flash once"). The start comes at once with 2 Hz, the stop when the three
//! seconds are over; another Signal meanwhile extends the flashing without a second start.

use std::time::{Duration, Instant};

/// How long the station identifies itself after a DCP Signal.
pub const FLASH_FOR: Duration = Duration::from_secs(3);
/// The flashing frequency, in Hz, as DCP Signal's "flash once" has it.
pub const FLASH_HZ: u32 = 2;

/// Whether the LED flashes, and until when.
#[derive(Clone, Copy, Debug, Default)]
pub struct LedFlash {
    until: Option<Instant>,
}

impl LedFlash {
    /// A DCP Signal at `now`: whether the flashing starts (else it goes on, longer).
    pub fn signal(&mut self, now: Instant) -> bool {
        self.until.replace(now + FLASH_FOR).is_none()
    }

    /// Whether the flashing is over at `now` (true once).
    pub fn over(&mut self, now: Instant) -> bool {
        match self.until {
            Some(t) if t <= now => self.until.take().is_some(),
            _ => false,
        }
    }

    /// When the flashing ends, if it goes on.
    pub fn until(&self) -> Option<Instant> {
        self.until
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_signal_extends_without_a_second_start() {
        let t0 = Instant::now();
        let mut led = LedFlash::default();
        assert!(led.signal(t0));
        assert!(!led.signal(t0 + Duration::from_secs(2)));
        assert!(!led.over(t0 + FLASH_FOR), "extended by the second signal");
        assert!(led.over(t0 + Duration::from_secs(5)));
        assert!(!led.over(t0 + Duration::from_secs(6)), "stopped once");
        assert!(led.until().is_none());
    }
}
