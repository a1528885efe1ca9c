use super::*;

/// `n` samples of a steady daemon: 12,000 KiB, 60 fds, p99 1 ms, with a little noise.
fn flat(n: usize) -> Vec<Sample> {
    (0..n)
        .map(|i| Sample {
            t_s: 10.0 * (i + 1) as f64,
            rss_kib: 12_000 + (i as u64 % 3) * 40,
            fds: 60 + (i as u64 % 2),
            p99_ms: Some(1.0 + 0.1 * (i % 4) as f64),
            ..Sample::default()
        })
        .collect()
}

fn failed(checks: &[Check]) -> Vec<&str> {
    checks
        .iter()
        .filter(|c| !c.ok)
        .map(|c| c.name.as_str())
        .collect()
}

#[test]
fn the_windows_scale_from_ci_to_two_hours() {
    let ci = windows(12).unwrap();
    assert_eq!((ci.warmup, ci.baseline, ci.last), (1, 1..4, 9..12));
    let ten = windows(10).unwrap();
    assert_eq!((ten.warmup, ten.baseline, ten.last), (1, 1..4, 7..10));
    let long = windows(120).unwrap();
    assert_eq!(
        (long.warmup, long.baseline, long.last),
        (12, 12..24, 108..120)
    );
    let three = windows(3).unwrap();
    assert_eq!((three.baseline, three.last), (1..2, 2..3));
    assert_eq!(windows(6).unwrap().last, 5..6);
    assert_eq!(windows(2), None);
    assert!(failed(&growth(&flat(2), &Limits::SOAK)).contains(&"enough samples to judge growth"));
}

#[test]
fn a_flat_run_passes() {
    for n in [3, 12, 120] {
        let checks = growth(&flat(n), &Limits::SOAK);
        assert_eq!(checks.len(), 3);
        assert!(failed(&checks).is_empty(), "{n}: {checks:#?}");
    }
}

#[test]
fn the_warm_up_is_not_judged() {
    let mut s = flat(12);
    s[0].rss_kib = 4_000;
    s[0].fds = 20;
    s[0].p99_ms = Some(0.1);
    assert!(failed(&growth(&s, &Limits::SOAK)).is_empty());
}

#[test]
fn an_rss_climb_of_6_percent_fails_and_4_percent_passes() {
    for (n, climb, fails) in [(12, 0.06, true), (120, 0.06, true), (12, 0.04, false)] {
        let mut s = flat(n);
        let w = windows(n).unwrap();
        let base = s[w.baseline.clone()]
            .iter()
            .map(|s| s.rss_kib)
            .max()
            .unwrap();
        // A steady climb to base + climb over the run after the warm-up.
        let steps = (n - w.warmup) as f64;
        for (k, x) in s.iter_mut().enumerate().skip(w.baseline.end) {
            let f = (k + 1 - w.warmup) as f64 / steps;
            x.rss_kib = x.rss_kib.max((base as f64 * (1.0 + climb * f)) as u64 + 1);
        }
        let checks = growth(&s, &Limits::SOAK);
        assert_eq!(
            failed(&checks) == ["RSS flat"],
            fails,
            "{n} {climb}: {checks:#?}"
        );
    }
}

#[test]
fn a_descriptor_leak_fails_and_two_more_pass() {
    let mut s = flat(12);
    s[11].fds = 63; // baseline max 61: +2 is the slack
    assert!(failed(&growth(&s, &Limits::SOAK)).is_empty());
    for (k, x) in s.iter_mut().enumerate().skip(2) {
        x.fds = 61 + k as u64; // one leaked a sample
    }
    assert_eq!(failed(&growth(&s, &Limits::SOAK)), ["open files flat"]);
    // Tiny counts: 5 % of 4 is nothing, the slack of 2 holds.
    let mut small = flat(12);
    small.iter_mut().for_each(|x| x.fds = 4);
    small[11].fds = 6;
    assert!(failed(&growth(&small, &Limits::SOAK)).is_empty());
    small[11].fds = 7;
    assert_eq!(failed(&growth(&small, &Limits::SOAK)), ["open files flat"]);
}

#[test]
fn a_p99_rise_in_every_sample_fails_and_a_burst_of_the_host_does_not() {
    let mut s = flat(120);
    // Baseline least 1.0 ms: allowed max(2.0, 3.0) = 3.0 ms.
    for x in &mut s[108..] {
        x.p99_ms = Some(3.5);
    }
    assert_eq!(failed(&growth(&s, &Limits::SOAK)), ["event p99 unchanged"]);
    s[119].p99_ms = Some(3.0);
    assert!(failed(&growth(&s, &Limits::SOAK)).is_empty());
    let mut s = flat(120);
    for x in &mut s[110..] {
        x.p99_ms = Some(40.0);
    }
    assert!(failed(&growth(&s, &Limits::SOAK)).is_empty());
    // CI's 12 samples: baseline 2nd-4th (least 1.1 ms, allowed 3.1 ms), last 10th-12th.
    let mut s = flat(12);
    for x in &mut s[9..] {
        x.p99_ms = Some(3.2);
    }
    assert_eq!(failed(&growth(&s, &Limits::SOAK)), ["event p99 unchanged"]);
    s[9].p99_ms = Some(3.1);
    assert!(failed(&growth(&s, &Limits::SOAK)).is_empty());
    for x in &mut s[9..] {
        x.p99_ms = None;
    }
    assert_eq!(failed(&growth(&s, &Limits::SOAK)), ["event p99 unchanged"]);
    // A slow baseline: the margin is 2x.
    assert_eq!(Limits::SOAK.allowed_p99(5.0), 10.0);
    assert_eq!(Limits::SOAK.allowed_p99(0.5), 2.5);
}

#[test]
fn the_ci_run_whose_host_slowed_at_the_end_passes_and_a_slower_daemon_does_not() {
    // The per-sample p99s of the CI run that failed under the median (ms): the host slowed
    // over the last two samples.
    let p99 = [
        8.03, 6.98, 7.38, 11.77, 10.46, 13.57, 9.85, 8.75, 8.24, 8.09, 17.72, 48.66,
    ];
    let mut s = flat(12);
    for (x, p) in s.iter_mut().zip(p99) {
        x.p99_ms = Some(p);
    }
    let checks = growth(&s, &Limits::SOAK);
    assert!(failed(&checks).is_empty(), "{checks:#?}");
    assert!(checks[2]
        .detail
        .starts_with("8.09 ms (last window, least) vs 6.98 ms"));
    // The same run from a daemon whose every fix got 8 ms slower after the first minute.
    for x in &mut s[6..] {
        x.p99_ms = x.p99_ms.map(|p| p + 8.0);
    }
    assert_eq!(failed(&growth(&s, &Limits::SOAK)), ["event p99 unchanged"]);
}

#[test]
fn proc_status_gives_the_resident_set() {
    let status = "Name:\tobu\nVmPeak:\t  123456 kB\nVmRSS:\t    9876 kB\nThreads:\t5\n";
    assert_eq!(vm_rss_kib(status), Some(9876));
    assert_eq!(vm_rss_kib("Name:\tobu\n"), None);
    assert_eq!(vm_rss_kib("VmRSS:\t 12 MB\n"), None);
    let me = rss_kib(std::process::id()).unwrap();
    assert!(me > 100, "{me} KiB");
    // This file is open while it is counted.
    let f = std::fs::File::open("/proc/self/status").unwrap();
    assert!(open_fds(std::process::id()).unwrap() >= 1);
    drop(f);
    assert_eq!(open_fds(u32::MAX), None);
    assert_eq!(rss_kib(u32::MAX), None);
}

#[test]
fn quantiles_are_nearest_rank() {
    let v: Vec<f64> = (1..=100).map(f64::from).collect();
    assert_eq!(quantile(&v, 0.5), Some(50.0));
    assert_eq!(quantile(&v, 0.99), Some(99.0));
    assert_eq!(quantile(&v, 1.0), Some(100.0));
    assert_eq!(quantile(&[], 0.5), None);
}

#[test]
fn a_row_has_every_figure() {
    let s = Sample {
        t_s: 60.0,
        rss_kib: 12_345,
        fds: 61,
        p99_ms: Some(1.234),
        v2x_sent: 100,
        v2x_counted: 99,
        ..Sample::default()
    };
    let row = s.row();
    for part in ["60", "12345", "61", "1.23", "100/99"] {
        assert!(row.contains(part), "{row}");
    }
}
