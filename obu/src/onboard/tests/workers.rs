//! Road workers (PSMs) in the display state. The test road's lanes run north, 3.5 m wide:
//! the vehicle drives in lane 3 (centre x = 3.5 m, edges at 1.75 and 5.25 m), so east
//! (+x) is to its right.

use super::*;
use crate::alert::WorkerView;
use crate::capacity::{MAX_HMI_WORKERS, MAX_WORKERS};
use crate::ingest::{IngestError, MessageKind};
use crate::security::{SecurityConfig, PSID_PSM};
use crate::testutil::{big_stack, psm, psm_at};
use crate::v2x::{DropReason, SecurityReason, V2xOutcome, V2xReceiver};
use j2735::frame::Message;
use j2735::msg::common::{DSecond, SemiMajorAxisAccuracy};
use j2735::msg::message_frame::{MessageFrame, MessageFrameValue};
use j2735::msg::personal_safety_message::{PersonalDeviceUserType, PersonalSafetyMessage};
use std::string::ToString;

const V: f32 = 40.0 / 3.6;

fn worker_at(obu: &mut Obu, t: u64, id: u8, x: f32, y: f32) {
    let r = obu.on_psm(
        Instant::from_millis(t),
        &psm(id, Point::new(x, y), t as u16),
    );
    assert_eq!(
        r.map(|i| (i.message, i.stored + i.unchanged + i.alert_changed)),
        Ok((MessageKind::Psm, 1))
    );
}

fn kinds(s: &HmiState) -> std::vec::Vec<AlertKind> {
    s.primary
        .iter()
        .chain(s.others.iter())
        .map(|a| a.kind)
        .collect()
}

fn near(a: f32, b: f32) -> bool {
    (a - b).abs() < 0.1
}

fn only_view(s: &HmiState) -> WorkerView {
    assert_eq!(s.workers.len(), 1, "{:?}", s.workers);
    s.workers[0]
}

#[test]
fn a_worker_in_the_own_lane_comes_before_the_lane_closure() {
    let mut obu = obu_with(true);
    worker_at(&mut obu, 0, 1, 3.5, 380.0);
    // 100 m before the closure of lane 3, the worker 80 m ahead in it.
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert_eq!(s.lane.map(|l| l.lane), Some(3));
    let primary = s.primary.unwrap_or_else(|| panic!("no alert: {s:?}"));
    assert_eq!(
        (primary.kind, primary.stage),
        (AlertKind::WorkerInLane, AlertStage::Warning)
    );
    assert!(
        primary.distance_m.is_some_and(|d| near(d, 80.0)),
        "{primary:?}"
    );
    assert!(kinds(&s).contains(&AlertKind::LaneClosedOwn));
    assert_eq!(s.stage, AlertStage::Warning);
    let w = only_view(&s);
    assert!(w.id == 1 && w.in_own_lane_path && w.verified);
    assert!(near(w.distance_m, 80.0) && near(w.lateral_m, 0.0), "{w:?}");
    assert_eq!((w.speed_mps, w.heading_deg, w.age_ms), (Some(0.0), None, 0));
    assert_eq!(AlertKind::WorkerInLane.to_string(), "worker in lane ahead");
}

#[test]
fn a_worker_on_the_shoulder_is_near_the_road_not_in_the_lane() {
    let mut obu = obu_with(false);
    // 2.5 m beyond the right edge (5.25 m) of lane 3: 4.25 m right of its centre.
    worker_at(&mut obu, 0, 2, 7.75, 350.0);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert!(!kinds(&s).contains(&AlertKind::WorkerInLane));
    let primary = s.primary.unwrap_or_else(|| panic!("no alert: {s:?}"));
    assert_eq!(
        (primary.kind, primary.stage),
        (AlertKind::WorkersNearRoad, AlertStage::Information)
    );
    assert!(primary.distance_m.is_some_and(|d| near(d, 50.0)));
    let w = only_view(&s);
    assert!(!w.in_own_lane_path && near(w.lateral_m, 4.25) && near(w.distance_m, 50.0));
    assert_eq!(
        AlertKind::WorkersNearRoad.to_string(),
        "workers near the road"
    );
}

#[test]
fn a_worker_within_a_metre_of_the_lane_edge_is_in_its_path() {
    let mut obu = obu_with(false);
    // Standing 0.8 m beyond the right edge: 2.55 m from the centre, half width + 1 m = 2.75.
    worker_at(&mut obu, 0, 3, 6.05, 360.0);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    let primary = s.primary.unwrap_or_else(|| panic!("no alert: {s:?}"));
    assert_eq!(primary.kind, AlertKind::WorkerInLane);
    assert!(primary.distance_m.is_some_and(|d| near(d, 60.0)));
    let w = only_view(&s);
    assert!(w.in_own_lane_path && near(w.lateral_m, 2.55));
    // 1.2 m beyond the edge (2.95 m from the centre): near the road only.
    let mut obu = obu_with(false);
    worker_at(&mut obu, 0, 3, 6.45, 360.0);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert_eq!(kinds(&s), [AlertKind::WorkersNearRoad]);
}

#[test]
fn a_worker_stepping_into_the_lane_calls_for_a_state_at_once() {
    let mut obu = obu_with(false);
    // Lane 3 (centre x = 3.5, edges 1.75 and 5.25): the worker 3.5 m right of its centre,
    // near the road; the vehicle's fix at 300 m matches lane 3.
    let step = |obu: &mut Obu, t: u64, x: f32| {
        obu.on_psm(
            Instant::from_millis(t),
            &psm(4, Point::new(x, 360.0), t as u16),
        )
        .map(|i| (i.stored, i.unchanged, i.alert_changed))
    };
    assert_eq!(step(&mut obu, 0, 7.0), Ok((1, 0, 0)));
    let s = drive(&mut obu, 50, 3.5, 300.0, V);
    assert_eq!(kinds(&s), [AlertKind::WorkersNearRoad]);
    // Moving within the near band: shown from the next state on.
    assert_eq!(step(&mut obu, 100, 6.4), Ok((0, 1, 0)));
    // Into the lane's path (2.5 m from the centre, within half the width plus 1 m): due now.
    assert_eq!(step(&mut obu, 200, 6.0), Ok((0, 0, 1)));
    assert_eq!(
        kinds(&obu.state(Instant::from_millis(200))),
        [AlertKind::WorkerInLane]
    );
    assert_eq!(step(&mut obu, 300, 5.0), Ok((0, 1, 0)));
    // And out of it again.
    assert_eq!(step(&mut obu, 400, 6.6), Ok((0, 0, 1)));
    // Without a lane match nothing is due: no fix has matched a lane on a new unit.
    let mut fresh = obu_with(false);
    assert_eq!(step(&mut fresh, 0, 7.0), Ok((1, 0, 0)));
    assert_eq!(step(&mut fresh, 100, 5.0), Ok((0, 1, 0)));
}

#[test]
fn a_signed_update_is_checked_when_due_or_when_it_changes_the_alert() {
    let mut obu = obu_with(false);
    let msg = |t: u64, x: f32| psm(4, Point::new(x, 360.0), t as u16);
    let at = Instant::from_millis;
    // A new worker is always due; then the vehicle's fix matches lane 3.
    assert_eq!(obu.psm_due(at(0), &msg(0, 7.0)), Ok(()));
    worker_at(&mut obu, 0, 4, 7.0, 360.0);
    let _ = drive(&mut obu, 50, 3.5, 300.0, V);
    // 100-400 ms later, still near the road: not worth a signature check.
    for t in [100, 200, 400, 449] {
        assert_eq!(
            obu.psm_due(at(t), &msg(t, 6.6)),
            Err(IngestError::NotDue),
            "{t} ms"
        );
    }
    assert_eq!(obu.rejected().get(IngestError::NotDue), 4);
    // Into the lane's path: checked at once, whatever the interval.
    assert_eq!(obu.psm_due(at(150), &msg(150, 6.0)), Ok(()));
    // 450 ms or more after the last update: due again.
    assert_eq!(
        obu.psm_due(at(500), &msg(500, 6.6)),
        Ok(()),
        "the interval is crate::worker::VERIFY_INTERVAL"
    );
    assert_eq!(crate::worker::VERIFY_INTERVAL, Duration::from_millis(450));
    // A worker stored from an unsigned PSM: the first signed one is due.
    let mut open = obu_with(false);
    let r = open.ingest_psm(at(0), &msg(0, 7.0), crate::store::Provenance::Unverified);
    assert_eq!(r.map(|i| i.stored), Ok(1));
    assert_eq!(open.psm_due(at(100), &msg(100, 7.0)), Ok(()));
    // And one that is not a road worker is left to the ingest check (its own reason).
    let mut pedestrian = msg(200, 7.0);
    pedestrian.basic_type = PersonalDeviceUserType::APEDESTRIAN;
    assert_eq!(obu.psm_due(at(200), &pedestrian), Ok(()));
}

#[test]
fn a_worker_behind_raises_nothing() {
    let mut obu = obu_with(false);
    worker_at(&mut obu, 0, 4, 3.5, 250.0);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert_eq!((s.primary, s.stage), (None, AlertStage::None));
    let w = only_view(&s);
    assert!(w.in_own_lane_path && near(w.distance_m, -50.0));
    // Beyond the approach distance (300 m at 40 km/h, plus the look-ahead): nothing yet.
    let mut obu = obu_with(false);
    worker_at(&mut obu, 0, 4, 3.5, 620.0);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert_eq!(s.primary, None);
    assert!(near(only_view(&s).distance_m, 320.0));
}

#[test]
fn the_worker_in_the_path_ahead_is_listed_before_a_crew_just_passed() {
    let mut obu = obu_with(false);
    // Eight workers 2-16 m behind the car (y 284-298, beside the lane), one 60 m ahead in it.
    for k in 0..8u8 {
        worker_at(&mut obu, 0, 20 + k, 7.0, 298.0 - 2.0 * f32::from(k));
    }
    worker_at(&mut obu, 0, 30, 3.5, 360.0);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert_eq!(s.workers.len(), MAX_HMI_WORKERS);
    let first = s.workers[0];
    assert!(
        first.id == 30 && first.in_own_lane_path && near(first.distance_m, 60.0),
        "{first:?}"
    );
    assert!(s.workers[1..].iter().all(|w| w.distance_m < 0.0));
    assert_eq!(s.primary.map(|a| a.kind), Some(AlertKind::WorkerInLane));
}

#[test]
fn a_worker_not_heard_for_a_second_is_gone() {
    let mut obu = obu_with(false);
    worker_at(&mut obu, 0, 5, 3.5, 380.0);
    assert_eq!(obu.next_deadline(), Some(Instant::from_millis(1000)));
    let s = drive(&mut obu, 999, 3.5, 300.0, V);
    assert_eq!(s.primary.map(|a| a.kind), Some(AlertKind::WorkerInLane));
    assert_eq!(only_view(&s).age_ms, 999);
    assert_eq!(obu.next_deadline(), Some(Instant::from_millis(1000)));
    assert_eq!(obu.poll(Instant::from_millis(999)), None);
    let s = obu.poll(Instant::from_millis(1000));
    let s = s.unwrap_or_else(|| panic!("the expiry changes the display"));
    assert!(s.workers.is_empty() && s.primary.is_none(), "{s:?}");
    assert!(obu.workers().is_empty());
    assert_eq!(obu.workers().stats().expired, 1);
    // A fix without a poll in between does not show it either.
    let mut obu = obu_with(false);
    worker_at(&mut obu, 0, 5, 3.5, 380.0);
    let s = drive(&mut obu, 1000, 3.5, 300.0, V);
    assert!(s.workers.is_empty() && s.primary.is_none());
}

#[test]
fn more_workers_than_the_store_holds_are_bounded_and_counted() {
    let mut obu = obu_with(false);
    let n = MAX_WORKERS + 5;
    for i in 0..n {
        let p = psm(i as u8, Point::new(3.5, 310.0 + 10.0 * i as f32), 0);
        let r = obu.on_psm(Instant::ZERO, &p);
        let want = if i < MAX_WORKERS {
            Ok(1)
        } else {
            Err(IngestError::StoreFull)
        };
        assert_eq!(r.map(|i| i.stored), want, "worker {i}");
    }
    assert_eq!(obu.workers().len(), MAX_WORKERS);
    assert_eq!(obu.rejected().get(IngestError::StoreFull), 5);
    let s = drive(&mut obu, 0, 3.5, 300.0, V);
    assert_eq!(s.workers.len(), MAX_HMI_WORKERS);
    // The nearest (10, 20, ... 80 m ahead), nearest first.
    for (k, w) in s.workers.iter().enumerate() {
        assert!(near(w.distance_m, 10.0 * (k + 1) as f32), "{k}: {w:?}");
    }
    assert!(s
        .primary
        .is_some_and(|a| a.distance_m.is_some_and(|d| near(d, 10.0))));
}

#[test]
fn malformed_psms_are_counted_and_never_panic() {
    let mut obu = obu_with(false);
    let at = testutil::at(Point::new(3.5, 380.0));
    let t = Instant::ZERO;
    let mut p = psm_at(6, 900_000_001, at.lon_e7(), 0);
    assert_eq!(obu.on_psm(t, &p), Err(IngestError::InvalidPosition));
    p = psm_at(6, at.lat_e7(), 1_800_000_001, 0);
    assert_eq!(obu.on_psm(t, &p), Err(IngestError::InvalidPosition));
    p = psm(6, Point::new(3.5, 380.0), 0);
    p.accuracy.semi_major = SemiMajorAxisAccuracy::UNAVAILABLE;
    assert_eq!(obu.on_psm(t, &p), Err(IngestError::AccuracyUnavailable));
    p = psm(6, Point::new(3.5, 380.0), 0);
    p.basic_type = PersonalDeviceUserType::APEDESTRIAN;
    assert_eq!(obu.on_psm(t, &p), Err(IngestError::NotRoadWorker));
    let r = obu.rejected();
    assert_eq!(
        (
            r.get(IngestError::InvalidPosition),
            r.get(IngestError::AccuracyUnavailable)
        ),
        (2, 1)
    );
    assert_eq!((r.get(IngestError::NotRoadWorker), r.total()), (1, 4));
    assert!(obu.workers().is_empty());
    // Speed, heading and secMark unavailable, the extremes of the ranges: kept.
    p = psm_at(6, 900_000_000, 1_800_000_000, 0);
    p.sec_mark = DSecond::UNAVAILABLE;
    assert_eq!(obu.on_psm(t, &p).map(|i| i.stored), Ok(1));
    p = psm(7, Point::new(3.5, 380.0), 0);
    p.sec_mark = DSecond::UNAVAILABLE;
    assert_eq!(obu.on_psm(t, &p).map(|i| i.stored), Ok(1));
    assert_eq!(
        obu.on_psm(t, &p),
        Err(IngestError::StaleMessage),
        "a repeat"
    );
    // Not finite speeds of the vehicle: no panic, the worker still placed.
    let s = drive(&mut obu, 0, 3.5, 300.0, f32::NAN);
    assert!(s
        .workers
        .iter()
        .any(|w| w.id == 7 && near(w.distance_m, 80.0)));
    let s = drive(&mut obu, 100, 3.5, 300.0, f32::INFINITY);
    assert!(s.workers.iter().all(|w| w.distance_m.is_finite()));
}

#[test]
fn a_psm_frame_goes_through_on_frame_and_the_v2x_path() {
    big_stack(|| {
        // A MessageFrame is as large as its largest alternative (a MAP): on the big stack.
        let mut obu = obu_with(false);
        let frame = MessageFrame {
            value: MessageFrameValue::PersonalSafetyMessage(
                psm(8, Point::new(3.5, 380.0), 0).into(),
            ),
            extensions: j2735::uper::Extensions::new(),
        };
        let r = obu.on_frame(Instant::ZERO, &frame);
        assert_eq!(r.map(|i| (i.message, i.stored)), Ok((MessageKind::Psm, 1)));
        assert_eq!(obu.counters().other_messages, 0);
    });
    assert_eq!(PersonalSafetyMessage::MESSAGE_ID, 32);
    big_stack(|| {
        let encode = |p: &PersonalSafetyMessage| {
            let mut buf = [0u8; 512];
            let n = j2735::frame::encode_message(p, &mut buf);
            buf[..n.unwrap_or_else(|e| panic!("{e:?}"))].to_vec()
        };
        let first = encode(&psm(9, Point::new(3.5, 380.0), 0));
        let next = encode(&psm(9, Point::new(3.5, 381.0), 100));
        let mut pedestrian = psm(10, Point::new(3.5, 380.0), 0);
        pedestrian.basic_type = PersonalDeviceUserType::APEDESTRIAN;
        let pedestrian = encode(&pedestrian);
        let mut obu = std::boxed::Box::new(Obu::default());
        let open = SecurityConfig {
            require_signed: false,
            ..SecurityConfig::DEFAULT
        };
        let mut rx = std::boxed::Box::new(V2xReceiver::<16>::with_security(open));
        assert_eq!(rx.trust().psid_for(32), Some(PSID_PSM));
        let t = Instant::ZERO;
        assert_eq!(obu.on_datagram(t, &first, &mut rx), V2xOutcome::Changed(32));
        assert_eq!(
            obu.on_datagram(t, &next, &mut rx),
            V2xOutcome::Unchanged(32)
        );
        assert_eq!(
            obu.on_datagram(t, &first, &mut rx),
            V2xOutcome::Dropped(DropReason::from(IngestError::StaleMessage))
        );
        assert_eq!(
            obu.on_datagram(t, &pedestrian, &mut rx),
            V2xOutcome::Dropped(DropReason::from(IngestError::NotRoadWorker))
        );
        let w = obu.workers().iter().next().copied();
        assert_eq!(
            w.map(|w| w.provenance()),
            Some(crate::store::Provenance::Unverified)
        );
        // Signatures required (the default): an unsigned PSM is dropped.
        let mut strict = std::boxed::Box::new(V2xReceiver::<16>::new());
        assert_eq!(
            obu.on_datagram(t, &first, &mut strict),
            V2xOutcome::Dropped(DropReason::from(SecurityReason::Unsigned))
        );
        assert_eq!(obu.workers().len(), 1);
    });
}
