//! `hil-sim`: roadside unit software and the hardware-in-the-loop bench of the OBU.
#![forbid(unsafe_code)]

use hil_sim::{hmi_bench, perf};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

const USAGE: &str = "hil-sim: roadside unit software and the OBU's hardware-in-the-loop bench

Usage:
  hil-sim hmi-server     run the real obu daemon and feed it the tablet tests' road, work
                         zone and drive at 10 Hz; prints the daemon's URL first
                         (env: HMI_PORT, HMI_STATE_DIR, OBU_BIN)
  hil-sim hmi-drive S    switch a running hmi-server to scene S (env: HMI_STATE_DIR)
  hil-sim bench-latency [--samples N]
                         GNSS datagram in -> state event out of the real daemon on the
                         loopback: p50/p99/max; fails when p99 >= 2 ms or a state is lost
  hil-sim load-test [--clients N] [--seconds S]
                         N tablets (default 50) follow /events while the daemon is fed at
                         10 Hz for S seconds (default 60): events per client and the
                         daemon's CPU; fails on a dropped client or CPU >= 10 % of a core
  hil-sim run SCENARIO.toml... [--out DIR] [--firmware ELF]
                         run scenarios against the real obu daemon; writes
                         DIR/<scenario>/report.json, states.jsonl and plots (default DIR:
                         hil-sim-out); fails when an expectation does not hold. With
                         --firmware: each scenario runs against the daemon and then against
                         the firmware image in QEMU (netduinoplus2; $QEMU or
                         qemu-system-arm), into DIR/<scenario>/daemon and .../firmware,
                         and the two HmiState timelines must match (timeline.json)
  hil-sim roadside SCENARIO.toml [--to HOST:PORT]... [--wrap raw|1609.2] [--rate HZ]
                 [--seconds S] [--rsu-files DIR]
                         the roadside unit: the scenario's lane map and work zones (GeoJSON,
                         WZDx, cones, camera) as MAP + TIM, broadcast over UDP (default
                         10 Hz, until stopped) and/or written as RSU 4.1 text files
  hil-sim record SCENARIO.toml OUT.nmea OUT.candump
                         the scenario's drive as a GNSS receiver's NMEA log (10 Hz GST, GGA,
                         RMC with its noise and dropouts) and a candump log of its speed
  hil-sim demo [--port P]
                         the field test: roadside, OBU and a drive through a work zone
                         (40 km/h road, limit 10 km/h, 100 m warning, lane change) with the
                         tablet app live at http://127.0.0.1:P (default 8080)
  hil-sim synth-camera --scenario FILE.toml --out DIR [--frames N] [--noise-px S]
                       [--seed K] [--miss-rate R]
                         synthetic camera data of the scenario's first `lanes` zone: cones
                         along the closed lanes, a camera beside the road before the zone;
                         writes DIR/calibration.json and DIR/detections.json (N frames,
                         default 10; S px noise, default 1; cones missed at rate R,
                         default 0.1; seed K, default 1)
  hil-sim --help         this text

The daemon is `obu` beside this executable (build both with the same profile), or $OBU_BIN.

Scenes: cruise, approach, warning, lane_closed, overspeed, in_zone, leaving;
switches: gnss_lost, gnss_back.";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args
        .iter()
        .map(String::as_str)
        .collect::<Vec<_>>()
        .as_slice()
    {
        ["hmi-server"] => server_options().and_then(|o| hmi_bench::serve(&o)),
        ["hmi-drive", scene] => state_dir().and_then(|d| hmi_bench::drive(&d, scene)),
        ["bench-latency", rest @ ..] => bench_latency(rest),
        ["run", rest @ ..] => run_scenarios(rest),
        ["roadside", scenario, rest @ ..] => roadside(scenario, rest),
        ["record", scenario, nmea, candump] => record(scenario, nmea, candump),
        ["demo", rest @ ..] => demo(rest),
        ["load-test", rest @ ..] => load_test(rest),
        ["synth-camera", rest @ ..] => synth_camera(rest),
        ["--help" | "-h"] => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        _ => Err(format!("unexpected arguments {args:?}\n\n{USAGE}")),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hil-sim: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `--name value` pairs into a lookup, refusing unknown names.
fn options<'a>(args: &[&'a str], known: &[&str]) -> Result<Vec<(&'a str, &'a str)>, String> {
    let mut out = Vec::new();
    let mut it = args.iter();
    while let Some(name) = it.next() {
        if !known.contains(name) {
            return Err(format!(
                "unknown option {name:?} (options: {})",
                known.join(", ")
            ));
        }
        let value = it.next().ok_or(format!("{name} needs a value"))?;
        out.push((*name, *value));
    }
    Ok(out)
}

fn number<T: std::str::FromStr>(
    opts: &[(&str, &str)],
    name: &str,
    default: T,
) -> Result<T, String> {
    match opts.iter().rev().find(|(n, _)| *n == name) {
        Some((_, v)) => v
            .parse()
            .map_err(|_| format!("{name} {v:?} is not a number")),
        None => Ok(default),
    }
}

fn bench_latency(args: &[&str]) -> Result<(), String> {
    let opts = options(args, &["--samples"])?;
    let samples: usize = number(&opts, "--samples", 2000)?;
    let obu = hil_sim::daemon::find_obu();
    let gnss = perf::latency(&obu, samples.max(1), Duration::from_millis(10))?;
    let tim = perf::tim_latency(&obu, samples.max(1), Duration::from_millis(10))?;
    let mut ok = true;
    for (what, r) in [
        ("GNSS datagram (NMEA)", &gnss),
        ("TIM datagram (roadside)", &tim),
    ] {
        let ms = |q: f64| r.quantile(q) / 1000.0;
        println!(
            "{what} in -> state event out ({} samples, {} lost): p50 {:.3} ms, p99 {:.3} ms, max {:.3} ms",
            r.sorted_us.len(),
            r.lost,
            ms(0.5),
            ms(0.99),
            ms(1.0)
        );
        ok &= r.lost == 0 && ms(0.99) < 2.0;
    }
    ok.then_some(())
        .ok_or("goal missed: p99 under 2 ms with nothing lost".into())
}

fn load_test(args: &[&str]) -> Result<(), String> {
    let opts = options(args, &["--clients", "--seconds"])?;
    let clients: usize = number(&opts, "--clients", 50)?;
    let seconds: f64 = number(&opts, "--seconds", 60.0)?;
    let obu = hil_sim::daemon::find_obu();
    let r = perf::load(&obu, clients.max(1), seconds.max(1.0))?;
    println!(
        "{} clients for {:.1} s: events per client {}..{}, longest gap {:.0} ms, dropped {} (daemon: {}), daemon CPU {:.2} % of one core",
        r.clients,
        r.seconds,
        r.events.0,
        r.events.1,
        r.max_gap_ms,
        r.dropped.len(),
        r.daemon_dropped,
        r.cpu_percent
    );
    for d in &r.dropped {
        println!("  dropped: {d}");
    }
    if !r.dropped.is_empty() || r.daemon_dropped > 0 || r.cpu_percent >= 10.0 {
        return Err("goal missed: no dropped client and daemon CPU under 10 % of a core".into());
    }
    Ok(())
}

/// `hil-sim synth-camera`: calibration and detections of a synthetic camera that sees the
/// cones of the scenario's first zone of source `lanes` (the ground truth).
fn synth_camera(args: &[&str]) -> Result<(), String> {
    use hil_sim::scenario::ZoneSource;
    use roadside::camera::{synthetic, CameraModel};
    let known = [
        "--scenario",
        "--out",
        "--frames",
        "--noise-px",
        "--seed",
        "--miss-rate",
    ];
    let opts = options(args, &known)?;
    let given = |name: &str| opts.iter().rev().find(|(n, _)| *n == name).map(|(_, v)| *v);
    let file = given("--scenario").ok_or("--scenario is required")?;
    let out = PathBuf::from(given("--out").ok_or("--out is required")?);
    let spec = synthetic::CaptureSpec {
        frames: number(&opts, "--frames", 10)?,
        noise_px: number(&opts, "--noise-px", 1.0)?,
        miss_rate: number(&opts, "--miss-rate", 0.1)?,
        seed: number(&opts, "--seed", 1)?,
        placement: synthetic::Placement::default(),
    };
    let scenario = hil_sim::scenario::Scenario::load(std::path::Path::new(file))?;
    let road = scenario.road()?;
    let (closed, zone) = (scenario.zones.iter())
        .find_map(|z| match &z.source {
            ZoneSource::Lanes {
                closed_lanes,
                start_m,
                end_m,
            } => Some((closed_lanes, (*start_m, *end_m))),
            _ => None,
        })
        .ok_or("the scenario has no zone of source \"lanes\"")?;
    let capture = synthetic::capture(&road, closed, zone, &spec).map_err(|e| e.to_string())?;
    let camera = &capture.scene.camera;
    let note = format!("synthetic, seed {}: {camera}", spec.seed);
    let files = capture.write(&out, &note)?;
    let model = CameraModel::homography(&road, &capture.calibration).map_err(|e| e.to_string())?;
    let [e, n, _] = camera.centre();
    let at = road.to_wgs84([e, n]).map_or("?".into(), |p| {
        format!("{:.7}, {:.7}", p.lat_deg(), p.lon_deg())
    });
    let cones = capture.scene.cones.len();
    println!(
        "{cones} cones on lanes {closed:?}, stations {zone:?} m; {} detections in {} frames",
        capture.detections(),
        spec.frames
    );
    println!("camera at {at}: {camera}");
    let rmse = model.rmse_m();
    println!(
        "{} control points, homography RMSE {rmse:.3} m; wrote {} and {}",
        capture.calibration.len(),
        files[0].display(),
        files[1].display()
    );
    Ok(())
}

/// The built-in scenario of `hil-sim demo`.
const DEMO: &str = include_str!("../../tests/scenarios/01_paper_drive.toml");

fn demo(args: &[&str]) -> Result<(), String> {
    let opts = options(args, &["--port", "--out"])?;
    let port: u16 = number(&opts, "--port", 8080)?;
    let out = opts
        .iter()
        .find(|(n, _)| *n == "--out")
        .map_or(PathBuf::from("hil-sim-out/demo"), |(_, v)| PathBuf::from(v));
    let scenario = hil_sim::scenario::Scenario::parse(DEMO)?;
    println!("hil-sim demo: {}", scenario.description.trim());
    let report = hil_sim::runner::run(
        &scenario,
        &hil_sim::runner::RunOptions {
            obu: hil_sim::daemon::find_obu(),
            out,
            http_port: port,
            progress: true,
            firmware: None,
        },
    )?;
    print_report(&report);
    report
        .passed
        .then_some(())
        .ok_or("an expectation did not hold".into())
}

fn roadside(scenario: &str, args: &[&str]) -> Result<(), String> {
    use roadside::broadcast::Wrapping;
    let s = hil_sim::scenario::Scenario::load(std::path::Path::new(scenario))?;
    let mut o = roadside::unit::RoadsideOptions {
        destinations: Vec::new(),
        wrapping: Wrapping::Raw,
        rate_hz: 10.0,
        duration: None,
        rsu_dir: None,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = || it.next().copied().ok_or(format!("{a} needs a value"));
        match *a {
            "--to" => {
                let v = value()?;
                o.destinations.push(
                    v.parse()
                        .map_err(|_| format!("--to {v:?}: give HOST:PORT with an IP address"))?,
                );
            }
            "--wrap" => {
                o.wrapping = match value()? {
                    "raw" => Wrapping::Raw,
                    "1609.2" => Wrapping::Ieee1609Unsecured,
                    w => return Err(format!("--wrap {w:?}: raw or 1609.2")),
                }
            }
            "--rate" => o.rate_hz = value()?.parse().map_err(|_| "--rate: a number of Hz")?,
            "--seconds" => {
                o.duration = Some(Duration::from_secs_f64(
                    value()?.parse().map_err(|_| "--seconds: a number")?,
                ))
            }
            "--rsu-files" => o.rsu_dir = Some(PathBuf::from(value()?)),
            other => return Err(format!("unknown option {other:?}")),
        }
    }
    if o.destinations.is_empty() && o.rsu_dir.is_none() {
        return Err("give --to HOST:PORT (broadcast) and/or --rsu-files DIR".into());
    }
    println!("hil-sim roadside: {}", roadside::unit::run(&s.site(), &o)?);
    Ok(())
}

fn record(scenario: &str, nmea_out: &str, candump_out: &str) -> Result<(), String> {
    use hil_sim::{drive, nmea};
    use roadside::clock::Utc;
    let s = hil_sim::scenario::Scenario::load(std::path::Path::new(scenario))?;
    let road = s.road()?;
    let samples = drive::simulate(&road, &s.drive, 900.0).map_err(|e| e.to_string())?;
    // A fixed start (2026-01-15T12:00:00Z) so the logs are reproducible; replay restamps.
    let t0_ms = 1_768_478_400_000u64;
    let mut text = String::new();
    for sample in &samples {
        let (Some(p), Some(position)) = (
            sample.reported,
            sample.reported.and_then(|p| road.to_wgs84(p)),
        ) else {
            continue;
        };
        let _ = p;
        text.push_str(&nmea::epoch(&nmea::Epoch {
            utc: Utc::from_unix_ms(t0_ms + (sample.t_s * 1000.0).round() as u64),
            position,
            speed_mps: sample.speed_mps,
            course_deg: sample.bearing_deg,
            sigma_m: s.drive.sigma_m.max(0.3),
        }));
    }
    std::fs::write(nmea_out, text).map_err(|e| format!("{nmea_out}: {e}"))?;
    std::fs::write(candump_out, drive::candump(&samples, t0_ms as f64 / 1000.0))
        .map_err(|e| format!("{candump_out}: {e}"))?;
    println!(
        "{} epochs to {nmea_out}, speed frames to {candump_out}",
        samples.iter().filter(|x| x.reported.is_some()).count()
    );
    Ok(())
}

/// Runs one scenario with `opts` and prints its report; true when every expectation held.
fn run_one(
    scenario: &hil_sim::scenario::Scenario,
    opts: &hil_sim::runner::RunOptions,
    v2x: &mut Vec<f64>,
) -> bool {
    match hil_sim::runner::run(scenario, opts) {
        Ok(r) => {
            print_report(&r);
            v2x.extend(r.v2x_to_screen_ms.iter().copied());
            r.passed
        }
        Err(e) => {
            println!("  ERROR {e}");
            false
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
    let daemon_ok = run_one(scenario, &daemon_opts, v2x);
    println!("  -- firmware in QEMU");
    let firmware_ok = run_one(scenario, &firmware_opts, v2x);
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
    let m = timeline::compare(
        &timeline::by_fix(&read(&daemon_opts)),
        &timeline::by_fix(&read(&firmware_opts)),
    );
    println!(
        "  {} timeline: {} of {} fixes show the same state (distance within {} m; largest difference {:.3} m)",
        if m.matches() { "PASS" } else { "FAIL" },
        m.fixes_matching,
        m.fixes_compared,
        timeline::TOLERANCE,
        m.max_distance_diff_m
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

fn run_scenarios(args: &[&str]) -> Result<(), String> {
    let mut files = Vec::new();
    let mut out = PathBuf::from("hil-sim-out");
    let mut firmware = None;
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match *a {
            "--out" => out = PathBuf::from(it.next().ok_or("--out needs a folder")?),
            "--firmware" => {
                let elf = it
                    .next()
                    .ok_or("--firmware needs the firmware image (ELF)")?;
                firmware = Some(hil_sim::firmware::FirmwareTarget::new(Path::new(elf))?);
            }
            f => files.push(PathBuf::from(f)),
        }
    }
    if files.is_empty() {
        return Err("give at least one scenario file".into());
    }
    let mut failed = Vec::new();
    let mut v2x = Vec::new();
    for f in &files {
        let scenario = hil_sim::scenario::Scenario::load(f)?;
        println!("=== {} ({})", scenario.name, f.display());
        let opts = hil_sim::runner::RunOptions {
            obu: hil_sim::daemon::find_obu(),
            out: hil_sim::runner::out_dir(&out, f),
            http_port: 0,
            progress: std::io::IsTerminal::is_terminal(&std::io::stderr()),
            firmware: None,
        };
        let passed = match &firmware {
            None => run_one(&scenario, &opts, &mut v2x),
            Some(target) => run_against_firmware(&scenario, &opts, target, &mut v2x),
        };
        if !passed {
            failed.push(scenario.name.clone());
        }
    }
    v2x.sort_by(f64::total_cmp);
    if !v2x.is_empty() {
        let q = |p: f64| v2x[((p * v2x.len() as f64).ceil() as usize).clamp(1, v2x.len()) - 1];
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

fn print_report(r: &hil_sim::runner::RunReport) {
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
    if let Some(f) = r.files.first() {
        println!("  report: {}", f.display());
    }
}

fn state_dir() -> Result<PathBuf, String> {
    std::env::var_os("HMI_STATE_DIR")
        .map(PathBuf::from)
        .ok_or_else(|| "set HMI_STATE_DIR (the bench's state directory)".to_string())
}

fn server_options() -> Result<hmi_bench::ServerOptions, String> {
    let port = match std::env::var("HMI_PORT") {
        Ok(p) => p
            .parse()
            .map_err(|_| format!("HMI_PORT {p:?} is not a port"))?,
        Err(_) => 0,
    };
    Ok(hmi_bench::ServerOptions {
        obu: hil_sim::daemon::find_obu(),
        port,
        state_dir: state_dir()?,
    })
}
