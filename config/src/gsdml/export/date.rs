// SPDX-License-Identifier: MIT OR Apache-2.0
//! The date of a GSDML file (the `yyyymmdd` of its name): a calendar date, given by the
//! caller, since the writer reads no clock.

use core::fmt;
use core::str::FromStr;

/// A calendar date (proleptic Gregorian), years 1 to 9999.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GsdmlDate {
    year: u16,
    month: u8,
    day: u8,
}

/// Why a text is not a date.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DateError {
    /// The text as given.
    pub text: String,
}

impl fmt::Display for DateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:?} is not a date; write it as YYYYMMDD or YYYY-MM-DD, e.g. 20250131",
            self.text
        )
    }
}

impl core::error::Error for DateError {}

impl GsdmlDate {
    /// The date `year`-`month`-`day`, if there is such a day.
    pub fn new(year: u16, month: u8, day: u8) -> Option<GsdmlDate> {
        let valid = (1..=9999).contains(&year)
            && (1..=12).contains(&month)
            && day >= 1
            && day <= days_in_month(year, month);
        valid.then_some(GsdmlDate { year, month, day })
    }

    /// The date `days` days after 1970-01-01 (negative: before), e.g. the seconds since the
    /// Unix epoch divided by 86400; `None` outside years 1 to 9999.
    pub fn from_unix_days(days: i64) -> Option<GsdmlDate> {
        // Counted from 0000-03-01 in eras of 400 years (146097 days), so that the leap day
        // ends a year; the usual civil-from-days computation.
        let z = days.checked_add(719_468)?;
        let era = z.div_euclid(146_097);
        let day_of_era = z.rem_euclid(146_097);
        let year_of_era =
            (day_of_era - day_of_era / 1460 + day_of_era / 36_524 - day_of_era / 146_096) / 365;
        let day_of_year = day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
        let mp = (5 * day_of_year + 2) / 153;
        let day = day_of_year - (153 * mp + 2) / 5 + 1;
        let month = if mp < 10 { mp + 3 } else { mp - 9 };
        let year = year_of_era + era * 400 + i64::from(month <= 2);
        GsdmlDate::new(
            u16::try_from(year).ok()?,
            u8::try_from(month).ok()?,
            u8::try_from(day).ok()?,
        )
    }

    /// The date (UTC) of `time`, e.g. `SystemTime::now()`: the caller reads the clock;
    /// `None` outside years 1970 to 9999.
    pub fn of(time: std::time::SystemTime) -> Option<GsdmlDate> {
        let seconds = time.duration_since(std::time::UNIX_EPOCH).ok()?.as_secs();
        GsdmlDate::from_unix_days(i64::try_from(seconds / 86_400).ok()?)
    }

    /// The year.
    pub fn year(self) -> u16 {
        self.year
    }

    /// The month, 1 to 12.
    pub fn month(self) -> u8 {
        self.month
    }

    /// The day of the month, from 1.
    pub fn day(self) -> u8 {
        self.day
    }

    /// `yyyymmdd`, as in a GSDML file name.
    pub fn compact(self) -> String {
        format!("{:04}{:02}{:02}", self.year, self.month, self.day)
    }
}

/// `yyyy-mm-dd`.
impl fmt::Display for GsdmlDate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:04}-{:02}-{:02}", self.year, self.month, self.day)
    }
}

/// `YYYYMMDD` or `YYYY-MM-DD`.
impl FromStr for GsdmlDate {
    type Err = DateError;

    fn from_str(text: &str) -> Result<GsdmlDate, DateError> {
        let error = || DateError {
            text: text.to_owned(),
        };
        let digits: String = match text.len() {
            8 => text.to_owned(),
            10 if text.as_bytes()[4] == b'-' && text.as_bytes()[7] == b'-' => {
                text.chars().filter(|&c| c != '-').collect()
            }
            _ => return Err(error()),
        };
        if digits.len() != 8 || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return Err(error());
        }
        let field = |range: core::ops::Range<usize>| digits[range].parse::<u16>().ok();
        let (Some(year), Some(month), Some(day)) = (field(0..4), field(4..6), field(6..8)) else {
            return Err(error());
        };
        GsdmlDate::new(year, month as u8, day as u8).ok_or_else(error)
    }
}

fn days_in_month(year: u16, month: u8) -> u8 {
    match month {
        2 if year.is_multiple_of(4) && (!year.is_multiple_of(100) || year.is_multiple_of(400)) => {
            29
        }
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn days_since_the_epoch() {
        let d = |y, m, day| GsdmlDate::new(y, m, day).unwrap();
        assert_eq!(GsdmlDate::from_unix_days(0), Some(d(1970, 1, 1)));
        assert_eq!(GsdmlDate::from_unix_days(-1), Some(d(1969, 12, 31)));
        assert_eq!(GsdmlDate::from_unix_days(11_016), Some(d(2000, 2, 29)));
        assert_eq!(GsdmlDate::from_unix_days(20_089), Some(d(2025, 1, 1)));
        assert_eq!(GsdmlDate::from_unix_days(i64::MAX), None);
        assert_eq!(GsdmlDate::from_unix_days(-800_000), None);
        // Every day of four centuries, one after the other.
        let mut previous = GsdmlDate::from_unix_days(-150_000).unwrap();
        for days in -149_999..150_000 {
            let next = GsdmlDate::from_unix_days(days).unwrap();
            assert!(next > previous, "{next} after {previous}");
            let wrapped = next.day == 1 && (next.month != previous.month);
            assert!(wrapped || next.day == previous.day + 1, "{previous} {next}");
            previous = next;
        }
    }

    #[test]
    fn the_date_of_a_time() {
        use std::time::{Duration, UNIX_EPOCH};
        let at = |seconds| GsdmlDate::of(UNIX_EPOCH + Duration::from_secs(seconds));
        assert_eq!(at(0), GsdmlDate::new(1970, 1, 1));
        assert_eq!(at(20_089 * 86_400 + 86_399), GsdmlDate::new(2025, 1, 1));
        assert_eq!(GsdmlDate::of(UNIX_EPOCH - Duration::from_secs(1)), None);
    }

    #[test]
    fn parsed_and_shown() {
        let date: GsdmlDate = "20240229".parse().unwrap();
        assert_eq!(date.to_string(), "2024-02-29");
        assert_eq!(date.compact(), "20240229");
        assert_eq!("2024-02-29".parse::<GsdmlDate>(), Ok(date));
        for bad in [
            "20230229",
            "2024-0229",
            "20241301",
            "2024/02/29",
            "",
            "+0240229",
            "00000101",
        ] {
            assert!(bad.parse::<GsdmlDate>().is_err(), "{bad}");
        }
        let e = "x".parse::<GsdmlDate>().unwrap_err();
        assert!(e.to_string().contains("YYYYMMDD"), "{e}");
    }
}
