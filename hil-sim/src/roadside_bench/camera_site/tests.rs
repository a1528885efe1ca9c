use super::*;
use geodesy::LatLon;
use j2735::MessageFrameValue;

/// A two-lane road running east, 3.5 m lanes, 800 m long.
fn road() -> Road {
    let at = LatLon::from_degrees(39.7392, -104.9903).unwrap();
    Road::straight(at, 90.0, 800.0, (2, 0), 3.5, 40.0)
}

fn spec(cameras: usize, users: Vec<SceneUserSpec>) -> CameraSiteSpec {
    CameraSiteSpec {
        at_m: 400.0,
        cameras,
        noise_px: 1.0,
        seed: 3,
        users,
    }
}

fn user(class: &str, path: &[[f64; 3]]) -> SceneUserSpec {
    SceneUserSpec {
        class: class.into(),
        path: path.to_vec(),
    }
}

/// The positions (road metres) of a tick's PSMs.
fn psm_positions(frames: &[Box<MessageFrame>], road: &Road) -> Vec<[f64; 2]> {
    frames
        .iter()
        .filter_map(|f| match &f.value {
            MessageFrameValue::PersonalSafetyMessage(p) => {
                let lat = f64::from(p.position.lat.get()) / 1e7;
                let lon = f64::from(p.position.long.get()) / 1e7;
                Some(road.to_local(LatLon::from_degrees(lat, lon)?))
            }
            _ => None,
        })
        .collect()
}

#[test]
fn the_street_lies_on_the_road_to_the_right_of_its_first_lane_edge() {
    let road = road();
    let p = ScenePlacement::on(&road, 400.0).unwrap();
    let lane1 = road.lanes[0].at(430.0).unwrap().point;
    let lane2 = road.lanes[1].at(430.0).unwrap().point;
    for (street, want) in [([1.75, 30.0], lane1), ([5.25, 30.0], lane2)] {
        let got = p.point(street);
        assert!(
            (got[0] - want[0]).hypot(got[1] - want[1]) < 1e-6,
            "{street:?}: {got:?} vs {want:?}"
        );
    }
    // A worker walking along the street (north in its frame) walks east on this road;
    // one walking across to the right (east in its frame) walks south.
    let mut t = Track {
        id: 1,
        class: RoadUserClass::Pedestrian,
        position: [5.25, 30.0],
        velocity: [0.0, 1.0],
        speed_mps: 1.0,
        heading_deg: Some(0.0),
        position_sigma_m: 0.1,
        position_ellipse: ErrorEllipse::circle(0.1),
        speed_sigma_mps: 0.1,
        heading_sigma_deg: None,
        first_seen_s: 0.0,
        last_seen_s: 0.0,
        hits: 3,
    };
    let east = p.track(&t);
    assert!((east.velocity[0] - 1.0).abs() < 1e-9 && east.velocity[1].abs() < 1e-9);
    assert_eq!(east.heading_deg.map(f64::round), Some(90.0));
    t.velocity = [1.0, 0.0];
    t.heading_deg = Some(90.0);
    let south = p.track(&t);
    assert!((south.velocity[1] + 1.0).abs() < 1e-9 && south.velocity[0].abs() < 1e-9);
    assert_eq!(south.heading_deg.map(f64::round), Some(180.0));
}

#[test]
fn a_worker_walking_into_the_open_lane_goes_out_where_he_is() {
    let road = road();
    // Stands in the closed lane 2, 40 m into the street, then walks 1.4 m/s into lane 1.
    let path = [[1.0, 5.25, 40.0], [3.5, 1.75, 40.0]];
    let mut site = LiveSite::new(
        &spec(1, vec![user("pedestrian", &path)]),
        &road,
        (2, [420.0, 520.0]),
        7,
    )
    .unwrap();
    let placement = ScenePlacement::on(&road, 400.0).unwrap();
    let now = Utc::from_unix_ms(1_700_000_000_000);
    let mut worst: f64 = 0.0;
    for k in 0..40 {
        let t = f64::from(k) * 0.1;
        let frames = site.tick(t, now);
        if k < 2 {
            // Not confirmed before its third hit.
            assert!(frames.is_empty(), "frame {k}");
            continue;
        }
        let got = psm_positions(&frames, &road);
        assert_eq!(got.len(), 1, "frame {k}");
        let (truth, _) = along_path(&path, t);
        let want = placement.point(truth);
        worst = worst.max((got[0][0] - want[0]).hypot(got[0][1] - want[1]));
    }
    // The camera's error and the tracker's lag at the start of the walk.
    eprintln!("worst error {worst} m");
    assert!(worst < 0.35, "worst error {worst} m");
    assert_eq!(site.failed(), 0);
}

#[test]
fn a_truck_hides_the_worker_from_camera_1_and_camera_2_still_tracks_him() {
    let road = road();
    let users = vec![
        user("pedestrian", &[[0.0, 5.25, 40.0]]),
        user("truck", &[[0.0, 1.75, 29.0]]),
    ];
    let now = Utc::from_unix_ms(1_700_000_000_000);
    for (cameras, want) in [(1, 0), (2, 1)] {
        let mut site =
            LiveSite::new(&spec(cameras, users.clone()), &road, (2, [420.0, 520.0]), 7).unwrap();
        let mut last = Vec::new();
        for k in 0..10 {
            last = site.tick(f64::from(k) * 0.1, now);
        }
        assert_eq!(last.len(), want, "{cameras} camera(s)");
        let hidden = site
            .views
            .iter()
            .filter(|v| v.camera == 1 && v.user == 1)
            .all(|v| v.pixels == 0);
        assert!(hidden, "camera 1 saw the worker");
        if cameras == 2 {
            assert!(site
                .views
                .iter()
                .filter(|v| v.camera == 2 && v.user == 1)
                .all(|v| v.pixels > 100));
        }
    }
}

#[test]
fn the_window_labels_are_the_full_frame_labels_cut_out() {
    use crate::roadside_bench::street::{labels, labels_window, masks, window_masks};
    let cam = crate::roadside_bench::street::pole_camera();
    let users: Vec<RoadUser> = [("pedestrian", [5.25, 40.0]), ("truck", [1.75, 31.0])]
        .iter()
        .enumerate()
        .map(|(k, (name, at))| {
            RoadUser::standing(k as u32, RoadUserClass::from_name(name).unwrap(), *at)
        })
        .collect();
    let size = cam.image_size().map(|v| v as u32);
    let full = labels(&cam, &users, 1.0, &mut Prng::new(5));
    let window = labels_window(&cam, &users, 1.0, &mut Prng::new(5));
    assert!(
        window.size[0] * window.size[1] < size[0] * size[1] / 4,
        "{:?}",
        window.size
    );
    assert_eq!(
        full.iter().filter(|&&l| l > 0).count(),
        window.labels.iter().filter(|&&l| l > 0).count()
    );
    assert_eq!(
        masks(&full, size, &users, &[]),
        window_masks(&window, size, &users, &[])
    );
}
