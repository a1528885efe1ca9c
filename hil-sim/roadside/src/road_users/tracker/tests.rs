use super::*;
use crate::ellipse::circle;

/// Seeded LCG + Box-Muller normal generator (test-only, deterministic).
struct Noise(u64);

impl Noise {
    fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }
}

fn obs(class: RoadUserClass, x: f64, y: f64, sigma_m: f64) -> Observation {
    Observation {
        class,
        position: [x, y],
        covariance_m2: circle(sigma_m),
        floor_m2: [[0.0; 2]; 2],
        size: None,
        at_border: false,
        road_axis: None,
    }
}

fn noisy(n: &mut Noise, class: RoadUserClass, truth: [f64; 2], sigma: f64) -> Observation {
    obs(
        class,
        truth[0] + sigma * n.normal(),
        truth[1] + sigma * n.normal(),
        sigma,
    )
}

fn tracker() -> RoadUserTracker {
    RoadUserTracker::new(TrackerSettings::default()).unwrap()
}

fn angle_diff_deg(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

#[test]
fn walking_pedestrian_estimates_and_honest_sigma() {
    let (mut tr, mut n) = (tracker(), Noise(42));
    let (speed, sigma) = (1.4, 0.1);
    let (mut sq_err, mut sum_sigma2, mut count) = (0.0, 0.0, 0.0);
    let (mut max_dv, mut max_dh, mut max_dp) = (0.0f64, 0.0f64, 0.0f64);
    let mut id = None;
    for k in 0..=50 {
        let t = k as f64 * 0.1;
        let truth = [speed * t, 0.0];
        let out = tr
            .update(t, &[noisy(&mut n, RoadUserClass::Pedestrian, truth, sigma)])
            .unwrap();
        if k < 2 {
            assert!(out.is_empty());
            continue;
        }
        assert_eq!(out.len(), 1, "t={t} {out:?}");
        let tk = &out[0];
        assert_eq!(*id.get_or_insert(tk.id), tk.id);
        assert_eq!(tk.class, RoadUserClass::Pedestrian);
        if t >= 2.0 - 1e-9 {
            let (dv, dh) = (
                (tk.speed_mps - speed).abs(),
                angle_diff_deg(tk.heading_deg.unwrap(), 90.0),
            );
            let (ex, ey) = (tk.position[0] - truth[0], tk.position[1] - truth[1]);
            let dp = ex.hypot(ey);
            assert!(
                dv < 0.2 && dh < 10.0 && dp < 0.2,
                "t={t} dv={dv} dh={dh} dp={dp}"
            );
            (max_dv, max_dh, max_dp) = (max_dv.max(dv), max_dh.max(dh), max_dp.max(dp));
            assert!(tk.heading_sigma_deg.unwrap() > 0.0 && tk.speed_sigma_mps > 0.0);
            if t > 2.0 + 1e-9 {
                // Per-axis error vs per-axis sigma (isotropic here).
                sq_err += (ex * ex + ey * ey) / 2.0;
                sum_sigma2 += tk.position_sigma_m * tk.position_sigma_m;
                count += 1.0;
            }
        }
    }
    let (rms, rep) = ((sq_err / count).sqrt(), (sum_sigma2 / count).sqrt());
    eprintln!(
        "walking: max |dv|={max_dv:.3} m/s max |dh|={max_dh:.2} deg max |dp|={max_dp:.3} m; rms err/axis={rms:.3} m reported sigma={rep:.3} m"
    );
    assert!(
        rms < 2.0 * rep && rms > 0.5 * rep,
        "rms={rms} reported={rep}"
    );
}

#[test]
fn crossing_pedestrians_keep_ids() {
    let (mut tr, mut n) = (tracker(), Noise(7));
    let truth = |t: f64| ([-10.0 + 1.4 * t, 0.0], [10.0 - 1.4 * t, 1.0]);
    let (mut id_a, mut id_b) = (None, None);
    for k in 0..=140 {
        let t = k as f64 * 0.1;
        let (a, b) = truth(t);
        let o = [
            noisy(&mut n, RoadUserClass::Pedestrian, a, 0.1),
            noisy(&mut n, RoadUserClass::Pedestrian, b, 0.1),
        ];
        let out = tr.update(t, &o).unwrap();
        if k < 2 {
            continue;
        }
        assert_eq!(out.len(), 2, "t={t}");
        let near = |p: [f64; 2]| {
            out.iter()
                .min_by(|x, y| dist(x.position, p).total_cmp(&dist(y.position, p)))
                .unwrap()
        };
        let (ta, tb) = (near(a), near(b));
        assert!(
            dist(ta.position, a) < 0.4 && dist(tb.position, b) < 0.4,
            "t={t}"
        );
        assert_eq!(*id_a.get_or_insert(ta.id), ta.id, "A swapped at t={t}");
        assert_eq!(*id_b.get_or_insert(tb.id), tb.id, "B swapped at t={t}");
    }
    assert_ne!(id_a, id_b);
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    (p[0] - q[0]).hypot(p[1] - q[1])
}

#[test]
fn car_passing_standing_worker() {
    let (mut tr, mut n) = (tracker(), Noise(99));
    let worker = [0.0, 2.0];
    let (mut id_car, mut id_worker) = (None, None);
    for k in 0..=60 {
        let t = k as f64 * 0.1;
        let car = [-40.0 + 15.0 * t, 0.0];
        let o = [
            noisy(&mut n, RoadUserClass::Car, car, 0.2),
            noisy(&mut n, RoadUserClass::Pedestrian, worker, 0.1),
        ];
        let out = tr.update(t, &o).unwrap();
        if k < 2 {
            continue;
        }
        assert_eq!(out.len(), 2);
        let c = out.iter().find(|x| x.class == RoadUserClass::Car).unwrap();
        let w = out
            .iter()
            .find(|x| x.class == RoadUserClass::Pedestrian)
            .unwrap();
        assert_eq!(*id_car.get_or_insert(c.id), c.id);
        assert_eq!(*id_worker.get_or_insert(w.id), w.id);
        // First few frames: velocity from 3 noisy fixes is inherently ~0.7 m/s
        // uncertain; from 1 s on (well before the car passes at 2.7 s) it must be low.
        if t >= 1.0 {
            assert!(w.speed_mps < 0.5, "worker speed {} at t={t}", w.speed_mps);
        }
        assert!(
            dist(w.position, worker) < if t >= 1.0 { 0.3 } else { 0.5 }
                && dist(c.position, car) < 1.0,
            "t={t} {out:?}"
        );
        if t > 1.0 {
            assert!(
                (c.speed_mps - 15.0).abs() < 1.0
                    && angle_diff_deg(c.heading_deg.unwrap(), 90.0) < 5.0
            );
        }
    }
}

#[test]
fn confirm_coast_and_drop() {
    let mut tr = tracker();
    let o = [obs(RoadUserClass::Pedestrian, 5.0, 5.0, 0.1)];
    assert!(tr.update(0.0, &o).unwrap().is_empty());
    assert!(tr.update(0.1, &o).unwrap().is_empty());
    let out = tr.update(0.2, &o).unwrap();
    assert_eq!(out.len(), 1);
    let id = out[0].id;
    assert_eq!(out[0].hits, 3);
    // Same frame twice is allowed (dt = 0).
    assert_eq!(tr.update(0.2, &[]).unwrap().len(), 1);
    // Young (three observations), it is kept but not reported while unseen.
    assert!(tr.update(0.3, &[]).unwrap().is_empty());
    for k in 4..=10 {
        assert_eq!(tr.update(f64::from(k) * 0.1, &o).unwrap()[0].id, id);
    }
    // Settled (ten), it coasts.
    for k in 11..=14 {
        let out = tr.update(f64::from(k) * 0.1, &[]).unwrap();
        assert_eq!(out.len(), 1, "coasting at k={k}");
        assert_eq!((out[0].id, out[0].hits), (id, 10));
        assert!(out[0].position_sigma_m > 0.0);
    }
    let out = tr.update(1.49, &o).unwrap();
    assert_eq!(
        (out.len(), out[0].id, out[0].hits, out[0].last_seen_s),
        (1, id, 11, 1.49)
    );
    // Unseen for the default 0.5 s, it coasts; longer, it ends.
    assert_eq!(tr.update(1.98, &[]).unwrap().len(), 1);
    assert!(tr.update(2.1, &[]).unwrap().is_empty());
    // A new observation there starts a new, unconfirmed track with a new id.
    assert!(tr.update(3.0, &o).unwrap().is_empty());
    assert!(tr.update(3.1, &o).unwrap().is_empty());
    assert_ne!(tr.update(3.2, &o).unwrap()[0].id, id);
}

#[test]
fn a_young_track_is_not_dead_reckoned_on_its_first_boxes() {
    // Three boxes confirm a car, the third 0.8 m to the side (a box of a partly seen car):
    // its velocity comes out metres a second sideways. Unseen, it is not reported: a
    // dead-reckoned position would leave the car within a few frames.
    let mut tr = tracker();
    let c = RoadUserClass::Car;
    for (k, x) in [0.0, 0.0, 0.8].into_iter().enumerate() {
        let t = k as f64 * 0.1;
        tr.update(t, &[obs(c, x, 11.0 * t, 0.1)]).unwrap();
    }
    let seen = tr.update(0.2, &[]).unwrap();
    assert_eq!(seen.len(), 1);
    assert!(seen[0].velocity[0] > 2.0, "{seen:?}");
    for t in [0.3, 0.4] {
        assert!(
            tr.update(t, &[]).unwrap().is_empty(),
            "reported unseen at {t}"
        );
    }
}

#[test]
fn a_track_takes_only_its_own_class_and_never_jumps() {
    let mut tr = tracker();
    let (c, v) = (RoadUserClass::Car, RoadUserClass::Van);
    for k in 0..10 {
        tr.update(f64::from(k) * 0.1, &[obs(c, 0.0, 0.0, 0.1)])
            .unwrap();
    }
    // A van or a cyclist where the car is does not continue the car's track.
    for (k, class) in [v, RoadUserClass::Cyclist].into_iter().enumerate() {
        let out = tr
            .update(1.0 + k as f64 * 0.1, &[obs(class, 0.0, 0.0, 0.1)])
            .unwrap();
        assert_eq!(out.len(), 1, "{class:?} must not join the car's track");
        assert_eq!((out[0].class, out[0].hits), (c, 10));
    }
    // A car 2 m away (a neighbour) does not either, though the track coasted 0.2 s.
    let out = tr.update(1.2, &[obs(c, 2.0, 0.0, 0.1)]).unwrap();
    assert_eq!((out.len(), out[0].hits), (1, 10), "{out:?}");
    assert_eq!(out[0].position, [0.0, 0.0]);
}

#[test]
fn time_back_and_non_finite_time_leave_tracker_unchanged() {
    let mut tr = tracker();
    tr.update(1.0, &[obs(RoadUserClass::Car, 0.0, 0.0, 0.5)])
        .unwrap();
    let before = tr.clone();
    let o = [obs(RoadUserClass::Car, 50.0, 0.0, 0.5)];
    assert_eq!(
        tr.update(0.9, &o),
        Err(TrackerError::TimeWentBack {
            last_s: 1.0,
            now_s: 0.9
        })
    );
    assert_eq!(tr.update(f64::NAN, &o), Err(TrackerError::NonFiniteTime));
    assert_eq!(
        tr.update(f64::INFINITY, &o),
        Err(TrackerError::NonFiniteTime)
    );
    assert_eq!(tr, before);
    assert!(!TrackerError::NonFiniteTime.to_string().is_empty());
}

#[test]
fn bad_observations_counted_and_ignored() {
    let mut tr = tracker();
    let p = RoadUserClass::Pedestrian;
    let bad = [
        obs(p, f64::NAN, 0.0, 0.1),
        obs(p, 0.0, f64::INFINITY, 0.1),
        obs(p, 0.0, 0.0, f64::NAN),
        obs(p, 0.0, 0.0, 0.0),
        // Not positive definite.
        Observation {
            covariance_m2: [[0.01, 0.02], [0.02, 0.01]],
            ..obs(p, 0.0, 0.0, 0.1)
        },
        // Not symmetric.
        Observation {
            covariance_m2: [[0.01, 1e300], [-1e300, 0.01]],
            ..obs(p, 0.0, 0.0, 0.1)
        },
        // A floor with a negative variance.
        Observation {
            floor_m2: [[-0.01, 0.0], [0.0, 0.01]],
            ..obs(p, 0.0, 0.0, 0.1)
        },
    ];
    // Tiny variances are a covariance (taken as 1 mm), not an underflow.
    let sharp = Observation {
        covariance_m2: circle(1e-85),
        ..obs(p, 5.0, 5.0, 0.1)
    };
    let huge_floor = Observation {
        floor_m2: circle(1e5),
        ..obs(p, 0.0, 0.0, 0.1)
    };
    for k in 0..3 {
        let mut frame = bad.to_vec();
        frame.extend([obs(p, 1.0, 1.0, 0.1), sharp, huge_floor]);
        frame.push(obs(p, 2.0e6, 0.0, 0.1));
        let out = tr.update(k as f64 * 0.1, &frame).unwrap();
        assert_eq!(out.len(), 2 * usize::from(k == 2));
        assert!(out
            .iter()
            .all(|t| t.position_ellipse.semi_major_m.is_finite()));
    }
    let r = tr.rejected();
    assert_eq!((r.non_finite, r.out_of_range, r.over_capacity), (21, 6, 0));
}

#[test]
fn max_tracks_bound() {
    let mut tr = tracker();
    let frame: Vec<_> = (0..300)
        .map(|i| obs(RoadUserClass::Car, i as f64 * 100.0, 0.0, 0.2))
        .collect();
    assert!(tr.update(0.0, &frame).unwrap().is_empty());
    assert_eq!(tr.rejected().over_capacity, 44);
    tr.update(0.1, &frame).unwrap();
    let out = tr.update(0.2, &frame).unwrap();
    assert_eq!(out.len(), RoadUserTracker::MAX_TRACKS);
    assert_eq!(tr.rejected().over_capacity, 44 * 3);
    let big = vec![obs(RoadUserClass::Car, 0.0, 0.0, 0.5); RoadUserTracker::MAX_OBSERVATIONS + 5];
    tr.update(0.3, &big).unwrap();
    assert_eq!(tr.rejected().over_frame_limit, 5);
}

#[test]
fn bad_settings_rejected() {
    let d = TrackerSettings::default();
    let cases = [
        (TrackerSettings { gate_m: 0.0, ..d }, "gate_m"),
        (
            TrackerSettings {
                gate_m: f64::NAN,
                ..d
            },
            "gate_m",
        ),
        (
            TrackerSettings {
                confirm_hits: 0,
                ..d
            },
            "confirm_hits",
        ),
        (
            TrackerSettings {
                max_coast_s: -1.0,
                ..d
            },
            "max_coast_s",
        ),
        (
            TrackerSettings {
                max_coast_s: f64::INFINITY,
                ..d
            },
            "max_coast_s",
        ),
        (
            TrackerSettings {
                accel_sigma_mps2: f64::NAN,
                ..d
            },
            "accel_sigma_mps2",
        ),
        (
            TrackerSettings {
                person_accel_sigma_mps2: 0.0,
                ..d
            },
            "person_accel_sigma_mps2",
        ),
        (
            TrackerSettings {
                max_report_sigma_m: -1.0,
                ..d
            },
            "max_report_sigma_m",
        ),
    ];
    for (s, field) in cases {
        assert_eq!(
            RoadUserTracker::new(s),
            Err(TrackerError::BadSettings(field))
        );
    }
    assert!(RoadUserTracker::new(d).is_ok());
}

#[test]
fn garbage_input_never_panics_and_outputs_stay_finite() {
    let (mut tr, mut n) = (tracker(), Noise(3));
    let vals = [
        0.0,
        1e-300,
        -1e-300,
        1e5,
        -9.9e5,
        1e300,
        f64::NAN,
        f64::NEG_INFINITY,
        3.0,
    ];
    for k in 0..200 {
        let t = k as f64 * 0.05;
        let frame: Vec<_> = (0..20)
            .map(|i| {
                let pick =
                    |n: &mut Noise| vals[(n.uniform() * vals.len() as f64) as usize % vals.len()];
                let class = RoadUserClass::ALL[i % 7];
                let road_axis = (i % 3 != 0).then(|| [pick(&mut n), pick(&mut n)]);
                Observation {
                    road_axis,
                    ..obs(
                        class,
                        pick(&mut n) + n.normal(),
                        pick(&mut n),
                        pick(&mut n).abs() + 1e-12,
                    )
                }
            })
            .collect();
        for tk in tr.update(t, &frame).unwrap() {
            let all = [
                tk.position[0],
                tk.position[1],
                tk.speed_mps,
                tk.position_sigma_m,
                tk.speed_sigma_mps,
            ];
            assert!(all.iter().all(|v| v.is_finite()), "{tk:?}");
            assert!(tk.heading_deg.is_none_or(|h| (0.0..360.0).contains(&h)));
        }
    }
}

#[test]
fn id_wrap_skips_ids_in_use() {
    let mut tr = tracker();
    let car = |x: f64| obs(RoadUserClass::Car, x, 0.0, 0.5);
    tr.update(0.0, &[car(0.0)]).unwrap(); // id 1
    tr.next_id = u32::MAX;
    tr.update(0.1, &[car(0.0), car(1000.0), car(2000.0), car(3000.0)])
        .unwrap();
    let mut ids: Vec<u32> = tr.tracks.iter().map(|t| t.id).collect();
    ids.sort_unstable();
    assert_eq!(ids, vec![0, 1, 2, u32::MAX]);
}

#[test]
fn a_track_is_reported_only_while_its_position_is_known() {
    let mut tr = tracker();
    // Three vague sightings (1 m) confirm a track that is not yet known to 0.4 m.
    let vague = [obs(RoadUserClass::Pedestrian, 5.0, 5.0, 1.0)];
    for k in 0..3 {
        assert!(tr.update(f64::from(k) * 0.1, &vague).unwrap().is_empty());
    }
    // Sharp ones make it known, and reported.
    let sharp = [obs(RoadUserClass::Pedestrian, 5.0, 5.0, 0.05)];
    let out = tr.update(0.3, &sharp).unwrap();
    assert_eq!(out.len(), 1, "{out:?}");
    assert!(out[0].position_sigma_m <= 0.4);
}

#[test]
fn a_fast_vehicle_is_confirmed_and_followed() {
    // 25 m/s (90 km/h) at 10 frames a second: 2.5 m a frame, beyond the jump limit of a
    // settled track, within that of a young one whose speed is not yet known.
    let mut tr = tracker();
    let mut last = Vec::new();
    for k in 0..10 {
        let t = f64::from(k) * 0.1;
        let o = [obs(RoadUserClass::Car, 0.0, 25.0 * t, 0.1)];
        last = tr.update(t, &o).unwrap();
    }
    assert_eq!(last.len(), 1, "{last:?}");
    assert_eq!(last[0].hits, 10);
    assert!((last[0].speed_mps - 25.0).abs() < 2.0, "{last:?}");
}

#[test]
fn a_side_taken_from_the_prior_does_not_average_out() {
    // A bus cut by the image border: every box takes its length from the class's prior, so
    // twenty of them are no better placed than one. The filter's own sigma shrinks; the
    // track reports the floor and stays unreported while that exceeds the 0.4 m limit.
    let mut tr = tracker();
    let cut = |y: f64| Observation {
        floor_m2: circle(0.6),
        ..obs(RoadUserClass::Bus, 8.0, y, 0.6)
    };
    for k in 0..20 {
        let t = f64::from(k) * 0.1;
        let out = tr.update(t, &[cut(12.0 * t)]).unwrap();
        assert!(out.is_empty(), "reported at {t}: {out:?}");
    }
    // Seen whole, its sigma is its own again.
    let out = tr
        .update(2.0, &[obs(RoadUserClass::Bus, 8.0, 24.0, 0.1)])
        .unwrap();
    assert_eq!(out.len(), 1);
    assert!(out[0].position_sigma_m < 0.4, "{out:?}");
    // A floor that is not a number is counted and ignored.
    let bad = Observation {
        floor_m2: [[f64::NAN, 0.0], [0.0, 0.0]],
        ..obs(RoadUserClass::Bus, 8.0, 25.2, 0.1)
    };
    let before = tr.rejected().non_finite;
    tr.update(2.1, &[bad]).unwrap();
    assert_eq!(tr.rejected().non_finite, before + 1);
}

/// Evidence that the size is `size`, each side known within `sigma_m` in one frame.
fn size_evidence(size: [f64; 3], sigma_m: f64) -> SizeEvidence {
    let w = 1.0 / (sigma_m * sigma_m);
    let mut information = [[0.0; 3]; 3];
    for (k, row) in information.iter_mut().enumerate() {
        row[k] = w;
    }
    SizeEvidence {
        information,
        vector: size.map(|v| w * v),
    }
}

#[test]
fn a_track_learns_its_road_users_size_and_tells_it_only_where_it_alone_is() {
    let mut tr = RoadUserTracker::new(TrackerSettings::default()).unwrap();
    let car = [4.2, 1.75, 1.45];
    let seen = |y: f64| Observation {
        size: Some(size_evidence(car, 0.3)),
        ..obs(RoadUserClass::Car, 5.0, y, 0.1)
    };
    // Too few frames: the class's prior stands.
    tr.update(0.0, &[seen(20.0)]).unwrap();
    tr.update(0.1, &[seen(21.0)]).unwrap();
    assert!(tr.size_near(RoadUserClass::Car, [5.0, 22.0], 0.2).is_none());
    for k in 2..30 {
        let t = f64::from(k) * 0.1;
        tr.update(t, &[seen(20.0 + 10.0 * t)]).unwrap();
    }
    // Last seen at 49 m at 2.9 s, predicted at 53 m at 3.3 s: 4 m on, beyond a car's
    // reach (3.3 m) of where it was last seen.
    let b = tr.size_near(RoadUserClass::Car, [5.0, 53.0], 3.3);
    let b = b.expect("one car track there");
    assert!((b.mean[0] - 4.2).abs() < 0.1, "{:?}", b.mean);
    let prior = RoadUserClass::Car.size_prior().sigma.length_m;
    assert!(b.sigma()[0] < prior / 3.0, "{:?}", b.sigma());
    // Another class, where it was rather than where it is, or nowhere near: no belief.
    assert!(tr.size_near(RoadUserClass::Van, [5.0, 53.0], 3.3).is_none());
    assert!(tr.size_near(RoadUserClass::Car, [5.0, 49.0], 3.3).is_none());
    assert!(tr.size_near(RoadUserClass::Car, [5.0, 80.0], 3.3).is_none());
    // Unseen for longer than the coast: the track is as good as ended.
    assert!(tr.size_near(RoadUserClass::Car, [5.0, 55.0], 3.5).is_none());
}

#[test]
fn two_tracks_near_one_detection_give_no_size() {
    let mut tr = RoadUserTracker::new(TrackerSettings::default()).unwrap();
    let person = |x: f64| Observation {
        size: Some(size_evidence([0.5, 0.5, 1.8], 0.05)),
        ..obs(RoadUserClass::Pedestrian, x, 30.0, 0.05)
    };
    for k in 0..10 {
        let t = f64::from(k) * 0.1;
        tr.update(t, &[person(10.0), person(10.9)]).unwrap();
    }
    assert!(tr
        .size_near(RoadUserClass::Pedestrian, [10.45, 30.0], 1.0)
        .is_none());
    assert!(tr
        .size_near(RoadUserClass::Pedestrian, [9.6, 30.0], 1.0)
        .is_some_and(|b| (b.mean[2] - 1.8).abs() < 0.05));
}

#[test]
fn a_non_finite_size_is_refused_with_the_observation() {
    let mut tr = RoadUserTracker::new(TrackerSettings::default()).unwrap();
    let mut e = size_evidence([4.5, 1.8, 1.5], 0.1);
    e.vector[0] = f64::NAN;
    let bad = Observation {
        size: Some(e),
        ..obs(RoadUserClass::Car, 5.0, 20.0, 0.1)
    };
    tr.update(0.0, &[bad]).unwrap();
    assert_eq!(tr.rejected().non_finite, 1);
}

#[test]
fn a_road_user_last_seen_at_the_border_is_not_coasted() {
    // Two settled tracks lose their road users at 2 s: the one last seen cut by the image
    // border left the view and is no longer reported; the other (hidden behind a
    // neighbour) coasts.
    let mut tr = RoadUserTracker::new(TrackerSettings::default()).unwrap();
    for k in 0..20 {
        let t = f64::from(k) * 0.1;
        let leaving = Observation {
            at_border: k >= 15,
            ..obs(RoadUserClass::Car, 2.0, 30.0 - 10.0 * t, 0.1)
        };
        tr.update(
            t,
            &[leaving, obs(RoadUserClass::Car, 9.0, 10.0 + 10.0 * t, 0.1)],
        )
        .unwrap();
    }
    let coasting = tr.update(2.1, &[]).unwrap();
    assert_eq!(coasting.len(), 1, "{coasting:?}");
    assert!((coasting[0].position[0] - 9.0).abs() < 0.2, "{coasting:?}");
}

#[test]
fn a_road_user_cut_in_one_camera_and_whole_in_another_coasts() {
    // Two cameras feed one tracker, each frame one update per camera at the same time. A
    // car leaving the first camera's view (cut by its border) while the second sees it
    // whole has not left the site's view: hidden at 2 s, it coasts, in either camera order.
    for border_last in [true, false] {
        let mut tr = RoadUserTracker::new(TrackerSettings::default()).unwrap();
        for k in 0..20 {
            let t = f64::from(k) * 0.1;
            let seen = obs(RoadUserClass::Car, 2.0, 30.0 - 10.0 * t, 0.1);
            let cut = Observation {
                at_border: true,
                ..seen
            };
            let order = if border_last {
                [seen, cut]
            } else {
                [cut, seen]
            };
            for o in order {
                tr.update(t, &[o]).unwrap();
            }
        }
        let coasting = tr.update(2.1, &[]).unwrap();
        assert_eq!(coasting.len(), 1, "border last {border_last}: {coasting:?}");
    }
}

#[test]
fn boxes_known_across_the_line_of_sight_give_a_narrow_ellipse_and_keep_neighbours_apart() {
    // Two workers standing 0.5 m apart across a camera's line of sight (north): each box is
    // 0.3 m off along it, 2 cm across (1 sigma); of that, 10 cm along it and 3 cm across
    // repeat from frame to frame (the size prior's share, the calibration's).
    let (mut tr, mut n) = (tracker(), Noise(7));
    let p = RoadUserClass::Pedestrian;
    let truths = [[0.0, 10.0], [0.5, 10.0]];
    let (along, across) = (0.3, 0.02);
    let covariance_m2 = [[across * across, 0.0], [0.0, along * along]];
    let mut ids: Option<[u32; 2]> = None;
    let (mut held, mut scored, mut east_sq) = (0, 0, 0.0);
    for k in 0..100 {
        let frame: Vec<Observation> = truths
            .iter()
            .map(|t| Observation {
                covariance_m2,
                floor_m2: [[0.03 * 0.03, 0.0], [0.0, 0.1 * 0.1]],
                ..obs(
                    p,
                    t[0] + across * n.normal(),
                    t[1] + along * n.normal(),
                    0.0,
                )
            })
            .collect();
        let out = tr.update(k as f64 * 0.1, &frame).unwrap();
        if k < 10 {
            continue;
        }
        assert_eq!(out.len(), 2, "frame {k}: {out:?}");
        // Each track stays with its worker: the one west is the same track throughout.
        let west = if out[0].position[0] < out[1].position[0] {
            0
        } else {
            1
        };
        let now = [out[west].id, out[1 - west].id];
        assert_eq!(*ids.get_or_insert(now), now, "frame {k}");
        for (tk, truth) in [&out[west], &out[1 - west]].into_iter().zip(truths) {
            east_sq += (tk.position[0] - truth[0]).powi(2);
            let e = &tk.position_ellipse;
            // Long along the line of sight (north), narrow across it: each axis floored by
            // the repeated error along it (to a tenth of a millimetre: the spread of a
            // person's two motion models turns the axes by a fraction of a degree).
            // An axis has no sense: 180 degrees is north too.
            let off_north = angle_diff_deg(e.orientation_deg, 0.0)
                .min(angle_diff_deg(e.orientation_deg, 180.0));
            assert!(off_north < 5.0, "{e:?}");
            assert!((e.semi_minor_m - 0.03).abs() < 1e-4, "{e:?}");
            assert!(
                e.semi_major_m >= 0.1 - 1e-4 && e.semi_major_m < 0.3,
                "{e:?}"
            );
            assert!((e.semi_major_m - tk.position_sigma_m).abs() < 1e-9);
            let d = [truth[0] - tk.position[0], truth[1] - tk.position[1]];
            scored += 1;
            held += usize::from(crate::ellipse::mahalanobis2(&e.covariance(), d) <= 5.99);
        }
    }
    // Across the line of sight the track is known better than one box.
    let east_rms = (east_sq / scored as f64).sqrt();
    assert!(east_rms < across, "east error {east_rms} m rms");
    assert!(held as f64 >= 0.9 * scored as f64, "{held} of {scored}");
}

#[test]
fn a_road_user_seen_whole_after_partial_views_is_taken_where_the_whole_view_puts_it() {
    // A worker standing 40 m down the line of sight (north), half hidden for a second and a
    // half: every box lies 0.5 m too far, an error the boxes share (their floor says so).
    // Then he is seen whole, known to 8 cm along the line of sight.
    let mut tr = tracker();
    let along = |sigma: f64| [[0.03 * 0.03, 0.0], [0.0, sigma * sigma]];
    let partial = Observation {
        covariance_m2: along(0.38),
        floor_m2: along(0.38),
        ..obs(RoadUserClass::Pedestrian, 11.0, 40.5, 0.0)
    };
    for k in 0..15 {
        tr.update(f64::from(k) * 0.1, &[partial]).unwrap();
    }
    let whole = Observation {
        covariance_m2: along(0.08),
        floor_m2: along(0.03),
        ..obs(RoadUserClass::Pedestrian, 11.0, 40.0, 0.0)
    };
    let out = tr.update(1.5, &[whole]).unwrap();
    assert_eq!(out.len(), 1, "{out:?}");
    // Re-anchored, the track restarts from the whole box; blended with the partial views
    // (their covariance raised to their shared error) it would keep part of their 0.5 m,
    // and more if averaged with them as if their error were independent.
    let off = out[0].position[1] - 40.0;
    assert!(off.abs() < 0.001, "{:?}", out[0]);
    assert!(
        (out[0].position_sigma_m - 0.08).abs() < 0.005,
        "{:?}",
        out[0]
    );
    // He stands: the restart is not taken for a step, the next boxes keep the track put.
    let mut n = Noise(13);
    for k in 16..40 {
        let whole = Observation {
            position: [11.0, 40.0 + 0.08 * n.normal()],
            ..whole
        };
        let out = tr.update(f64::from(k) * 0.1, &[whole]).unwrap();
        let off = out[0].position[1] - 40.0;
        assert!(off.abs() < 0.06, "frame {k}: {:?}", out[0]);
        assert!(out[0].speed_mps < 0.3, "frame {k}: {:?}", out[0]);
    }
}

#[test]
fn a_vehicle_seen_whole_after_partial_views_restarts_its_position_and_keeps_its_speed() {
    // A car driving north at 10 m/s, half hidden for a second: each box 0.3 m too far
    // along the line of sight (north), an error they share (known to 0.35 m, within what a
    // track may report). Then it is seen whole.
    let mut tr = tracker();
    let along = |sigma: f64| [[0.05 * 0.05, 0.0], [0.0, sigma * sigma]];
    let at = |t: f64| 10.0 + 10.0 * t;
    let mut before = None;
    for k in 0..10 {
        let t = f64::from(k) * 0.1;
        let partial = Observation {
            covariance_m2: along(0.35),
            floor_m2: along(0.35),
            ..obs(RoadUserClass::Car, 5.0, at(t) + 0.3, 0.0)
        };
        before = tr.update(t, &[partial]).unwrap().into_iter().next();
    }
    let before = before.expect("a confirmed track");
    let whole = Observation {
        covariance_m2: along(0.1),
        floor_m2: along(0.03),
        ..obs(RoadUserClass::Car, 5.0, at(1.0), 0.0)
    };
    let out = tr.update(1.0, &[whole]).unwrap();
    assert_eq!(out.len(), 1, "{out:?}");
    assert_eq!(out[0].id, before.id);
    // Where the whole box puts it, at the speed the track had: the restart is not a jump
    // of 0.3 m in a tenth of a second.
    assert!((out[0].position[1] - at(1.0)).abs() < 1e-9, "{:?}", out[0]);
    let dv =
        (out[0].velocity[0] - before.velocity[0]).hypot(out[0].velocity[1] - before.velocity[1]);
    assert!(dv < 1e-9, "{before:?} -> {:?}", out[0]);
}

#[test]
fn a_standing_worker_who_walks_off_keeps_his_track() {
    // Five seconds standing, boxes known to 3 cm (near the camera), then off at 2 m/s² (a
    // brisk start) to 1.5 m/s: a track that took him as standing must let him go.
    let (mut tr, mut n) = (tracker(), Noise(17));
    let (accel, top) = (2.0, 1.5);
    let walked = |s: f64| {
        let ramp = top / accel;
        if s < ramp {
            0.5 * accel * s * s
        } else {
            0.5 * accel * ramp * ramp + top * (s - ramp)
        }
    };
    let truth = |t: f64| [2.0 + walked((t - 5.0).max(0.0)), 12.0];
    let mut id = None;
    for k in 0..80 {
        let t = f64::from(k) * 0.1;
        let out = tr
            .update(
                t,
                &[noisy(&mut n, RoadUserClass::Pedestrian, truth(t), 0.03)],
            )
            .unwrap();
        if k < 3 {
            continue;
        }
        assert_eq!(out.len(), 1, "{t} s: {out:?}");
        assert_eq!(*id.get_or_insert(out[0].id), out[0].id, "{t} s: {out:?}");
        let off = (out[0].position[0] - truth(t)[0]).hypot(out[0].position[1] - truth(t)[1]);
        // Standing, a few centimetres; a second and a half after he walks off, with him.
        if !(5.0..6.5).contains(&t) {
            assert!(off < 0.1, "{t} s: {:?}", out[0]);
        }
    }
}

/// Two observations of one worker along the line of sight (north), in part 0.5 m too far and
/// whole where he stands.
fn partial_and_whole(noise_m: f64) -> (Observation, Observation) {
    let along = |sigma: f64| [[0.03 * 0.03, 0.0], [0.0, sigma * sigma]];
    let partial = Observation {
        covariance_m2: along(0.38),
        floor_m2: along(0.38),
        ..obs(RoadUserClass::Pedestrian, 11.0, 40.5, 0.0)
    };
    let whole = Observation {
        covariance_m2: along(0.08),
        floor_m2: along(0.03),
        ..obs(RoadUserClass::Pedestrian, 11.0, 40.0 + noise_m, 0.0)
    };
    (partial, whole)
}

#[test]
fn a_second_camera_seeing_whole_what_the_first_sees_in_part_builds_up_the_track() {
    // Each frame, camera A sees the worker in part and camera B sees him whole, both at the
    // frame's time. B's boxes add up: the track is not re-anchored on each of them.
    let mut tr = tracker();
    let mut n = Noise(7);
    let mut last = Vec::new();
    for k in 0..30 {
        let t = f64::from(k) * 0.1;
        let (partial, whole) = partial_and_whole(0.08 * n.normal());
        tr.update(t, &[partial]).unwrap();
        last = tr.update(t, &[whole]).unwrap();
    }
    assert_eq!(last.len(), 1, "{last:?}");
    // One of B's boxes alone is known to 8 cm; re-anchored every frame the track would be too.
    let along = last[0].position_ellipse.semi_major_m;
    assert!(along < 0.06, "{:?}", last[0]);
    assert!((last[0].position[1] - 40.0).abs() < 0.08, "{:?}", last[0]);
}

#[test]
fn one_partial_frame_between_whole_ones_does_not_reanchor_the_track() {
    let mut tr = tracker();
    let mut n = Noise(11);
    for k in 0..30 {
        let (_, whole) = partial_and_whole(0.08 * n.normal());
        tr.update(f64::from(k) * 0.1, &[whole]).unwrap();
    }
    let (partial, whole) = partial_and_whole(0.0);
    tr.update(3.0, &[partial]).unwrap();
    let out = tr.update(3.1, &[whole]).unwrap();
    assert_eq!(out.len(), 1, "{out:?}");
    // Re-anchored, the track would rest on this one box (8 cm).
    assert!(out[0].position_ellipse.semi_major_m < 0.06, "{:?}", out[0]);
}

/// A road's direction at `deg` degrees from north, and positions in its frame (x across,
/// y along) turned onto the site's axes.
struct Road(f64);

impl Road {
    fn axis(&self) -> [f64; 2] {
        let a = self.0.to_radians();
        [a.sin(), a.cos()]
    }
    fn at(&self, across: f64, along: f64) -> [f64; 2] {
        let [ux, uy] = self.axis();
        [across * uy + along * ux, -across * ux + along * uy]
    }
    /// A covariance with these 1-sigmas across and along the road (and correlation `rho`).
    fn cov(&self, across: f64, along: f64, rho: f64) -> Cov2 {
        let [ux, uy] = self.axis();
        let (v, u) = ([uy, -ux], [ux, uy]);
        let c = rho * across * along;
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                across * across * v[i] * v[j]
                    + along * along * u[i] * u[j]
                    + c * (v[i] * u[j] + u[i] * v[j])
            })
        })
    }
    /// A van's box far down the road, known to 27 cm across it and to `along` m along it.
    fn far_van(&self, across: f64, along_m: f64, along: f64) -> Observation {
        let [x, y] = self.at(across, along_m);
        Observation {
            covariance_m2: self.cov(0.27, along, 0.2),
            road_axis: Some(self.axis()),
            ..obs(RoadUserClass::Van, x, y, 0.0)
        }
    }
}

#[test]
fn a_young_vehicle_track_does_not_take_the_box_of_a_neighbour_in_the_next_lane() {
    // Van A is seen once in its lane and then hidden; van B, 3.5 m across in the next lane,
    // is seen from 0.2 s on, driving at 12 m/s. The road's direction keeps A's young track
    // from reaching across (its velocity prior and its gate): B's first box starts a track
    // of its own, and B's track reports B. On a road running north and on one running
    // north-east by north.
    for road in [Road(0.0), Road(37.0)] {
        let mut tr = tracker();
        tr.update(0.0, &[road.far_van(-3.5, -48.4, 0.97)]).unwrap();
        tr.update(0.1, &[]).unwrap();
        tr.update(0.2, &[road.far_van(0.0, -49.1, 0.97)]).unwrap();
        assert_eq!(tr.tracks.len(), 2, "B's box started a track of its own");
        let mut out = Vec::new();
        for k in 3..10 {
            let t = f64::from(k) * 0.1;
            let b = road.far_van(0.0, -49.1 + 12.0 * (t - 0.2), 0.6);
            out = tr.update(t, &[b]).unwrap();
        }
        assert_eq!(out.len(), 1, "{out:?}");
        assert!((out[0].first_seen_s - 0.2).abs() < 1e-9, "{:?}", out[0]);
        let [ux, uy] = road.axis();
        let across = out[0].velocity[0] * uy - out[0].velocity[1] * ux;
        assert!(across.abs() < 1.0, "{:?}", out[0]);
    }
}

#[test]
fn a_vehicle_seen_side_on_keeps_its_track_when_it_brakes_hard() {
    // Seen side-on, a car's box is known to 2 cm along the road and to 30 cm across it. It
    // drives at 12 m/s for three seconds, then brakes at 8 m/s² to a stop: the
    // constant-velocity model runs ahead of it by far more than its box's error along the
    // road, and the gate's margin along the road keeps its track.
    let road = Road(0.0);
    let mut tr = tracker();
    let mut ids = Vec::new();
    for k in 0..60 {
        let t = f64::from(k) * 0.1;
        let braking = (t - 3.0).clamp(0.0, 1.5);
        let along = 12.0 * t.min(3.0) + 12.0 * braking - 4.0 * braking * braking;
        let [x, y] = road.at(0.0, along);
        let o = Observation {
            covariance_m2: road.cov(0.3, 0.02, 0.0),
            road_axis: Some(road.axis()),
            ..obs(RoadUserClass::Car, x, y, 0.0)
        };
        ids.extend(tr.update(t, &[o]).unwrap().iter().map(|t| t.id));
    }
    ids.dedup();
    assert_eq!(ids.len(), 1, "{ids:?}");
    assert_eq!(tr.tracks.len(), 1);
}
