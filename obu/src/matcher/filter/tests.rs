use super::*;

/// Three lanes 3.5 m wide, centres 3.5 m left, 0 and 3.5 m right of lane 2's; the car at
/// lateral offset `y` from lane 2's centre, heading along the road with rate `vy`.
fn cands(y: f32) -> [Candidate; 3] {
    [(1, 3.5), (2, 0.0), (3, -3.5)].map(|(id, c)| Candidate {
        lane: LaneId(id),
        lateral: y - c,
        width: 3.5,
        bearing_deg: 0.0,
    })
}

fn obs(sigma: f32, vy: f32) -> Observation {
    let speed = 20.0f32;
    Observation {
        sigma_m: sigma,
        speed_mps: Some(speed),
        // Left of the road's bearing (0) by the angle whose sine is vy / speed.
        course_deg: Some((-libm::asinf(vy / speed).to_degrees()).rem_euclid(360.0)),
    }
}

fn step(f: &mut LaneFilter, k: u64, y: f32, o: &Observation) -> Verdict {
    let c = cands(y);
    f.update(Instant::from_millis(k * 100), &c, o, &FilterConfig::DEFAULT)
}

fn lane_of(v: &Verdict) -> Option<u8> {
    v.best.map(|i| cands(0.0)[i].lane.0)
}

#[test]
fn a_clean_fix_in_a_lane_centre_is_shown_at_once() {
    let mut f = LaneFilter::new();
    let v = step(&mut f, 0, 0.1, &obs(0.3, 0.0));
    assert_eq!(lane_of(&v), Some(2));
    assert!(v.percent >= FilterConfig::DEFAULT.show_percent, "{v:?}");
}

#[test]
fn a_multipath_jump_is_rejected_counted_and_the_lane_kept() {
    let mut f = LaneFilter::new();
    for k in 0..30 {
        step(&mut f, k, 0.0, &obs(0.5, 0.0));
    }
    let v = step(&mut f, 30, 7.0, &obs(0.5, 0.0));
    assert!(v.outlier);
    assert_eq!(f.outliers(), 1);
    assert_eq!(lane_of(&v), Some(2));
    let v = step(&mut f, 31, 0.1, &obs(0.5, 0.0));
    assert!(!v.outlier);
    assert_eq!(lane_of(&v), Some(2));
    assert!(v.percent >= 95, "{v:?}");
}

#[test]
fn a_lane_change_moves_the_belief_once() {
    let mut f = LaneFilter::new();
    let mut shown = Vec::<u8, 64>::new();
    for k in 0..100u64 {
        // 2 -> 1 (left) between 3 s and 7 s.
        let t = k as f32 / 10.0;
        let w = clamp((t - 3.0) / 4.0, 0.0, 1.0);
        let vy = if (3.0..7.0).contains(&t) {
            3.5 / 4.0
        } else {
            0.0
        };
        let v = step(&mut f, k, 3.5 * w, &obs(0.5, vy));
        if v.percent >= 80 {
            let lane = lane_of(&v).unwrap_or(0);
            if shown.last() != Some(&lane) {
                let _ = shown.push(lane);
            }
        }
    }
    assert_eq!(shown.as_slice(), &[2, 1]);
}

#[test]
fn a_few_metres_off_the_edge_keep_the_road_a_long_excursion_leaves_it() {
    let mut f = LaneFilter::new();
    for k in 0..30 {
        step(&mut f, k, -3.5, &obs(1.0, 0.0));
    }
    // One second 3 m beyond the right edge of lane 3 (its centre at -3.5, edge -5.25):
    // no car moves 4.75 m sideways in 0.1 s, so these are outliers until a second of them.
    for k in 30..40 {
        let v = step(&mut f, k, -8.25, &obs(1.0, 0.0));
        assert!(v.best.is_some(), "fix {k}: {v:?}");
    }
    // A minute 12 m beyond the edge, with no lane in reach: off the road.
    for k in 40..60 {
        let v = f.update(
            Instant::from_millis(k * 100),
            &[],
            &obs(1.0, 0.0),
            &FilterConfig::DEFAULT,
        );
        assert_eq!(v.best, None);
    }
}
