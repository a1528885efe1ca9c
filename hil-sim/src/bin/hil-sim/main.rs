//! `hil-sim`: roadside unit software and the hardware-in-the-loop bench of the OBU. The
//! command line is declared in `args` (`clap` derive); the scenario runs are in `run`.
#![forbid(unsafe_code)]

mod args;
mod road_users;
mod run;

use args::{Cli, Command, RoadsideArgs, SoakArgs, SynthCameraArgs, Wrap};
use clap::Parser;
use hil_sim::{hmi_bench, perf};
use roadside::broadcast::Wrapping;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

fn main() -> ExitCode {
    let result = match Cli::parse().command {
        Command::HmiServer => server_options().and_then(|o| hmi_bench::serve(&o)),
        Command::HmiDrive { scene } => state_dir().and_then(|d| hmi_bench::drive(&d, &scene)),
        Command::BenchLatency { samples } => bench_latency(samples),
        Command::LoadTest { clients, seconds } => load_test(clients, seconds),
        Command::Soak(a) => soak(&a),
        Command::Run(a) => run::scenarios(&a),
        Command::Roadside(a) => roadside(&a),
        Command::Record {
            scenario,
            nmea,
            candump,
        } => record(&scenario, &nmea, &candump),
        Command::Demo { port, out } => demo(port, out),
        Command::SynthCamera(a) => synth_camera(&a),
        Command::RoadUsers(a) => road_users::road_users(&a),
        Command::BenchRsuFleet {
            rsus,
            messages,
            base_port,
        } => bench_rsu_fleet(rsus, messages, base_port),
        Command::TestRsu {
            dir,
            port,
            mib,
            users,
            to,
            max_rows,
        } => test_rsu(dir, port, &mib, &users, to, max_rows),
        Command::TestRsuAgent {
            mib,
            max_rows,
            to,
            pki,
            log,
        } => match hil_sim::test_rsu::agent::Mib::parse(&mib) {
            Some(m) => {
                hil_sim::test_rsu::run_agent(m, max_rows, to, pki.as_deref(), log.as_deref())
            }
            None => Err(format!("--mib {mib}: ntcip1218 or rsu4.1")),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("hil-sim: {e}");
            ExitCode::FAILURE
        }
    }
}

fn bench_rsu_fleet(rsus: usize, messages: usize, base_port: u16) -> Result<(), String> {
    let dir = hil_sim::fleet_bench::default_dir();
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let f = hil_sim::fleet_bench::run(rsus, messages, base_port, &dir, &exe);
    let _ = std::fs::remove_dir_all(&dir);
    let f = f?;
    println!(
        "{} RSUs x {} messages (NTCIP 1218, SNMPv3 SHA/AES-128, one snmpd + agent per RSU on loopback ports):",
        f.rsus, f.messages
    );
    println!(
        "  converged from empty tables in {:.2} s (goal under 10 s)",
        f.converge.as_secs_f64()
    );
    println!(
        "  poll with nothing to change: {:.1} reads and {:.1} writes per RSU, {:.2} s for the fleet (goal: reads only)",
        f.idle_reads_per_rsu,
        f.idle_writes_per_rsu,
        f.idle_poll.as_secs_f64()
    );
    println!(
        "  memory: roadside (this process) {:.1} MB RSS; the {} test RSUs {:.0} MB RSS in all",
        f.roadside_rss_kb as f64 / 1024.0,
        f.rsus,
        f.rsus_rss_kb as f64 / 1024.0
    );
    let ok = f.converge < Duration::from_secs(10) && f.idle_writes_per_rsu == 0.0;
    ok.then_some(()).ok_or("goal missed".into())
}

fn test_rsu(
    dir: PathBuf,
    port: u16,
    mib: &str,
    users: &[String],
    to: Vec<std::net::SocketAddr>,
    max_rows: u32,
) -> Result<(), String> {
    use hil_sim::test_rsu::{agent::Mib, TestRsu, TestRsuConfig, TestUser};
    let mib = Mib::parse(mib).ok_or(format!("--mib {mib}: ntcip1218 or rsu4.1"))?;
    let protocol = |p: &str| -> Result<&'static str, String> {
        [
            "MD5", "SHA", "SHA-224", "SHA-256", "SHA-384", "SHA-512", "DES", "AES", "AES-192",
            "AES-256",
        ]
        .into_iter()
        .find(|k| k.eq_ignore_ascii_case(p))
        .ok_or(format!("unknown protocol {p}"))
    };
    let users = users
        .iter()
        .map(|u| match u.split(':').collect::<Vec<_>>()[..] {
            [name, auth, ap, privacy, pp] => Ok(TestUser {
                name: name.into(),
                auth: protocol(auth)?,
                auth_password: ap.into(),
                privacy: protocol(privacy)?,
                priv_password: pp.into(),
            }),
            _ => Err(format!("--user {u}: NAME:AUTH:AUTHPASS:PRIV:PRIVPASS")),
        })
        .collect::<Result<Vec<_>, String>>()?;
    let hil_sim = std::env::current_exe().map_err(|e| e.to_string())?;
    let rsu = TestRsu::start(TestRsuConfig {
        dir,
        port,
        mib,
        users,
        community: None,
        broadcast_to: to,
        max_rows,
        pki: None,
        hil_sim,
    })?;
    println!(
        "test RSU on {} (snmpd log in {})",
        rsu.address(),
        rsu.dir().display()
    );
    loop {
        std::thread::sleep(Duration::from_secs(3600));
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

/// `hil-sim soak`: the run's rows as it goes, then every check; fails unless all hold.
fn soak(a: &SoakArgs) -> Result<(), String> {
    let opts = hil_sim::soak::SoakOptions {
        obu: hil_sim::daemon::find_obu(),
        minutes: a.minutes,
        sample_s: a.sample_s,
        clients: a.clients,
        out: a.out.clone(),
    };
    opts.validate()?;
    println!(
        "hil-sim soak: {} min, a sample every {} s, {} tablets, out {}",
        a.minutes,
        a.sample_s,
        a.clients,
        a.out.display()
    );
    let report = hil_sim::soak::run(&opts)?;
    for c in &report.checks {
        let mark = if c.ok { "ok  " } else { "FAIL" };
        println!("{mark} {}: {}", c.name, c.detail);
    }
    println!("wrote {}", a.out.join("soak.json").display());
    report
        .passed
        .then_some(())
        .ok_or("a soak check failed".into())
}

/// `hil-sim synth-camera`: calibration and detections of a synthetic camera that sees the
/// cones of the scenario's first zone of source `lanes` (the ground truth).
fn synth_camera(a: &SynthCameraArgs) -> Result<(), String> {
    use hil_sim::roadside_bench::synthetic_camera as synthetic;
    use hil_sim::scenario::ZoneSource;
    use roadside::camera::CameraModel;
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
const DEMO: &str = include_str!("../../../../tests/scenarios/01_paper_drive.toml");

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
    run::print_report(&report);
    report
        .passed
        .then_some(())
        .ok_or("an expectation did not hold".into())
}

fn roadside(a: &RoadsideArgs) -> Result<(), String> {
    let s = hil_sim::scenario::Scenario::load(&a.scenario)?;
    let o = roadside::rsu::RoadsideOptions {
        destinations: a.to.clone(),
        wrapping: match a.wrap {
            Wrap::Raw => Wrapping::Raw,
            Wrap::Ieee1609 => Wrapping::Ieee1609Unsecured,
        },
        rate_hz: a.rate,
        duration: a.seconds.map(Duration::from_secs_f64),
        rsu_dir: a.rsu_files.clone(),
        pki_dir: a.pki.clone(),
        signing: s.signing.settings(),
    };
    if o.destinations.is_empty() && o.rsu_dir.is_none() {
        return Err("give --to HOST:PORT (broadcast) and/or --rsu-files DIR".into());
    }
    let summary = roadside::rsu::run(&s.site(), &o).map_err(|e| e.to_string())?;
    println!("hil-sim roadside: {summary}");
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
            sigma_m: s.drive.reported_sigma(),
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
    let pin = match std::env::var("HMI_PIN") {
        Ok(p) if (4..=32).contains(&p.len()) && p.bytes().all(|b| b.is_ascii_alphanumeric()) => {
            Some(p)
        }
        Ok(p) => return Err(format!("HMI_PIN {p:?}: expected 4 to 32 letters or digits")),
        Err(_) => None,
    };
    Ok(hmi_bench::ServerOptions {
        obu: hil_sim::daemon::find_obu(),
        port,
        state_dir: state_dir()?,
        pin,
    })
}
