//! `hil-sim`: roadside unit software and the hardware-in-the-loop bench of the OBU. The
//! command line is declared with `clap` (derive): one subcommand per job, each flag with
//! its help text and default.
#![forbid(unsafe_code)]

use clap::{Parser, Subcommand, ValueEnum};
use hil_sim::{hmi_bench, perf};
use roadside::broadcast::Wrapping;
use std::net::SocketAddr;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

/// hil-sim: roadside unit software and the OBU's hardware-in-the-loop bench.
#[derive(Debug, Parser)]
#[command(
    name = "hil-sim",
    args_override_self = true,
    after_help = "The daemon is `obu` beside this executable (build both with the same profile), \
                  or $OBU_BIN.\n\n\
                  Scenes: cruise, approach, warning, lane_closed, overspeed, in_zone, leaving;\n\
                  switches: gnss_lost, gnss_back."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The jobs of the bench and the roadside unit.
#[derive(Debug, Subcommand)]
enum Command {
    /// Run the real obu daemon and feed it the tablet tests' road, work zone and drive at
    /// 10 Hz; prints the daemon's URL first (env: HMI_PORT, HMI_STATE_DIR, OBU_BIN).
    HmiServer,
    /// Switch a running hmi-server to a scene (env: HMI_STATE_DIR).
    HmiDrive {
        /// The scene (cruise, approach, warning, lane_closed, overspeed, in_zone, leaving)
        /// or a switch (gnss_lost, gnss_back).
        scene: String,
    },
    /// GNSS datagram in -> state event out of the real daemon on the loopback: p50/p99/max;
    /// fails when p99 >= 2 ms or a state is lost.
    BenchLatency {
        /// Datagrams measured (for GNSS and for TIM each).
        #[arg(long, value_name = "N", default_value_t = 2000)]
        samples: usize,
    },
    /// N tablets follow /events while the daemon is fed at 10 Hz: events per client and
    /// the daemon's CPU; fails on a dropped client or CPU >= 10 % of a core.
    LoadTest {
        /// Tablets following /events.
        #[arg(long, value_name = "N", default_value_t = 50)]
        clients: usize,
        /// How long the daemon is fed, seconds.
        #[arg(long, value_name = "S", default_value_t = 60.0)]
        seconds: f64,
    },
    /// Run scenarios against the real obu daemon; writes DIR/<scenario>/report.json,
    /// states.jsonl and plots; fails when an expectation does not hold.
    Run(RunArgs),
    /// The roadside unit: the scenario's lane map and work zones (GeoJSON, WZDx, cones,
    /// camera) as MAP + TIM, broadcast over UDP (--to, until stopped unless --seconds)
    /// and/or written as RSU 4.1 text files (--rsu-files); give at least one of the two.
    Roadside(RoadsideArgs),
    /// The scenario's drive as a GNSS receiver's NMEA log (10 Hz GST, GGA, RMC with its
    /// noise and dropouts) and a candump log of its speed.
    Record {
        /// The scenario file.
        #[arg(value_name = "SCENARIO.toml")]
        scenario: PathBuf,
        /// Where the NMEA log goes.
        #[arg(value_name = "OUT.nmea")]
        nmea: PathBuf,
        /// Where the candump log goes.
        #[arg(value_name = "OUT.candump")]
        candump: PathBuf,
    },
    /// The field test: roadside, OBU and a drive through a work zone (40 km/h road, limit
    /// 10 km/h, 100 m warning, lane change) with the tablet app live.
    Demo {
        /// HTTP port of the tablet app (http://127.0.0.1:P).
        #[arg(long, value_name = "P", default_value_t = 8080)]
        port: u16,
        /// Where the run's report goes.
        #[arg(long, value_name = "DIR", default_value = "hil-sim-out/demo")]
        out: PathBuf,
    },
    /// Synthetic camera data of the scenario's first `lanes` zone: cones along the closed
    /// lanes, a camera beside the road before the zone; writes DIR/calibration.json and
    /// DIR/detections.json.
    SynthCamera(SynthCameraArgs),
}

/// `hil-sim run`.
#[derive(Debug, clap::Args)]
struct RunArgs {
    /// Scenario files.
    #[arg(value_name = "SCENARIO.toml", required = true)]
    files: Vec<PathBuf>,
    /// Where the reports go (DIR/<scenario>/...).
    #[arg(long, value_name = "DIR", default_value = "hil-sim-out")]
    out: PathBuf,
    /// Also run each scenario against this firmware image in QEMU (netduinoplus2; $QEMU or
    /// qemu-system-arm), into DIR/<scenario>/daemon and .../firmware; the two HmiState
    /// timelines must match (timeline.json).
    #[arg(long, value_name = "ELF")]
    firmware: Option<PathBuf>,
}

/// `hil-sim roadside`.
#[derive(Debug, clap::Args)]
struct RoadsideArgs {
    /// The scenario file (its `[road]` and `[[zones]]`).
    #[arg(value_name = "SCENARIO.toml")]
    scenario: PathBuf,
    /// Broadcast to this UDP destination (repeat for more).
    #[arg(long, value_name = "HOST:PORT", value_parser = destination)]
    to: Vec<SocketAddr>,
    /// Bare MessageFrames or IEEE 1609.2 unsecured data.
    #[arg(long, value_name = "raw|1609.2", default_value = "raw")]
    wrap: Wrap,
    /// Broadcast rate, Hz.
    #[arg(long, value_name = "HZ", default_value_t = 10.0)]
    rate: f64,
    /// Stop after this many seconds (default: until stopped).
    #[arg(long, value_name = "S")]
    seconds: Option<f64>,
    /// Write the messages as RSU 4.1 text files into this folder.
    #[arg(long, value_name = "DIR")]
    rsu_files: Option<PathBuf>,
}

/// `--wrap`.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum Wrap {
    /// Bare MessageFrames.
    Raw,
    /// IEEE 1609.2 unsecured data.
    #[value(name = "1609.2")]
    Ieee1609,
}

/// `hil-sim synth-camera`.
#[derive(Debug, clap::Args)]
struct SynthCameraArgs {
    /// The scenario file (its first zone of source `lanes` is the ground truth).
    #[arg(long, value_name = "FILE.toml")]
    scenario: PathBuf,
    /// Where calibration.json and detections.json go.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// Frames of detections.
    #[arg(long, value_name = "N", default_value_t = 10)]
    frames: usize,
    /// Pixel noise of the control points and boxes, 1-sigma per axis.
    #[arg(long, value_name = "S", default_value_t = 1.0)]
    noise_px: f64,
    /// Seed of the noise and the misses.
    #[arg(long, value_name = "K", default_value_t = 1)]
    seed: u64,
    /// Probability that a cone is missed in a frame.
    #[arg(long, value_name = "R", default_value_t = 0.1)]
    miss_rate: f64,
}

/// A `--to` value: an IP address and a port.
fn destination(v: &str) -> Result<SocketAddr, String> {
    v.parse()
        .map_err(|_| format!("{v:?}: give HOST:PORT with an IP address"))
}

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::HmiServer => server_options().and_then(|o| hmi_bench::serve(&o)),
        Command::HmiDrive { scene } => state_dir().and_then(|d| hmi_bench::drive(&d, &scene)),
        Command::BenchLatency { samples } => bench_latency(samples),
        Command::LoadTest { clients, seconds } => load_test(clients, seconds),
        Command::Run(a) => run_scenarios(&a),
        Command::Roadside(a) => roadside(&a),
        Command::Record {
            scenario,
            nmea,
            candump,
        } => record(&scenario, &nmea, &candump),
        Command::Demo { port, out } => demo(port, out),
        Command::SynthCamera(a) => synth_camera(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hil-sim: {e}");
            ExitCode::FAILURE
        }
    }
}

fn bench_latency(samples: usize) -> Result<(), String> {
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

fn load_test(clients: usize, seconds: f64) -> Result<(), String> {
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
fn synth_camera(a: &SynthCameraArgs) -> Result<(), String> {
    use hil_sim::scenario::ZoneSource;
    use roadside::camera::{synthetic, CameraModel};
    let spec = synthetic::CaptureSpec {
        frames: a.frames,
        noise_px: a.noise_px,
        miss_rate: a.miss_rate,
        seed: a.seed,
        placement: synthetic::Placement::default(),
    };
    let out = &a.out;
    let scenario = hil_sim::scenario::Scenario::load(&a.scenario)?;
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
    let files = capture.write(out, &note)?;
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

fn demo(port: u16, out: PathBuf) -> Result<(), String> {
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

fn roadside(a: &RoadsideArgs) -> Result<(), String> {
    let s = hil_sim::scenario::Scenario::load(&a.scenario)?;
    let o = roadside::unit::RoadsideOptions {
        destinations: a.to.clone(),
        wrapping: match a.wrap {
            Wrap::Raw => Wrapping::Raw,
            Wrap::Ieee1609 => Wrapping::Ieee1609Unsecured,
        },
        rate_hz: a.rate,
        duration: a.seconds.map(Duration::from_secs_f64),
        rsu_dir: a.rsu_files.clone(),
    };
    if o.destinations.is_empty() && o.rsu_dir.is_none() {
        return Err("give --to HOST:PORT (broadcast) and/or --rsu-files DIR".into());
    }
    println!("hil-sim roadside: {}", roadside::unit::run(&s.site(), &o)?);
    Ok(())
}

fn record(scenario: &Path, nmea_out: &Path, candump_out: &Path) -> Result<(), String> {
    use hil_sim::{drive, nmea};
    use roadside::clock::Utc;
    let s = hil_sim::scenario::Scenario::load(scenario)?;
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
    std::fs::write(nmea_out, text).map_err(|e| format!("{}: {e}", nmea_out.display()))?;
    std::fs::write(candump_out, drive::candump(&samples, t0_ms as f64 / 1000.0))
        .map_err(|e| format!("{}: {e}", candump_out.display()))?;
    println!(
        "{} epochs to {}, speed frames to {}",
        samples.iter().filter(|x| x.reported.is_some()).count(),
        nmea_out.display(),
        candump_out.display()
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

fn run_scenarios(a: &RunArgs) -> Result<(), String> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    fn parse(line: &str) -> Result<Command, clap::Error> {
        Cli::try_parse_from(line.split_whitespace()).map(|c| c.command)
    }

    #[test]
    fn the_command_line_is_consistent() {
        Cli::command().debug_assert();
    }

    #[test]
    fn the_invocations_of_ci_readme_and_the_browser_tests_parse() {
        for line in [
            "hil-sim run a.toml b.toml --out target/hil-sim-out",
            "hil-sim run a.toml --out out/firmware --firmware obu/firmware/x.elf",
            "hil-sim load-test --clients 50 --seconds 10",
            "hil-sim demo",
            "hil-sim bench-latency",
            "hil-sim load-test",
            "hil-sim roadside s.toml --to 192.168.1.20:1516 --wrap 1609.2",
            "hil-sim roadside s.toml --rsu-files rsu-out",
            "hil-sim hmi-server",
            "hil-sim hmi-drive gnss_lost",
            "hil-sim record s.toml o.nmea o.candump",
            "hil-sim synth-camera --scenario s.toml --out d --frames 3 --noise-px 0.5",
        ] {
            assert!(parse(line).is_ok(), "{line}: {:?}", parse(line).err());
        }
    }

    #[test]
    fn values_and_defaults_arrive_typed() {
        let Ok(Command::Roadside(a)) = parse(
            "hil-sim roadside s.toml --to 127.0.0.1:1 --to 127.0.0.1:2 --wrap 1609.2 --seconds 2",
        ) else {
            panic!("roadside did not parse");
        };
        assert_eq!(a.to.len(), 2);
        assert!(matches!(a.wrap, Wrap::Ieee1609));
        assert_eq!((a.rate, a.seconds, a.rsu_files), (10.0, Some(2.0), None));
        let Ok(Command::Run(r)) = parse("hil-sim run a.toml --out x b.toml --out y") else {
            panic!("run did not parse");
        };
        // Scenario files before and after the flags; the last --out wins, as before.
        assert_eq!(r.files, [PathBuf::from("a.toml"), PathBuf::from("b.toml")]);
        assert_eq!(r.out, PathBuf::from("y"));
        let Ok(Command::SynthCamera(c)) = parse("hil-sim synth-camera --scenario s --out o") else {
            panic!("synth-camera did not parse");
        };
        assert_eq!(
            (c.frames, c.noise_px, c.seed, c.miss_rate),
            (10, 1.0, 1, 0.1)
        );
    }

    #[test]
    fn bad_values_are_refused() {
        for line in [
            "hil-sim run",
            "hil-sim roadside s.toml --to example.org:1516",
            "hil-sim roadside s.toml --wrap tls",
            "hil-sim roadside s.toml --rate fast",
            "hil-sim load-test --clients many",
            "hil-sim synth-camera --out d",
            "hil-sim hmi-server extra",
            "hil-sim frobnicate",
        ] {
            assert!(parse(line).is_err(), "{line} parsed");
        }
    }
}
