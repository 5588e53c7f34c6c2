//! Durations as people read them (`12.3 s`, `4m 05s`, `2h 07m`): in plans, progress lines
//! and run summaries. A leaf: it imports nothing of the crate.

/// Seconds as "1h 02m", "3m 05s" or "12.3 s".
pub fn human_seconds(s: f64) -> String {
    if s >= 3600.0 {
        format!(
            "{}h {:02}m",
            (s / 3600.0) as u64,
            ((s % 3600.0) / 60.0) as u64
        )
    } else if s >= 60.0 {
        format!("{}m {:02}s", (s / 60.0) as u64, (s % 60.0) as u64)
    } else {
        format!("{s:.1} s")
    }
}

#[cfg(test)]
mod tests {
    use super::human_seconds;

    #[test]
    fn seconds_minutes_and_hours() {
        assert_eq!(human_seconds(12.34), "12.3 s");
        assert_eq!(human_seconds(245.0), "4m 05s");
        assert_eq!(human_seconds(7620.0), "2h 07m");
    }
}
