//! The bench of the tablet app's browser tests (`hmi-web/tests`): `hil-sim hmi-server`
//! runs the real `obu` daemon and feeds it, over its real UDP inputs, a divided road
//! (three lanes east, two west), a work zone closing the right eastbound lane with a
//! reduced limit, and a car driving one of the [`SCENES`] at 10 Hz; `hil-sim hmi-drive
//! SCENE` switches the scene. Both share a control file in the state directory.
//!
//! A scene loops the car over a window of stations so that it holds for as long as a
//! test needs (the zone is valid until further notice). Each alert stage of the core has
//! a scene: `approach` (Information), `warning` (Warning, a complying driver), `urgent`
//! (Urgent: still in the closed lane where a lane change no longer fits) and `in_zone`.
//! The [`SWITCHES`] act on top of the scene: `gnss_lost`/`gnss_back` stop and resume the
//! GNSS feed (the core dead-reckons for a few seconds, "Estimated", then reports the
//! position "Lost"), and `time_fault`/`time_ok` stamp the NMEA time [`TIME_FAULT_MS`]
//! ahead of the real clock and back (the daemon compares GNSS time with its system clock:
//! "time unverified").

use crate::daemon::Daemon;
use crate::nmea::{self, Epoch};
use obu::LatLon;
use obu_daemon::config::{Config, LaneMethod};
use roadside::clock::{unix_ms_now, Utc};
use roadside::messages::{self, SignSpeed, WorkZone, DURATION_INDEFINITE};
use roadside::road::Road;
use std::io::Write;
use std::net::UdpSocket;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// One scene: the car drives `lane` at `speed_mps` from station `from_m` to `to_m`
/// (metres along the lane from its start) and starts over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scene {
    /// Name used by the driver command.
    pub name: &'static str,
    /// Lane driven.
    pub lane: u8,
    /// First station of the loop.
    pub from_m: f64,
    /// Last station of the loop.
    pub to_m: f64,
    /// Speed, m/s.
    pub speed_mps: f64,
}

/// Station where the zone starts on lane 3 (and, beside it, on lanes 1 and 2).
pub const ZONE_START_M: f64 = 1500.0;
/// Station where it ends.
pub const ZONE_END_M: f64 = 1700.0;

/// The scenes. With the default settings (warning 100 m, lead time 9 s, approach at 3x
/// the warning distance, overspeed 5 km/h over the 40 km/h limit, a lane change takes
/// max(5 s, 30 m)): cruise far before the zone; speeding the same at 27 m/s (97 km/h on
/// the 80 km/h road: the speed alarm with no alert); approach 250-550 m before it at 22 m/s
/// (warning 198 m); warning 10-80 m before it at 10.5 m/s in the open lane 2, below the
/// zone limit; lane_closed the same in the closed lane 3; urgent 10-40 m before it in the
/// closed lane 3 at 10.5 m/s (a lane change needs 52 m); overspeed 10-60 m before it at
/// 22 m/s (slowing to 40 km/h by the zone needs more than the comfortable 2.5 m/s²: Urgent);
/// in_zone inside it; leaving just after it.
pub const SCENES: &[Scene] = &[
    Scene {
        name: "cruise",
        lane: 2,
        from_m: 100.0,
        to_m: 800.0,
        speed_mps: 22.0,
    },
    Scene {
        name: "speeding",
        lane: 2,
        from_m: 100.0,
        to_m: 600.0,
        speed_mps: 27.0,
    },
    Scene {
        name: "approach",
        lane: 2,
        from_m: 950.0,
        to_m: 1250.0,
        speed_mps: 22.0,
    },
    Scene {
        name: "warning",
        lane: 2,
        from_m: 1420.0,
        to_m: 1490.0,
        speed_mps: 10.5,
    },
    Scene {
        name: "lane_closed",
        lane: 3,
        from_m: 1420.0,
        to_m: 1490.0,
        speed_mps: 10.5,
    },
    Scene {
        name: "urgent",
        lane: 3,
        from_m: 1460.0,
        to_m: 1490.0,
        speed_mps: 10.5,
    },
    Scene {
        name: "overspeed",
        lane: 2,
        from_m: 1440.0,
        to_m: 1490.0,
        speed_mps: 22.0,
    },
    Scene {
        name: "in_zone",
        lane: 2,
        from_m: 1520.0,
        to_m: 1680.0,
        speed_mps: 10.5,
    },
    Scene {
        name: "leaving",
        lane: 2,
        from_m: 1705.0,
        to_m: 1740.0,
        speed_mps: 13.0,
    },
];

/// Switches that act on top of the scene.
pub const SWITCHES: &[&str] = &["gnss_lost", "gnss_back", "time_fault", "time_ok"];

/// How far ahead of the real clock `time_fault` stamps the NMEA time, milliseconds.
pub const TIME_FAULT_MS: i64 = 120_000;

/// The scene called `name`.
pub fn scene(name: &str) -> Option<&'static Scene> {
    SCENES.iter().find(|s| s.name == name)
}

impl Scene {
    /// Station of the car `t_s` seconds into the scene.
    pub fn station(&self, t_s: f64) -> f64 {
        let span = (self.to_m - self.from_m).max(1.0);
        self.from_m + (self.speed_mps * t_s.max(0.0)) % span
    }
}

/// The bench road: a divided road east from a point in Denver, 3000 m long.
pub fn road() -> Road {
    let reference = LatLon::from_degrees(39.739_2, -104.990_3).unwrap_or_default();
    Road::straight(reference, 90.0, 3000.0, (3, 2), 3.6, 80.0)
}

/// The bench zone: lane 3 closed from 1500 to 1700 m, 40 km/h, valid from `start`
/// until further notice.
pub fn zone(start: Utc) -> WorkZone {
    WorkZone {
        closed_lanes: vec![3],
        start_m: ZONE_START_M,
        end_m: ZONE_END_M,
        speed_limit: Some(SignSpeed {
            value: 40,
            mph: false,
        }),
        packet_id: *b"HILBENCH1",
        msg_cnt: 1,
        start,
        duration_min: DURATION_INDEFINITE,
    }
}

/// What the driver asked for: the scene, whether GNSS is fed and whether its time is off.
#[derive(Debug, Clone, PartialEq)]
pub struct Control {
    /// Scene name.
    pub scene: String,
    /// False during a GNSS dropout.
    pub gnss: bool,
    /// True while the NMEA time runs [`TIME_FAULT_MS`] ahead of the real clock.
    pub time_fault: bool,
}

impl Control {
    fn path(dir: &Path) -> PathBuf {
        dir.join("hil-sim-scene")
    }

    /// Reads the control file (`cruise` with GNSS and the right time when there is none
    /// yet): `SCENE gnss_ok|gnss_lost [time_ok|time_fault]`.
    pub fn read(dir: &Path) -> Self {
        let text = std::fs::read_to_string(Self::path(dir)).unwrap_or_default();
        let mut words = text.split_whitespace();
        let scene = words
            .next()
            .filter(|s| scene(s).is_some())
            .unwrap_or("cruise");
        Self {
            scene: scene.to_string(),
            gnss: words.next() != Some("gnss_lost"),
            time_fault: words.next() == Some("time_fault"),
        }
    }

    /// Writes it atomically (a reader never sees half a file).
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let tmp = dir.join("hil-sim-scene.tmp");
        let gnss = if self.gnss { "gnss_ok" } else { "gnss_lost" };
        let time = if self.time_fault {
            "time_fault"
        } else {
            "time_ok"
        };
        std::fs::write(&tmp, format!("{} {gnss} {time}\n", self.scene))?;
        std::fs::rename(tmp, Self::path(dir))
    }

    /// Offset of the NMEA time from the real clock, milliseconds.
    pub fn clock_offset_ms(&self) -> i64 {
        if self.time_fault {
            TIME_FAULT_MS
        } else {
            0
        }
    }
}

/// `hil-sim hmi-drive NAME`: switches the scene or GNSS of a running bench.
pub fn drive(dir: &Path, name: &str) -> Result<(), String> {
    let mut control = Control::read(dir);
    match name {
        "gnss_lost" => control.gnss = false,
        "gnss_back" => control.gnss = true,
        "time_fault" => control.time_fault = true,
        "time_ok" => control.time_fault = false,
        _ if scene(name).is_some() => control.scene = name.to_string(),
        _ => {
            let names: Vec<_> = SCENES
                .iter()
                .map(|s| s.name)
                .chain(SWITCHES.iter().copied())
                .collect();
            return Err(format!(
                "unknown scene {name:?}; scenes: {}",
                names.join(", ")
            ));
        }
    }
    control
        .write(dir)
        .map_err(|e| format!("cannot write the control file in {}: {e}", dir.display()))
}

/// Where the bench runs.
#[derive(Debug, Clone)]
pub struct ServerOptions {
    /// The `obu` executable.
    pub obu: PathBuf,
    /// HTTP port of the daemon (0: any).
    pub port: u16,
    /// Kept across restarts: the daemon's settings and the control file.
    pub state_dir: PathBuf,
    /// The daemon's pairing PIN (`[http] pin`); `None`: the daemon makes one.
    pub pin: Option<String>,
}

/// The bench's MAP and TIM as UPER bytes, the zone valid from two minutes ago.
pub fn bench_messages() -> Result<(Vec<u8>, Vec<u8>), String> {
    let road = road();
    let zone = zone(Utc::from_unix_ms(unix_ms_now().saturating_sub(120_000)));
    let built = messages::build_map(&road, 1501, 1, Some(&zone))
        .and_then(|map| Ok((map, messages::build_tim(&road, &zone)?)));
    let (map, tim) = built.map_err(|e| format!("building the bench's MAP and TIM: {e}"))?;
    let map = messages::encode(&map).map_err(|e| e.to_string())?;
    let tim = messages::encode(&tim).map_err(|e| e.to_string())?;
    Ok((map, tim))
}

/// Sends the bench's inputs to a daemon: MAP and TIM to its V2X port and the car's NMEA
/// epoch to its GNSS port, one tick at a time.
#[derive(Debug)]
pub struct Feeder {
    sock: UdpSocket,
    road: Road,
    map: Vec<u8>,
    tim: Vec<u8>,
    signer: std::sync::Arc<roadside::signer::RsuSigner>,
}

impl Feeder {
    /// A feeder of the bench road and zone.
    pub fn new() -> Result<Self, String> {
        let (map, tim) = bench_messages()?;
        let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
        Ok(Self {
            sock,
            road: road(),
            map,
            tim,
            signer: crate::bench_pki::signer()?,
        })
    }

    /// One tick: MAP and TIM, then (unless `gnss` is false) the epoch of the car `t_s`
    /// seconds into `scene`. Datagrams lost on the way are part of radio life: no retry.
    pub fn tick(&self, daemon: &Daemon, scene: &str, t_s: f64, gnss: bool) {
        self.tick_with_clock(daemon, scene, t_s, gnss, 0);
    }

    /// [`Feeder::tick`] with the NMEA time `clock_offset_ms` off the real clock (the
    /// roadside messages keep the real time).
    pub fn tick_with_clock(
        &self,
        daemon: &Daemon,
        scene: &str,
        t_s: f64,
        gnss: bool,
        clock_offset_ms: i64,
    ) {
        let now = roadside::clock::unix_ms_now();
        for frame in [&self.map, &self.tim] {
            if let Ok(signed) = self.signer.sign(frame, now) {
                let _ = self.sock.send_to(&signed, &daemon.v2x);
            }
        }
        if gnss {
            self.send_epoch_with_clock(daemon, scene, t_s, clock_offset_ms);
        }
    }

    /// Only the NMEA epoch of the car `t_s` seconds into `scene` (one datagram).
    pub fn send_epoch(&self, daemon: &Daemon, scene: &str, t_s: f64) {
        self.send_epoch_with_clock(daemon, scene, t_s, 0);
    }

    fn send_epoch_with_clock(&self, daemon: &Daemon, scene: &str, t_s: f64, offset_ms: i64) {
        let utc = Utc::from_unix_ms(unix_ms_now().saturating_add_signed(offset_ms));
        if let Some(e) = car_epoch_at(&self.road, scene, t_s, utc) {
            let _ = self.sock.send_to(nmea::epoch(&e).as_bytes(), &daemon.gnss);
        }
    }
}

/// Starts the daemon for the bench: HTTP on `port`, state in `state_dir`, with what
/// `adjust` changes in the bench's configuration ([`crate::daemon::config`]).
pub fn start_daemon(
    obu: &Path,
    state_dir: &Path,
    port: u16,
    adjust: impl FnOnce(&mut Config),
) -> Result<Daemon, String> {
    // Port 0: the daemon binds any free port and names it on its first line (no race with
    // another bench picking the same "free" port).
    let mut config = crate::daemon::config(state_dir, 0, port)?;
    adjust(&mut config);
    Daemon::start(obu, state_dir, &config)
}

/// The bench world's lane setting: its scenes loop the car over a short window, jumping
/// back tens of metres at each loop, which the lane filter rightly rejects as outliers; the
/// bench world's daemon therefore decides lanes fix by fix. Scenarios use the default.
pub fn per_fix_lanes(config: &mut Config) {
    config.lane.method = LaneMethod::PerFix;
}

/// The core's configuration matching [`per_fix_lanes`] (for tests of the scenes on the core).
pub fn core_config() -> obu::AlertConfig {
    obu::AlertConfig {
        matcher: obu::matcher::MatcherConfig::PER_FIX,
        ..obu::AlertConfig::DEFAULT
    }
}

/// `hil-sim hmi-server`: starts the daemon (with the pairing PIN of `opts`, if any), prints
/// its URL as the first line, then feeds
/// it at 10 Hz until it exits (a SIGTERM to the process group stops both).
pub fn serve(opts: &ServerOptions) -> Result<(), String> {
    let mut daemon = start_daemon(&opts.obu, &opts.state_dir, opts.port, |c| {
        c.http.pin.clone_from(&opts.pin);
        per_fix_lanes(c);
    })?;
    println!("{}", daemon.http);
    std::io::stdout().flush().map_err(|e| e.to_string())?;
    let feeder = Feeder::new()?;
    let tick = Duration::from_millis(100);
    let mut next = Instant::now();
    let mut current = Control::read(&opts.state_dir);
    let mut since = Instant::now();
    loop {
        if let Ok(Some(status)) = daemon.child.try_wait() {
            return Err(format!("the daemon exited: {status}"));
        }
        let control = Control::read(&opts.state_dir);
        if control.scene != current.scene {
            since = Instant::now();
        }
        current = control;
        feeder.tick_with_clock(
            &daemon,
            &current.scene,
            since.elapsed().as_secs_f64(),
            current.gnss,
            current.clock_offset_ms(),
        );
        next += tick;
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
}

/// The receiver's epoch for the car `t_s` seconds into `scene`, now.
pub fn car_epoch(road: &Road, scene_name: &str, t_s: f64) -> Option<Epoch> {
    car_epoch_at(road, scene_name, t_s, Utc::now())
}

/// The receiver's epoch for the car `t_s` seconds into `scene`, stamped `utc`.
pub fn car_epoch_at(road: &Road, scene_name: &str, t_s: f64, utc: Utc) -> Option<Epoch> {
    scene_epoch(road, scene(scene_name)?, t_s, utc)
}

/// The receiver's epoch for a car driving scene `s` on `road`, `t_s` seconds in, stamped
/// `utc` (0.3 m accuracy).
pub fn scene_epoch(road: &Road, s: &Scene, t_s: f64, utc: Utc) -> Option<Epoch> {
    let on = road.lane(s.lane)?.at(s.station(t_s))?;
    Some(Epoch {
        utc,
        position: road.to_wgs84(on.point)?,
        speed_mps: s.speed_mps,
        course_deg: on.bearing_deg,
        sigma_m: 0.3,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn switches_act_on_top_of_the_scene() {
        let dir = std::env::temp_dir().join(format!("hmi-bench-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert_eq!(Control::read(&dir).scene, "cruise");
        drive(&dir, "urgent").unwrap();
        drive(&dir, "gnss_lost").unwrap();
        drive(&dir, "time_fault").unwrap();
        let c = Control::read(&dir);
        assert_eq!(
            (c.scene.as_str(), c.gnss, c.time_fault),
            ("urgent", false, true)
        );
        assert_eq!(c.clock_offset_ms(), TIME_FAULT_MS);
        drive(&dir, "time_ok").unwrap();
        drive(&dir, "gnss_back").unwrap();
        let c = Control::read(&dir);
        assert_eq!(
            (c.scene.as_str(), c.gnss, c.time_fault),
            ("urgent", true, false)
        );
        assert_eq!(c.clock_offset_ms(), 0);
        assert!(drive(&dir, "nonsense").unwrap_err().contains("time_fault"));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_urgent_scene_stays_in_the_closed_lane_within_a_lane_change() {
        let s = scene("urgent").unwrap();
        assert_eq!(s.lane, 3);
        // a lane change needs max(5 s x speed, 30 m) = 52.5 m
        let lane_change_m = (5.0 * s.speed_mps).max(30.0);
        for k in 0..200 {
            let d = ZONE_START_M - s.station(f64::from(k) * 0.1);
            assert!((10.0..=40.0).contains(&d) && d < lane_change_m, "{d}");
        }
    }
}
