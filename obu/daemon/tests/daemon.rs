//! The real `obu` binary, driven through its real inputs: UDP V2X datagrams, NMEA over UDP,
//! and HTTP (static app, SSE with resume, settings that survive a restart, status, hostile
//! requests), and SIGTERM.

mod common;

use common::{
    http, open_events, pair, read_events, request, run_of, status, temp_dir, vector, Daemon,
};
use j2735::msg::personal_safety_message::{PersonalDeviceUserType, PersonalSafetyMessage};
use std::io::{Read, Write};
use std::net::{TcpStream, UdpSocket};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The pairing PIN of the tests' configuration.
const PIN: &str = "a1b2c3";

/// Starts the daemon with the configuration file `config`.
fn start(config: &Path) -> Daemon {
    Daemon::start(["--config".as_ref(), config.as_os_str()])
}

fn write_config(dir: &Path, gnss_port: u16) -> PathBuf {
    let path = dir.join("obu.toml");
    let text = format!(
        "[v2x]\nbind = \"127.0.0.1:0\"\n[gnss]\nsource = \"nmea-udp\"\naddress = \"127.0.0.1:{gnss_port}\"\n\
         [http]\nbind = \"127.0.0.1:0\"\nsettings_file = \"{}\"\nheartbeat_ms = 200\nrequest_timeout_ms = 1000\npin = \"{PIN}\"\n\
         [security]\nrequire_signed = false\n",
        dir.join("settings.json").display()
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn nmea(body: &str) -> String {
    let sum = body.bytes().fold(0u8, |a, b| a ^ b);
    format!("${body}*{sum:02X}\r\n")
}

/// NMEA of one epoch at the MAP vector's reference point area.
fn epoch(t: u32) -> String {
    let time = format!("1200{:02}.{:02}", t / 10, (t % 10) * 10);
    nmea(&format!(
        "GPGGA,{time},4207.4074,N,08345.9259,W,4,12,0.6,200.0,M,,M,,"
    )) + &nmea(&format!(
        "GPRMC,{time},A,4207.4074,N,08345.9259,W,020.0,090.0,020124,,"
    ))
}

#[test]
fn serves_the_app_health_and_validated_settings_that_survive_a_restart() {
    let dir = temp_dir("settings");
    let cfg = write_config(&dir, 0);
    let d = start(&cfg);
    assert_eq!(http(&d.http, "GET", "/healthz", ""), (200, "ok".into()));
    let (code, page) = http(&d.http, "GET", "/", "");
    assert_eq!(code, 200);
    assert!(
        page.contains("<html") || page.contains("<!DOCTYPE"),
        "the tablet app is served"
    );
    assert_eq!(http(&d.http, "GET", "/no-such-file", "").0, 404);
    let good = r#"{"warning_distance_m":250.0,"lead_time_s":12.0,"sound":false,"units":"mph","theme":"night"}"#;
    let (code, body) = http(&d.http, "PUT", "/api/settings", good);
    assert_eq!(code, 401, "a write needs pairing: {body}");
    let cookie = pair(&d.http, PIN);
    let put = |body: &str| {
        let (code, _, text) = request(&d.http, "PUT", "/api/settings", &[&cookie], body);
        (code, text)
    };
    let (code, body) = put(
        r#"{"warning_distance_m":5,"lead_time_s":9,"sound":true,"units":"mph","theme":"night"}"#,
    );
    assert_eq!(code, 400);
    assert!(body.contains("warning_distance_m"), "{body}");
    assert_eq!(put("{not json").0, 400);
    assert_eq!(put(good).0, 200);
    assert!(d.stop().success(), "SIGTERM is a clean exit");
    let d = start(&cfg);
    assert_eq!(
        request(&d.http, "PUT", "/api/settings", &[&cookie], good).0,
        200,
        "still paired after a restart"
    );
    let (code, body) = http(&d.http, "GET", "/api/settings", "");
    assert_eq!(code, 200);
    let saved: serde_json::Value = serde_json::from_str(&body).unwrap();
    let wanted: serde_json::Value = serde_json::from_str(good).unwrap();
    assert_eq!(saved, wanted);
    assert!(d.stop().success());
}

#[test]
fn counts_v2x_messages_and_drops_by_reason() {
    let dir = temp_dir("v2x");
    let d = start(&write_config(&dir, 0));
    let udp = UdpSocket::bind("127.0.0.1:0").unwrap();
    let map = vector("map_work_zone");
    let tim = vector("tim_work_zone_left_lane_closed");
    udp.send_to(&map, d.v2x()).unwrap();
    assert!(
        (128..256).contains(&tim.len()),
        "the long-form length below fits this TIM"
    );
    let mut wrapped = vec![0x03, 0x80, 0x81, tim.len() as u8];
    wrapped.extend_from_slice(&tim);
    udp.send_to(&wrapped, d.v2x()).unwrap();
    udp.send_to(&map[..map.len() / 2], d.v2x()).unwrap();
    udp.send_to(b"Version=0.7\nType=MAP\n", d.v2x()).unwrap();
    udp.send_to(&vec![0u8; 9000], d.v2x()).unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let s = status(&d.http);
    assert_eq!(s["mode"], "core", "{s}");
    assert!(s["bridge"].is_null(), "{s}");
    let c = &s["counters"];
    assert_eq!(c["messages"]["MAP"], 1, "{s}");
    assert_eq!(c["messages"]["TIM"], 1, "{s}");
    assert_eq!(
        c["decode_errors"]
            .as_object()
            .map(|m| m.values().filter_map(|v| v.as_u64()).sum::<u64>()),
        Some(1),
        "{s}"
    );
    assert_eq!(c["decode_errors"]["unexpected end"], 1, "the half MAP: {s}");
    assert_eq!(
        c["envelope_errors"],
        serde_json::json!({"RSU text: missing key": 1}),
        "the record without PSID and Payload: {s}"
    );
    assert_eq!(c["v2x_dropped"]["datagram too large"], 1, "{s}");
    assert!(s["active_maps"].as_u64().unwrap() >= 1, "{s}");
    assert!(s["active_zones"].as_u64().unwrap() >= 1, "{s}");
    assert_eq!(s["workers"]["stored"], 0, "{s}");
    // A road worker's PSM, twice (the second a move), and a pedestrian's.
    udp.send_to(&worker_psm(5, 0), d.v2x()).unwrap();
    udp.send_to(&worker_psm(5, 100), d.v2x()).unwrap();
    let pedestrian = psm_bytes(6, 0, PersonalDeviceUserType::APEDESTRIAN);
    udp.send_to(&pedestrian, d.v2x()).unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let s = status(&d.http);
    assert_eq!(
        s["workers"],
        serde_json::json!({"stored": 1, "new": 1, "updated": 1, "evicted": 0, "expired": 0}),
        "{s}"
    );
    assert_eq!(s["counters"]["messages"]["PSM"], 2, "{s}");
    assert_eq!(
        s["counters"]["ingest_errors"]["PSM: not a road worker"], 1,
        "{s}"
    );
}

/// A road worker's PSM (id `[0, 0, 0, id]`, 0.5 m accuracy) at `secMark` `sec_mark`.
fn worker_psm(id: u8, sec_mark: u16) -> Vec<u8> {
    psm_bytes(id, sec_mark, PersonalDeviceUserType::APUBLICSAFETYWORKER)
}

fn psm_bytes(id: u8, sec_mark: u16, kind: PersonalDeviceUserType) -> Vec<u8> {
    use j2735::msg::common::{DSecond, Latitude, Longitude, SemiMajorAxisAccuracy, TemporaryID};
    let mut psm = <PersonalSafetyMessage as j2735::uper::Placeholder>::placeholder();
    psm.basic_type = kind;
    psm.id = TemporaryID([0, 0, 0, id]);
    psm.sec_mark = DSecond::new(sec_mark).unwrap();
    psm.position.lat = Latitude::new(397_392_000).unwrap();
    psm.position.long = Longitude::new(-1_049_903_000).unwrap();
    psm.accuracy.semi_major = SemiMajorAxisAccuracy::new(10).unwrap();
    let mut buf = [0u8; 256];
    let n = j2735::frame::encode_message(&psm, &mut buf).unwrap();
    buf[..n].to_vec()
}

#[test]
fn fixes_become_numbered_events_and_a_client_resumes_where_it_left() {
    let dir = temp_dir("sse");
    let d = start(&write_config(&dir, 0));
    let gnss_port = d.gnss();
    let gps = UdpSocket::bind("127.0.0.1:0").unwrap();
    let mut events = open_events(&d.http, None);
    for t in 0..5 {
        gps.send_to(epoch(t).as_bytes(), gnss_port).unwrap();
        std::thread::sleep(Duration::from_millis(30));
    }
    let got = read_events(&mut events, 5);
    assert_eq!(got.len(), 5, "one state per fix");
    assert!(
        got.windows(2).all(|w| w[1].0 == w[0].0 + 1),
        "consecutive ids: {:?}",
        got.iter().map(|e| e.0).collect::<Vec<_>>()
    );
    let state = &got[4].1["state"];
    assert_eq!(state["gnss_ok"], true);
    assert!((state["speed_mps"].as_f64().unwrap() - 20.0 * 0.514444).abs() < 0.01);
    let last_seen = got[2].0;
    drop(events);
    let run = run_of(&d.http);
    let mut resumed = open_events(&d.http, Some(&format!("{run}-{last_seen}")));
    let again = read_events(&mut resumed, 2);
    assert_eq!(
        again.iter().map(|e| e.0).collect::<Vec<_>>(),
        vec![last_seen + 1, last_seen + 2]
    );
    // An id of an earlier run (its numbers started again at 1 here): served as a new
    // client, with the newest state first and then every new one.
    let mut other = open_events(&d.http, Some(&format!("{}-{}", run - 1, 1000)));
    let newest = read_events(&mut other, 1)[0].0;
    assert!(
        (5..1000).contains(&newest),
        "the newest state, not a replay: {newest}"
    );
    gps.send_to(epoch(5).as_bytes(), gnss_port).unwrap();
    assert_eq!(
        read_events(&mut other, 1)[0].0,
        newest + 1,
        "live after the newest"
    );
    gps.send_to(b"$GPGGA,garbage*00\r\n", gnss_port).unwrap();
    std::thread::sleep(Duration::from_millis(200));
    assert!(status(&d.http)["counters"]["nmea_errors"]
        .as_object()
        .is_some_and(|m| !m.is_empty()));
}

#[test]
fn gnss_loss_is_published_within_a_second() {
    let dir = temp_dir("stale");
    let d = start(&write_config(&dir, 0));
    let gnss_port = d.gnss();
    let gps = UdpSocket::bind("127.0.0.1:0").unwrap();
    let mut events = open_events(&d.http, None);
    gps.send_to(epoch(0).as_bytes(), gnss_port).unwrap();
    // Skip states from before the fix (the daemon publishes "no GNSS" at start).
    let live = (0..20)
        .map(|_| read_events(&mut events, 1))
        .find(|e| e.first().is_some_and(|e| e.1["state"]["gnss_ok"] == true));
    assert!(live.is_some(), "the fix is published");
    let t0 = Instant::now();
    let later = read_events(&mut events, 1);
    assert_eq!(later.len(), 1, "the dropout is published");
    assert_eq!(later[0].1["state"]["gnss_ok"], false);
    assert!(
        t0.elapsed() < Duration::from_millis(1600),
        "within the 1 s timeout plus one poll"
    );
}

#[test]
fn hostile_http_is_refused_and_counted() {
    let dir = temp_dir("hostile");
    let d = start(&write_config(&dir, 0));
    // Oversized headers.
    let mut s = TcpStream::connect(&d.http).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let big = "a".repeat(64 * 1024);
    let _ = write!(
        s,
        "GET / HTTP/1.1\r\nHost: {}\r\nX-Big: {big}\r\n\r\n",
        d.http
    );
    let mut out = String::new();
    let _ = s.read_to_string(&mut out);
    assert!(
        !out.starts_with("HTTP/1.1 200"),
        "oversized request not served"
    );
    // A request that never finishes is cut off by the timeout.
    let mut slow = TcpStream::connect(&d.http).unwrap();
    slow.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    write!(slow, "GET / HTTP/1.1\r\nHost: {}\r\n", d.http).unwrap();
    let t0 = Instant::now();
    let mut buf = [0u8; 64];
    let _ = slow.read(&mut buf);
    assert!(
        t0.elapsed() < Duration::from_secs(4),
        "slow request closed by the 1 s timeout"
    );
    // A settings body over the limit.
    let cookie = pair(&d.http, PIN);
    let big = "x".repeat(10_000);
    let (code, _, _) = request(&d.http, "PUT", "/api/settings", &[&cookie], &big);
    assert!(code == 413 || code == 400, "got {code}");
    assert_eq!(
        http(&d.http, "GET", "/healthz", ""),
        (200, "ok".into()),
        "still serving"
    );
    // A paired client that closes in the middle of its body: cut off, not too large.
    let mut cut = TcpStream::connect(&d.http).unwrap();
    cut.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    write!(
        cut,
        "PUT /api/settings HTTP/1.1\r\nHost: {}\r\n{cookie}\r\nContent-Type: application/json\r\nContent-Length: 100\r\n\r\n{{\"warn",
        d.http
    )
    .unwrap();
    cut.shutdown(std::net::Shutdown::Write).unwrap();
    let mut answer = String::new();
    let _ = cut.read_to_string(&mut answer);
    let s = status(&d.http);
    let rejected = &s["counters"]["http_rejected"];
    assert_eq!(
        rejected["body too large"], 1,
        "the 10,000-octet body only: {s}"
    );
    assert_eq!(rejected["body cut off"], 1, "{s}");
}

#[test]
fn a_new_zone_is_published_at_once_without_waiting_for_a_fix() {
    let dir = temp_dir("zone-now");
    let d = start(&write_config(&dir, 0));
    let mut events = open_events(&d.http, None);
    let udp = UdpSocket::bind("127.0.0.1:0").unwrap();
    udp.send_to(&vector("map_work_zone"), d.v2x()).unwrap();
    udp.send_to(&vector("tim_work_zone_left_lane_closed"), d.v2x())
        .unwrap();
    // No GNSS at all: the states come from the messages alone. Besides them there is
    // the "no GNSS" state of the start, which may come before or after the MAP's.
    let got = read_events(&mut events, 3);
    let counts: Vec<(u64, u64)> = got
        .iter()
        .map(|e| {
            (
                e.1["state"]["maps"].as_u64().unwrap(),
                e.1["state"]["zones"].as_u64().unwrap(),
            )
        })
        .collect();
    assert!(counts.contains(&(1, 0)), "a state for the MAP: {counts:?}");
    // The TIM has two data frames (closure, speed limit): two zones.
    assert_eq!(
        counts.last(),
        Some(&(1, 2)),
        "a state for the TIM: {counts:?}"
    );
    // The same TIM again changes nothing: no state.
    udp.send_to(&vector("tim_work_zone_left_lane_closed"), d.v2x())
        .unwrap();
    let last = got.last().unwrap().0;
    let mut quiet = open_events(&d.http, Some(&format!("{}-{last}", run_of(&d.http))));
    quiet
        .get_mut()
        .set_read_timeout(Some(Duration::from_millis(700)))
        .unwrap();
    assert!(
        read_events(&mut quiet, 1).is_empty(),
        "a repeat is not news"
    );
}
