//! The console's web server: the participant's page and its API, the researcher's page and
//! theirs (docs/studies.md, "The page's API"), on axum over tokio. Each request is served
//! on a blocking thread (the adapter and the database are synchronous) and answered only
//! after what it records is stored.

use crate::participant::{Action, Conduct, ConductError, perform};
use axum::Router;
use axum::body::Bytes;
use axum::extract::{Query, State};
use axum::http::{HeaderMap, HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use rand::TryRngCore;
use rand::rngs::OsRng;
use serde_json::{Value, json};
use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::{SystemTime, UNIX_EPOCH};

/// The largest request body the API reads.
const MAX_BODY_BYTES: usize = 16 * 1024;

/// The page's files, in the binary.
const INDEX_HTML: &str = include_str!("../assets/index.html");
const APP_JS: &str = include_str!("../assets/app.js");
const STYLE_CSS: &str = include_str!("../assets/style.css");
const ADMIN_HTML: &str = include_str!("../assets/admin.html");
const ADMIN_JS: &str = include_str!("../assets/admin.js");

/// What every handler shares.
struct Shared {
    conduct: Conduct,
    admin_token: String,
    scene: Value,
}

type App = Arc<Shared>;

/// A fresh unguessable token: 128 bits from the operating system, as hex.
pub fn new_token() -> String {
    let mut bytes = [0u8; 16];
    OsRng
        .try_fill_bytes(&mut bytes)
        .expect("the operating system gives random bytes");
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Milliseconds since the Unix epoch.
fn now_ms() -> i64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// The console's routes over `conduct`, the researcher's pages behind `admin_token`.
pub fn router(conduct: Conduct, admin_token: String) -> Router {
    let scene = conduct.stage.scene();
    let app: App = Arc::new(Shared {
        conduct,
        admin_token,
        scene,
    });
    Router::new()
        .route(
            "/",
            get(|| async { page(INDEX_HTML, "text/html; charset=utf-8") }),
        )
        .route(
            "/p/{token}",
            get(|| async { page(INDEX_HTML, "text/html; charset=utf-8") }),
        )
        .route(
            "/admin",
            get(|| async { page(ADMIN_HTML, "text/html; charset=utf-8") }),
        )
        .route(
            "/assets/app.js",
            get(|| async { page(APP_JS, "text/javascript; charset=utf-8") }),
        )
        .route(
            "/assets/admin.js",
            get(|| async { page(ADMIN_JS, "text/javascript; charset=utf-8") }),
        )
        .route(
            "/assets/style.css",
            get(|| async { page(STYLE_CSS, "text/css; charset=utf-8") }),
        )
        .route("/api/study", get(study))
        .route("/api/scene", get(scene_of))
        .route("/api/participants", post(enroll))
        .route("/api/session", get(session))
        .route("/api/shown", post(|s, h, b| act(s, h, b, parse_shown)))
        .route("/api/stop", post(|s, h, b| act(s, h, b, parse_stop)))
        .route(
            "/api/statement",
            post(|s, h, b| act(s, h, b, parse_statement)),
        )
        .route("/api/end", post(|s, h, b| act(s, h, b, parse_end)))
        .route("/api/rating", post(|s, h, b| act(s, h, b, parse_rating)))
        .route("/api/leave", post(leave))
        .route("/api/admin/participants", get(admin_participants))
        .route("/api/admin/events", get(admin_events))
        .layer(axum::extract::DefaultBodyLimit::max(MAX_BODY_BYTES))
        .with_state(app)
}

/// Serves `router` on `listen` until the process is stopped (Ctrl-C or SIGTERM), calling
/// `ready` with the bound address once connections are accepted.
pub fn run(
    listen: SocketAddr,
    router: Router,
    ready: impl FnOnce(SocketAddr) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(listen).await?;
        ready(listener.local_addr()?)?;
        axum::serve(listener, router)
            .with_graceful_shutdown(stopped())
            .await
    })
}

/// Resolves when the process is asked to stop.
async fn stopped() {
    #[cfg(unix)]
    {
        use tokio::signal::unix::{SignalKind, signal};
        match signal(SignalKind::terminate()) {
            Ok(mut terminate) => {
                tokio::select! {
                    _ = tokio::signal::ctrl_c() => {}
                    _ = terminate.recv() => {}
                }
            }
            Err(_) => {
                let _ = tokio::signal::ctrl_c().await;
            }
        }
    }
    #[cfg(not(unix))]
    {
        let _ = tokio::signal::ctrl_c().await;
    }
}

/// The address the console listens on, checked: loopback unless `public` (which needs an
/// admin token given by the researcher, not one drawn and printed).
pub fn check_listen(addr: SocketAddr, public: bool, token_given: bool) -> Result<(), String> {
    if addr.ip().is_loopback() {
        return Ok(());
    }
    if !public {
        return Err(format!(
            "--listen {addr}: not a loopback address; participants on other machines reach the console only with --public (and an admin token in TRUSTCBR_CONSOLE_ADMIN_TOKEN)"
        ));
    }
    if !token_given {
        return Err(format!(
            "--listen {addr} --public: set the admin token in TRUSTCBR_CONSOLE_ADMIN_TOKEN (at least 16 characters), so the researcher's pages are not guarded by a token printed to a terminal"
        ));
    }
    Ok(())
}

fn page(body: &'static str, content_type: &'static str) -> Response {
    (
        [
            (header::CONTENT_TYPE, HeaderValue::from_static(content_type)),
            (header::CACHE_CONTROL, HeaderValue::from_static("no-cache")),
            (
                header::CONTENT_SECURITY_POLICY,
                HeaderValue::from_static(
                    "default-src 'self'; style-src 'self'; script-src 'self'; img-src 'self' data:",
                ),
            ),
        ],
        body,
    )
        .into_response()
}

fn json_reply(status: StatusCode, body: Value) -> Response {
    (
        status,
        [(header::CACHE_CONTROL, HeaderValue::from_static("no-store"))],
        axum::Json(body),
    )
        .into_response()
}

fn error(status: StatusCode, message: impl std::fmt::Display) -> Response {
    json_reply(status, json!({"error": message.to_string()}))
}

fn failure(e: ConductError) -> Response {
    match e {
        ConductError::Refused(m) if m == "unknown participant token" => {
            error(StatusCode::UNAUTHORIZED, m)
        }
        ConductError::Refused(m) => error(StatusCode::CONFLICT, m),
        e => {
            eprintln!("console: {e}");
            error(StatusCode::INTERNAL_SERVER_ERROR, e)
        }
    }
}

fn bearer(headers: &HeaderMap) -> Option<&str> {
    headers
        .get(header::AUTHORIZATION)?
        .to_str()
        .ok()?
        .strip_prefix("Bearer ")
}

/// Compares two tokens in time independent of where they differ.
fn same_token(a: &str, b: &str) -> bool {
    a.len() == b.len()
        && a.bytes()
            .zip(b.bytes())
            .fold(0u8, |acc, (x, y)| acc | (x ^ y))
            == 0
}

fn is_admin(app: &Shared, headers: &HeaderMap) -> bool {
    bearer(headers).is_some_and(|t| same_token(t, &app.admin_token))
}

async fn blocking<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    tokio::task::spawn_blocking(f)
        .await
        .expect("a request's work does not panic")
}

async fn study(State(app): State<App>) -> Response {
    let study = &app.conduct.study;
    json_reply(
        StatusCode::OK,
        json!({
            "title": study.title,
            "consent": study.consent,
            "domain": study.domain,
            "minutes": study.minutes,
        }),
    )
}

async fn scene_of(State(app): State<App>) -> Response {
    json_reply(StatusCode::OK, app.scene.clone())
}

async fn enroll(State(app): State<App>, body: Bytes) -> Response {
    let consented = serde_json::from_slice::<Value>(&body)
        .ok()
        .is_some_and(|v| v["consent"] == true);
    if !consented {
        return error(
            StatusCode::BAD_REQUEST,
            "send {\"consent\": true}: a participant starts by consenting",
        );
    }
    blocking(move || {
        let token = new_token();
        match app.conduct.db.enroll(&app.conduct.study, &token, now_ms()) {
            Ok(p) => json_reply(
                StatusCode::CREATED,
                json!({"token": token, "participant": p.pseudonym()}),
            ),
            Err(e) => failure(e.into()),
        }
    })
    .await
}

async fn session(State(app): State<App>, headers: HeaderMap) -> Response {
    let Some(token) = bearer(&headers).map(str::to_owned) else {
        return error(
            StatusCode::UNAUTHORIZED,
            "send the participant's token as `Authorization: Bearer TOKEN`",
        );
    };
    blocking(
        move || match perform(&app.conduct, &token, None, now_ms()) {
            Ok(state) => json_reply(StatusCode::OK, state),
            Err(e) => failure(e),
        },
    )
    .await
}

type Parse = fn(&Value) -> Result<Action, String>;

async fn act(State(app): State<App>, headers: HeaderMap, body: Bytes, parse: Parse) -> Response {
    let Some(token) = bearer(&headers).map(str::to_owned) else {
        return error(
            StatusCode::UNAUTHORIZED,
            "send the participant's token as `Authorization: Bearer TOKEN`",
        );
    };
    let action = match serde_json::from_slice::<Value>(&body) {
        Ok(value) => match parse(&value) {
            Ok(action) => action,
            Err(m) => return error(StatusCode::BAD_REQUEST, m),
        },
        Err(e) => {
            return error(
                StatusCode::BAD_REQUEST,
                format!("the body is not JSON: {e}"),
            );
        }
    };
    blocking(
        move || match perform(&app.conduct, &token, Some(&action), now_ms()) {
            Ok(state) => json_reply(StatusCode::OK, state),
            Err(e) => failure(e),
        },
    )
    .await
}

fn field_u64(body: &Value, name: &str) -> Result<u64, String> {
    body[name]
        .as_u64()
        .ok_or_else(|| format!("field `{name}`: a whole number >= 0 is required"))
}

fn field_f64(body: &Value, name: &str) -> Result<f64, String> {
    body[name]
        .as_f64()
        .ok_or_else(|| format!("field `{name}`: a number is required"))
}

fn parse_shown(body: &Value) -> Result<Action, String> {
    Ok(Action::Shown {
        command: field_u64(body, "command")?,
    })
}

fn parse_stop(body: &Value) -> Result<Action, String> {
    Ok(Action::Stop {
        command: field_u64(body, "command")?,
        at_s: field_f64(body, "at_s")?,
    })
}

fn parse_statement(body: &Value) -> Result<Action, String> {
    let cause = match &body["cause"] {
        Value::Null => None,
        Value::String(s) => Some(s.clone()),
        _ => return Err("field `cause`: a cause's name or null is required".into()),
    };
    Ok(Action::Statement {
        command: field_u64(body, "command")?,
        cause,
    })
}

fn parse_end(body: &Value) -> Result<Action, String> {
    Ok(Action::End {
        command: field_u64(body, "command")?,
    })
}

fn parse_rating(body: &Value) -> Result<Action, String> {
    Ok(Action::Rating {
        number: usize::try_from(field_u64(body, "rating")?).map_err(|e| e.to_string())?,
        value: field_f64(body, "value")?,
    })
}

/// A page that is closed sends a beacon, which carries no header: its token is in the body.
async fn leave(State(app): State<App>, headers: HeaderMap, body: Bytes) -> Response {
    let token = bearer(&headers).map(str::to_owned).or_else(|| {
        serde_json::from_slice::<Value>(&body)
            .ok()
            .and_then(|v| v["token"].as_str().map(str::to_owned))
    });
    let Some(token) = token else {
        return error(StatusCode::UNAUTHORIZED, "no participant token");
    };
    blocking(
        move || match perform(&app.conduct, &token, Some(&Action::Leave), now_ms()) {
            Ok(_) => StatusCode::NO_CONTENT.into_response(),
            Err(e) => failure(e),
        },
    )
    .await
}

async fn admin_participants(State(app): State<App>, headers: HeaderMap) -> Response {
    if !is_admin(&app, &headers) {
        return error(
            StatusCode::UNAUTHORIZED,
            "the researcher's pages need the admin token",
        );
    }
    blocking(move || match crate::export::overview(&app.conduct) {
        Ok(rows) => json_reply(StatusCode::OK, rows),
        Err(e) => failure(e),
    })
    .await
}

async fn admin_events(
    State(app): State<App>,
    headers: HeaderMap,
    Query(query): Query<HashMap<String, String>>,
) -> Response {
    if !is_admin(&app, &headers) {
        return error(
            StatusCode::UNAUTHORIZED,
            "the researcher's pages need the admin token",
        );
    }
    let Some(wanted) = query.get("participant").cloned() else {
        return error(
            StatusCode::BAD_REQUEST,
            "name the participant: ?participant=P001",
        );
    };
    blocking(move || {
        let db = &app.conduct.db;
        let found = match db.participants() {
            Ok(all) => all.into_iter().find(|p| p.pseudonym() == wanted),
            Err(e) => return failure(e.into()),
        };
        let Some(participant) = found else {
            return error(StatusCode::NOT_FOUND, format!("no participant {wanted}"));
        };
        match db.events(participant.number) {
            Ok(events) => json_reply(
                StatusCode::OK,
                events
                    .iter()
                    .map(|e| crate::export::event_line(&participant, e))
                    .collect(),
            ),
            Err(e) => failure(e.into()),
        }
    })
    .await
}
