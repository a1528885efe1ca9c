//! The spoofing scenarios' attacks through the OBU core, without the 45 s run in real
//! time: for every scenario file with an `[attacker]`, a core that trusts the bench PKI
//! takes the real roadside's signed MAP and TIM (as the daemon and the firmware do, through
//! `Obu::on_datagram`), then the attacker's datagrams: each is dropped with the reason the
//! scenario's `forged_dropped` expectation names, and nothing the driver sees changes. As
//! a control, the same forged frame signed now by the real RSU is taken and changes the
//! stores: the attacks are ones the security stops, not frames the core ignores anyway.

use hil_sim::bench_pki;
use hil_sim::expect::Expectation;
use hil_sim::nmea::{self, Epoch};
use hil_sim::roadside_bench::attacker::Attacker;
use hil_sim::scenario::Scenario;
use obu::input::nmea::{parse, FixAssembler};
use obu::security::SecurityConfig;
use obu::v2x::{DropReason, V2xOutcome, V2xReceiver};
use obu::{AlertConfig, HmiState, Instant, Obu};
use roadside::clock::{unix_ms_now, Utc};
use roadside::messages;
use roadside::signer::RsuSigner;
use std::path::{Path, PathBuf};
use std::sync::Arc;

type Receiver = V2xReceiver<1024>;

fn scenario_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/scenarios");
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// What a state shows of the roadside's data: lane maps, zones, and the update counts.
fn held(s: &HmiState) -> (u8, u8, u8, u32, u32, u32) {
    let c = &s.counters;
    (
        s.maps,
        s.zones,
        s.unverified,
        c.maps_updated,
        c.zones_updated,
        c.zones_cancelled,
    )
}

/// A core with the bench's anchors, a GNSS fix (so it has time and position) and the real
/// roadside's MAP and TIMs, signed by `signer` (the scenario's way of signing), taken at
/// `now_ms`; the zones the scenario removes are then cancelled by the roadside (a second
/// later), before any attack.
fn unit_with_real_zone(s: &Scenario, now_ms: u64, signer: &RsuSigner) -> (Box<Obu>, Box<Receiver>) {
    let road = s.road().unwrap();
    let zones =
        roadside::zone_sources::build_zones(&s.site(), &road, Utc::from_unix_ms(now_ms - 120_000))
            .unwrap();
    let mut obu = Box::new(Obu::new(AlertConfig::DEFAULT));
    let mut rx = Box::new(Receiver::with_security(SecurityConfig::DEFAULT));
    for anchor in [bench_pki::ROOT, bench_pki::CA] {
        rx.trust_mut().add_anchor(anchor).unwrap();
    }
    let lane = road.lane(s.drive.lane).unwrap();
    let at = lane.at(s.drive.start_m).unwrap();
    let epoch = Epoch {
        utc: Utc::from_unix_ms(now_ms),
        position: road.to_wgs84(at.point).unwrap(),
        speed_mps: 11.0,
        course_deg: at.bearing_deg,
        sigma_m: 0.3,
    };
    let mut fixes = FixAssembler::new();
    let mut got = Vec::new();
    for line in nmea::epoch(&epoch).lines() {
        fixes.push(&parse(line).unwrap(), |e| got.extend(e.outcome.ok()));
    }
    fixes.finish(|e| got.extend(e.outcome.ok()));
    assert_eq!(got.len(), 1, "one epoch, one fix");
    for fix in got {
        obu.on_fix(Instant::ZERO, fix);
    }
    let map = messages::build_map(&road, 1, 1, zones.first()).unwrap();
    let mut frames = vec![messages::encode(&map).unwrap()];
    for z in &zones {
        frames.push(messages::encode(&messages::build_tim(&road, z).unwrap()).unwrap());
    }
    for frame in frames {
        let signed = signer.sign(&frame, now_ms).unwrap();
        let outcome = obu.on_datagram(Instant::ZERO, &signed, &mut rx);
        assert!(
            matches!(outcome, V2xOutcome::Changed(_)),
            "the real roadside's frame: {outcome:?}"
        );
    }
    for (spec, zone) in s.site().zones.iter().zip(&zones) {
        if spec.removed_at_s.is_some() {
            let mut cancel = zone.clone();
            cancel.duration_min = 0;
            cancel.msg_cnt = cancel.msg_cnt.wrapping_add(1) % 128;
            let frame = messages::encode(&messages::build_tim(&road, &cancel).unwrap()).unwrap();
            let signed = signer.sign(&frame, now_ms + 1000).unwrap();
            let outcome = obu.on_datagram(Instant::from_millis(1000), &signed, &mut rx);
            assert!(
                matches!(outcome, V2xOutcome::Changed(_)),
                "the real roadside's cancel: {outcome:?}"
            );
        }
    }
    (obu, rx)
}

#[test]
fn every_forged_datagram_is_dropped_for_the_reason_its_scenario_names() {
    let mut attacks = 0;
    for path in scenario_files() {
        let s = Scenario::load(&path).unwrap();
        let Some(spec) = &s.attacker else {
            continue;
        };
        attacks += 1;
        let name = path.display();
        let reason = s
            .expectations
            .iter()
            .find_map(|e| match e {
                Expectation::ForgedDropped { reason, .. } => Some(reason.clone()),
                _ => None,
            })
            .unwrap_or_else(|| panic!("{name}: no forged_dropped expectation"));
        assert!(
            s.expectations.contains(&Expectation::RoadsideKept),
            "{name}: no roadside_kept expectation"
        );
        let reason = DropReason::ALL
            .iter()
            .copied()
            .find(|r| r.as_str() == reason)
            .unwrap_or_else(|| panic!("{name}: {reason:?} is no drop reason"));
        let now_ms = unix_ms_now();
        // The roadside's signer as the scenario signs; the attacker's clone shares what it
        // signed once (for the replayed original).
        let genuine = Arc::new(s.signing.apply(&bench_pki::signer().unwrap()));
        let (mut obu, mut rx) = unit_with_real_zone(&s, now_ms, &genuine);
        let before = obu.state(Instant::from_millis(1000));
        let removes = s.site().zones.iter().any(|z| z.removed_at_s.is_some());
        assert!(
            before.maps > 0 && (removes || before.zones > 0),
            "{name}: {before:?}"
        );
        let road = s.road().unwrap();
        let zones = roadside::zone_sources::build_zones(
            &s.site(),
            &road,
            Utc::from_unix_ms(now_ms - 120_000),
        )
        .unwrap();
        let attacker = Attacker::new(spec.kind, &road, &zones, &genuine).unwrap();
        // Ten datagrams a second apart (the core's clock and the GNSS time move on).
        for k in 2..=11u64 {
            let at = Instant::from_millis(k * 1000);
            let datagram = attacker.datagram(now_ms + k * 1000).unwrap();
            let outcome = obu.on_datagram(at, &datagram, &mut rx);
            assert_eq!(outcome, V2xOutcome::Dropped(reason), "{name}, datagram {k}");
            assert_eq!(held(&obu.state(at)), held(&before), "{name}, datagram {k}");
        }
        // The control: the forged frame, had the real RSU signed it anew now, would change
        // what the driver sees.
        let at = Instant::from_millis(12_000);
        let fresh = bench_pki::signer().unwrap();
        let signed = fresh.sign(attacker.frame(), now_ms + 12_000).unwrap();
        let outcome = obu.on_datagram(at, &signed, &mut rx);
        assert!(
            matches!(outcome, V2xOutcome::Changed(_)),
            "{name}: the control was {outcome:?}"
        );
        assert_ne!(held(&obu.state(at)), held(&before), "{name}: the control");
    }
    assert_eq!(attacks, 5, "the five spoofing scenarios");
}
