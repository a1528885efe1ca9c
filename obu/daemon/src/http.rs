//! The tablet's HTTP server: the embedded app, `GET /events` (Server-Sent Events of the
//! `HmiState`, resumable with `Last-Event-ID`, with a heartbeat), `GET/PUT /api/settings`,
//! `GET /api/status` (with the mode: `"core"`, or `"bridge"` and the firmware link) and
//! `GET /healthz`. The same in both modes.
//!
//! Robustness: headers must arrive within the request timeout and fit 16 KiB, a settings body
//! 4 KiB; event-stream clients are limited, and one that falls behind by more than the event
//! ring is dropped (it resumes from the ring when it reconnects). Every refusal is counted.

use crate::assets;
use crate::counters::group;
use crate::hub::Hub;
use crate::settings::{Settings, SettingsFile};
use axum::extract::{DefaultBodyLimit, State};
use axum::http::{header, HeaderMap, StatusCode, Uri};
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use futures_util::stream::{self, Stream, StreamExt};
use std::convert::Infallible;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::broadcast::error::RecvError;

/// What the handlers share.
#[derive(Clone)]
pub struct AppState {
    /// The hub.
    pub hub: Arc<Hub>,
    /// Where settings are saved.
    pub settings_file: Arc<SettingsFile>,
    /// Event-stream clients connected now.
    pub clients: Arc<AtomicUsize>,
    /// Most event-stream clients.
    pub max_clients: usize,
    /// Heartbeat period.
    pub heartbeat: Duration,
    /// The firmware link in bridge mode; `None` when the daemon runs the core itself.
    pub bridge: Option<Arc<crate::bridge::Status>>,
}

/// The routes.
pub fn router(state: AppState) -> Router {
    Router::new()
        .route("/events", get(events))
        .route("/api/settings", get(get_settings).put(put_settings))
        .route("/api/status", get(status))
        .route("/healthz", get(|| async { "ok" }))
        .fallback(get(static_file))
        .layer(DefaultBodyLimit::max(4096))
        .with_state(state)
}

async fn static_file(uri: Uri, State(app): State<AppState>) -> Response {
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    match assets::find(path) {
        Some((mime, body)) => (
            [
                (header::CONTENT_TYPE, mime),
                (header::CACHE_CONTROL, "no-cache"),
            ],
            body,
        )
            .into_response(),
        None => {
            app.hub.counters.add(group::HTTP_REJECTED, "not found");
            (StatusCode::NOT_FOUND, "not found").into_response()
        }
    }
}

async fn get_settings(State(app): State<AppState>) -> Json<Settings> {
    Json(app.hub.settings())
}

async fn put_settings(State(app): State<AppState>, body: axum::body::Bytes) -> Response {
    let bad = |msg: String| {
        (
            StatusCode::BAD_REQUEST,
            Json(serde_json::json!({ "error": msg })),
        )
            .into_response()
    };
    let settings: Settings = match serde_json::from_slice(&body) {
        Ok(s) => s,
        Err(e) => {
            app.hub
                .counters
                .add(group::HTTP_REJECTED, "invalid settings");
            return bad(format!("invalid settings: {e}"));
        }
    };
    if let Err(e) = settings.validate() {
        app.hub
            .counters
            .add(group::HTTP_REJECTED, "invalid settings");
        return bad(e);
    }
    if let Err(e) = app.settings_file.save(&settings) {
        return (
            StatusCode::INTERNAL_SERVER_ERROR,
            Json(serde_json::json!({ "error": format!("cannot save: {e}") })),
        )
            .into_response();
    }
    app.hub.set_settings(settings);
    Json(settings).into_response()
}

async fn status(State(app): State<AppState>) -> Json<serde_json::Value> {
    let (gnss_age_ms, fix_quality) = app.hub.gnss();
    let (maps, zones) = app.hub.stored();
    Json(serde_json::json!({
        "mode": if app.bridge.is_some() { "bridge" } else { "core" },
        "bridge": app.bridge.as_ref().map(|b| b.to_json()),
        "uptime_s": app.hub.uptime_s(),
        "gnss_age_ms": gnss_age_ms,
        "fix_quality": fix_quality,
        "active_maps": maps,
        "active_zones": zones,
        "event_clients": app.clients.load(Ordering::Relaxed),
        "counters": app.hub.counters.snapshot(),
    }))
}

/// Holds one event-stream slot; frees it when the stream ends.
struct ClientSlot(Arc<AtomicUsize>);

impl Drop for ClientSlot {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::Relaxed);
    }
}

async fn events(State(app): State<AppState>, headers: HeaderMap) -> Response {
    if app.clients.fetch_add(1, Ordering::Relaxed) >= app.max_clients {
        app.clients.fetch_sub(1, Ordering::Relaxed);
        app.hub
            .counters
            .add(group::HTTP_REJECTED, "too many event clients");
        return (StatusCode::SERVICE_UNAVAILABLE, "too many event clients").into_response();
    }
    app.hub.counters.add(group::SSE_CLIENTS, "connected");
    let slot = ClientSlot(app.clients.clone());
    let last_id = headers
        .get("last-event-id")
        .and_then(|v| v.to_str().ok())
        .and_then(|v| {
            let seq = app.hub.resume_seq(v);
            if seq.is_none() {
                app.hub
                    .counters
                    .add(group::SSE_CLIENTS, "resume id of another run");
            }
            seq
        });
    let heartbeat = app.heartbeat;
    Sse::new(event_stream(app, last_id, slot))
        .keep_alive(KeepAlive::new().interval(heartbeat).text("hb"))
        .into_response()
}

/// The replay after `last_id` (or the newest state for a new client), then live events.
fn event_stream(
    app: AppState,
    last_id: Option<u64>,
    slot: ClientSlot,
) -> impl Stream<Item = Result<SseEvent, Infallible>> {
    let rx = app.hub.subscribe();
    let backlog = match last_id {
        Some(id) => app.hub.since(id),
        None => app.hub.latest().into_iter().collect(),
    };
    let sent = backlog.last().map_or(last_id.unwrap_or(0), |e| e.seq);
    let first: Vec<Result<SseEvent, Infallible>> = backlog
        .iter()
        .map(|e| Ok(to_sse(&app.hub, e).retry(Duration::from_millis(1000))))
        .collect();
    let first = stream::iter(first);
    let hub = app.hub.clone();
    let live = stream::unfold((rx, slot, sent), move |(mut rx, slot, sent)| {
        let hub = hub.clone();
        async move {
            loop {
                match rx.recv().await {
                    Ok(e) if e.seq <= sent => continue,
                    Ok(e) => {
                        let seq = e.seq;
                        return Some((Ok(to_sse(&hub, &e)), (rx, slot, seq)));
                    }
                    Err(RecvError::Lagged(_)) => {
                        hub.counters.add(group::SSE_CLIENTS, "dropped: too slow");
                        return None;
                    }
                    Err(RecvError::Closed) => return None,
                }
            }
        }
    });
    first.chain(live)
}

fn to_sse(hub: &crate::hub::Hub, e: &crate::hub::Event) -> SseEvent {
    SseEvent::default()
        .event("state")
        .id(hub.event_id(e.seq))
        .data(&e.json)
}
