//! The tablet's HTTP server: the embedded app, `GET /events` (Server-Sent Events of the
//! `HmiState`, resumable with `Last-Event-ID`, with a heartbeat: [`events`]), `GET/PUT
//! /api/settings` and `GET/POST /api/pair` ([`mod@write`]), `GET /api/status` (with the mode:
//! `"core"`, or `"bridge"` and the firmware link) and `GET /healthz`. The same in both modes.
//!
//! Reads are open to any client on the unit's network; a settings write needs the session
//! cookie of a paired tablet ([`crate::pairing`]). Before any of this, the accept loop
//! ([`crate::serve`]) has checked the Host ([`crate::host`]) and watches every
//! connection's deadlines ([`crate::conn`]). Every refusal is counted by its reason.

pub mod events;
pub mod write;

use crate::assets;
use crate::counters::group;
use crate::hub::Hub;
use crate::pairing::Pairing;
use crate::settings::{Settings, SettingsFile};
use axum::extract::State;
use axum::http::{header, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use axum::{Json, Router};
use std::sync::Arc;
use std::time::Duration;

/// Largest request body taken (a settings or pairing document), octets.
pub const MAX_BODY: usize = 4096;

/// What the handlers share.
#[derive(Clone)]
pub struct AppState {
    /// The hub.
    pub hub: Arc<Hub>,
    /// Where settings are saved.
    pub settings_file: Arc<SettingsFile>,
    /// The PIN and the paired tablets' sessions.
    pub pairing: Arc<Pairing>,
    /// The event-stream slots.
    pub slots: Arc<events::Slots>,
    /// The open connections.
    pub conns: Arc<crate::conn::Table>,
    /// Heartbeat period.
    pub heartbeat: Duration,
    /// The firmware link in bridge mode; `None` when the daemon runs the core itself.
    pub bridge: Option<Arc<crate::bridge::Status>>,
}

/// The routes.
pub fn router(state: AppState) -> Router {
    Router::new()
        .route("/events", get(events::events))
        .route("/api/settings", get(get_settings).put(write::put_settings))
        .route("/api/pair", get(write::pair_status).post(write::pair))
        .route("/api/status", get(status))
        .route("/healthz", get(|| async { "ok" }))
        .fallback(get(static_file))
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

async fn status(State(app): State<AppState>) -> Json<serde_json::Value> {
    let (gnss_age_ms, receiver) = app.hub.gnss();
    let (maps, zones) = app.hub.stored();
    Json(serde_json::json!({
        "mode": if app.bridge.is_some() { "bridge" } else { "core" },
        "bridge": app.bridge.as_ref().map(|b| b.to_json()),
        "uptime_s": app.hub.uptime_s(),
        "gnss_age_ms": gnss_age_ms,
        "fix_quality": receiver.fix_quality(),
        "gnss": receiver.to_json(),
        "active_maps": maps,
        "active_zones": zones,
        "event_clients": app.slots.len(),
        "open_connections": app.conns.len(),
        "paired_tablets": app.pairing.sessions(),
        "workers": app.hub.workers().map(|(stored, w)| serde_json::json!({
            "stored": stored, "new": w.new, "updated": w.updated,
            "evicted": w.evicted, "expired": w.expired,
        })),
        "counters": app.hub.counters.snapshot(),
    }))
}
