use super::*;
use heapless::Vec;

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

/// White noise of 1-sigma `sigma` for fix `k` (deterministic: a uniform spread over 13
/// levels, scaled to that sigma).
fn noise(k: u64, sigma: f32) -> f32 {
    ((k * 5 % 13) as f32 - 6.0) / 3.74 * sigma
}

#[test]
fn a_jump_beyond_the_edge_is_held_off_then_the_road_is_left() {
    let mut f = LaneFilter::new();
    for k in 0..30 {
        step(&mut f, k, -3.5 + noise(k, 0.5), &obs(0.5, 0.0));
    }
    // 3 m beyond the right edge of lane 3 (centre -3.5, edge -5.25): no car moves 4.75 m
    // sideways in 0.1 s, so the first nine are outliers and lane 3 keeps its belief.
    for k in 30..39 {
        let v = step(&mut f, k, -8.25 + noise(k, 0.5), &obs(0.5, 0.0));
        assert!(v.outlier, "fix {k}: {v:?}");
        assert_eq!(lane_of(&v), Some(3));
        assert!(v.percent >= 90 && v.off_road_percent < 5, "fix {k}: {v:?}");
    }
    // The tenth restarts the track there; staying there moves the belief off the road
    // (the receiver's error is white: no bias can carry a fix that far).
    let mut last = None;
    for k in 39..60 {
        last = Some(step(&mut f, k, -8.25 + noise(k, 0.5), &obs(0.5, 0.0)));
    }
    let v = last.unwrap_or_else(|| unreachable!());
    assert!(!v.outlier && v.off_road_percent > v.percent, "{v:?}");
    // No lane in reach at all: nine outliers, then off the road for certain.
    for k in 60..69 {
        let v = f.update(
            Instant::from_millis(k * 100),
            &[],
            &obs(1.0, 0.0),
            &FilterConfig::DEFAULT,
        );
        assert!(v.outlier && v.best.is_none(), "fix {k}: {v:?}");
    }
    let v = f.update(
        Instant::from_millis(6_900),
        &[],
        &obs(1.0, 0.0),
        &FilterConfig::DEFAULT,
    );
    assert!(
        !v.outlier && v.best.is_none() && v.off_road_percent == 100,
        "{v:?}"
    );
}

#[test]
fn a_lane_that_ends_beside_lanes_that_go_on_is_no_jump() {
    let mut f = LaneFilter::new();
    for k in 0..30 {
        step(&mut f, k, 0.0, &obs(0.5, 0.0));
    }
    // Lane 2 ends; lanes 1 and 3 go on (the car drifts onto lane 3's side).
    let c = cands(-2.0);
    let v = f.update(
        Instant::from_millis(3_000),
        &[c[0], c[2]],
        &obs(0.5, 0.0),
        &FilterConfig::DEFAULT,
    );
    assert!(!v.outlier, "{v:?}");
    assert_eq!(v.best.map(|i| [c[0], c[2]][i].lane.0), Some(3));
}

#[test]
fn a_huge_reported_error_does_not_poison_the_track() {
    let mut f = LaneFilter::new();
    step(&mut f, 0, 0.0, &obs(0.5, 0.0));
    step(&mut f, 1, 0.0, &obs(f32::MAX, 0.0));
    for k in 2..20 {
        step(&mut f, k, 0.0, &obs(0.5, 0.0));
    }
    let v = step(&mut f, 20, 0.0, &obs(0.5, 0.0));
    assert_eq!(lane_of(&v), Some(2));
    assert!(v.percent >= 90, "{v:?}");
}

/// A receiver whose fixes scatter little but wander: a bias drifting from 0 to 2.2 m to
/// the left over 40 s carries the fixes across lane 2's left edge into lane 1.
fn drifting_bias(k: u64) -> f32 {
    2.2 * clamp(k as f32 / 400.0, 0.0, 1.0) + noise(k, 0.2)
}

#[test]
fn a_bias_that_wanders_into_the_next_lane_does_not_move_the_lane() {
    let mut f = LaneFilter::new();
    for k in 0..600 {
        let v = step(&mut f, k, drifting_bias(k), &obs(1.0, 0.0));
        if v.percent >= FilterConfig::DEFAULT.show_percent {
            assert_eq!(lane_of(&v), Some(2), "fix {k}: {v:?}");
        }
        if k == 599 {
            // A lane is still named: the bias has not been mistaken for lane 1.
            assert!(v.percent >= FilterConfig::DEFAULT.show_percent, "{v:?}");
        }
    }
}

#[test]
fn a_lane_change_under_a_bias_is_followed() {
    let mut f = LaneFilter::new();
    let mut shown = Vec::<u8, 64>::new();
    for k in 0..600u64 {
        // The bias of the test above; the car changes 2 -> 3 (right) at 50 s over 4 s.
        let t = k as f32 / 10.0;
        let w = clamp((t - 50.0) / 4.0, 0.0, 1.0);
        let vy = if (50.0..54.0).contains(&t) {
            -3.5 / 4.0
        } else {
            0.0
        };
        let v = step(&mut f, k, drifting_bias(k) - 3.5 * w, &obs(1.0, vy));
        if v.percent >= FilterConfig::DEFAULT.show_percent {
            let lane = lane_of(&v).unwrap_or(0);
            if shown.last() != Some(&lane) {
                let _ = shown.push(lane);
            }
        }
    }
    // With 2.2 m of bias to the left the fixes end in lane 2: the lane shown is 3.
    assert_eq!(shown.as_slice(), &[2, 3]);
}

#[test]
fn a_slow_lane_change_is_not_taken_for_bias() {
    let mut f = LaneFilter::new();
    let mut shown = Vec::<u8, 64>::new();
    let mut last = None;
    for k in 0..600u64 {
        // 2 -> 1 (left) over 8 s from 10 s on; 0.3 m white noise, 1 m reported.
        let t = k as f32 / 10.0;
        let w = clamp((t - 10.0) / 8.0, 0.0, 1.0);
        let vy = if (10.0..18.0).contains(&t) {
            3.5 / 8.0
        } else {
            0.0
        };
        let v = step(&mut f, k, 3.5 * w + noise(k, 0.3), &obs(1.0, vy));
        if v.percent >= FilterConfig::DEFAULT.show_percent {
            let lane = lane_of(&v).unwrap_or(0);
            if shown.last() != Some(&lane) {
                let _ = shown.push(lane);
            }
        }
        last = Some(v);
    }
    assert_eq!(shown.as_slice(), &[2, 1]);
    let v = last.unwrap_or_else(|| unreachable!());
    assert_eq!(lane_of(&v), Some(1));
    assert!(v.percent >= FilterConfig::DEFAULT.show_percent, "{v:?}");
}

#[test]
fn fixes_that_stay_far_beyond_the_edge_leave_the_road_even_without_scatter() {
    // A receiver reporting 1 m whose fixes do not scatter: the filter takes the error for
    // a bias, but not one of 5.75 m (4 m beyond lane 3's edge).
    let mut f = LaneFilter::new();
    for k in 0..30 {
        step(&mut f, k, -3.5, &obs(1.0, 0.0));
    }
    let mut last = None;
    for k in 30..120 {
        last = Some(step(&mut f, k, -9.25, &obs(1.0, 0.0)));
    }
    let v = last.unwrap_or_else(|| unreachable!());
    assert!(!v.outlier && v.off_road_percent > v.percent, "{v:?}");
}

#[test]
fn the_bias_prior_names_the_lane_a_steady_offset_is_nearest() {
    // 1.2 m left of lane 2's centre, steady: a 1.2 m bias is far likelier than -2.3 m
    // (lane 1), and only the bias's prior can say so.
    let mut f = LaneFilter::new();
    let mut last = None;
    for k in 0..50 {
        let v = step(&mut f, k, 1.2 + noise(k, 0.2), &obs(1.0, 0.0));
        if v.percent >= FilterConfig::DEFAULT.show_percent {
            assert_eq!(lane_of(&v), Some(2), "fix {k}: {v:?}");
        }
        last = Some(v);
    }
    let v = last.unwrap_or_else(|| unreachable!());
    assert_eq!(lane_of(&v), Some(2));
    assert!(v.percent >= FilterConfig::DEFAULT.show_percent, "{v:?}");
}
