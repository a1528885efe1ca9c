//! Road users from the roadside camera, measured on rendered scenes with known truth:
//! vanishing points and focal length against the renderer's camera, localization error per
//! class at 1 px and 2 px mask noise beside the paper's field table, and the per-frame time
//! of localization and tracking for 20 road users at 1080p.
//!
//! `cargo bench -p hil-sim --bench road_users -- [FRAMES] [--png PATH]`

use std::time::Instant;

use hil_sim::roadside_bench::street::{
    self, coco_json, labels, masks, picture, random_users, CocoFrame, RoadUser, World,
};
use hil_sim::roadside_bench::synthetic_camera::PinholeCamera;
use roadside::camera::Homography;
use roadside::rng::Prng;
use roadside::road_users::calibrate::{calibrate, cross_check, SceneCalibration};
use roadside::road_users::detections::parse_coco;
use roadside::road_users::edgelets::EdgeletSettings;
use roadside::road_users::localize::{Localized, Localizer, Rejections};
use roadside::road_users::pipeline::{paper_text, stats};
use roadside::road_users::tracker::{Observation, RoadUserTracker, TrackerSettings};
use roadside::road_users::vanishing::{angle_between, RansacSettings};
use roadside::road_users::RoadUserClass;

/// Reference points for the homography: lane-marking corners surveyed on the road.
fn reference_homography(cam: &PinholeCamera, rng: &mut Prng, noise_px: f64) -> Homography {
    let mut pairs = Vec::new();
    for y in [20.0, 26.0, 34.0, 45.0] {
        for x in [0.0, 3.5, 7.0, 10.5] {
            if let Some(p) = cam.project([x, y]) {
                let px = [
                    p[0] + noise_px * rng.normal(),
                    p[1] + noise_px * rng.normal(),
                ];
                pairs.push((px, [x, y]));
            }
        }
    }
    Homography::estimate(&pairs).expect("the reference points fix a homography")
}

fn print_calibration(cam: &PinholeCamera, cal: &SceneCalibration, h: &Homography) {
    let f = cam.focal_px();
    let truth = [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]].map(|d| cam.vanishing_point(d));
    let found = [cal.points.road, cal.points.across, cal.points.vertical];
    println!(
        "vanishing points ({} edgelets), angle to the truth seen by the true camera:",
        cal.edgelets
    );
    for (k, name) in ["road", "across", "vertical"].iter().enumerate() {
        let a = angle_between(found[k], truth[k], f, &cal.principal).unwrap_or(f64::NAN);
        println!("  {name:<9} {a:.3}°  ({} inliers)", cal.support[k].inliers);
    }
    println!(
        "focal length {:.1} px, truth {f:.1} px: error {:+.2} %",
        cal.focal_px,
        100.0 * (cal.focal_px / f - 1.0)
    );
    match cross_check(cal, h.matrix(), 0.0) {
        Ok(c) => println!(
            "cross-check with the reference-point homography: road {:.3}°, across {:.3}°, vertical {:.3}°, homography focal {:.1} px",
            c.road_deg,
            c.across_deg,
            c.vertical_deg,
            c.homography_focal_px.unwrap_or(f64::NAN)
        ),
        Err(e) => println!("cross-check failed: {e}"),
    }
}

#[derive(Default)]
struct ClassErrors {
    errors: Vec<f64>,
}

/// The command line: `[FRAMES] [--seed N] [--users N] [--png PATH]`.
struct Options {
    frames: usize,
    seed: u64,
    users: usize,
    png: Option<String>,
}

impl Options {
    fn parse() -> Self {
        let args: Vec<String> = std::env::args()
            .skip(1)
            .filter(|a| a != "--bench")
            .collect();
        let value = |flag: &str| {
            args.iter()
                .position(|a| a == flag)
                .and_then(|i| args.get(i + 1))
        };
        let number =
            |flag: &str, default: u64| value(flag).and_then(|v| v.parse().ok()).unwrap_or(default);
        Self {
            frames: args.first().and_then(|a| a.parse().ok()).unwrap_or(300),
            seed: number("--seed", 0x5eed_0000),
            users: number("--users", 4) as usize,
            png: value("--png").cloned(),
        }
    }
}

fn run_table(
    cam: &PinholeCamera,
    loc: &Localizer,
    world: &World,
    opts: &Options,
    noise_px: f64,
) -> ([ClassErrors; 7], [ClassErrors; 7], Rejections, usize) {
    let mut rng = Prng::new(opts.seed + (noise_px * 10.0) as u64);
    let mut per: [ClassErrors; 7] = Default::default();
    let mut raw_per: [ClassErrors; 7] = Default::default();
    let mut rejected = Rejections::default();
    let mut detections = 0;
    let size = cam.image_size().map(|v| v as u32);
    for k in 0..opts.frames {
        let mut classes = RoadUserClass::ALL.to_vec();
        classes.rotate_left(k % 7);
        let users = random_users(world, cam, &mut rng, opts.users, 40.0, &classes);
        let lab = labels(cam, &users, noise_px, &mut rng);
        let found = masks(&lab, size, &users, &[]);
        let sil: Vec<_> = found.iter().map(|(_, s)| s.clone()).collect();
        detections += sil.len();
        let (boxes, rej) = loc.frame(&sil);
        rejected.add(&rej);
        for b in boxes {
            let truth: &RoadUser = &users[found[b.index].0];
            let c = b.position;
            let raw = b.road_user.centre;
            raw_per[RoadUserClass::ALL
                .iter()
                .position(|x| *x == truth.class)
                .unwrap_or(0)]
            .errors
            .push((raw[0] - truth.centre[0]).hypot(raw[1] - truth.centre[1]) * 100.0);
            let e = (c[0] - truth.centre[0]).hypot(c[1] - truth.centre[1]);
            let slot = RoadUserClass::ALL
                .iter()
                .position(|x| *x == truth.class)
                .unwrap_or(0);
            per[slot].errors.push(e * 100.0);
        }
    }
    (per, raw_per, rejected, detections)
}

fn main() {
    let opts = Options::parse();
    let world = World::work_zone();
    let cam = street::pole_camera();
    let mut rng = Prng::new(7);
    let background = picture(&world, &cam, &[]);
    if let Some(path) = &opts.png {
        background.save(path).expect("write the PNG");
    }
    let grey = image::DynamicImage::ImageRgb8(background).to_luma8();
    let t0 = Instant::now();
    let cal = calibrate(
        &grey,
        &EdgeletSettings::default(),
        &RansacSettings::default(),
    )
    .expect("calibrates");
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    println!("calibration from one 1920x1080 frame: {ms:.0} ms");
    let h = reference_homography(&cam, &mut rng, 0.5);
    print_calibration(&cam, &cal, &h);
    let loc = Localizer::new(&cal, h.matrix()).expect("a ground camera");
    for noise in [1.0, 2.0] {
        let (per, raw, rej, n) = run_table(&cam, &loc, &world, &opts, noise);
        println!(
            "\nmask noise {noise} px, {} frames of {} road users within 40 m, {n} detections, rejected {rej:?}",
            opts.frames, opts.users
        );
        println!("class         n   mean    std    max  (cm)  paper mean / max  footprint centre mean / max");
        for (k, class) in RoadUserClass::ALL.iter().enumerate() {
            let (mean, std, max) = stats(&per[k].errors);
            let paper = paper_text(*class);
            let (rm, _, rx) = stats(&raw[k].errors);
            let name = class.name();
            let count = per[k].errors.len();
            println!("{name:<10} {count:>4} {mean:6.1} {std:6.1} {max:6.1}        {paper:<12}      {rm:.1} / {rx:.1}");
        }
    }
    time_frames(&cam, &loc, &world);
}

/// Per-frame time for 20 road users: the detector's COCO file of the frame (RLE masks)
/// parsed into hulls, every mask's box built and checked, the positions tracked.
fn time_frames(cam: &PinholeCamera, loc: &Localizer, world: &World) {
    let mut rng = Prng::new(99);
    let size = cam.image_size().map(|v| v as u32);
    let mut texts = Vec::new();
    while texts.len() < 50 {
        let users = random_users(world, cam, &mut rng, 20, 60.0, &RoadUserClass::ALL);
        if users.len() < 20 {
            continue;
        }
        let lab = labels(cam, &users, 1.0, &mut rng);
        let frame = CocoFrame {
            file_name: "f.png",
            size,
            labels: &lab,
            users: &users,
            missed: &[],
        };
        texts.push(coco_json(&[frame]).to_string());
    }
    let mut tracker = RoadUserTracker::new(TrackerSettings::default()).expect("settings");
    let rounds = 10;
    let (mut masks_seen, mut boxes) = (0, 0);
    let t0 = Instant::now();
    for r in 0..rounds {
        for (k, text) in texts.iter().enumerate() {
            let frames = parse_coco(text).expect("our own COCO text");
            let sil = &frames[0].silhouettes;
            masks_seen += sil.len();
            let (found, _) = loc.frame(sil);
            boxes += found.len();
            let obs: Vec<Observation> = found.iter().map(Localized::observation).collect();
            let t = (r * texts.len() + k) as f64 * 0.1;
            let _ = tracker.update(t, &obs);
        }
    }
    let n = (rounds * texts.len()) as f64;
    let per = t0.elapsed().as_secs_f64() * 1e3 / n;
    println!(
        "\nper frame, 20 road users at 1920x1080 (COCO RLE masks parsed, boxes built, tracked): {per:.2} ms ({:.1} masks, {:.1} unoccluded boxes a frame)",
        masks_seen as f64 / n,
        boxes as f64 / n
    );
}
