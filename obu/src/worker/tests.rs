use j2735::msg::common::{DSecond, Heading, Latitude, Longitude, SemiMajorAxisAccuracy, Velocity};
use j2735::msg::personal_safety_message::PersonalDeviceUserType;

use super::*;
use crate::capacity::MAX_WORKERS;
use crate::testutil::psm_at;

const LAT: i32 = 400_000_000;
const LON: i32 = -1_050_000_000;

fn worker(id: u8, at_ms: u64, sec_mark: u16) -> Worker {
    let psm = psm_at(id, LAT, LON + i32::from(id) * 100, sec_mark);
    let w = Worker::from_psm(Instant::from_millis(at_ms), &psm, Provenance::Verified);
    w.unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_worker_keeps_the_psm_in_its_units() {
    let mut psm = psm_at(7, LAT, LON, 1234);
    psm.speed = Velocity::new(75).unwrap_or(Velocity::UNAVAILABLE);
    psm.heading = Heading::new(7200).unwrap_or(Heading::UNAVAILABLE);
    let w = Worker::from_psm(Instant::from_millis(5), &psm, Provenance::Unverified);
    let w = w.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(w.id().as_u32(), 7);
    assert_eq!((w.position().lat_e7(), w.position().lon_e7()), (LAT, LON));
    // 75 x 0.02 m/s, 7200 x 0.0125 degree, 10 x 0.05 m.
    assert!(w.speed_mps().is_some_and(|v| (v - 1.5).abs() < 1e-6));
    assert!(w.heading_deg().is_some_and(|h| (h - 90.0).abs() < 1e-4));
    assert!((w.accuracy_m() - 0.5).abs() < 1e-6);
    assert_eq!(w.provenance(), Provenance::Unverified);
    assert_eq!(core::mem::size_of::<Worker>(), 32);
    let psm = psm_at(7, LAT, LON, 1234);
    let w = Worker::from_psm(Instant::ZERO, &psm, Provenance::Verified);
    let w = w.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((w.speed_mps(), w.heading_deg()), (Some(0.0), None));
}

#[test]
fn psms_without_a_usable_worker_are_rejected_by_reason() {
    let reject = |psm: &PersonalSafetyMessage| {
        Worker::from_psm(Instant::ZERO, psm, Provenance::Verified).err()
    };
    let mut psm = psm_at(1, Latitude::UNAVAILABLE.get(), LON, 0);
    assert_eq!(reject(&psm), Some(IngestError::InvalidPosition));
    psm = psm_at(1, LAT, Longitude::UNAVAILABLE.get(), 0);
    assert_eq!(reject(&psm), Some(IngestError::InvalidPosition));
    psm = psm_at(1, LAT, LON, 0);
    psm.accuracy.semi_major = SemiMajorAxisAccuracy::UNAVAILABLE;
    assert_eq!(reject(&psm), Some(IngestError::AccuracyUnavailable));
    for t in [
        PersonalDeviceUserType::Unavailable,
        PersonalDeviceUserType::APEDESTRIAN,
        PersonalDeviceUserType::APEDALCYCLIST,
        PersonalDeviceUserType::AnANIMAL,
        PersonalDeviceUserType::Extension(3),
    ] {
        psm = psm_at(1, LAT, LON, 0);
        psm.basic_type = t;
        assert_eq!(reject(&psm), Some(IngestError::NotRoadWorker), "{t:?}");
    }
}

#[test]
fn sec_mark_order_wraps_at_the_minute() {
    let at = |s| worker(1, 0, s);
    assert!(at(1100).follows(&at(1000)));
    assert!(at(100).follows(&at(59_900)), "across the minute");
    assert!(!at(1000).follows(&at(1000)), "a repeat");
    assert!(!at(900).follows(&at(1000)), "older");
    assert!(!at(59_900).follows(&at(100)), "older, across the minute");
    // Unavailable: only an exact repeat (same secMark and msgCnt) is refused.
    let u = at(DSecond::UNAVAILABLE.get());
    assert!(!u.follows(&u) && at(1000).follows(&u) && u.follows(&at(1000)));
}

#[test]
fn updates_replace_expire_after_a_second() {
    let mut s = WorkerStore::new();
    assert_eq!(s.update(worker(1, 0, 0), None), Ok(WorkerUpdate::New));
    assert_eq!(
        s.update(worker(1, 100, 100), None),
        Ok(WorkerUpdate::Updated)
    );
    assert_eq!(
        s.update(worker(1, 150, 50), None),
        Err(IngestError::StaleMessage)
    );
    assert_eq!(s.len(), 1);
    assert_eq!(s.next_expiry(), Some(Instant::from_millis(1100)));
    assert_eq!(s.current(Instant::from_millis(1099)).count(), 1);
    assert_eq!(s.current(Instant::from_millis(1100)).count(), 0);
    assert_eq!(s.expire(Instant::from_millis(1099)), 0);
    assert_eq!(s.expire(Instant::from_millis(1100)), 1);
    assert!(s.is_empty() && s.next_expiry().is_none());
    // An expired worker comes back as new whatever its secMark.
    assert_eq!(s.update(worker(1, 1200, 0), None), Ok(WorkerUpdate::New));
    assert_eq!(
        s.stats(),
        WorkerStats {
            new: 2,
            updated: 1,
            evicted: 0,
            expired: 1
        }
    );
}

#[test]
fn unverified_never_replaces_verified() {
    let mut s = WorkerStore::new();
    assert_eq!(s.update(worker(1, 0, 0), None), Ok(WorkerUpdate::New));
    let psm = psm_at(1, LAT, LON, 100);
    let forged = Worker::from_psm(Instant::from_millis(100), &psm, Provenance::Unverified);
    let forged = forged.unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.update(forged, None), Ok(WorkerUpdate::Refused));
    assert_eq!(s.iter().next().map(|w| w.heard()), Some(Instant::ZERO));
}

#[test]
fn unverified_workers_cannot_lock_a_verified_one_out() {
    let mut s = WorkerStore::new();
    // A full store of fresh unverified workers, all nearer the vehicle than the newcomer.
    for id in 0..MAX_WORKERS as u8 {
        let psm = psm_at(id, LAT, LON + i32::from(id) * 100, 0);
        let at = Instant::from_millis(100 + u64::from(id));
        let w = Worker::from_psm(at, &psm, Provenance::Unverified);
        let w = w.unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(s.update(w, None), Ok(WorkerUpdate::New));
    }
    let vehicle = LatLon::new(LAT, LON);
    let unverified_far = {
        let psm = psm_at(50, LAT, LON + 5000, 0);
        let w = Worker::from_psm(Instant::from_millis(200), &psm, Provenance::Unverified);
        w.unwrap_or_else(|e| panic!("{e}"))
    };
    assert_eq!(
        s.update(unverified_far, vehicle),
        Err(IngestError::StoreFull),
        "an unverified newcomer follows the ordinary rules"
    );
    // Verified workers farther than all of them (LON + 6000 and more) still get in, each
    // in an unverified worker's slot; none has been silent for 500 ms, so the one farthest
    // from the vehicle at LON goes first (id 15 at LON + 1500), not the stalest (id 0,
    // heard at 100 ms, the nearest), then id 14.
    let gone = |s: &WorkerStore, id: u32| s.iter().all(|w| w.id().as_u32() != id);
    let signed = |s: &mut WorkerStore, id: u8, at_ms: u64, vehicle| {
        assert_eq!(
            s.update(worker(id, at_ms, 0), vehicle),
            Ok(WorkerUpdate::Evicted)
        );
    };
    signed(&mut s, 60, 200, vehicle);
    assert!(gone(&s, 15) && !gone(&s, 0) && !gone(&s, 60));
    signed(&mut s, 61, 210, vehicle);
    assert!(gone(&s, 14) && !gone(&s, 60) && !gone(&s, 61));
    // The vehicle's position unknown: the stalest unverified (id 0).
    signed(&mut s, 62, 220, None);
    assert!(gone(&s, 0));
    // At 650 ms id 1 (heard at 101 ms) has been silent for 549 ms: it goes, although id 13
    // is farther.
    signed(&mut s, 63, 650, vehicle);
    assert!(gone(&s, 1) && !gone(&s, 13));
    assert!([60, 61, 62, 63].iter().all(|&id| !gone(&s, id)));
}

#[test]
fn a_full_store_replaces_a_far_or_silent_worker_only() {
    let mut s = WorkerStore::new();
    for id in 0..MAX_WORKERS as u8 {
        assert_eq!(
            s.update(worker(id, u64::from(id), 0), None),
            Ok(WorkerUpdate::New)
        );
    }
    // All heard within 500 ms, vehicle unknown: refused.
    let mut far = worker(100, 400, 0);
    assert_eq!(s.update(far, None), Err(IngestError::StoreFull));
    // The vehicle at worker 1's place (LON + 100): worker 15 (LON + 1500) is the farthest.
    // A new worker at LON + 2000 is not nearer; one at LON + 1000 is and takes its slot.
    let vehicle = LatLon::new(LAT, LON + 100);
    far = worker(20, 400, 0);
    assert_eq!(s.update(far, vehicle), Err(IngestError::StoreFull));
    let mut near = worker(10, 400, 0);
    near.id = WorkerId([9, 9, 9, 9]);
    assert_eq!(s.update(near, vehicle), Ok(WorkerUpdate::Evicted));
    assert!(s.iter().all(|w| w.id().as_u32() != 15));
    // 500 ms after worker 0 (the stalest) it gives way to anyone.
    assert_eq!(
        s.update(worker(100, 500, 0), None),
        Ok(WorkerUpdate::Evicted)
    );
    assert!(s.iter().all(|w| w.id().as_u32() != 0));
    assert_eq!(s.len(), MAX_WORKERS);
    assert_eq!(
        (s.stats().evicted, s.stats().new),
        (2, MAX_WORKERS as u32 + 2)
    );
}
