//! `hil-sim run`: scenarios against the daemon (and the firmware), their reports printed.

use crate::args::RunArgs;

/// Runs one scenario with `opts` and prints its report; true when every expectation held,
/// with the run's roadside -> screen delays (ms, one per roadside change it showed).
fn run_one(
    scenario: &hil_sim::scenario::Scenario,
    opts: &hil_sim::runner::RunOptions,
    v2x: &mut Vec<f64>,
) -> (bool, Vec<f64>) {
    match hil_sim::runner::run(scenario, opts) {
        Ok(r) => {
            print_report(&r);
            v2x.extend(r.v2x_to_screen_ms.iter().copied());
            (r.passed, r.v2x_to_screen_ms)
        }
        Err(e) => {
            println!("  ERROR {e}");
            (false, Vec::new())
        }
    }
}

/// Runs one scenario against the daemon, then against the firmware in QEMU, and compares
/// the two `HmiState` timelines fix by fix (`timeline.json` beside the two reports).
fn run_against_firmware(
    scenario: &hil_sim::scenario::Scenario,
    opts: &hil_sim::runner::RunOptions,
    target: &hil_sim::firmware::FirmwareTarget,
    v2x: &mut Vec<f64>,
) -> bool {
    use hil_sim::timeline;
    let root = opts.out.clone();
    let daemon_opts = hil_sim::runner::RunOptions {
        out: root.join("daemon"),
        ..opts.clone()
    };
    let firmware_opts = hil_sim::runner::RunOptions {
        out: root.join("firmware"),
        firmware: Some(target.clone()),
        ..opts.clone()
    };
    println!("  -- daemon");
    let (daemon_ok, daemon_delays) = run_one(scenario, &daemon_opts, v2x);
    println!("  -- firmware in QEMU");
    let (firmware_ok, firmware_delays) = run_one(scenario, &firmware_opts, v2x);
    let log = firmware_opts.out.join("obu-state").join("firmware.log");
    if let Some(line) = std::fs::read_to_string(&log)
        .unwrap_or_default()
        .lines()
        .rfind(|l| l.contains(" stack "))
    {
        println!("  firmware's last report: {}", line.trim());
    }
    let read = |o: &hil_sim::runner::RunOptions| {
        std::fs::read_to_string(o.out.join("states.jsonl")).unwrap_or_default()
    };
    let mut m = timeline::compare(
        &timeline::by_fix(&read(&daemon_opts)),
        &timeline::by_fix(&read(&firmware_opts)),
    );
    m.delay_fixes = timeline::delay_fixes(&daemon_delays, &firmware_delays);
    println!(
        "  {} timeline: {} of {} fixes show the same state (distance within {} m; largest difference {:.3} m); {} met different roadside inputs (at most {}: {} for {} roadside changes, {} spanned by the firmware's later delivery), {} settling after them",
        if m.matches() { "PASS" } else { "FAIL" },
        m.fixes_matching,
        m.fixes_compared,
        timeline::TOLERANCE,
        m.max_distance_diff_m,
        m.fixes_skipped,
        m.allowed_skipped(),
        m.allowed_skipped() - m.delay_fixes,
        m.roadside_changes,
        m.delay_fixes,
        m.fixes_settling
    );
    for (k, path, d, f) in m.mismatches.iter().take(5) {
        println!("       fix {k}: {path}: daemon {d}, firmware {f}");
    }
    let json = serde_json::to_string_pretty(&m).unwrap_or_default();
    if let Err(e) = std::fs::write(root.join("timeline.json"), json) {
        println!("  ERROR timeline.json: {e}");
        return false;
    }
    daemon_ok && firmware_ok && m.matches()
}

pub fn scenarios(a: &RunArgs) -> Result<(), String> {
    let (files, out) = (&a.files, &a.out);
    let firmware = match &a.firmware {
        Some(elf) => Some(hil_sim::firmware::FirmwareTarget::new(elf)?),
        None => None,
    };
    let mut failed = Vec::new();
    let mut v2x = Vec::new();
    for f in files {
        let scenario = hil_sim::scenario::Scenario::load(f)?;
        println!("=== {} ({})", scenario.name, f.display());
        let opts = hil_sim::runner::RunOptions {
            obu: hil_sim::daemon::find_obu(),
            out: hil_sim::runner::out_dir(out, f),
            http_port: 0,
            progress: std::io::IsTerminal::is_terminal(&std::io::stderr()),
            firmware: None,
        };
        let passed = match &firmware {
            None => run_one(&scenario, &opts, &mut v2x).0,
            Some(target) => run_against_firmware(&scenario, &opts, target, &mut v2x),
        };
        if !passed {
            failed.push(scenario.name.clone());
        }
    }
    v2x.sort_by(f64::total_cmp);
    if !v2x.is_empty() {
        let q = |p: f64| hil_sim::soak::verdict::quantile(&v2x, p).unwrap_or(f64::NAN);
        println!(
            "=== roadside -> screen over the runs ({} message changes): p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
            v2x.len(),
            q(0.5),
            q(0.99),
            q(1.0)
        );
    }
    println!(
        "=== {} of {} scenarios passed",
        files.len() - failed.len(),
        files.len()
    );
    failed
        .is_empty()
        .then_some(())
        .ok_or(format!("failed: {}", failed.join(", ")))
}

pub fn print_report(r: &hil_sim::runner::RunReport) {
    for o in &r.outcomes {
        println!(
            "  {} {:?}: {}",
            if o.passed { "ok  " } else { "FAIL" },
            o.expectation,
            o.detail
        );
    }
    if let Some(d) = r.first_warning_m {
        println!("  the warning fired {d:.1} m before the work zone");
    }
    let [p50, p99, max] = r.fix_to_screen_ms;
    println!(
        "  {} fixes, {} states; fix -> screen p50 {p50:.2} ms, p99 {p99:.2} ms, max {max:.2} ms; roadside -> screen [{}]; V2X sent {} lost {} corrupted {}",
        r.fixes_sent,
        r.states,
        r.v2x_to_screen_ms.iter().map(|t| format!("{t:.1} ms")).collect::<Vec<_>>().join(", "),
        r.v2x.sent,
        r.v2x.lost,
        r.v2x.corrupted
    );
    if let Some(radio) = &r.radio {
        println!(
            "  radio -> firmware: {} V2X frames received, {} delivered over the serial link, {} dropped with its {} receive buffers full",
            radio.received,
            radio.delivered,
            radio.dropped,
            hil_sim::radio::QUEUE_FRAMES
        );
    }
    if let Some([mean, max]) = r.camera_frame_ms {
        println!(
            "  camera site: {} worker PSMs; a frame took {mean:.1} ms on average, {max:.1} ms at most (period 100 ms)",
            r.worker_psms
        );
    }
    if let Some(a) = &r.attack {
        let at = |t: Option<f64>| t.map_or("-".into(), |t| format!("{t:.1} s"));
        println!(
            "  attacker {:?}: {} datagrams sent ({} failed) from t = {} to {}; device counters: {}",
            a.kind,
            a.sent.sent,
            a.sent.failed,
            at(a.sent.first_sent_s),
            at(a.sent.last_sent_s),
            a.device.as_ref().map_or_else(
                || a.device_error.clone().unwrap_or_default(),
                |d| d.source.to_string()
            )
        );
    }
    if let Some(f) = r.files.first() {
        println!("  report: {}", f.display());
    }
}
