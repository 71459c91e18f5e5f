// SPDX-License-Identifier: MIT OR Apache-2.0
//! `PROCIMG_WAKE_AHEAD_US`: how long before the next STARTOP is due an IO-Base program's
//! synchronous client wakes and polls for it (`AttachOptions::wake_ahead`). The IO-Base
//! calls have no parameter for it, and a program built against them cannot be changed, so
//! it is set where the CP index's instance is (`PROCIMG_CP<n>`): in the environment. Unset
//! or empty: the client library's default, [`WAKE_AHEAD`]; `0`: the STARTOP thread sleeps
//! until procimgd wakes it and spends no CPU time polling.

use procimg_client::WAKE_AHEAD;
use std::time::Duration;

/// The variable's name.
pub(crate) const VAR: &str = "PROCIMG_WAKE_AHEAD_US";

/// The lead the environment asks for, or why its value is not one.
pub(crate) fn from_env() -> Result<Duration, String> {
    parse(std::env::var(VAR).ok().as_deref())
}

/// The lead a value of the variable asks for (`None`: unset).
fn parse(value: Option<&str>) -> Result<Duration, String> {
    let Some(text) = value.map(str::trim).filter(|t| !t.is_empty()) else {
        return Ok(WAKE_AHEAD);
    };
    text.parse::<u64>().map(Duration::from_micros).map_err(|_| {
        format!(
            "{VAR}={text:?} is not a whole number of microseconds: unset it for the default \
             ({} µs), or give 0 to sleep until STARTOP",
            WAKE_AHEAD.as_micros()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unset_or_empty_is_the_default_and_zero_turns_it_off() {
        assert_eq!(parse(None), Ok(WAKE_AHEAD));
        assert_eq!(parse(Some(" ")), Ok(WAKE_AHEAD));
        assert_eq!(parse(Some("0")), Ok(Duration::ZERO));
        assert_eq!(parse(Some("80")), Ok(Duration::from_micros(80)));
    }

    #[test]
    fn anything_else_is_refused_with_the_variable_named() {
        let e = parse(Some("50us")).unwrap_err();
        assert!(e.contains("PROCIMG_WAKE_AHEAD_US=\"50us\""), "{e}");
        assert!(parse(Some("-1")).is_err());
    }
}
