//! TIM validity windows: `startYear`, `startTime` (minute of the year, UTC) and
//! `durationTime` (minutes; 32000 = indefinite, 0 = cancelled) as calendar dates.

/// `startTime` value meaning "invalid".
const INVALID_MINUTE: u32 = 527_040;

/// The validity window in words, with the raw values.
pub fn validity(year: Option<u16>, start: u32, duration: u16, indefinite: u16) -> String {
    let year = year.filter(|y| *y != 0).map(u32::from);
    let raw = format!(
        "(startYear {}, startTime {start}, durationTime {duration})",
        year.map_or("absent".to_string(), |y| y.to_string())
    );
    let from = match year {
        _ if start >= INVALID_MINUTE => return format!("from an invalid startTime {raw}"),
        Some(y) => format!("{} UTC", date(y, start)),
        None => format!("minute {start} of the current year"),
    };
    let span = match (duration, year) {
        (0, _) => "for 0 min: cancelled".to_string(),
        (d, _) if d == indefinite => "indefinitely".to_string(),
        (d, Some(y)) => format!("for {d} min, until {} UTC", date(y, start + u32::from(d))),
        (d, None) => format!("for {d} min"),
    };
    format!("from {from} {span} {raw}")
}

fn is_leap(year: u32) -> bool {
    (year.is_multiple_of(4) && !year.is_multiple_of(100)) || year.is_multiple_of(400)
}

fn minutes_in(year: u32) -> u32 {
    if is_leap(year) {
        366 * 1440
    } else {
        365 * 1440
    }
}

/// `YYYY-MM-DD hh:mm` of minute `minute` counted from the start of `year` (later years
/// when it runs past the year's end).
pub fn date(year: u32, minute: u32) -> String {
    let (mut year, mut minute) = (year, minute);
    while minute >= minutes_in(year) {
        minute -= minutes_in(year);
        year += 1;
    }
    let february = if is_leap(year) { 29 } else { 28 };
    let months = [31, february, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31];
    let (mut day, time) = (minute / 1440, minute % 1440);
    let mut month = 1;
    for length in months {
        if day < length {
            break;
        }
        day -= length;
        month += 1;
    }
    let (hour, min) = (time / 60, time % 60);
    format!("{year:04}-{month:02}-{:02} {hour:02}:{min:02}", day + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_count_leap_years() {
        assert_eq!(date(2024, 0), "2024-01-01 00:00");
        assert_eq!(date(2024, 59 * 1440 + 61), "2024-02-29 01:01");
        assert_eq!(date(2023, 59 * 1440), "2023-03-01 00:00");
        assert_eq!(date(2023, 525_600 + 30), "2024-01-01 00:30");
        assert_eq!(date(2100, 59 * 1440), "2100-03-01 00:00");
    }

    #[test]
    fn windows_in_words() {
        assert_eq!(
            validity(Some(2024), 1440, 120, 32000),
            "from 2024-01-02 00:00 UTC for 120 min, until 2024-01-02 02:00 UTC \
             (startYear 2024, startTime 1440, durationTime 120)"
        );
        assert!(validity(None, 10, 32000, 32000)
            .starts_with("from minute 10 of the current year indefinitely"));
        assert!(validity(Some(2024), 10, 0, 32000).contains("cancelled"));
        assert!(validity(Some(2024), 527_040, 5, 32000).starts_with("from an invalid startTime"));
    }
}
