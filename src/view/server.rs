//! The view's web server: axum on a one-thread tokio runtime takes the connections (any
//! number, kept alive as long as the browser likes) and hands each request to one
//! dispatching thread; evaluations go on to one evaluating thread.
//!
//! - It binds where it is told: the command line binds 127.0.0.1 unless `--listen` names
//!   another address, and then every request must carry the random token printed in the URL
//!   (`?token=…`). Without a token a request whose `Host` is not the loopback's is
//!   refused (a page of another site cannot reach the server through a name that resolves to
//!   127.0.0.1).
//! - It serves the page and its scripts from the binary and the API under `/api/`; the only
//!   files it reads from disk are the robot's visual meshes ([`ViewState::mesh`]), asked for
//!   by index (`/api/mesh/<k>`), never by a path: the files the URDF's `<visual>` elements
//!   name, found inside the URDF's directory or the ROS package they point into.
//! - A request body is at most [`MAX_BODY`] bytes (413 beyond).
//! - Evaluations wait in a slot of one: a newer request answers the waiting one with
//!   `{"stale": true}` at once, so a fast drag never queues work behind the one evaluation
//!   running.

use super::{placement_from_json, placement_json, ViewState};
use crate::error::{Error, Result};
use crate::evaluate::evaluator::Evaluator;
use crate::search::run::{Observer, Progress, Stage};
use serde_json::{json, Value};
use std::net::SocketAddr;
use std::sync::{mpsc, Condvar, Mutex};

/// Largest request body accepted, bytes.
pub(crate) const MAX_BODY: usize = 64 * 1024;

const INDEX_HTML: &str = include_str!("assets/index.html");
const VIEW_JS: &[u8] = include_bytes!("assets/view.js");
const THREE_JS: &[u8] = include_bytes!("../../vendor/three/three.module.min.js");
const ORBIT_JS: &[u8] = include_bytes!("../../vendor/three/OrbitControls.js");
const THREE_LICENSE: &[u8] = include_bytes!("../../vendor/three/three-LICENSE");

/// The page's scripts and the three.js licence: path, bytes, content type. The loaders are
/// three.js 0.160.1's `examples/jsm/loaders/` files, unchanged (the COLLADA loader imports
/// the TGA one).
const ASSETS: [(&str, &[u8], &str); 8] = [
    ("/assets/view.js", VIEW_JS, "text/javascript"),
    ("/assets/three.module.min.js", THREE_JS, "text/javascript"),
    ("/assets/OrbitControls.js", ORBIT_JS, "text/javascript"),
    (
        "/assets/loaders/STLLoader.js",
        include_bytes!("../../vendor/three/loaders/STLLoader.js"),
        "text/javascript",
    ),
    (
        "/assets/loaders/ColladaLoader.js",
        include_bytes!("../../vendor/three/loaders/ColladaLoader.js"),
        "text/javascript",
    ),
    (
        "/assets/loaders/OBJLoader.js",
        include_bytes!("../../vendor/three/loaders/OBJLoader.js"),
        "text/javascript",
    ),
    (
        "/assets/loaders/TGALoader.js",
        include_bytes!("../../vendor/three/loaders/TGALoader.js"),
        "text/javascript",
    ),
    ("/assets/three-LICENSE", THREE_LICENSE, "text/plain"),
];

/// The answer to `GET /api/mesh/<k>`: the mesh's bytes, 400 for anything but a decimal
/// index, 404 for an index the robot has no mesh of, 500 when the file cannot be read.
fn mesh_response(state: &ViewState, k: &str) -> Answer {
    if k.is_empty() || k.len() > 9 || !k.bytes().all(|b| b.is_ascii_digit()) {
        return error_response(400, "a mesh is asked for by its index, /api/mesh/<k>");
    }
    let Ok(k) = k.parse::<usize>() else {
        return error_response(400, "a mesh is asked for by its index, /api/mesh/<k>");
    };
    match state.mesh(k) {
        None => error_response(
            404,
            &format!(
                "no mesh {k}: the robot has {} visual meshes",
                state.meshes.len()
            ),
        ),
        Some(Err(e)) => error_response(500, &e.to_string()),
        Some(Ok((b, ctype))) => bytes_response(&b, ctype),
    }
}

/// An answer to a request: status, content type and body.
struct Answer {
    code: u16,
    ctype: &'static str,
    body: Vec<u8>,
}

impl Answer {
    fn with_status_code(mut self, code: u16) -> Self {
        self.code = code;
        self
    }

    fn into_response(self) -> axum::response::Response {
        let mut r = axum::response::Response::new(axum::body::Body::from(self.body));
        *r.status_mut() = axum::http::StatusCode::from_u16(self.code)
            .unwrap_or(axum::http::StatusCode::INTERNAL_SERVER_ERROR);
        let h = r.headers_mut();
        use axum::http::header::{
            HeaderValue, CACHE_CONTROL, CONTENT_TYPE, X_CONTENT_TYPE_OPTIONS,
        };
        h.insert(CONTENT_TYPE, HeaderValue::from_static(self.ctype));
        h.insert(X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff"));
        h.insert(CACHE_CONTROL, HeaderValue::from_static("no-store"));
        r
    }
}

/// A request handed from the connections to the dispatching thread, with the channel its
/// answer goes back on.
struct Request {
    get: bool,
    post: bool,
    /// Path and query.
    url: String,
    host: Option<String>,
    body: Vec<u8>,
    /// The body was longer than [`MAX_BODY`] (and was not read further).
    too_large: bool,
    reply: tokio::sync::oneshot::Sender<Answer>,
}

impl Request {
    fn url(&self) -> &str {
        &self.url
    }

    /// Send the answer; a browser that left meanwhile is no error.
    fn respond(self, a: Answer) -> std::result::Result<(), Answer> {
        self.reply.send(a)
    }
}

/// A bound server, not yet serving.
pub struct Bound {
    listener: std::net::TcpListener,
    /// The address it listens on (the port chosen when 0 was asked for).
    pub addr: SocketAddr,
    /// The token every request must carry (`None` on the loopback address).
    pub token: Option<String>,
}

impl Bound {
    /// The page's address, with the token when there is one.
    pub fn url(&self) -> String {
        let host = if self.addr.ip().is_unspecified() {
            "127.0.0.1".to_string()
        } else {
            match self.addr {
                SocketAddr::V4(a) => a.ip().to_string(),
                SocketAddr::V6(a) => format!("[{}]", a.ip()),
            }
        };
        let mut u = format!("http://{host}:{}/", self.addr.port());
        if let Some(t) = &self.token {
            u.push_str(&format!("?token={t}"));
        }
        u
    }
}

/// Bind `addr`; with `token`, every request must carry a random token (printed in
/// [`Bound::url`]). Errors: the address is taken or cannot be bound (the system's words).
pub fn bind(addr: SocketAddr, token: bool) -> Result<Bound> {
    let cannot = |e: std::io::Error| Error::Invalid(format!("cannot listen on {addr}: {e}"));
    let listener = std::net::TcpListener::bind(addr).map_err(cannot)?;
    let bound = listener.local_addr().map_err(cannot)?;
    listener.set_nonblocking(true).map_err(cannot)?;
    let token = token.then(|| format!("{:032x}", rand::random::<u128>()));
    Ok(Bound {
        listener,
        addr: bound,
        token,
    })
}

/// Progress and answer of the optimisation run from the page.
#[derive(Default)]
struct OptState {
    state: &'static str,
    stage: Option<&'static str>,
    done: usize,
    total: usize,
    best_j: Option<f64>,
    answer: Option<Value>,
    error: Option<String>,
    secs: Option<f64>,
}

struct OptObserver<'a>(&'a Mutex<OptState>);

impl Observer for OptObserver<'_> {
    fn begin(&self, stage: Stage, total: usize) {
        if let Ok(mut g) = self.0.lock() {
            g.stage = Some(match stage {
                Stage::Grid => "grid",
                Stage::Refinement => "refinement",
            });
            g.done = 0;
            g.total = total;
        }
    }
    fn progress(&self, p: Progress) {
        if let Ok(mut g) = self.0.lock() {
            g.done = p.done;
            g.total = p.total;
            if p.best_j.is_some() {
                g.best_j = p.best_j;
            }
        }
    }
}

/// An evaluation waiting for the evaluating thread.
struct Pending {
    seq: u64,
    body: Value,
    req: Request,
}

#[derive(Default)]
struct Slot {
    pending: Mutex<Option<Pending>>,
    ready: Condvar,
    /// The listener ended: the evaluating thread ends too.
    closing: std::sync::atomic::AtomicBool,
}

/// Serve `state` on `bound` until the listener fails (the process is ended to stop it).
pub fn serve(bound: Bound, state: &ViewState) -> Result<()> {
    let slot = Slot::default();
    let opt = Mutex::new(OptState {
        state: "idle",
        ..Default::default()
    });
    let ev = state.evaluator();
    let index = INDEX_HTML.replace("__TOKEN__", bound.token.as_deref().unwrap_or(""));
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_io()
        .build()
        .map_err(|e| Error::Invalid(format!("cannot start the web server: {e}")))?;
    let listener = bound
        .listener
        .try_clone()
        .map_err(|e| Error::Invalid(format!("cannot start the web server: {e}")))?;
    let (tx, rx) = mpsc::channel::<Request>();
    let routes = Routes {
        bound: &bound,
        state,
        index: &index,
        slot: &slot,
        opt: &opt,
    };
    std::thread::scope(|s| {
        // The connections: axum on the one-thread runtime. When it ends (the listener
        // failed), the channel closes and so does the dispatching loop below.
        s.spawn(move || {
            runtime.block_on(async move {
                let Ok(listener) = tokio::net::TcpListener::from_std(listener) else {
                    return;
                };
                let app = axum::Router::new().fallback(receive).with_state(tx);
                let _ = axum::serve(listener, app).await;
            })
        });
        s.spawn(|| evaluate_waiting(&slot, state, &ev));
        for req in rx.iter() {
            if !routes.handle(s, req) {
                break;
            }
        }
        // The listener ended: wake the evaluating thread to end too.
        slot.closing
            .store(true, std::sync::atomic::Ordering::Relaxed);
        slot.ready.notify_all();
        Ok(())
    })
}

/// The evaluating thread: evaluate the placement waiting in the slot and answer it, until
/// the listener ends.
fn evaluate_waiting<'c>(slot: &Slot, state: &ViewState<'c>, ev: &Evaluator<'_, 'c>) {
    // A robot without inverse kinematics has no scratch: each request says why.
    let mut sc = ev.scratch();
    loop {
        let p = {
            let Ok(mut g) = slot.pending.lock() else {
                return;
            };
            loop {
                if let Some(p) = g.take() {
                    break p;
                }
                if slot.closing.load(std::sync::atomic::Ordering::Relaxed) {
                    return;
                }
                g = match slot.ready.wait(g) {
                    Ok(g) => g,
                    Err(_) => return,
                };
            }
        };
        let answer = match &mut sc {
            Ok(sc) => placement_from_json(&p.body).and_then(|at| state.evaluate(ev, sc, &at)),
            Err(e) => Err(Error::Invalid(e.to_string())),
        };
        let _ = match answer {
            Ok(mut v) => {
                v["seq"] = json!(p.seq);
                p.req.respond(json_response(200, &v))
            }
            Err(e) => p.req.respond(error_response(400, &e.to_string())),
        };
    }
}

/// What the dispatching thread routes requests to: the server's binding, the view, the page,
/// the evaluation slot and the state of the optimisation.
struct Routes<'a, 'c> {
    bound: &'a Bound,
    state: &'a ViewState<'c>,
    index: &'a str,
    slot: &'a Slot,
    opt: &'a Mutex<OptState>,
}

impl<'a, 'c> Routes<'a, 'c> {
    /// Answer one request (an evaluation is handed to the evaluating thread, an optimisation
    /// started on a thread of `s`); `false`: the slot is broken, stop dispatching.
    fn handle<'scope>(&self, s: &'scope std::thread::Scope<'scope, '_>, req: Request) -> bool
    where
        'a: 'scope,
    {
        let state = self.state;
        if let Some(r) = refuse(self.bound, &req) {
            let _ = req.respond(r);
            return true;
        }
        let url = req.url().to_string();
        let path = url.split('?').next().unwrap_or("").to_string();
        let (get, post) = (req.get, req.post);
        match (path.as_str(), get, post) {
            ("/", true, _) => {
                let _ = req.respond(bytes_response(
                    self.index.as_bytes(),
                    "text/html; charset=utf-8",
                ));
            }
            (p, true, _) if ASSETS.iter().any(|a| a.0 == p) => {
                if let Some((_, b, ctype)) = ASSETS.iter().find(|a| a.0 == p) {
                    let _ = req.respond(bytes_response(b, ctype));
                }
            }
            (p, true, _) if p.starts_with("/api/mesh/") => {
                let k = &p["/api/mesh/".len()..];
                let _ = req.respond(mesh_response(state, k));
            }
            ("/api/scene", true, _) => {
                let _ = req.respond(json_response(200, &state.scene()));
            }
            ("/api/evaluate", _, true) => return self.queue_evaluation(req),
            ("/api/playback", _, true) => {
                let a = playback_answer(state, &req);
                let _ = req.respond(a);
            }
            ("/api/export", _, true) => {
                let a = export_answer(state, &req);
                let _ = req.respond(a);
            }
            ("/api/optimise", true, _) => {
                let v = self.opt.lock().map(|g| opt_json(&g)).unwrap_or(Value::Null);
                let _ = req.respond(json_response(200, &v));
            }
            ("/api/optimise", _, true) => {
                self.start_optimise(s);
                let v = self.opt.lock().map(|g| opt_json(&g)).unwrap_or(Value::Null);
                let _ = req.respond(json_response(200, &v));
            }
            (
                "/" | "/api/scene" | "/api/evaluate" | "/api/playback" | "/api/export"
                | "/api/optimise",
                _,
                _,
            ) => {
                let _ = req.respond(error_response(405, "method not allowed"));
            }
            (p, _, _) if ASSETS.iter().any(|a| a.0 == p) || p.starts_with("/api/mesh/") => {
                let _ = req.respond(error_response(405, "method not allowed"));
            }
            _ => {
                let _ = req.respond(error_response(404, "not found"));
            }
        }
        true
    }

    /// Put an evaluation in the slot, answering the one it replaces (or itself, if the
    /// waiting one is newer) as stale; `false`: the slot is broken.
    fn queue_evaluation(&self, req: Request) -> bool {
        let body = match read_json(&req) {
            Ok(b) => b,
            Err((code, msg)) => {
                let _ = req.respond(error_response(code, &msg));
                return true;
            }
        };
        let seq = body.get("seq").and_then(Value::as_u64).unwrap_or(0);
        let new = Pending { seq, body, req };
        let Ok(mut g) = self.slot.pending.lock() else {
            return false;
        };
        let stale = match g.take() {
            Some(old) if old.seq > new.seq => {
                *g = Some(old);
                Some(new)
            }
            old => {
                *g = Some(new);
                old
            }
        };
        drop(g);
        self.slot.ready.notify_one();
        if let Some(p) = stale {
            let _ = p
                .req
                .respond(json_response(200, &json!({"stale": true, "seq": p.seq})));
        }
        true
    }

    /// Start the optimisation on a thread of `s` unless one is running.
    fn start_optimise<'scope>(&self, s: &'scope std::thread::Scope<'scope, '_>)
    where
        'a: 'scope,
    {
        let started = match self.opt.lock() {
            Ok(mut g) if g.state != "running" => {
                *g = OptState {
                    state: "running",
                    ..Default::default()
                };
                true
            }
            _ => false,
        };
        if started {
            let (opt, state) = (self.opt, self.state);
            s.spawn(move || {
                let r = crate::search::run(&state.config.job, &OptObserver(opt));
                if let Ok(mut g) = opt.lock() {
                    record_optimise(&mut g, r);
                }
            });
        }
    }
}

/// Record the end of the optimisation: its answer, or why it failed.
fn record_optimise(g: &mut OptState, r: Result<crate::search::OptimiseOutcome>) {
    match r {
        Ok(o) => match o.report.best() {
            Some(b) => {
                g.state = "done";
                g.secs = Some(o.secs);
                g.answer = Some(json!({
                    "placement": placement_json(&b.placement),
                    "energy_j": b.feasible().map(|f| f.energy_j),
                    "supply_text": b.feasible().map(|f| super::one_decimal(f.supply_j)),
                }));
            }
            None => {
                g.state = "failed";
                g.error = Some("no feasible placement".into());
            }
        },
        Err(e) => {
            g.state = "failed";
            g.error = Some(e.to_string());
        }
    }
}

/// The answer to `/api/playback`: the frames of the print at the placement in the body.
fn playback_answer(state: &ViewState, req: &Request) -> Answer {
    let r = read_json(req).and_then(|b| {
        let at = placement_from_json(&b).map_err(|e| (400, e.to_string()))?;
        let frames = b.get("frames").and_then(Value::as_u64).unwrap_or(200);
        state
            .playback(&at, frames as usize)
            .map_err(|e| (400, e.to_string()))
    });
    match r {
        Ok(v) => json_response(200, &v),
        Err((c, m)) => error_response(c, &m),
    }
}

/// The answer to `/api/export`: the robot program files written for the placement in the
/// body.
fn export_answer(state: &ViewState, req: &Request) -> Answer {
    let r = read_json(req).and_then(|b| {
        let at = placement_from_json(&b).map_err(|e| (400, e.to_string()))?;
        state.export(&at).map_err(|e| (409, e.to_string()))
    });
    match r {
        Ok(files) => json_response(
            200,
            &json!({"written": files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>()}),
        ),
        Err((c, m)) => error_response(c, &m),
    }
}

fn opt_json(g: &OptState) -> Value {
    json!({
        "state": g.state, "stage": g.stage, "done": g.done, "total": g.total,
        "best_j": g.best_j, "answer": g.answer, "error": g.error, "secs": g.secs,
    })
}

/// Why a request is refused before it is routed: a missing or wrong token (403), a `Host`
/// other than the loopback's on a loopback server (403), a body over [`MAX_BODY`] (413).
fn refuse(bound: &Bound, req: &Request) -> Option<Answer> {
    if let Some(t) = &bound.token {
        let query = req.url().split_once('?').map_or("", |(_, q)| q);
        let ok = query
            .split('&')
            .any(|kv| kv.strip_prefix("token=").is_some_and(|v| constant_eq(v, t)));
        if !ok {
            return Some(error_response(
                403,
                "this server needs the token printed with its URL",
            ));
        }
    } else {
        let host = req.host.as_deref().map(str::to_ascii_lowercase);
        let port = bound.addr.port();
        let allowed = [
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ];
        if !host.is_some_and(|h| allowed.contains(&h)) {
            return Some(error_response(
                403,
                "the view answers only on its loopback address",
            ));
        }
    }
    if req.too_large {
        return Some(error_response(413, "request body too large"));
    }
    None
}

fn constant_eq(a: &str, b: &str) -> bool {
    a.len() == b.len() && a.bytes().zip(b.bytes()).fold(0u8, |d, (x, y)| d | (x ^ y)) == 0
}

/// The body as JSON (at most [`MAX_BODY`] bytes, checked by [`refuse`]): `(status,
/// message)` otherwise.
fn read_json(req: &Request) -> std::result::Result<Value, (u16, String)> {
    serde_json::from_slice(&req.body).map_err(|e| (400, format!("the request is not JSON: {e}")))
}

fn bytes_response(b: &[u8], ctype: &'static str) -> Answer {
    Answer {
        code: 200,
        ctype,
        body: b.to_vec(),
    }
}

/// Take a request off a connection: its body up to [`MAX_BODY`] bytes, handed to the
/// dispatching thread, whose answer is sent back.
async fn receive(
    axum::extract::State(tx): axum::extract::State<mpsc::Sender<Request>>,
    req: axum::extract::Request,
) -> axum::response::Response {
    let (parts, body) = req.into_parts();
    let (body, too_large) = match axum::body::to_bytes(body, MAX_BODY).await {
        Ok(b) => (b.to_vec(), false),
        Err(_) => (Vec::new(), true),
    };
    let (reply, answer) = tokio::sync::oneshot::channel();
    let req = Request {
        get: parts.method == axum::http::Method::GET,
        post: parts.method == axum::http::Method::POST,
        url: parts
            .uri
            .path_and_query()
            .map_or_else(|| parts.uri.path().to_string(), |p| p.as_str().to_string()),
        host: parts
            .headers
            .get(axum::http::header::HOST)
            .and_then(|v| v.to_str().ok())
            .map(str::to_string),
        body,
        too_large,
        reply,
    };
    if tx.send(req).is_err() {
        return error_response(503, "the view is ending").into_response();
    }
    match answer.await {
        Ok(a) => a,
        Err(_) => error_response(500, "no answer"),
    }
    .into_response()
}

fn json_response(code: u16, v: &Value) -> Answer {
    // serde_json writes a non-finite number as null, which the page shows as "n/a".
    let text = serde_json::to_vec(v).unwrap_or_else(|_| b"null".to_vec());
    bytes_response(&text, "application/json").with_status_code(code)
}

fn error_response(code: u16, msg: &str) -> Answer {
    json_response(code, &json!({ "error": msg }))
}
