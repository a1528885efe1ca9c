//! The writes: `PUT /api/settings` (a paired tablet only) and pairing, `POST /api/pair`
//! (the PIN in, a session cookie out) and `GET /api/pair` (whether this client is paired).
//!
//! A write must be JSON (`Content-Type: application/json`): a page of another site can
//! send no such request without the browser asking first (CORS preflight, which the
//! daemon does not grant), and the session cookie is `SameSite=Strict` besides. Every
//! refusal is counted under `http_rejected` by its reason.

use super::{AppState, MAX_BODY};
use crate::counters::group;
use crate::pairing::{self, Attempt};
use crate::settings::Settings;
use axum::body::{Body, Bytes};
use axum::extract::{Request, State};
use axum::http::{header, HeaderMap, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde::Deserialize;
use std::time::Instant;

/// A JSON error answer; `close` ends the connection after it (the body was not read).
fn refuse(status: StatusCode, error: &str, close: bool) -> Response {
    let mut r = (status, Json(serde_json::json!({ "error": error }))).into_response();
    if close {
        r.headers_mut().insert(
            header::CONNECTION,
            header::HeaderValue::from_static("close"),
        );
    }
    r
}

/// The request body as JSON octets, or the answer refusing it (counted).
async fn json_body(app: &AppState, headers: &HeaderMap, body: Body) -> Result<Bytes, Response> {
    let counters = &app.hub.counters;
    let is_json = headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.split(';').next())
        .is_some_and(|m| m.trim().eq_ignore_ascii_case("application/json"));
    if !is_json {
        counters.add(group::HTTP_REJECTED, "not JSON");
        let msg = "expected Content-Type: application/json";
        return Err(refuse(StatusCode::UNSUPPORTED_MEDIA_TYPE, msg, true));
    }
    let declared = headers
        .get(header::CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.parse::<u64>().ok());
    if declared.is_some_and(|n| n > MAX_BODY as u64) {
        counters.add(group::HTTP_REJECTED, "body too large");
        return Err(refuse(
            StatusCode::PAYLOAD_TOO_LARGE,
            "body too large",
            true,
        ));
    }
    axum::body::to_bytes(body, MAX_BODY).await.map_err(|e| {
        if over_the_limit(&e) {
            counters.add(group::HTTP_REJECTED, "body too large");
            refuse(StatusCode::PAYLOAD_TOO_LARGE, "body too large", true)
        } else {
            // The client closed or broke the connection before the body ended.
            counters.add(group::HTTP_REJECTED, "body cut off");
            refuse(StatusCode::BAD_REQUEST, "body cut off", true)
        }
    })
}

/// Whether reading a body failed on [`MAX_BODY`] (a body without a `Content-Length`, or
/// longer than it said), not on the connection.
fn over_the_limit(e: &axum::Error) -> bool {
    let mut source: Option<&(dyn std::error::Error + 'static)> = Some(e);
    while let Some(err) = source {
        if err.is::<http_body_util::LengthLimitError>() {
            return true;
        }
        source = err.source();
    }
    false
}

fn cookies(headers: &HeaderMap) -> impl Iterator<Item = &str> {
    headers
        .get_all(header::COOKIE)
        .iter()
        .filter_map(|v| v.to_str().ok())
}

/// `PUT /api/settings`: 401 unless the request carries a paired tablet's session cookie.
pub async fn put_settings(State(app): State<AppState>, req: Request) -> Response {
    let (parts, body) = req.into_parts();
    let counters = &app.hub.counters;
    if !app
        .pairing
        .authorised(cookies(&parts.headers), Instant::now())
    {
        counters.add(group::HTTP_REJECTED, "not paired");
        let mut r = refuse(
            StatusCode::UNAUTHORIZED,
            "pairing required: send the unit's PIN to POST /api/pair",
            true,
        );
        r.headers_mut().insert(
            header::WWW_AUTHENTICATE,
            header::HeaderValue::from_static("Pairing realm=\"obu\""),
        );
        return r;
    }
    let body = match json_body(&app, &parts.headers, body).await {
        Ok(b) => b,
        Err(r) => return r,
    };
    let settings: Settings = match serde_json::from_slice(&body) {
        Ok(s) => s,
        Err(e) => {
            counters.add(group::HTTP_REJECTED, "invalid settings");
            let msg = format!("invalid settings: {e}");
            return refuse(StatusCode::BAD_REQUEST, &msg, false);
        }
    };
    if let Err(e) = settings.validate() {
        counters.add(group::HTTP_REJECTED, "invalid settings");
        return refuse(StatusCode::BAD_REQUEST, &e.to_string(), false);
    }
    if let Err(e) = app.settings_file.save(&settings) {
        let msg = format!("cannot save: {e}");
        return refuse(StatusCode::INTERNAL_SERVER_ERROR, &msg, false);
    }
    app.hub.set_settings(settings);
    Json(settings).into_response()
}

/// The body of `POST /api/pair`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PairRequest {
    pin: String,
}

/// `POST /api/pair` with `{"pin": "..."}`: 200 and the session cookie, 403 for a wrong
/// PIN (with the tries left before a lockout), 429 while locked (with `Retry-After`).
pub async fn pair(State(app): State<AppState>, req: Request) -> Response {
    let (parts, body) = req.into_parts();
    let counters = &app.hub.counters;
    let body = match json_body(&app, &parts.headers, body).await {
        Ok(b) => b,
        Err(r) => return r,
    };
    let Ok(PairRequest { pin }) = serde_json::from_slice(&body) else {
        counters.add(group::HTTP_REJECTED, "pairing: bad request");
        let msg = "expected {\"pin\": \"...\"}";
        return refuse(StatusCode::BAD_REQUEST, msg, false);
    };
    match app.pairing.attempt(&pin, Instant::now()) {
        Attempt::Paired(token) => {
            counters.add(group::PAIRING, "paired");
            let cookie = pairing::set_cookie(&token);
            (
                [(header::SET_COOKIE, cookie)],
                Json(serde_json::json!({ "paired": true })),
            )
                .into_response()
        }
        Attempt::WrongPin { left } => {
            counters.add(group::HTTP_REJECTED, "pairing: wrong PIN");
            let body = serde_json::json!({ "error": "wrong PIN", "tries_left": left });
            (StatusCode::FORBIDDEN, Json(body)).into_response()
        }
        Attempt::Locked(d) => {
            counters.add(group::HTTP_REJECTED, "pairing: locked");
            let secs = d.as_secs() + u64::from(d.subsec_nanos() > 0);
            let body = serde_json::json!({
                "error": "too many wrong PINs: pairing is locked",
                "retry_after_s": secs,
            });
            let retry = [(header::RETRY_AFTER, secs.to_string())];
            (StatusCode::TOO_MANY_REQUESTS, retry, Json(body)).into_response()
        }
        Attempt::Unavailable => {
            let msg = "no random source for a session token";
            refuse(StatusCode::SERVICE_UNAVAILABLE, msg, false)
        }
    }
}

/// `GET /api/pair`: `{"paired": bool, "locked_for_s": n}` for this client.
pub async fn pair_status(State(app): State<AppState>, headers: HeaderMap) -> Response {
    let now = Instant::now();
    let locked = app.pairing.locked_for(now);
    Json(serde_json::json!({
        "paired": app.pairing.authorised(cookies(&headers), now),
        "locked_for_s": locked.as_secs() + u64::from(locked.subsec_nanos() > 0),
    }))
    .into_response()
}
