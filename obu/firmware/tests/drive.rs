//! On target: a synthetic drive through the committed work zone, through the firmware's byte
//! interfaces. The `map_work_zone` MAP and the `tim_work_zone_left_lane_closed` TIM go in as
//! `obu::link` frames on the V2X port, then GST + GGA + RMC sentences at 10 Hz on the NMEA
//! port, driving east along lane 1 (and its line before and after it) at 20 m/s with the
//! firmware's own alert settings (`obu_firmware::CONFIG`: 100 m, 9 s, so the warning comes
//! 180 m before the zone, before the car reaches the 95 m lane).
//!
//! Checked: the distance shown at every fix against the geometry's, and its decrease by the
//! distance driven; the first warning within one fix of the trigger distance; lane 1 matched
//! while on it and its closure shown there; inside the zone; the alert cleared past the end.
//! The TIM path runs on past lane 1's end (over the stop line): on the lane the zone lasts
//! to the lane's end, and the alert with it.
//!
//! The expected geometry comes from the vectors' JER, in build.rs (`work_zone.rs`): lane 1's
//! centreline from the MAP's node offsets, and the TIM path's ends projected on it. Nothing
//! expected is computed by the OBU.
//!
//! As `obu/tests/end_to_end.rs` explains, the committed TIM's region is `forward` along its
//! westward node order with heading slice 247.5-292.5 degrees (westbound), while the MAP's
//! lanes are ingress lanes driven eastbound: as committed, no vehicle on the lane is warned
//! (checked first here). The drive then sends the TIM with its regions set to `reverse` and
//! heading slice 67.5-112.5 degrees, `msgCnt` + 1 so that it replaces the stored zones,
//! everything else as committed (`wz::TIM_EASTBOUND`: decoded, changed and re-encoded by
//! build.rs with the codec on the build host; a TIM decode buffer does not fit the RAM
//! beside the firmware's).
#![no_std]
#![no_main]

mod common;

use common::{feed_nmea, feed_v2x, frame, tally, vector, Epoch};
use defmt_semihosting as _;
use obu::alert::{AlertKind, LaneAdvice, ZoneState};
use obu::{HmiState, Instant};
use obu_firmware::app::{Firmware, Messages};
use obu_firmware::CONFIG;

include!(concat!(env!("OUT_DIR"), "/vectors.rs"));

mod wz {
    include!(concat!(env!("OUT_DIR"), "/work_zone.rs"));
}

/// Drive speed, m/s.
const SPEED: f64 = 20.0;
/// Fix period, ms (10 Hz).
const EPOCH_MS: u64 = 100;
/// Travel per fix, metres.
const STEP: f64 = SPEED * EPOCH_MS as f64 / 1000.0;
/// The drive starts this far before the zone start, metres: within the approach distance
/// (3 x 180 m), and half a fix off the trigger so that no fix falls exactly on it.
const START_BEFORE: f64 = 259.0;
/// Slack for the expected distances: the few centimetres between the lane and TIM path
/// lines, f32 rounding, the linear lat/lon conversion.
const MARGIN: f64 = 0.1;
/// UTC of the clock's zero: 2025-06-17 12:10:00, minute 241 210 of 2025, ten minutes into
/// the TIM's validity (start minute 241 200, 60 minutes).
const UTC0_MS: u32 = (12 * 60 + 10) * 60_000;
const DATE: (u8, u8, u8) = (17, 6, 25);
/// GNSS error (GST, 1 sigma per axis), metres: an RTK-class receiver. Lane 1 tapers to zero
/// width at its west end; the lane is named once the fix is confidently inside it.
const SD_M: f64 = 0.2;
/// From this station on (metres from the lane's west end; the lane widens from nothing
/// there to 3.36 m at 40 m, so 0.84 m here) the car must be matched to lane 1.
const MATCHED_FROM: f64 = 10.0;

/// What one fix showed, kept for the checks after the drive.
#[derive(Clone, Copy)]
struct Sample {
    /// Station of the fix on the lane line (metres from the lane's start, negative before);
    /// `f32` keeps 202 samples within the test binary's RAM.
    station: f32,
    state: ZoneState,
    distance: Option<f32>,
    lane: Option<(u32, u8)>,
    primary: Option<(AlertKind, Option<f32>)>,
    advice: LaneAdvice,
    lane_1_closed: bool,
}

impl Sample {
    fn of(s: f64, h: &HmiState) -> Self {
        Sample {
            station: s as f32,
            state: h.zone_state,
            distance: h.distance_m,
            lane: h.lane.map(|l| (l.map, l.lane)),
            primary: h.primary.map(|a| (a.kind, a.distance_m)),
            advice: h.advice,
            lane_1_closed: h.closed_lanes.contains(&wz::LANE_ID),
        }
    }

    /// The station, metres.
    fn s(&self) -> f64 {
        f64::from(self.station)
    }

    /// Metres to the zone start by the vectors' geometry.
    fn expected(&self) -> f64 {
        wz::ZONE_START_S - self.s()
    }
}

/// Fixes kept by the drive (it sends 201: 259 m + the zone + 80 m at 2 m a fix).
const MAX_SAMPLES: usize = 202;

/// East/north (metres from the reference point) and course at station `s` of lane 1 in its
/// direction of travel, straight on beyond both ends.
fn lane_point(s: f64) -> (f64, f64, f64) {
    let d = wz::DRIVE;
    let i = d
        .iter()
        .rposition(|n| n.2 <= s)
        .unwrap_or(0)
        .min(d.len() - 2);
    let (a, b) = (d[i], d[i + 1]);
    let t = (s - a.2) / (b.2 - a.2);
    let course = if s >= d[d.len() - 1].2 {
        d[d.len() - 1].3
    } else {
        a.3
    };
    (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1), course)
}

struct State {
    fw: &'static mut Firmware,
    msgs: &'static mut Messages,
    wire: &'static mut [u8; 512],
    samples: &'static mut heapless::Vec<Sample, MAX_SAMPLES>,
    /// The simulated clock, ms.
    t: u64,
    /// The receiver sends UBX NAV-PVT instead of NMEA.
    ubx: bool,
}

impl State {
    fn now(&self) -> Instant {
        Instant::from_millis(self.t)
    }

    /// Sends one UPER MessageFrame as a link frame; returns the states it yielded.
    fn send(&mut self, uper: &[u8]) -> u32 {
        let now = self.now();
        let wire = frame(uper, &mut self.wire[..]);
        feed_v2x(self.fw, self.msgs, now, wire).1
    }

    /// One epoch at station `s`: GST + GGA + RMC on the NMEA port, then a poll; the clock
    /// then advances by one epoch. Returns the state of the fix.
    fn fix_at(&mut self, s: f64) -> HmiState {
        let (east, north, course) = lane_point(s);
        let epoch = Epoch {
            utc_ms: UTC0_MS + self.t as u32,
            date: DATE,
            lat: wz::REF_LAT_DEG + north * wz::DEG_PER_M_NORTH,
            lon: wz::REF_LON_DEG + east * wz::DEG_PER_M_EAST,
            speed_mps: SPEED,
            course_deg: course,
            sd_m: SD_M,
        };
        let now = self.now();
        let (state, n) = if self.ubx {
            feed_nmea(self.fw, now, &epoch.nav_pvt())
        } else {
            for line in [epoch.gst(), epoch.gga()] {
                let (none, n0) = feed_nmea(self.fw, now, line.as_bytes());
                assert!(none.is_none() && n0 == 0, "GST and GGA alone are no fix");
            }
            feed_nmea(self.fw, now, epoch.rmc().as_bytes())
        };
        assert_eq!(n, 1, "the RMC (or the NAV-PVT) completes the epoch's fix");
        let _ = self.fw.poll(now);
        self.t += EPOCH_MS;
        state.expect("a state per fix")
    }

    /// Fixes from station `from` to `to` (inclusive, [`STEP`] apart) into `samples`.
    fn drive(&mut self, from: f64, to: f64) {
        self.samples.clear();
        let steps = ((to - from) / STEP) as usize;
        for k in 0..=steps {
            let s = from + k as f64 * STEP;
            let h = self.fix_at(s);
            self.samples
                .push(Sample::of(s, &h))
                .unwrap_or_else(|_| panic!("more than {} fixes", MAX_SAMPLES));
        }
        assert_eq!(self.fw.nmea_errors, 0, "every sentence parsed");
    }
}

fn lane_name(l: Option<(u32, u8)>) -> i32 {
    l.map_or(-1, |(_, lane)| i32::from(lane))
}

/// Drives from [`START_BEFORE`] m before the zone start to 80 m past its end at 20 m/s and
/// checks what every fix showed.
fn drive_and_check(st: &mut State) {
    let trigger = CONFIG
        .warn_distance_m
        .max(CONFIG.lead_time_s * SPEED as f32) as f64;
    let approach = trigger * CONFIG.approach_factor as f64;
    let length = wz::ZONE_END_S - wz::ZONE_START_S;
    defmt::info!(
        "zone from station {=f64} to {=f64} m ({=f64} m), lane 1 is {=f64} m; trigger {=f64} m at {=f64} m/s",
        wz::ZONE_START_S,
        wz::ZONE_END_S,
        length,
        wz::LANE_LENGTH_M,
        trigger,
        SPEED
    );
    assert!(
        START_BEFORE < approach,
        "the drive starts within the approach"
    );
    st.drive(wz::ZONE_START_S - START_BEFORE, wz::ZONE_END_S + 80.0);
    let samples = &st.samples[..];

    // Logged every 20 m for the record.
    for x in samples.iter().step_by(10) {
        defmt::info!(
            "s {=f64} m: {} shown {} expected {=f64} lane {=i32} primary {}",
            x.s(),
            defmt::Debug2Format(&x.state),
            x.distance,
            x.expected(),
            lane_name(x.lane),
            defmt::Debug2Format(&x.primary.map(|p| p.0))
        );
    }

    // The distance shown is the distance to the zone start along the lane.
    let mut checked = 0;
    for x in samples {
        let e = x.expected();
        if e > -length {
            let d = x.distance.expect("a distance before the zone end") as f64;
            assert!(
                (d - e).abs() <= MARGIN,
                "at {}: shown {} m, expected {} m",
                x.s(),
                d,
                e
            );
            checked += 1;
        }
    }
    // ... and it shrinks by the distance driven, fix after fix.
    for w in samples.windows(2) {
        if let (Some(a), Some(b)) = (w[0].distance, w[1].distance) {
            if w[1].expected() > -length {
                let driven = (a - b) as f64;
                assert!(
                    (driven - STEP).abs() <= 0.05,
                    "between {} and {}: {} m less, driven {} m",
                    w[0].s(),
                    w[1].s(),
                    driven,
                    STEP
                );
            }
        }
    }

    // The warning: at the last fix before the trigger would be passed, so at or before
    // it and at most the look-ahead early (one fix period plus the display latency).
    let lookahead = SPEED * (EPOCH_MS as f64 / 1000.0 + CONFIG.display_latency_s as f64);
    let first = samples
        .iter()
        .position(|x| x.state == ZoneState::Warning)
        .expect("a warning");
    let w = samples[first];
    let shown = w.distance.expect("distance") as f64;
    defmt::info!(
        "first warning at station {=f64} m: shown {=f64} m, expected {=f64} m, trigger {=f64} m, look-ahead {=f64} m, primary {}",
        w.s(),
        shown,
        w.expected(),
        trigger,
        lookahead,
        defmt::Debug2Format(&w.primary)
    );
    assert!(
        w.expected() >= trigger - MARGIN && w.expected() <= trigger + lookahead + MARGIN,
        "warning {} m before the zone, trigger {} m (look-ahead {} m)",
        w.expected(),
        trigger,
        lookahead
    );
    assert!(
        shown >= trigger && shown <= trigger + lookahead,
        "shown {} m at the first warning, trigger {} m",
        shown,
        trigger
    );
    assert!(
        shown > trigger + lookahead - STEP,
        "not earlier than the last fix before the trigger: shown {} m",
        shown
    );
    let (kind, at) = w.primary.expect("an alert with the warning");
    assert!(kind <= AlertKind::WorkZoneAhead, "a zone alert: {:?}", kind);
    assert_eq!(at, w.distance, "the alert's distance is the zone's");
    assert!(
        samples[..first]
            .iter()
            .all(|x| x.state == ZoneState::Approaching && x.expected() > trigger),
        "approaching until then"
    );

    // Matched to lane 1 while on it; in the warning there, the own-lane closure.
    let tol = CONFIG.matcher.end_tolerance_m as f64;
    let (mut on_lane, mut own_closure) = (0, 0);
    for x in samples {
        if x.s() < -tol - STEP {
            assert!(x.lane.is_none(), "off map at {}", x.s());
        }
        if x.s() >= MATCHED_FROM && x.s() <= wz::LANE_LENGTH_M - 5.0 {
            assert_eq!(
                x.lane,
                Some((wz::MAP_ID, wz::LANE_ID)),
                "on lane 1 at {}",
                x.s()
            );
            on_lane += 1;
            if x.state == ZoneState::Warning {
                assert_eq!(x.primary.map(|p| p.0), Some(AlertKind::LaneClosedOwn));
                assert_eq!(x.advice, LaneAdvice::MoveRight, "lane 2 is on the right");
                assert!(x.lane_1_closed);
                own_closure += 1;
            }
        }
    }
    assert!(own_closure > 0, "warned on lane 1 before the zone");

    // Inside up to where the zone leaves lane 1 (its end, or the lane's end when the path
    // runs on past it); then cleared once past the zone's end.
    // The core takes points of the path at most 2 m apart: its end on the lane may fall
    // up to that much before the lane's end.
    const PATH_STEP: f64 = 2.0;
    let zone_end_on_lane = wz::ZONE_END_S.min(wz::LANE_LENGTH_M);
    let inside_len = zone_end_on_lane - PATH_STEP - wz::ZONE_START_S;
    let (mut inside, mut cleared) = (0, 0);
    let mut last_alert = None;
    for x in samples {
        let e = x.expected();
        if e < -MARGIN && e > -inside_len + MARGIN {
            assert_eq!(x.state, ZoneState::InZone, "in the zone at {}", x.s());
            assert_eq!(x.primary.map(|p| p.0), Some(AlertKind::LaneClosedOwn));
            inside += 1;
        }
        if x.primary.is_some() {
            last_alert = Some(x.s());
        }
        if e < -length - STEP - MARGIN {
            assert!(
                matches!(x.state, ZoneState::Leaving | ZoneState::None),
                "past the zone at {}",
                x.s()
            );
            assert!(x.primary.is_none(), "alert cleared at {}", x.s());
            cleared += 1;
        }
    }
    let last_alert = last_alert.expect("alerts");
    defmt::info!(
        "last alert at station {=f64} m, zone end at {=f64} m (TIM points at {=[?]})",
        last_alert,
        wz::ZONE_END_S,
        wz::ZONE_NODES_S
    );
    assert!(
        last_alert > zone_end_on_lane - PATH_STEP - STEP - MARGIN,
        "the alert lasts to the zone's end on the lane ({} m), last at {} m",
        zone_end_on_lane,
        last_alert
    );
    let last = samples[samples.len() - 1];
    assert_eq!(last.state, ZoneState::None, "nothing once well past");
    defmt::info!(
        "drive: {=usize} fixes, {=u32} distances checked, {=u32} on lane 1 ({=u32} warned of its closure), {=u32} in zone, {=u32} cleared after",
        samples.len(),
        checked,
        on_lane,
        own_closure,
        inside,
        cleared
    );
}

#[defmt_test::tests]
mod tests {
    use super::{tally, vector, wz, Sample, State, MAP_TIM_VECTORS};
    use obu::alert::ZoneState;

    const MAP: &str = "map_work_zone";
    const TIM: &str = "tim_work_zone_left_lane_closed";

    #[init]
    fn init() -> State {
        let fw = super::common::firmware();
        let msgs = super::common::messages(super::common::UNSIGNED_TAKEN);
        State {
            fw,
            msgs,
            wire: cortex_m::singleton!(: [u8; 512] = [0; 512]).unwrap(),
            samples: cortex_m::singleton!(: heapless::Vec<Sample, { super::MAX_SAMPLES }> = heapless::Vec::new()).unwrap(),
            t: 0,
            ubx: false,
        }
    }

    #[test]
    fn map_and_committed_tim_are_accepted(st: &mut State) {
        // Painted here rather than in `init`, whose frame holds `Firmware::new`'s value on
        // its way into the static: the high-water is the tests'.
        obu_firmware::board::paint_stack();
        assert_eq!(st.send(vector(MAP_TIM_VECTORS, MAP)), 1);
        assert_eq!(st.send(vector(MAP_TIM_VECTORS, TIM)), 1);
        let c = tally(&st.fw.v2x_counters);
        defmt::info!("v2x after MAP + TIM: {}", c);
        assert_eq!((c.accepted, c.bad_frames, c.undecodable), (2, 0, 0));
        assert_eq!((c.rejected, c.other), (0, 0));
        assert_eq!(st.fw.obu().maps().len(), 1);
        assert_eq!(
            st.fw.obu().zones().len(),
            2,
            "two data frames: closure, speed limit"
        );
        st.t += 1000;
    }

    /// The committed TIM is westbound only: an eastbound car on lane 1 is matched to the
    /// lane but not warned.
    #[test]
    fn committed_tim_does_not_concern_eastbound_traffic(st: &mut State) {
        st.drive(0.0, wz::LANE_LENGTH_M);
        let mut matched = 0;
        for x in st.samples.iter() {
            if x.s() >= super::MATCHED_FROM && x.s() <= wz::LANE_LENGTH_M - 5.0 {
                assert_eq!(x.lane, Some((wz::MAP_ID, wz::LANE_ID)), "on lane 1");
                matched += 1;
            }
            assert!(
                x.state == ZoneState::None && x.primary.is_none(),
                "no alert at {}",
                x.s()
            );
        }
        defmt::info!(
            "committed TIM: {=usize} fixes along lane 1, {=u32} matched, no alert",
            st.samples.len(),
            matched
        );
        // The GNSS goes stale (the matcher forgets the lane) before the next drive.
        st.t += 2000;
        let now = st.now();
        let stale = st.fw.poll(now).expect("the GNSS went stale");
        assert!(!stale.gnss_ok);
    }

    #[test]
    fn eastbound_tim_replaces_the_zones(st: &mut State) {
        // The MAP again (a repeat: only its age is refreshed), then the changed TIM, which
        // replaces both zones and so yields a state.
        st.send(vector(MAP_TIM_VECTORS, MAP));
        assert_eq!(st.send(wz::TIM_EASTBOUND), 1, "eastbound TIM stored");
        let c = tally(&st.fw.v2x_counters);
        assert_eq!((c.accepted, c.bad_frames, c.undecodable), (4, 0, 0));
        assert_eq!(st.fw.obu().zones().len(), 2, "the two zones replaced");
    }

    /// From [`START_BEFORE`] m before the zone start to 80 m past its end at 20 m/s.
    #[test]
    fn drive_warns_at_the_configured_distance(st: &mut State) {
        super::drive_and_check(st);
    }

    /// The same drive from a u-blox receiver: UBX NAV-PVT frames (RTK fixed, hAcc the
    /// NMEA drive's GST error) on the GNSS port instead of NMEA.
    #[test]
    fn the_same_drive_from_a_ubx_receiver(st: &mut State) {
        // The GNSS goes stale (the matcher forgets the lane) before the next drive.
        st.t += 2000;
        let now = st.now();
        let _ = st.fw.poll(now);
        // The roadside's repeats refresh the MAP and the zones (they age out otherwise).
        st.send(vector(MAP_TIM_VECTORS, MAP));
        st.send(wz::TIM_EASTBOUND);
        assert_eq!(st.fw.obu().zones().len(), 2, "the zones still stored");
        st.ubx = true;
        let errors = st.fw.nmea_errors;
        super::drive_and_check(st);
        assert_eq!(st.fw.nmea_errors, errors, "every frame read");
        assert_eq!(
            st.fw.obu().state(st.now()).accuracy_source,
            obu::fix::AccuracySource::Ubx
        );
    }

    #[test]
    fn stack_high_water(_st: &mut State) {
        let (used, size) = obu_firmware::board::stack_high_water();
        defmt::info!(
            "stack high-water (drive): {=usize} of {=usize} B",
            used,
            size
        );
    }
}
