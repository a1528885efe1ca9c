//! The bench's WZDx feed: a scenario's feed versions as WZDx 4.2 documents on its road,
//! served over HTTP on a loopback port (the version by the time since the drive started,
//! with an `ETag` so the roadside's conditional requests get a 304).

use roadside::clock::Utc;
use roadside::road::Road;
use serde::Deserialize;
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// One version of the feed (`[[rsu_deployment.feed]]`).
#[derive(Debug, Clone, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct FeedVersion {
    /// From this many seconds into the drive.
    pub at_s: f64,
    /// The event's closed lanes (map lane ids).
    #[serde(default)]
    pub closed_lanes: Vec<u8>,
    /// Event start, metres along the road's first lane.
    #[serde(default)]
    pub start_m: f64,
    /// Event end, metres.
    #[serde(default)]
    pub end_m: f64,
    /// Reduced speed limit, km/h.
    pub limit_kmh: Option<u16>,
    /// The event is no longer in the feed (an empty feed).
    #[serde(default)]
    pub removed: bool,
    /// The feed answers text that is no WZDx document.
    #[serde(default)]
    pub malformed: bool,
}

/// RFC 3339 of Unix ms (whole seconds, UTC).
fn rfc3339(unix_ms: u64) -> String {
    Utc::from_unix_ms(unix_ms).rfc3339_seconds()
}

/// The WZDx document of `v` on `road`: one work-zone event along the forward lanes from
/// `start_m` to `end_m`, started an hour before `now_ms` and ending a day after.
///
/// # Errors
///
/// The stations are off the road.
pub fn document(road: &Road, v: &FeedVersion, now_ms: u64) -> Result<String, String> {
    if v.malformed {
        return Ok("<html>502 Bad Gateway</html>".into());
    }
    let first = road.lanes.first().ok_or("the road has no lane")?;
    let heading = first
        .at(0.0)
        .ok_or("the first lane has no geometry")?
        .bearing_deg;
    // The lanes running the first lane's way (the event's carriageway).
    let forward: Vec<_> = road
        .lanes
        .iter()
        .filter(|l| {
            l.at(0.0).is_some_and(|on| {
                let d = (on.bearing_deg - heading).rem_euclid(360.0);
                d.min(360.0 - d) < 45.0
            })
        })
        .collect();
    let mut path = Vec::new();
    let steps = 8;
    for k in 0..=steps {
        let station = v.start_m + (v.end_m - v.start_m) * f64::from(k) / f64::from(steps);
        let on = first
            .at(station)
            .ok_or(format!("station {station} m is off the road"))?;
        let p = road.to_wgs84(on.point).ok_or("a point off the globe")?;
        path.push(json!([p.lon_deg(), p.lat_deg()]));
    }
    let lanes: Vec<Value> = forward
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let status = if v.closed_lanes.contains(&l.id) {
                "closed"
            } else {
                "open"
            };
            json!({"order": i + 1, "type": "general", "status": status})
        })
        .collect();
    let mut properties = json!({
        "core_details": {
            "event_type": "work-zone",
            "data_source_id": "bench",
            "road_names": ["Bench Road"],
            "direction": "eastbound",
            "description": "bench work zone"
        },
        "start_date": rfc3339(now_ms - 3_600_000),
        "end_date": rfc3339(now_ms + 86_400_000),
        "is_start_date_verified": true,
        "is_end_date_verified": true,
        "is_start_position_verified": true,
        "is_end_position_verified": true,
        "location_method": "channel-device-method",
        "vehicle_impact": "some-lanes-closed",
        "lanes": lanes
    });
    if let Some(kph) = v.limit_kmh {
        properties["reduced_speed_limit_kph"] = json!(kph);
    }
    let features = if v.removed {
        json!([])
    } else {
        json!([{
            "id": "bench-event-1",
            "type": "Feature",
            "properties": properties,
            "geometry": {"type": "LineString", "coordinates": path}
        }])
    };
    let doc = json!({
        "feed_info": {
            "update_date": rfc3339(now_ms),
            "publisher": "hil-sim bench",
            "version": "4.2",
            "data_sources": [{"data_source_id": "bench", "organization_name": "hil-sim"}]
        },
        "type": "FeatureCollection",
        "features": features
    });
    let text = doc.to_string();
    // The roadside must read the closure the scenario means: checked with its own parser.
    if !v.removed {
        let zones =
            roadside::geojson::work_zones_from_wzdx(road, &text).map_err(|e| e.to_string())?;
        let mut want = v.closed_lanes.clone();
        want.sort_unstable();
        let got = zones.first().map(|z| {
            let mut l = z.closed_lanes.clone();
            l.sort_unstable();
            l
        });
        if got.as_ref() != Some(&want) {
            return Err(format!(
                "the bench's WZDx event closes {got:?}, not {want:?}"
            ));
        }
    }
    Ok(text)
}

/// The feed server.
#[derive(Debug)]
pub struct FeedServer {
    /// Its address.
    pub addr: SocketAddr,
    /// Requests answered.
    pub requests: Arc<AtomicU64>,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl FeedServer {
    /// Serves `docs` (one per version, from `at_s[i]` seconds after `t0`).
    ///
    /// # Errors
    ///
    /// The listening socket.
    pub fn start(docs: Vec<(f64, String)>, t0: Instant) -> Result<Self, String> {
        let listener = TcpListener::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
        listener.set_nonblocking(true).map_err(|e| e.to_string())?;
        let addr = listener.local_addr().map_err(|e| e.to_string())?;
        let stop = Arc::new(AtomicBool::new(false));
        let requests = Arc::new(AtomicU64::new(0));
        let (flag, count) = (Arc::clone(&stop), Arc::clone(&requests));
        let thread = std::thread::spawn(move || {
            while !flag.load(Ordering::Relaxed) {
                match listener.accept() {
                    Ok((stream, _)) => {
                        let t = t0.elapsed().as_secs_f64();
                        let current = docs.iter().rposition(|(at, _)| *at <= t).unwrap_or(0);
                        let _ = answer(stream, current, &docs[current].1);
                        count.fetch_add(1, Ordering::Relaxed);
                    }
                    Err(_) => std::thread::sleep(Duration::from_millis(10)),
                }
            }
        });
        Ok(Self {
            addr,
            requests,
            stop,
            thread: Some(thread),
        })
    }

    /// The feed's URL.
    pub fn url(&self) -> String {
        format!("http://{}/wzdx/feed.geojson", self.addr)
    }
}

impl Drop for FeedServer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// Answers one HTTP/1.1 request: 304 when its `If-None-Match` is the version's ETag.
fn answer(mut stream: TcpStream, version: usize, body: &str) -> std::io::Result<()> {
    stream.set_nonblocking(false)?;
    stream.set_read_timeout(Some(Duration::from_secs(2)))?;
    let mut request = Vec::new();
    let mut buf = [0u8; 1024];
    while !request.windows(4).any(|w| w == b"\r\n\r\n") && request.len() < 16 * 1024 {
        let n = stream.read(&mut buf)?;
        if n == 0 {
            break;
        }
        request.extend_from_slice(&buf[..n]);
    }
    let etag = format!("\"v{version}\"");
    let text = String::from_utf8_lossy(&request).to_ascii_lowercase();
    let unchanged = text
        .lines()
        .any(|l| l.starts_with("if-none-match:") && l.contains(&etag.to_ascii_lowercase()));
    let reply = if unchanged {
        format!("HTTP/1.1 304 Not Modified\r\nETag: {etag}\r\nConnection: close\r\n\r\n")
    } else {
        format!(
            "HTTP/1.1 200 OK\r\nContent-Type: application/geo+json\r\nETag: {etag}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
            body.len()
        )
    };
    stream.write_all(reply.as_bytes())
}
