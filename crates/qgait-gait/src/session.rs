//! Who and what a report is about: the subject and the session as given on the command line
//! (`--subject-id`, `--date`, `--age`, `--sex`, `--height`, `--mass`, `--condition`), for the
//! report's header block and `summary.json`'s `subject` object, and the warnings the run
//! emitted, for its warnings section.
//!
//! A session's date defaults to the first recording's modification date (UTC), formatted
//! here from [`std::time::SystemTime`] ([`date_of`], [`civil_from_days`]): the workspace has
//! no date crate of its own (chrono comes in only through a dependency of a dependency), and a
//! calendar date is a dozen lines.

use std::time::{SystemTime, UNIX_EPOCH};

/// The subject and the session, as given; `None` where not given.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Session {
    /// `--subject-id`.
    pub subject_id: Option<String>,
    /// The session's date, `YYYY-MM-DD`: `--date`, else the first recording's modification
    /// date (UTC).
    pub date: Option<String>,
    /// Where [`Session::date`] came from: `given` or the file whose modification date it is.
    pub date_from: Option<String>,
    /// Age in years.
    pub age: Option<f64>,
    /// `male` or `female`.
    pub sex: Option<&'static str>,
    /// Height (m).
    pub height: Option<f64>,
    /// Body mass (kg).
    pub mass: Option<f64>,
    /// `--condition`: shoes, orthoses, assistive device, ... as the clinician wrote it.
    pub condition: Option<String>,
}

impl Session {
    /// The body mass index (kg/m²), when height and mass are both given.
    pub fn bmi(&self) -> Option<f64> {
        match (self.height, self.mass) {
            (Some(h), Some(m)) if h > 0.0 => Some(m / (h * h)),
            _ => None,
        }
    }

    /// `summary.json`'s `subject` object: every field, `null` where not given.
    pub fn summary(&self) -> SubjectSummary<'_> {
        SubjectSummary {
            id: self.subject_id.as_deref(),
            date: self.date.as_deref(),
            date_from: self.date_from.as_deref(),
            age: self.age,
            sex: self.sex,
            height_m: self.height,
            mass_kg: self.mass,
            bmi: self.bmi(),
            condition: self.condition.as_deref(),
        }
    }
}

/// `summary.json`'s `subject` object ([`Session::summary`]): every field, `null` where not
/// given.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SubjectSummary<'a> {
    /// `--subject-id`.
    pub id: Option<&'a str>,
    /// The session's date, `YYYY-MM-DD`.
    pub date: Option<&'a str>,
    /// Where the date came from.
    pub date_from: Option<&'a str>,
    /// Age in years.
    pub age: Option<f64>,
    /// `male` or `female`.
    pub sex: Option<&'static str>,
    /// Height (m).
    pub height_m: Option<f64>,
    /// Body mass (kg).
    pub mass_kg: Option<f64>,
    /// The body mass index (kg/m²).
    pub bmi: Option<f64>,
    /// `--condition`.
    pub condition: Option<&'a str>,
}

/// The proleptic Gregorian date `(year, month, day)` of a day counted from 1970-01-01 (day
/// 0; negative before). Howard Hinnant's `civil_from_days`
/// (<https://howardhinnant.github.io/date_algorithms.html>), exact for every `i64` day that
/// fits.
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // day of the era, 0..=146096
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // 0..=399
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // 0..=365, from 1 March
    let mp = (5 * doy + 2) / 153; // month from March, 0..=11
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = yoe + era * 400 + i64::from(month <= 2);
    (year, month, day)
}

/// A time's UTC date as `YYYY-MM-DD`.
pub fn date_of(t: SystemTime) -> String {
    let secs = match t.duration_since(UNIX_EPOCH) {
        Ok(d) => d.as_secs() as i64,
        Err(e) => -(e.duration().as_secs_f64().ceil() as i64),
    };
    let (y, m, d) = civil_from_days(secs.div_euclid(86_400));
    format!("{y:04}-{m:02}-{d:02}")
}

/// The modification date (UTC, `YYYY-MM-DD`) of a file; `None` for what is not a readable file
/// (a `builtin:` gait) or where the file system keeps no modification time.
pub fn file_date(path: &str) -> Option<String> {
    let meta = std::fs::metadata(path).ok()?;
    meta.is_file()
        .then(|| meta.modified().ok().map(date_of))
        .flatten()
}

/// `--date`: a calendar date `YYYY-MM-DD` that exists (months 1-12, the month's days, 29
/// February in leap years only); the text back when it is one.
pub fn parse_date(text: &str) -> Option<String> {
    let t = text.trim();
    let parts: Vec<&str> = t.split('-').collect();
    let [y, m, d] = parts.as_slice() else {
        return None;
    };
    if y.len() != 4 || m.len() != 2 || d.len() != 2 {
        return None;
    }
    let all_digits = |s: &str| s.bytes().all(|b| b.is_ascii_digit());
    if !(all_digits(y) && all_digits(m) && all_digits(d)) {
        return None;
    }
    let (y, m, d): (i64, u32, u32) = (y.parse().ok()?, m.parse().ok()?, d.parse().ok()?);
    let leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
    let days = match m {
        1 | 3 | 5 | 7 | 8 | 10 | 12 => 31,
        4 | 6 | 9 | 11 => 30,
        2 if leap => 29,
        2 => 28,
        _ => return None,
    };
    (1..=days).contains(&d).then(|| t.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn days_since_1970_are_calendar_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
        // 2000-02-29 (a leap day of a century divisible by 400) is day 11016.
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(11_017), (2000, 3, 1));
        // 2100 is no leap year: 28 February then 1 March.
        assert_eq!(civil_from_days(47_540), (2100, 2, 28));
        assert_eq!(civil_from_days(47_541), (2100, 3, 1));
        // Every day of 1999-2001 in order: the day count and the calendar agree.
        let mut day = civil_from_days(10_592); // 1999-01-01
        assert_eq!(day, (1999, 1, 1));
        for n in 10_593..11_688 {
            let next = civil_from_days(n);
            let same_month = next.0 == day.0 && next.1 == day.1 && next.2 == day.2 + 1;
            let new_month = next.2 == 1 && (next.1 == day.1 % 12 + 1);
            assert!(same_month || new_month, "{day:?} then {next:?}");
            day = next;
        }
        assert_eq!(day, (2001, 12, 31));
    }

    #[test]
    fn a_time_is_its_utc_date() {
        // 2026-11-28T23:59:59Z and one second later.
        let t = UNIX_EPOCH + Duration::from_secs(1_795_910_399);
        assert_eq!(date_of(t), "2026-11-28");
        assert_eq!(date_of(t + Duration::from_secs(1)), "2026-11-29");
        assert_eq!(date_of(UNIX_EPOCH - Duration::from_secs(1)), "1969-12-31");
    }

    #[test]
    fn only_real_dates_parse() {
        assert_eq!(parse_date("2024-02-29").as_deref(), Some("2024-02-29"));
        for bad in [
            "2023-02-29",
            "1900-02-29",
            "2024-13-01",
            "2024-04-31",
            "2024-4-3",
            "24-04-03",
            "2024/04/03",
            "03.04.2024",
            "",
        ] {
            assert_eq!(parse_date(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_file_has_a_date_and_a_builtin_gait_none() {
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("m.mot");
        std::fs::write(&f, "x").unwrap();
        let today = date_of(SystemTime::now());
        let got = file_date(f.to_str().unwrap()).unwrap();
        // (Unless the day changed between the two readings.)
        assert!(
            got == today || got == date_of(SystemTime::now()),
            "{got} {today}"
        );
        assert_eq!(file_date("builtin:normal"), None);
        assert_eq!(file_date(dir.path().to_str().unwrap()), None);
    }

    #[test]
    fn the_bmi_needs_both_height_and_mass() {
        let mut s = Session {
            height: Some(1.8),
            ..Session::default()
        };
        assert_eq!(s.bmi(), None);
        s.mass = Some(81.0);
        assert!((s.bmi().unwrap() - 25.0).abs() < 1e-12);
        let j = s.summary();
        assert_eq!(j.height_m, Some(1.8));
        assert_eq!(j.id, None);
        let text = serde_json::to_string(&j).unwrap();
        assert!(text.starts_with(r#"{"id":null,"date":null"#), "{text}");
    }
}
