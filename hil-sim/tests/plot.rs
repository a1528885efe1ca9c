//! The report plots of a synthetic drive: a straight 3-lane road east, a zone closing lane 3
//! from 400 m to 500 m, the car starting in lane 3, changing to lane 2 and slowing down.

use std::path::{Path, PathBuf};

use hil_sim::plot::{write_plots, PlotInput, PlotLane, TrackPoint};

const LANE_WIDTH: f64 = 3.5;
const ZONE: (f64, f64) = (400.0, 500.0);
const WARNING_M: f64 = 150.0;

/// A fresh directory under the system temp dir, unique per test and process.
fn out_dir(name: &str) -> PathBuf {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!(
        "hil-sim-plot-{name}-{}-{nanos}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Lane n's centreline is n-1 lane widths north of the road's reference line.
fn lane_north(lane: u8) -> f64 {
    f64::from(lane - 1) * LANE_WIDTH
}

fn lanes() -> Vec<PlotLane> {
    (1..=3)
        .map(|id| PlotLane {
            id,
            centre: vec![[-100.0, lane_north(id)], [900.0, lane_north(id)]],
            width_m: LANE_WIDTH,
        })
        .collect()
}

fn zones() -> Vec<Vec<[f64; 2]>> {
    vec![vec![[ZONE.0, lane_north(3)], [ZONE.1, lane_north(3)]]]
}

/// Speed (m/s) at east position x: 25 m/s, braking to 15 m/s before the zone, 22 m/s after.
fn true_speed(x: f64) -> f64 {
    match x {
        x if x < 150.0 => 25.0,
        x if x < 380.0 => 25.0 - 10.0 * (x - 150.0) / 230.0,
        x if x < 520.0 => 15.0,
        x => (15.0 + (x - 520.0) * 0.1).min(22.0),
    }
}

fn zone_state(x: f64) -> &'static str {
    let d = ZONE.0 - x;
    match x {
        _ if d > 300.0 => "None",
        _ if d > WARNING_M => "Approaching",
        _ if d > 0.0 => "Warning",
        x if x <= ZONE.1 => "InZone",
        _ => "Leaving",
    }
}

/// North position and true lane: lane 3, changing to lane 2 between 250 m and 300 m east.
fn lateral(x: f64) -> (f64, u8) {
    let f = ((x - 250.0) / 50.0).clamp(0.0, 1.0);
    let north = lane_north(3) - f * LANE_WIDTH;
    (north, if f < 0.5 { 3 } else { 2 })
}

fn point(t_s: f64, x: f64) -> TrackPoint {
    let (north, lane) = lateral(x);
    let speed = true_speed(x) + 0.2 * (t_s * 1.3).sin();
    let state = zone_state(x);
    let limit = if state == "None" { 27.8 } else { 16.7 };
    let stale = (17.0..19.0).contains(&t_s);
    let primary = match state {
        _ if stale => Some("GnssStale"),
        "Approaching" => Some("ReducedSpeedAhead"),
        "Warning" if lane == 3 => Some("LaneClosedOwn"),
        "Warning" | "InZone" if speed > limit => Some("Overspeed"),
        "Warning" => Some("ReducedSpeedAhead"),
        _ => None,
    };
    // The OBU lags the lane change by one second and has no lane while GNSS is stale.
    let matched = if stale {
        None
    } else {
        Some(lateral(x - speed).1)
    };
    TrackPoint {
        t_s,
        true_point: [x, north],
        true_lane: lane,
        true_distance_m: Some(ZONE.0 - x),
        speed_mps: (!stale).then_some(speed),
        limit_mps: Some(limit),
        zone_state: state.to_string(),
        primary: primary.map(str::to_string),
        matched_lane: matched,
    }
}

fn synthetic_track() -> Vec<TrackPoint> {
    let (mut t, mut x, dt) = (0.0, 0.0, 0.5);
    let mut track = Vec::new();
    while x < 650.0 {
        track.push(point(t, x));
        x += true_speed(x) * dt;
        t += dt;
    }
    track
}

fn assert_plots(files: &[PathBuf], dir: &Path) {
    let names = [
        "speed_alert.svg",
        "speed_alert.png",
        "trajectory.svg",
        "trajectory.png",
        "lanes.svg",
        "lanes.png",
    ];
    for name in names {
        let path = dir.join(name);
        assert!(files.contains(&path), "{name} not returned: {files:?}");
        let len = std::fs::metadata(&path).expect(name).len();
        assert!(len > 2_000, "{name} is only {len} bytes");
    }
    for name in ["speed_alert.png", "trajectory.png", "lanes.png"] {
        let bytes = std::fs::read(dir.join(name)).expect(name);
        assert!(
            bytes.starts_with(b"\x89PNG\r\n\x1a\n"),
            "{name} is not a PNG"
        );
    }
}

fn svg_text(dir: &Path, name: &str) -> String {
    let text = std::fs::read_to_string(dir.join(name)).expect(name);
    assert!(text.contains("<svg"), "{name} has no <svg");
    assert!(text.trim_end().ends_with("</svg>"), "{name} is not closed");
    text
}

#[test]
fn synthetic_drive_writes_all_plots() {
    let (track, lanes, zones) = (synthetic_track(), lanes(), zones());
    let input = PlotInput {
        title: "synthetic drive",
        track: &track,
        lanes: &lanes,
        zones: &zones,
        warning_distance_m: Some(WARNING_M),
    };
    let dir = out_dir("synthetic");
    let files = write_plots(&dir, &input).expect("plots written");
    assert_eq!(files.len(), 6);
    assert_plots(&files, &dir);

    let speed = svg_text(&dir, "speed_alert.svg");
    for label in [
        "speed (km/h)",
        "distance before the zone start",
        "LaneClosedOwn",
        "InZone",
    ] {
        assert!(speed.contains(label), "speed_alert.svg lacks {label:?}");
    }
    // 650 m by 7 m: drawn along the road, rotated into its direction (east = 090°).
    let trajectory = svg_text(&dir, "trajectory.svg");
    for label in [
        "along the road",
        "heading 090°",
        "lateral, left +",
        "lane 3",
    ] {
        assert!(trajectory.contains(label), "trajectory.svg lacks {label:?}");
    }
    let lanes_svg = svg_text(&dir, "lanes.svg");
    for label in [
        "time since the drive start (s)",
        "lane id",
        "OBU had no lane",
    ] {
        assert!(lanes_svg.contains(label), "lanes.svg lacks {label:?}");
    }
    println!("plots written to {}", dir.display());
}

/// A 90° left bend of radius 60 m: not long and narrow, so drawn east/north at equal scales.
#[test]
fn bend_is_drawn_at_equal_scales() {
    let bend = |r: f64, k: u32| {
        let a = f64::from(k) * std::f64::consts::FRAC_PI_2 / 20.0;
        [r * a.sin(), 60.0 - r * a.cos()]
    };
    let lanes: Vec<PlotLane> = (1..=2)
        .map(|id| PlotLane {
            id,
            centre: (0..=20)
                .map(|k| bend(60.0 + f64::from(id) * 3.5, k))
                .collect(),
            width_m: 3.5,
        })
        .collect();
    let zones = vec![(12..=16).map(|k| bend(67.0, k)).collect::<Vec<_>>()];
    let track: Vec<TrackPoint> = (0..=20)
        .map(|k| TrackPoint {
            t_s: f64::from(k),
            true_point: bend(63.5, k),
            true_lane: 1,
            true_distance_m: Some(80.0 - 5.0 * f64::from(k)),
            speed_mps: Some(8.0),
            zone_state: (if k < 8 { "Approaching" } else { "Warning" }).to_string(),
            matched_lane: Some(1),
            ..TrackPoint::default()
        })
        .collect();
    let input = PlotInput {
        title: "bend",
        track: &track,
        lanes: &lanes,
        zones: &zones,
        warning_distance_m: None,
    };
    let dir = out_dir("bend");
    assert_plots(&write_plots(&dir, &input).expect("plots written"), &dir);
    let trajectory = svg_text(&dir, "trajectory.svg");
    assert!(trajectory.contains("east (m; equal scales)"));
    assert!(trajectory.contains("<polygon"), "lane bands missing");
}

#[test]
fn empty_input_does_not_panic() {
    let input = PlotInput {
        title: "",
        track: &[],
        lanes: &[],
        zones: &[],
        warning_distance_m: None,
    };
    let dir = out_dir("empty");
    let files = write_plots(&dir, &input).expect("plots written");
    assert_eq!(files.len(), 6);
    assert!(svg_text(&dir, "speed_alert.svg").contains("no data"));
}

#[test]
fn degenerate_values_do_not_panic() {
    let nan = f64::NAN;
    let odd = TrackPoint {
        t_s: nan,
        true_point: [nan, f64::INFINITY],
        true_lane: 0,
        true_distance_m: None,
        speed_mps: Some(nan),
        limit_mps: Some(f64::NEG_INFINITY),
        zone_state: "Bogus".to_string(),
        primary: Some(String::new()),
        matched_lane: None,
    };
    let still = TrackPoint {
        t_s: 1.0,
        true_point: [5.0, 5.0],
        ..odd.clone()
    };
    let track = vec![odd, still.clone(), still];
    let lanes = vec![PlotLane {
        id: 7,
        centre: vec![[nan, 0.0], [1.0, 1.0], [1.0, 1.0]],
        width_m: nan,
    }];
    let zones = vec![vec![], vec![[2.0, 2.0]]];
    let input = PlotInput {
        title: "degenerate",
        track: &track,
        lanes: &lanes,
        zones: &zones,
        warning_distance_m: Some(nan),
    };
    let dir = out_dir("degenerate");
    let files = write_plots(&dir, &input).expect("plots written");
    assert_eq!(files.len(), 6);
}
