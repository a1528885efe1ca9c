//! The command line: one subcommand per job, each flag with its help text and default
//! (`clap` derive).

use clap::{Parser, Subcommand, ValueEnum};
use std::net::SocketAddr;
use std::path::PathBuf;

/// hil-sim: roadside unit software and the OBU's hardware-in-the-loop bench.
#[derive(Debug, Parser)]
#[command(
    name = "hil-sim",
    args_override_self = true,
    after_help = "The daemon is `obu` beside this executable (build both with the same profile), \
                  or $OBU_BIN.\n\n\
                  Scenes: cruise, speeding (speed alarm, no alert), approach (stage Information), warning (Warning, complying \
                  driver), lane_closed, urgent (Urgent: in the closed lane 10-40 m before the \
                  zone), overspeed, in_zone, leaving;\n\
                  switches: gnss_lost, gnss_back (position Estimated, then Lost), time_fault, \
                  time_ok (NMEA time 2 min ahead of the clock: time unverified)."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// The jobs of the bench and the roadside unit.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the real obu daemon and feed it the tablet tests' road, work zone and drive at
    /// 10 Hz; prints the daemon's URL first (env: HMI_PORT, HMI_STATE_DIR, HMI_PIN: the
    /// daemon's pairing PIN, OBU_BIN).
    HmiServer,
    /// Switch a running hmi-server to a scene (env: HMI_STATE_DIR).
    HmiDrive {
        /// The scene (cruise, speeding, approach, warning, lane_closed, urgent, overspeed, in_zone,
        /// leaving) or a switch (gnss_lost, gnss_back, time_fault, time_ok).
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
    /// The real obu daemon for a long run: a car lapping the work zone (NMEA 10 Hz), the
    /// signed roadside at 10 Hz, N tablets on /events, forged/garbage V2X, refused settings
    /// writes, foreign Hosts and slow bodies; samples RSS, open files, CPU, event latency
    /// and counters every S seconds (a row each, DIR/soak.json); fails on growth after the
    /// warm-up (RSS, files over 5 %, p99 over max(2x, +2 ms)), a dropped client or event,
    /// a forged datagram not dropped for its reason, or counters that do not add up.
    Soak(SoakArgs),
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
    /// A rendered site with known truth for `roadside road-users` (road users from camera
    /// folders): --synthesize DIR writes DIR/cam1/ (and cam2/), each with its first frame's
    /// PNG, detections.json (COCO masks) and calibration.json (reference points), and
    /// DIR/truth.json and DIR/zone.json (the work zone's area).
    RoadUsers(RoadUsersArgs),
    /// One roadside fleet reconciling N test RSUs (snmpd + agent each, loopback ports) x M
    /// messages over SNMPv3 authPriv: time to converge from empty (goal under 10 s), SNMP
    /// requests per RSU of a poll when nothing changed (goal: reads only), memory; exit 1
    /// when a goal is missed.
    BenchRsuFleet {
        /// RSUs.
        #[arg(long, default_value_t = 200)]
        rsus: usize,
        /// Messages per RSU.
        #[arg(long, default_value_t = 4)]
        messages: usize,
        /// First loopback port.
        #[arg(long, default_value_t = 17200)]
        base_port: u16,
    },
    /// A test RSU until stopped: Debian's snmpd on a loopback port with SNMPv3 users and the
    /// NTCIP 1218 or RSU 4.1 tables, broadcasting each enabled row's payload (--to).
    TestRsu {
        /// Its folder (snmpd.conf, log).
        #[arg(long, value_name = "DIR", default_value = "hil-sim-out/test-rsu")]
        dir: PathBuf,
        /// Loopback UDP port of its SNMP agent.
        #[arg(long, default_value_t = 16161)]
        port: u16,
        /// `ntcip1218` or `rsu4.1`.
        #[arg(long, default_value = "ntcip1218")]
        mib: String,
        /// An SNMPv3 user, `NAME:AUTH:AUTHPASS:PRIV:PRIVPASS` with net-snmp's protocol names
        /// (e.g. `roadside:SHA:authpass1:AES:privpass1`; repeatable).
        #[arg(long = "user", value_name = "SPEC")]
        users: Vec<String>,
        /// Where the rows' payloads go (repeatable).
        #[arg(long = "to", value_name = "ADDR")]
        to: Vec<std::net::SocketAddr>,
        /// Rows per table.
        #[arg(long, default_value_t = 32)]
        max_rows: u32,
    },
    /// The test RSU's SNMP agent: snmpd starts it (pass_persist) for the NTCIP 1218 or
    /// RSU 4.1 tables; it broadcasts each enabled row's payload over UDP (--to).
    #[command(hide = true)]
    TestRsuAgent {
        /// `ntcip1218` or `rsu4.1`.
        #[arg(long)]
        mib: String,
        /// Rows per table.
        #[arg(long, default_value_t = 32)]
        max_rows: u32,
        /// Where the rows' payloads go (repeatable).
        #[arg(long = "to", value_name = "ADDR")]
        to: Vec<std::net::SocketAddr>,
        /// The RSU's IEEE 1609.2 PKI folder, for rows it is asked to sign.
        #[arg(long, value_name = "DIR")]
        pki: Option<PathBuf>,
        /// Where first transmissions and counts are logged.
        #[arg(long, value_name = "FILE")]
        log: Option<PathBuf>,
    },
}

/// `hil-sim run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Scenario files.
    #[arg(value_name = "SCENARIO.toml", required = true)]
    pub files: Vec<PathBuf>,
    /// Where the reports go (DIR/<scenario>/...).
    #[arg(long, value_name = "DIR", default_value = "hil-sim-out")]
    pub out: PathBuf,
    /// Also run each scenario against this firmware image in QEMU (netduinoplus2; $QEMU or
    /// qemu-system-arm), into DIR/<scenario>/daemon and .../firmware; the two HmiState
    /// timelines must match (timeline.json).
    #[arg(long, value_name = "ELF")]
    pub firmware: Option<PathBuf>,
}

/// `hil-sim soak`.
#[derive(Debug, clap::Args)]
pub struct SoakArgs {
    /// Length of the run, minutes.
    #[arg(long, value_name = "M", default_value_t = 120.0)]
    pub minutes: f64,
    /// Time between samples, seconds (the run needs 3 samples at least).
    #[arg(long, value_name = "S", default_value_t = 60.0)]
    pub sample_s: f64,
    /// Tablets following /events.
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub clients: usize,
    /// Where soak.json and the daemon's state go.
    #[arg(long, value_name = "DIR", default_value = "hil-sim-out/soak")]
    pub out: PathBuf,
}

/// `hil-sim roadside`.
#[derive(Debug, clap::Args)]
pub struct RoadsideArgs {
    /// The scenario file (its `[road]` and `[[zones]]`).
    #[arg(value_name = "SCENARIO.toml")]
    pub scenario: PathBuf,
    /// Broadcast to this UDP destination (repeat for more).
    #[arg(long, value_name = "HOST:PORT", value_parser = destination)]
    pub to: Vec<SocketAddr>,
    /// Bare MessageFrames or IEEE 1609.2 unsecured data.
    #[arg(long, value_name = "raw|1609.2", default_value = "raw")]
    pub wrap: Wrap,
    /// Broadcast rate, Hz.
    #[arg(long, value_name = "HZ", default_value_t = 10.0)]
    pub rate: f64,
    /// Stop after this many seconds (default: until stopped).
    #[arg(long, value_name = "S")]
    pub seconds: Option<f64>,
    /// Write the messages as RSU 4.1 text files into this folder.
    #[arg(long, value_name = "DIR")]
    pub rsu_files: Option<PathBuf>,
    /// Sign with the RSU certificate and key of this `roadside pki` folder: broadcasts are
    /// IEEE 1609.2 signed data (replacing --wrap), RSU files say Signature=True.
    #[arg(long, value_name = "DIR")]
    pub pki: Option<PathBuf>,
}

/// `--wrap`.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum Wrap {
    /// Bare MessageFrames.
    Raw,
    /// IEEE 1609.2 unsecured data.
    #[value(name = "1609.2")]
    Ieee1609,
}

/// `hil-sim synth-camera`.
#[derive(Debug, clap::Args)]
pub struct SynthCameraArgs {
    /// The scenario file (its first zone of source `lanes` is the ground truth).
    #[arg(long, value_name = "FILE.toml")]
    pub scenario: PathBuf,
    /// Where calibration.json and detections.json go.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Frames of detections.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub frames: usize,
    /// Pixel noise of the control points and boxes, 1-sigma per axis.
    #[arg(long, value_name = "S", default_value_t = 1.0)]
    pub noise_px: f64,
    /// Seed of the noise and the misses.
    #[arg(long, value_name = "K", default_value_t = 1)]
    pub seed: u64,
    /// Probability that a cone is missed in a frame.
    #[arg(long, value_name = "R", default_value_t = 0.1)]
    pub miss_rate: f64,
}

/// `hil-sim road-users`.
#[derive(Debug, clap::Args)]
pub struct RoadUsersArgs {
    /// Write a rendered site (cam1/, cam2/, truth.json, zone.json) here.
    #[arg(long, value_name = "DIR")]
    pub synthesize: PathBuf,
    /// Frames a second of the videos.
    #[arg(long, value_name = "F", default_value_t = 10.0)]
    pub fps: f64,
    /// Frames to synthesize.
    #[arg(long, value_name = "N", default_value_t = 100)]
    pub frames: usize,
    /// Cameras to synthesize (1 or 2).
    #[arg(long, value_name = "N", default_value_t = 2, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub views: u8,
    /// Mask noise of the synthesized detections, pixels.
    #[arg(long, value_name = "S", default_value_t = 1.0)]
    pub noise_px: f64,
    /// Seed of the synthesized traffic and noise.
    #[arg(long, value_name = "K", default_value_t = 1)]
    pub seed: u64,
    /// Synthesize at half resolution (960x540).
    #[arg(long)]
    pub small: bool,
}

/// A `--to` value: an IP address and a port.
fn destination(v: &str) -> Result<SocketAddr, String> {
    v.parse()
        .map_err(|_| format!("{v:?}: give HOST:PORT with an IP address"))
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
            "hil-sim soak --minutes 2 --sample-s 10",
            "hil-sim soak --minutes 10 --sample-s 60 --clients 20 --out o",
            "hil-sim roadside s.toml --to 192.168.1.20:1516 --wrap 1609.2",
            "hil-sim roadside s.toml --rsu-files rsu-out",
            "hil-sim hmi-server",
            "hil-sim hmi-drive gnss_lost",
            "hil-sim record s.toml o.nmea o.candump",
            "hil-sim synth-camera --scenario s.toml --out d --frames 3 --noise-px 0.5",
            "hil-sim road-users --synthesize site --frames 30 --small",
            "hil-sim road-users --synthesize site --frames 100 --views 1 --seed 3 --fps 5",
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
        // Scenario files before and after the flags; the last --out wins.
        assert_eq!(r.files, [PathBuf::from("a.toml"), PathBuf::from("b.toml")]);
        assert_eq!(r.out, PathBuf::from("y"));
        let Ok(Command::Soak(s)) = parse("hil-sim soak") else {
            panic!("soak did not parse");
        };
        assert_eq!((s.minutes, s.sample_s, s.clients), (120.0, 60.0, 50));
        assert_eq!(s.out, PathBuf::from("hil-sim-out/soak"));
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
            "hil-sim soak --minutes soon",
            "hil-sim soak --sample-s",
            "hil-sim synth-camera --out d",
            "hil-sim road-users",
            "hil-sim road-users --synthesize d --views 3",
            "hil-sim road-users --synthesize d --truth t.json",
            "hil-sim road-users site/cam1 site/cam2 --truth site/truth.json",
            "hil-sim pki site-pki",
            "hil-sim hmi-server extra",
            "hil-sim frobnicate",
        ] {
            assert!(parse(line).is_err(), "{line} parsed");
        }
    }
}
