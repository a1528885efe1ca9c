//! The live WZDx feed against a local HTTP server whose feed changes: conditional requests,
//! the reduced limit and the closed lanes followed, an ended event cancelled, and a
//! malformed, failing, oversized or unreachable feed keeping the last good state.

use roadside::publisher::Publisher;
use roadside::road::Road;
use roadside::service::feed_zones;
use roadside::wzdx_feed::{FeedConfig, FeedPoll, FeedPoller, FeedProblem};
use std::io::{Read, Write};
use std::net::TcpListener;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// What the server answers: status, ETag, body.
type Answer = Arc<Mutex<(u16, String, String)>>;

/// A one-thread HTTP/1.1 server answering every request with the current `Answer` (304 when
/// the request's If-None-Match is its ETag); it records the requests' If-None-Match.
fn server(answer: Answer, seen: Arc<Mutex<Vec<String>>>) -> String {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = listener.local_addr().unwrap();
    std::thread::spawn(move || {
        for stream in listener.incoming() {
            let Ok(mut s) = stream else { continue };
            let mut buf = vec![0u8; 8192];
            let mut got = Vec::new();
            while !got.windows(4).any(|w| w == b"\r\n\r\n") {
                let n = s.read(&mut buf).unwrap_or(0);
                if n == 0 {
                    break;
                }
                got.extend_from_slice(&buf[..n]);
            }
            let text = String::from_utf8_lossy(&got).to_ascii_lowercase();
            let inm = text
                .lines()
                .find_map(|l| l.strip_prefix("if-none-match:"))
                .map(|v| v.trim().to_string())
                .unwrap_or_default();
            seen.lock().unwrap().push(inm.clone());
            let (status, etag, body) = answer.lock().unwrap().clone();
            let reply = if status == 200 && !etag.is_empty() && inm == etag.to_ascii_lowercase() {
                format!("HTTP/1.1 304 Not Modified\r\nETag: {etag}\r\nConnection: close\r\n\r\n")
            } else {
                format!(
                    "HTTP/1.1 {status} X\r\nETag: {etag}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
                    body.len()
                )
            };
            let _ = s.write_all(reply.as_bytes());
        }
    });
    format!("http://{addr}/feed.geojson")
}

fn road() -> Road {
    let text = include_str!("../../tests/data/lane_map_3lanes.geojson");
    roadside::geojson::load_lane_map(text).unwrap()
}

/// The fixture feed with the event's end a day from now, its limit and its right lane
/// status as given.
fn feed(limit_kph: u32, right_closed: bool) -> String {
    let text = include_str!("../../tests/data/wzdx_right_lane_closed.geojson");
    let mut doc: serde_json::Value = serde_json::from_str(text).unwrap();
    let p = &mut doc["features"][0]["properties"];
    p["end_date"] = serde_json::json!("2099-01-01T00:00:00Z");
    p["reduced_speed_limit_kph"] = serde_json::json!(limit_kph);
    p["lanes"][1]["status"] = serde_json::json!(if right_closed { "open" } else { "closed" });
    p["lanes"][2]["status"] = serde_json::json!(if right_closed { "closed" } else { "open" });
    doc.to_string()
}

fn config(url: String, max_bytes: u64) -> FeedConfig {
    FeedConfig {
        url,
        poll_s: 1.0,
        timeout_s: 1.0,
        max_bytes,
        cancel_for_s: 10.0,
    }
}

#[test]
fn a_changing_feed_is_followed_and_a_bad_one_keeps_the_last_good() {
    let answer: Answer = Arc::new(Mutex::new((200, "\"a\"".into(), feed(40, true))));
    let seen = Arc::new(Mutex::new(Vec::new()));
    let url = server(Arc::clone(&answer), Arc::clone(&seen));
    let mut poller = FeedPoller::new(&config(url, 1 << 20));
    let road = road();
    let mut publisher = Publisher::default();
    let now = roadside::clock::unix_ms_now();
    let publish = |p: &mut Publisher, text: &str| {
        let zones = feed_zones(&road, text).unwrap();
        p.update(&road, &zones, now, now + 3_600_000).unwrap()
    };

    let FeedPoll::Changed(first) = poller.poll() else {
        panic!("first poll")
    };
    let first_tims = publish(&mut publisher, &first);
    assert_eq!(first_tims.messages.len(), 2);
    // The same ETag: a conditional request, answered 304.
    assert_eq!(poller.poll(), FeedPoll::Unchanged);
    assert_eq!(seen.lock().unwrap().last().unwrap(), "\"a\"");

    // The reduced limit changes: a new TIM.
    *answer.lock().unwrap() = (200, "\"b\"".into(), feed(30, true));
    let FeedPoll::Changed(slower) = poller.poll() else {
        panic!("limit change")
    };
    let u = publish(&mut publisher, &slower);
    assert!(u.changed && u.cancels.is_empty());
    assert_ne!(
        u.messages[1].message.frame(),
        first_tims.messages[1].message.frame()
    );

    // The closure moves to the other lane: a new TIM again.
    *answer.lock().unwrap() = (200, "\"c\"".into(), feed(30, false));
    let FeedPoll::Changed(moved) = poller.poll() else {
        panic!("lane change")
    };
    let lanes = |t: &str| feed_zones(&road, t).unwrap()[0].zone.closed_lanes.clone();
    assert_eq!(lanes(&moved).len(), 1);
    assert_ne!(lanes(&moved), lanes(&first));
    assert!(publish(&mut publisher, &moved).changed);

    // A server error, a body that is no feed, an oversized body: the last good stands.
    *answer.lock().unwrap() = (503, String::new(), "busy".into());
    assert_eq!(poller.poll(), FeedPoll::Failed(FeedProblem::Status(503)));
    *answer.lock().unwrap() = (200, "\"d\"".into(), "<html>oops</html>".into());
    let FeedPoll::Changed(junk) = poller.poll() else {
        panic!("junk")
    };
    assert!(feed_zones(&road, &junk).is_err());
    poller.refused();
    // Refused, it is fetched whole again (no validator sent) and refused again.
    let FeedPoll::Changed(again) = poller.poll() else {
        panic!("junk again")
    };
    assert_eq!(again, junk);
    assert_eq!(seen.lock().unwrap().last().unwrap(), "");
    poller.refused();

    // The event ends: it leaves the feed, and its cancel is made.
    let mut ended: serde_json::Value = serde_json::from_str(&moved).unwrap();
    ended["features"] = serde_json::json!([]);
    *answer.lock().unwrap() = (200, "\"e\"".into(), ended.to_string());
    let FeedPoll::Changed(gone) = poller.poll() else {
        panic!("ended")
    };
    let u = publish(&mut publisher, &gone);
    assert_eq!((u.messages.len(), u.cancels.len()), (1, 1));

    let counts = &poller.counts;
    assert_eq!(counts.get("changed"), Some(&4));
    assert_eq!(counts.get("unchanged"), Some(&1));
    assert_eq!(counts.get("http_status"), Some(&1));
    assert_eq!(counts.get("malformed"), Some(&2));
}

#[test]
fn an_oversized_or_unreachable_feed_is_a_clear_problem() {
    let answer: Answer = Arc::new(Mutex::new((200, String::new(), "x".repeat(5000))));
    let url = server(answer, Arc::new(Mutex::new(Vec::new())));
    let mut poller = FeedPoller::new(&config(url, 1000));
    assert_eq!(poller.poll(), FeedPoll::Failed(FeedProblem::TooLarge(1000)));
    // A port nothing listens on.
    let free = TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap();
    let mut poller = FeedPoller::new(&config(format!("http://{free}/feed"), 1000));
    let FeedPoll::Failed(p) = poller.poll() else {
        panic!("unreachable")
    };
    assert_eq!(p.reason(), "unreachable", "{p}");
    // A server that accepts and never answers: the timeout.
    let silent = TcpListener::bind("127.0.0.1:0").unwrap();
    let addr = silent.local_addr().unwrap();
    std::thread::spawn(move || {
        let _held: Vec<_> = silent.incoming().take(1).collect();
        std::thread::sleep(Duration::from_secs(5));
    });
    let mut poller = FeedPoller::new(&config(format!("http://{addr}/feed"), 1000));
    assert_eq!(poller.poll(), FeedPoll::Failed(FeedProblem::Timeout));
}
