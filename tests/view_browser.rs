//! `printwatt view` in a real browser: headless Chromium driven over WebDriver (Debian's
//! `chromium-driver`). The page loads, the scene renders (a canvas that is not one colour), a
//! scripted drag of the part changes the energy to what `printwatt energy --at` prints for the
//! placement it lands on (to the printed digits), a typed placement the arm cannot reach shows
//! its reason, and the export button writes the hand-off (and refuses to overwrite it). The
//! server's own limits (loopback host, body size, unknown paths) are checked over plain HTTP.
//!
//! `.ci/run` installs `chromium` and `chromium-driver`. Without them the test fails and says so
//! (set `PRINTWATT_SKIP_BROWSER=1` to skip it knowingly).

mod common;

use common::root;
use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A child process ended when dropped.
#[derive(Debug)]
struct Kill(Child);
impl Drop for Kill {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn find(names: &[&str], env: &str) -> Option<PathBuf> {
    if let Some(p) = std::env::var_os(env) {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|d| names.iter().map(move |n| d.join(n)))
        .find(|p| p.is_file())
}

/// One HTTP/1.1 request to `host:port` (Connection: close): status and body.
fn http(
    addr: &str,
    method: &str,
    path: &str,
    body: Option<&[u8]>,
    host: Option<&str>,
) -> (u16, String) {
    let mut s = TcpStream::connect(addr).expect("connect");
    s.set_read_timeout(Some(Duration::from_secs(120))).unwrap();
    let body = body.unwrap_or(b"");
    let head = format!(
        "{method} {path} HTTP/1.1\r\nHost: {}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
        host.unwrap_or(addr),
        body.len()
    );
    s.write_all(head.as_bytes()).unwrap();
    // A server may refuse before reading the whole body (413): a failed write is fine then.
    let _ = s.write_all(body);
    // The head, then a body of Content-Length bytes, chunks, or up to the close.
    let mut raw = Vec::new();
    let mut byte = [0u8; 1];
    while !raw.ends_with(b"\r\n\r\n") {
        match s.read(&mut byte) {
            Ok(1) => raw.push(byte[0]),
            _ => break,
        }
    }
    let head = String::from_utf8_lossy(&raw).to_ascii_lowercase();
    let code = head
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let length = head
        .lines()
        .find_map(|l| l.strip_prefix("content-length:"))
        .and_then(|v| v.trim().parse::<usize>().ok());
    let mut body = Vec::new();
    if let Some(n) = length {
        body.resize(n, 0);
        let _ = s.read_exact(&mut body);
    } else if head.contains("transfer-encoding: chunked") {
        let mut r = BufReader::new(s);
        loop {
            let mut line = String::new();
            if r.read_line(&mut line).unwrap_or(0) == 0 {
                break;
            }
            let n = usize::from_str_radix(line.trim(), 16).unwrap_or(0);
            if n == 0 {
                break;
            }
            let mut chunk = vec![0; n + 2];
            if r.read_exact(&mut chunk).is_err() {
                break;
            }
            body.extend_from_slice(&chunk[..n]);
        }
    } else {
        let _ = s.read_to_end(&mut body);
    }
    (code, String::from_utf8_lossy(&body).into_owned())
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// `printwatt view --port 0` with `extra` arguments; its address `host:port`.
fn start_view(extra: &[&str]) -> (Kill, String) {
    let port: &[&str] = if extra.contains(&"--listen") {
        &[]
    } else {
        &["--port", "0"]
    };
    let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("view")
        .args(port)
        .args(extra)
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("printwatt view starts");
    let out = c.stdout.take().unwrap();
    let mut line = String::new();
    BufReader::new(out).read_line(&mut line).unwrap();
    let url = line
        .split_whitespace()
        .find(|w| w.starts_with("http://"))
        .unwrap_or_else(|| panic!("no URL in `{line}`"))
        .to_string();
    let addr = url
        .trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string();
    (Kill(c), addr)
}

/// `printwatt energy --at` for `at`: its `supply energy … J` figure, or its error text.
fn energy_at(at: &str) -> Result<String, String> {
    energy_at_with(at, &[])
}

/// [`energy_at`] with `extra` arguments (another robot).
fn energy_at_with(at: &str, extra: &[&str]) -> Result<String, String> {
    let o = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(["energy", "--no-csv", "--at", at])
        .args(extra)
        .current_dir(root())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    if !o.status.success() {
        return Err(String::from_utf8_lossy(&o.stderr).into_owned());
    }
    let line = text
        .lines()
        .find(|l| l.starts_with("supply energy "))
        .expect("a supply line");
    Ok(line.split_whitespace().nth(2).unwrap().to_string())
}

/// A WebDriver session on its own chromedriver. Dropped, it closes the browser and then ends
/// chromedriver's whole process group, so a failed test leaves no browser rendering behind
/// (a left-over headless Chromium keeps a software-rendered page busy and starves later tests).
struct Driver {
    addr: String,
    session: String,
    chromedriver: Child,
}

impl Drop for Driver {
    fn drop(&mut self) {
        if !self.session.is_empty() {
            let _ = http(
                &self.addr,
                "DELETE",
                &format!("/session/{}", self.session),
                None,
                None,
            );
        }
        let group = format!("-{}", self.chromedriver.id());
        let _ = Command::new("kill").args(["-KILL", "--", &group]).status();
        let _ = self.chromedriver.kill();
        let _ = self.chromedriver.wait();
    }
}

impl Driver {
    fn call(&self, method: &str, path: &str, body: Value) -> Value {
        let p = format!("/session/{}{path}", self.session);
        let b = body.to_string();
        let (code, text) = http(
            &self.addr,
            method,
            &p,
            (method == "POST").then_some(b.as_bytes()),
            None,
        );
        let v: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
        assert_eq!(code, 200, "WebDriver {method} {path}: {text}");
        v["value"].clone()
    }
    fn js(&self, script: &str) -> Value {
        self.call(
            "POST",
            "/execute/sync",
            json!({"script": script, "args": []}),
        )
    }
    fn wait(&self, what: &str, script: &str) -> Value {
        let t0 = Instant::now();
        loop {
            let v = self.js(script);
            if !(v.is_null() || v == json!(false)) {
                return v;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(60),
                "timed out waiting for {what}"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }
    /// The scene renders: the WebGL canvas holds many colours, not a blank fill.
    fn assert_scene_drawn(&self) {
        let colours = self.js(
            "const c = document.querySelector('#scene canvas'); const s = document.createElement('canvas'); \
             s.width = 200; s.height = 120; const g = s.getContext('2d'); g.drawImage(c, 0, 0, 200, 120); \
             const px = g.getImageData(0, 0, 200, 120).data; const set = new Set(); \
             for (let i = 0; i < px.length; i += 4) set.add(px[i] << 16 | px[i+1] << 8 | px[i+2]); return set.size;",
        );
        assert!(
            colours.as_u64().unwrap() > 50,
            "the canvas is (nearly) blank: {colours} colours"
        );
    }
    fn settled(&self) -> Value {
        self.wait(
            "the evaluation of the placement shown",
            "return window.pwView && window.pwView.ready && window.pwView.settled() ? \
             {place: window.pwView.place, supply: document.getElementById('supply').textContent, \
              status: document.getElementById('status').textContent, \
              reason: document.getElementById('reason').textContent} : null",
        )
    }
}

fn at_text(p: &Value) -> String {
    format!(
        "{},{},{},{}",
        p["x_m"].as_f64().unwrap(),
        p["y_m"].as_f64().unwrap(),
        p["z_m"].as_f64().unwrap(),
        p["yaw_deg"].as_f64().unwrap()
    )
}

fn browser_or_skip() -> Option<(PathBuf, PathBuf)> {
    let chromium = find(
        &["chromium", "chromium-browser", "google-chrome"],
        "PRINTWATT_CHROMIUM",
    );
    let driver = find(&["chromedriver"], "PRINTWATT_CHROMEDRIVER");
    match (chromium, driver) {
        (Some(c), Some(d)) => Some((c, d)),
        _ => {
            assert!(
                std::env::var_os("PRINTWATT_SKIP_BROWSER").is_some(),
                "no Chromium or chromedriver found: `apt-get install chromium chromium-driver` (.ci/run does), set PRINTWATT_CHROMIUM / PRINTWATT_CHROMEDRIVER, or PRINTWATT_SKIP_BROWSER=1"
            );
            None
        }
    }
}

fn start_driver(chromium: &Path, driver: &Path) -> Driver {
    let port = free_port();
    let child = Command::new(driver)
        .arg(format!("--port={port}"))
        .process_group(0)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromedriver starts");
    // Owned from here on, so a failed start also ends chromedriver (no session yet to close).
    let mut d = Driver {
        addr: format!("127.0.0.1:{port}"),
        session: String::new(),
        chromedriver: child,
    };
    let addr = d.addr.clone();
    let t0 = Instant::now();
    while TcpStream::connect(&addr).is_err() {
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "chromedriver does not listen"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    let caps = json!({"capabilities": {"alwaysMatch": {
        "browserName": "chrome",
        "goog:chromeOptions": {
            "binary": chromium.display().to_string(),
            "args": ["--headless=new", "--no-sandbox", "--disable-gpu-sandbox",
                     "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
                     "--window-size=1400,850", "--disable-dev-shm-usage",
                     "--no-first-run", "--disable-background-networking"]
        }
    }}});
    let (code, text) = http(
        &addr,
        "POST",
        "/session",
        Some(caps.to_string().as_bytes()),
        None,
    );
    assert_eq!(code, 200, "new WebDriver session: {text}");
    let v: Value = serde_json::from_str(&text).unwrap();
    d.session = v["value"]["sessionId"].as_str().unwrap().to_string();
    d
}

#[test]
fn the_view_follows_a_drag_with_the_energy_of_energy_at_shows_why_not_and_exports() {
    let Some((chromium, driver)) = browser_or_skip() else {
        return;
    };
    let export = std::env::temp_dir().join(format!("pw-view-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&export);
    let (_view, addr) = start_view(&["--export", export.to_str().unwrap()]);
    let d = start_driver(&chromium, &driver);
    d.call("POST", "/url", json!({"url": format!("http://{addr}/")}));
    let first = d.settled();
    assert_eq!(first["status"], "feasible", "the start placement: {first}");

    d.assert_scene_drawn();

    // The arm is drawn with its collision pieces to scale: every mesh piece of the scene,
    // the IRB 6700's forearm in four of them (its fork open).
    let hulls = d.js(
        "return [window.pwView.scene.shapes.filter(s => s.kind === 'hull').length, \
         window.pwView.scene.shapes.filter(s => s.kind === 'hull' && s.label.includes('link_4')).length, \
         window.pwView.hullPieces()];",
    );
    assert!(hulls[0].as_u64().unwrap() >= 10, "{hulls}");
    assert_eq!(hulls[1], 4, "the forearm's pieces: {hulls}");
    assert_eq!(hulls[2], hulls[0], "every mesh piece drawn: {hulls}");

    // A scripted drag of the bed with the mouse moves the part and re-evaluates it.
    let xy = d.js("return window.pwView.bedScreen();");
    let (x, y) = (
        xy[0].as_f64().unwrap().round() as i64,
        xy[1].as_f64().unwrap().round() as i64,
    );
    d.call(
        "POST",
        "/actions",
        json!({"actions": [{"type": "pointer", "id": "mouse", "parameters": {"pointerType": "mouse"},
            "actions": [
                {"type": "pointerMove", "duration": 0, "x": x, "y": y, "origin": "viewport"},
                {"type": "pointerDown", "button": 0},
                {"type": "pointerMove", "duration": 200, "x": x - 25, "y": y + 10, "origin": "viewport"},
                {"type": "pointerMove", "duration": 200, "x": x - 50, "y": y + 20, "origin": "viewport"},
                {"type": "pointerUp", "button": 0}
            ]}]}),
    );
    let dragged = d.settled();
    assert_ne!(
        dragged["place"], first["place"],
        "the drag did not move the part"
    );
    let at = at_text(&dragged["place"]);
    match energy_at(&at) {
        Ok(supply) if dragged["status"] == "feasible" => {
            assert_eq!(dragged["supply"], supply.as_str(), "at {at}")
        }
        other => panic!("the drag ended at {at}, shown as {dragged}; energy --at: {other:?}"),
    }

    // Typed values: a placement the arm cannot reach shows the reason energy --at gives.
    d.js(
        "for (const [k, v] of [['x', 0.5], ['y', 0], ['z', 0], ['yaw', 0]]) { const e = document.getElementById('in-' + k); \
         e.value = v; e.dispatchEvent(new Event('change')); } return true;",
    );
    let bad = d.settled();
    assert!(
        bad["status"].as_str().unwrap().starts_with("INFEASIBLE"),
        "{bad}"
    );
    let why = energy_at("0.5,0,0,0").expect_err("unreachable");
    let reason = bad["reason"].as_str().unwrap();
    assert!(
        !reason.is_empty() && why.contains(reason),
        "shown `{reason}`, energy --at said `{why}`"
    );

    // Back to the dragged placement; the export button writes the hand-off, once.
    let p = &dragged["place"];
    d.js(&format!(
        "for (const [k, v] of [['x', {}], ['y', {}], ['z', {}], ['yaw', {}]]) {{ const e = document.getElementById('in-' + k); \
         e.value = v; e.dispatchEvent(new Event('change')); }} return true;",
        p["x_m"], p["y_m"], p["z_m"], p["yaw_deg"]
    ));
    d.settled();
    d.js("document.getElementById('export').click(); return true;");
    d.wait(
        "the export",
        "return document.body.dataset.exported === 'yes' ? true : null",
    );
    for f in [
        "wobj_print.mod",
        "frame.json",
        "path_base.gcode",
        "path_base.mod",
    ] {
        assert!(export.join(f).is_file(), "{f} not written");
    }
    d.js("delete document.body.dataset.exported; document.getElementById('export').click(); return true;");
    let again = d.wait(
        "the refused export",
        "return document.body.dataset.exported === 'error' ? document.getElementById('export-status').textContent : null",
    );
    assert!(
        again.as_str().unwrap().contains("--force"),
        "a second export must refuse to overwrite: {again}"
    );
    let _ = std::fs::remove_dir_all(&export);
}

/// A browser opens up to six connections at once for the page's scripts and keeps them
/// open. Bursts of connections made together while every core is busy are all answered, each
/// connection kept open, and a kept connection answers again. (A server that queued a burst's
/// connections behind threads held by kept-alive ones left a script unanswered under load,
/// and the page never loaded.)
#[test]
fn the_view_server_answers_bursts_of_kept_alive_connections_under_load() {
    let (_view, addr) = start_view(&[]);
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
    let burners: Vec<_> = (0..2 * cores)
        .map(|_| {
            let stop = stop.clone();
            std::thread::spawn(move || {
                let mut x = 0u64;
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
                }
            })
        })
        .collect();
    let ask = |s: &mut TcpStream, path: &str| {
        let head = format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\n\r\n");
        s.write_all(head.as_bytes()).unwrap();
    };
    // The answer's status and body length, read by its Content-Length; the connection stays
    // open. None: no answer within 20 s.
    let answer = |s: &mut TcpStream| -> Option<(u16, usize)> {
        s.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
        let mut r = BufReader::new(s);
        let mut status = String::new();
        r.read_line(&mut status).ok()?;
        let mut length = 0;
        loop {
            let mut l = String::new();
            r.read_line(&mut l).ok()?;
            let l = l.trim_end().to_ascii_lowercase();
            if l.is_empty() {
                break;
            }
            if let Some(v) = l.strip_prefix("content-length:") {
                length = v.trim().parse().ok()?;
            }
        }
        let mut body = vec![0u8; length];
        r.read_exact(&mut body).ok()?;
        Some((status.split_whitespace().nth(1)?.parse().ok()?, length))
    };
    let path = "/assets/OrbitControls.js";
    let mut missing = Vec::new();
    for round in 0..5 {
        // Sixteen connections made at once, then a request on each.
        let mut conns: Vec<TcpStream> = (0..16)
            .map(|_| {
                let a = addr.clone();
                std::thread::spawn(move || TcpStream::connect(a).expect("connect"))
            })
            .collect::<Vec<_>>()
            .into_iter()
            .map(|t| t.join().unwrap())
            .collect();
        for s in conns.iter_mut() {
            ask(s, path);
        }
        for (k, s) in conns.iter_mut().enumerate() {
            match answer(s) {
                Some((200, n)) if n > 0 => {}
                other => missing.push(format!("round {round}, connection {k}: {other:?}")),
            }
        }
        // Each connection was kept open and answers again.
        for (k, s) in conns.iter_mut().enumerate().rev() {
            ask(s, path);
            if !matches!(answer(s), Some((200, _))) {
                missing.push(format!("round {round}, connection {k}, second request"));
            }
        }
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    for b in burners {
        b.join().unwrap();
    }
    assert!(missing.is_empty(), "unanswered: {missing:?}");
}

#[test]
fn the_view_server_refuses_foreign_hosts_large_bodies_and_unknown_paths() {
    let (_view, addr) = start_view(&[]);
    let (code, _) = http(&addr, "GET", "/", None, None);
    assert_eq!(code, 200);
    let (code, _) = http(&addr, "GET", "/", None, Some("example.com"));
    assert_eq!(code, 403, "a foreign Host is refused");
    let (code, _) = http(&addr, "GET", "/../Cargo.toml", None, None);
    assert_eq!(code, 404, "no file from disk");
    let (code, _) = http(&addr, "GET", "/assets/view.rs", None, None);
    assert_eq!(code, 404);
    let big = vec![b' '; 100 * 1024];
    let (code, _) = http(&addr, "POST", "/api/evaluate", Some(&big), None);
    assert_eq!(code, 413, "a large body is refused");
    let (code, body) = http(
        &addr,
        "POST",
        "/api/evaluate",
        Some(br#"{"x_m": 1500, "y_m": 0, "z_m": 0, "yaw_deg": 0}"#),
        None,
    );
    assert_eq!(code, 400, "{body}");
    assert!(body.contains("mm"), "millimetres typed as metres: {body}");
    let (code, body) = http(&addr, "POST", "/api/evaluate", Some(b"{"), None);
    assert_eq!(code, 400, "{body}");
}

#[test]
fn the_view_on_another_address_needs_its_token() {
    let port = free_port();
    let (_view, addr) = start_view(&["--listen", &format!("127.0.0.2:{port}")]);
    let (addr, token) = addr.split_once("/?token=").expect("a token in the URL");
    assert_eq!(token.len(), 32);
    let (code, _) = http(addr, "GET", "/", None, None);
    assert_eq!(code, 403, "no token");
    let (code, _) = http(addr, "GET", "/?token=0000", None, None);
    assert_eq!(code, 403, "a wrong token");
    let (code, body) = http(
        addr,
        "GET",
        &format!("/api/scene?token={token}"),
        None,
        None,
    );
    assert_eq!(code, 200, "{body}");
}

#[test]
fn the_view_of_a_run_directory_starts_at_its_answer() {
    let (_view, addr) = start_view(&["--run", "results/optimise-default"]);
    let (code, body) = http(&addr, "GET", "/api/scene", None, None);
    assert_eq!(code, 200);
    let scene: Value = serde_json::from_str(&body).unwrap();
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("results/optimise-default/summary.json")).unwrap(),
    )
    .unwrap();
    for k in ["x_m", "y_m", "z_m", "yaw_deg"] {
        let (a, b) = (
            scene["start"][k].as_f64().unwrap(),
            summary["best"]["placement"][k].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-9, "{k}: {a} vs {b}");
    }
}

#[test]
fn the_view_of_a_missing_run_says_so() {
    let o = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(["view", "--port", "0", "--run", "no-such-run-here"])
        .current_dir(root())
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--run no-such-run-here") && err.contains("summary.json"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn the_view_server_answers_a_superseded_evaluation_as_stale_and_the_newest_in_full() {
    // A 10-layer wall: each evaluation takes milliseconds, so a burst of requests overlaps
    // the one being evaluated.
    let (_view, addr) = start_view(&["--path", "paths/wall_multilayer.gcode"]);
    let n = 24u64;
    let answers: Vec<(u64, u16, Value)> = std::thread::scope(|s| {
        let hs: Vec<_> = (1..=n)
            .map(|seq| {
                let addr = addr.clone();
                s.spawn(move || {
                    let body = json!({"x_m": 1.5, "y_m": 0.0, "z_m": 0.2 + 0.001 * seq as f64, "yaw_deg": 0.0, "seq": seq});
                    let (code, text) = http(
                        &addr,
                        "POST",
                        "/api/evaluate",
                        Some(body.to_string().as_bytes()),
                        None,
                    );
                    (seq, code, serde_json::from_str(&text).unwrap_or(Value::Null))
                })
            })
            .collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    // Every request is answered; each answer is either stale (with its own seq) or the
    // evaluation of its own placement.
    let stale: Vec<u64> = answers
        .iter()
        .filter(|a| a.2.get("stale") == Some(&Value::Bool(true)))
        .map(|a| a.0)
        .collect();
    for (seq, code, v) in &answers {
        assert_eq!(*code, 200, "seq {seq}: {v}");
        assert_eq!(v.get("seq").and_then(Value::as_u64), Some(*seq), "{v}");
    }
    assert!(
        !stale.is_empty(),
        "a burst of {n} overlapping requests dropped none: {answers:?}"
    );
    assert!(stale.len() < n as usize, "some requests must be evaluated");
    // The newest request that arrived last is never dropped for an older one: the largest
    // seq is evaluated.
    assert!(!stale.contains(&n), "the newest request was dropped");
}

/// `printwatt view` with `args`: its address, or its exit and stderr when it refuses.
fn try_view(args: &[&str]) -> Result<(Kill, String), String> {
    let mut c = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .arg("view")
        .args(args)
        .current_dir(root())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("printwatt view starts");
    let out = c.stdout.take().unwrap();
    let mut line = String::new();
    BufReader::new(out).read_line(&mut line).unwrap();
    match line.split_whitespace().find(|w| w.starts_with("http://")) {
        Some(url) => Ok((
            Kill(c),
            url.trim_start_matches("http://")
                .trim_end_matches('/')
                .to_string(),
        )),
        None => {
            let o = c.wait_with_output().unwrap();
            Err(String::from_utf8_lossy(&o.stderr).into_owned())
        }
    }
}

#[test]
fn the_view_of_a_stations_run_shows_one_station_with_the_moves_it_prints() {
    let dir = common::scratch("view", "stations");
    let _ = std::fs::remove_dir_all(&dir);
    let out = dir.display().to_string();
    let o = common::bin()
        .args([
            "stations",
            "--path",
            "paths/floor_four_rooms.gcode",
            "--relocation-cost",
            "20000",
            "--wrist-margin",
            "0",
            "--out",
            &out,
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", common::stderr_of(&o));
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let segs = summary["segments"].as_array().unwrap();
    assert!(segs.len() >= 2, "a multi-station plan");
    let (_view, addr) = try_view(&[
        "--port",
        "0",
        "--path",
        "paths/floor_four_rooms.gcode",
        "--wrist-margin",
        "0",
        "--run",
        &out,
        "--station",
        "2",
    ])
    .unwrap();
    let (code, body) = http(&addr, "GET", "/api/scene", None, None);
    assert_eq!(code, 200, "{body}");
    let scene: Value = serde_json::from_str(&body).unwrap();
    let at = &segs[1]["at"];
    for k in ["x_m", "y_m", "z_m", "yaw_deg"] {
        let (a, b) = (scene["start"][k].as_f64().unwrap(), at[k].as_f64().unwrap());
        assert!((a - b).abs() < 1e-9, "{k}: view {a}, station {b}");
    }
    // Only the station's moves: its first point is the start of its first move.
    let full = printwatt::toolpath::load(
        &root().join("paths/floor_four_rooms.gcode"),
        &printwatt::toolpath::ReadOptions::default(),
    )
    .unwrap();
    let first = segs[1]["moves"][0].as_u64().unwrap() as usize;
    let p0 = full.move_start(first);
    let pts = scene["path"]["points_m"].as_array().unwrap();
    let q0 = [
        pts[0].as_f64().unwrap(),
        pts[1].as_f64().unwrap(),
        pts[2].as_f64().unwrap(),
    ];
    assert!(
        (q0[0] - p0.x).abs() < 1e-9 && (q0[1] - p0.y).abs() < 1e-9,
        "{q0:?} vs {p0:?}"
    );
    // A station the plan does not have is refused with the range.
    let why = try_view(&[
        "--port",
        "0",
        "--path",
        "paths/floor_four_rooms.gcode",
        "--run",
        &out,
        "--station",
        "99",
    ])
    .expect_err("station 99 is refused");
    assert!(why.contains("stations 1 to"), "{why}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_view_of_a_study_case_takes_its_robot_path_options_and_answer() {
    let dir = common::scratch("view", "study");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let study = dir.join("s.toml");
    std::fs::write(
        &study,
        format!(
            "[study]\nname = \"tiny\"\noptions = [\"--max-evals\", \"10\", \"--no-margin-trade\"]\n\n[[robot]]\nname = \"ur\"\nrobot = \"ur10e\"\n\n[[cell]]\nname = \"near\"\nx = \"0.6:0.8:0.1\"\ny = \"0\"\nz = \"0,0.1\"\nyaw = \"0,90\"\n\n[[path]]\nname = \"ring\"\nfile = \"{}\"\n",
            root().join("paths/seed000_test_path.gcode").display()
        ),
    )
    .unwrap();
    let run = dir.join("run").display().to_string();
    let o = common::bin()
        .args(["study", &study.display().to_string(), "--out", &run])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", common::stderr_of(&o));
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("run/summary.json")).unwrap())
            .unwrap();
    let case = &summary["cases"][0];
    assert_eq!(case["status"], "feasible", "{case}");
    let (_view, addr) =
        try_view(&["--port", "0", "--run", &run, "--case", "ur/near/ring"]).unwrap();
    let (code, body) = http(&addr, "GET", "/api/scene", None, None);
    assert_eq!(code, 200, "{body}");
    let scene: Value = serde_json::from_str(&body).unwrap();
    assert_eq!(scene["robot"], "Universal Robots UR10e");
    assert!(scene["path_file"]
        .as_str()
        .unwrap()
        .ends_with("seed000_test_path.gcode"));
    for k in ["x_m", "y_m", "z_m", "yaw_deg"] {
        let (a, b) = (
            scene["start"][k].as_f64().unwrap(),
            case["placement"][k].as_f64().unwrap(),
        );
        assert!((a - b).abs() < 1e-9, "{k}: view {a}, case {b}");
    }
    // The energy map is the cell's grid: 3 x 1 x 2 x 2 placements.
    assert_eq!(scene["map"].as_array().unwrap().len(), 12);
    let why =
        try_view(&["--port", "0", "--run", &run, "--case", "7"]).expect_err("case 7 is refused");
    assert!(why.contains("no case `7`"), "{why}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The page of `printwatt view` with `args` (robot and path) loads, renders a canvas that is
/// not blank, shows the start placement's supply energy as `printwatt energy --at` with the
/// same `args` prints it, and reports what it drew the robot from: `window.pwView.drawn` with
/// the visual boxes (`boxes`) and the collision mesh pieces drawn (`hulls`).
fn check_robot_page(args: &[&str]) -> Option<Value> {
    let (chromium, driver) = browser_or_skip()?;
    let (_view, addr) = start_view(args);
    let d = start_driver(&chromium, &driver);
    d.call("POST", "/url", json!({"url": format!("http://{addr}/")}));
    let first = d.settled();
    d.assert_scene_drawn();
    let at = at_text(&first["place"]);
    match energy_at_with(&at, args) {
        Ok(supply) if first["status"].as_str().unwrap().starts_with("feasible") => {
            assert_eq!(first["supply"], supply.as_str(), "at {at}")
        }
        other => panic!("the page starts at {at}, shown as {first}; energy --at: {other:?}"),
    }
    // The arm is posed (a playback arrived) before its pieces are counted.
    d.wait(
        "the arm drawn",
        "return window.pwView.playback !== null && document.body.dataset.drawn === 'yes' ? true : null",
    );
    let drawn = d.js(
        "return Object.assign({}, window.pwView.drawn, {boxes: window.pwView.visualBoxes(), \
         hulls: window.pwView.hullPieces(), status: document.getElementById('status').textContent, \
         line: document.getElementById('drawn').textContent, scene_visuals: window.pwView.scene.visuals.length, \
         shapes: window.pwView.scene.shapes});",
    );
    Some(drawn)
}

/// The collision mesh pieces of the links in `drawn`'s scene (the pedestal, head and hose
/// are not links).
fn link_pieces(drawn: &Value) -> usize {
    drawn["shapes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|s| s["role"] == "link" && s["pedestal"] == false)
        .count()
}

#[test]
fn the_view_of_the_ur10e_draws_its_collision_pieces_and_the_energy_of_energy_at() {
    let Some(drawn) =
        check_robot_page(&["--robot", "ur10e", "--path", "paths/wall_multilayer.gcode"])
    else {
        return;
    };
    // The shipped arms have no <visual>: every link drawn from its collision pieces.
    assert_eq!(drawn["scene_visuals"], 0, "{drawn}");
    assert_eq!(drawn["visual"], 0, "{drawn}");
    let n = link_pieces(&drawn);
    assert!(n >= 7, "{drawn}");
    assert_eq!(drawn["collision"], n, "{drawn}");
    assert_eq!(
        drawn["hulls"], n,
        "every collision mesh piece drawn: {drawn}"
    );
    assert!(
        drawn["line"].as_str().unwrap().contains(&format!(
            "0 visual element(s) (0 mesh(es)) and {n} collision shape(s)"
        )),
        "{drawn}"
    );
}

#[test]
fn the_view_of_the_irb4600_draws_its_collision_pieces_and_the_energy_of_energy_at() {
    let Some(drawn) = check_robot_page(&[
        "--robot",
        "abb_irb4600_40_255",
        "--path",
        "paths/wall_multilayer.gcode",
    ]) else {
        return;
    };
    assert_eq!(drawn["scene_visuals"], 0, "{drawn}");
    assert_eq!(drawn["visual"], 0, "{drawn}");
    let n = link_pieces(&drawn);
    // Its forearm is several convex pieces (collision/README.md).
    assert!(n >= 10, "{drawn}");
    assert_eq!(drawn["collision"], n, "{drawn}");
    assert_eq!(drawn["hulls"], n, "{drawn}");
}

/// A COLLADA cube of edge 100 mm standing on its link's origin, in millimetres
/// (`<unit meter="0.001">`) with `<up_axis>Z_UP`: in the link frame, x and y in ±0.05 m and
/// z in 0..0.1 m.
const CUBE_DAE: &str = r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="cube" name="cube"><mesh>
      <source id="cube-pos">
        <float_array id="cube-pos-array" count="24">-50 -50 0 50 -50 0 50 50 0 -50 50 0 -50 -50 100 50 -50 100 50 50 100 -50 50 100</float_array>
        <technique_common><accessor source="#cube-pos-array" count="8" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="cube-vtx"><input semantic="POSITION" source="#cube-pos"/></vertices>
      <triangles count="12"><input semantic="VERTEX" source="#cube-vtx" offset="0"/>
        <p>0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7</p>
      </triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="scene"><node id="cube-node"><instance_geometry url="#cube"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##;

/// A Wavefront box 0.2 × 0.1 × 0.06 m about its origin.
const BOX_OBJ: &str = "v -0.1 -0.05 -0.03\nv 0.1 -0.05 -0.03\nv 0.1 0.05 -0.03\nv -0.1 0.05 -0.03\n\
v -0.1 -0.05 0.03\nv 0.1 -0.05 0.03\nv 0.1 0.05 0.03\nv -0.1 0.05 0.03\n\
f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";

/// A user's robot directory: the ROS-Industrial IRB 6640 package (tests/data/ros_industrial)
/// copied with a URDF whose `<visual>` elements name meshes the test can check: the published
/// collision STLs for links 1 to 4, an OBJ box for link 5 (at an origin 0.1 m up z), a
/// millimetre Z-up COLLADA cube for link 6, and for the base a `.dae` that is no COLLADA (its
/// load fails: the base keeps its collision hull). Link 3 also names two files outside the
/// package (not drawn, not served). The drive file is `robot init`'s. Returns the directory
/// and the drive file.
fn irb6640_with_visuals(name: &str) -> (PathBuf, PathBuf) {
    let d = common::scratch("view", name);
    let src = root().join("tests/data/ros_industrial/abb_irb6640_support");
    let pkg = d.join("abb_irb6640_support");
    let meshes = pkg.join("meshes/irb6640_185_280");
    std::fs::create_dir_all(meshes.join("collision")).unwrap();
    std::fs::create_dir_all(meshes.join("visual")).unwrap();
    std::fs::create_dir_all(pkg.join("urdf")).unwrap();
    for e in std::fs::read_dir(src.join("meshes/irb6640_185_280/collision")).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), meshes.join("collision").join(e.file_name())).unwrap();
    }
    std::fs::write(meshes.join("visual/link_6.dae"), CUBE_DAE).unwrap();
    std::fs::write(meshes.join("visual/link_5.obj"), BOX_OBJ).unwrap();
    std::fs::write(meshes.join("visual/base_link.dae"), "not a COLLADA file").unwrap();
    std::fs::write(d.join("outside.stl"), "solid outside\nendsolid outside\n").unwrap();
    let mut urdf = std::fs::read_to_string(src.join("urdf/irb6640_185_280.urdf")).unwrap();
    let v = "package://abb_irb6640_support/meshes/irb6640_185_280/visual/";
    let c = "package://abb_irb6640_support/meshes/irb6640_185_280/collision/";
    for l in [
        "link_1",
        "link_2",
        "link_3",
        "link_4",
        "cylinder_link",
        "piston_link",
    ] {
        urdf = urdf.replace(&format!("{v}{l}.dae"), &format!("{c}{l}.stl"));
    }
    urdf = urdf.replace(&format!("{v}link_5.dae"), &format!("{v}link_5.obj"));
    let link5 = format!("<mesh filename=\"{v}link_5.obj\"/>");
    let at = urdf.find(&link5).expect("link_5's visual");
    let open = urdf[..at].rfind("<visual").unwrap();
    let head_end = open + urdf[open..].find('>').unwrap() + 1;
    urdf.insert_str(head_end, "<origin xyz=\"0 0 0.1\" rpy=\"0 0 0\"/>");
    let link3 = format!("<mesh filename=\"{c}link_3.stl\"/>");
    let at = urdf.find(&link3).expect("link_3's visual");
    let end = at + urdf[at..].find("</visual>").unwrap() + "</visual>".len();
    urdf.insert_str(
        end,
        "\n    <visual><geometry><mesh filename=\"package://abb_irb6640_support/../outside.stl\"/></geometry></visual>\
         \n    <visual><geometry><mesh filename=\"../../outside.stl\"/></geometry></visual>",
    );
    let file = pkg.join("urdf/irb6640_185_280.urdf");
    std::fs::write(&file, urdf).unwrap();
    std::fs::create_dir_all(d.join("cell")).unwrap();
    let drive = d.join("cell/drive.toml");
    let o = common::bin()
        .args([
            "robot",
            "init",
            file.to_str().unwrap(),
            "--out",
            drive.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", common::stderr_of(&o));
    (d, drive)
}

/// The box of an STL file's vertices (m): min and max.
fn stl_box(p: &Path) -> ([f64; 3], [f64; 3]) {
    let v = printwatt::robot::mesh::read_vertices(p).unwrap();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in v {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

fn close3(a: &Value, b: [f64; 3], tol: f64) -> bool {
    (0..3).all(|k| (a[k].as_f64().unwrap() - b[k]).abs() < tol)
}

#[test]
fn the_view_of_a_user_robot_draws_its_visual_meshes_in_metres_and_falls_back_where_one_fails() {
    if browser_or_skip().is_none() {
        return;
    }
    let (dir, drive) = irb6640_with_visuals("irb6640-page");
    let drive_arg = drive.display().to_string();
    let drawn = check_robot_page(&[
        "--robot",
        &drive_arg,
        "--path",
        "paths/wall_multilayer.gcode",
    ])
    .unwrap();
    // Links 1 to 6 from their visual meshes (four STL, one OBJ, one COLLADA); the base's
    // COLLADA file does not load: the base is drawn from its collision hull, and said.
    assert_eq!(drawn["visual"], 6, "{drawn}");
    assert_eq!(drawn["visualBodies"], json!([1, 2, 3, 4, 5, 6]), "{drawn}");
    assert_eq!(
        drawn["collision"], 1,
        "only the base from collision shapes: {drawn}"
    );
    assert_eq!(drawn["hulls"], 1, "{drawn}");
    let failed = drawn["failed"].as_array().unwrap();
    assert_eq!(failed.len(), 1, "{drawn}");
    assert!(
        failed[0].as_str().unwrap().contains("base_link.dae"),
        "{drawn}"
    );
    let status = drawn["status"].as_str().unwrap();
    assert!(
        status.contains("failed to load") && status.contains("base_link"),
        "the status line names the fallback: {status}"
    );
    let line = drawn["line"].as_str().unwrap();
    assert!(
        line.contains("6 visual element(s) (6 mesh(es)) and 1 collision shape(s)"),
        "{line}"
    );
    assert!(
        line.contains("outside.stl"),
        "the files not drawn are named: {line}"
    );
    // Each mesh in metres in its link's frame: the STLs as their vertices, the OBJ at its
    // origin 0.1 m up, the millimetre Z-up COLLADA cube standing on the link's origin.
    let boxes = drawn["boxes"].as_array().unwrap();
    let of = |l: &str| {
        boxes
            .iter()
            .find(|b| b["link"] == l)
            .unwrap_or_else(|| panic!("no visual of {l}: {drawn}"))
    };
    let col = dir.join("abb_irb6640_support/meshes/irb6640_185_280/collision");
    for l in ["link_1", "link_2", "link_3", "link_4"] {
        let (lo, hi) = stl_box(&col.join(format!("{l}.stl")));
        let b = of(l);
        assert!(
            close3(&b["min"], lo, 1e-4) && close3(&b["max"], hi, 1e-4),
            "{l}: drawn {b}, file {lo:?}..{hi:?}"
        );
    }
    let b = of("link_5");
    assert!(
        close3(&b["min"], [-0.1, -0.05, 0.07], 1e-6) && close3(&b["max"], [0.1, 0.05, 0.13], 1e-6),
        "link_5's OBJ box at its origin: {b}"
    );
    let b = of("link_6");
    assert_eq!(b["kind"], "mesh");
    assert!(
        close3(&b["min"], [-0.05, -0.05, 0.0], 1e-6) && close3(&b["max"], [0.05, 0.05, 0.1], 1e-6),
        "link_6's COLLADA cube in metres, z up: {b}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_view_serves_only_the_visual_meshes_the_urdf_references_by_index() {
    let (dir, drive) = irb6640_with_visuals("irb6640-server");
    let drive_arg = drive.display().to_string();
    let (_view, addr) = start_view(&[
        "--robot",
        &drive_arg,
        "--path",
        "paths/wall_multilayer.gcode",
    ]);
    let (code, body) = http(&addr, "GET", "/api/scene", None, None);
    assert_eq!(code, 200, "{body}");
    let scene: Value = serde_json::from_str(&body).unwrap();
    // The chain's visual meshes, each once: base (the failing .dae), links 1 to 6; the
    // balancer's links are no part of the chain, and the files outside the package are not
    // served.
    let meshes = scene["meshes"].as_array().unwrap();
    let files: Vec<&str> = meshes.iter().map(|m| m["file"].as_str().unwrap()).collect();
    assert_eq!(meshes.len(), 7, "{files:?}");
    assert!(
        files
            .iter()
            .all(|f| !f.contains("outside") && !f.contains("piston") && !f.contains("cylinder")),
        "{files:?}"
    );
    let skipped = scene["visuals_skipped"].as_array().unwrap();
    assert_eq!(
        skipped
            .iter()
            .filter(|s| s.as_str().unwrap().contains("outside.stl"))
            .count(),
        2,
        "{skipped:?}"
    );
    let pkg = dir.join("abb_irb6640_support");
    for (k, m) in meshes.iter().enumerate() {
        assert_eq!(m["index"], k);
        let (code, body) = http(&addr, "GET", &format!("/api/mesh/{k}"), None, None);
        assert_eq!(code, 200, "mesh {k}");
        let f = m["file"].as_str().unwrap();
        let rel = f.strip_prefix("package://abb_irb6640_support/").unwrap();
        let want = std::fs::read(pkg.join(rel)).unwrap();
        assert!(
            body == String::from_utf8_lossy(&want),
            "mesh {k}: not the bytes of {f}"
        );
    }
    // An index out of range is not found; anything but an index is a bad request.
    let (code, _) = http(
        &addr,
        "GET",
        &format!("/api/mesh/{}", meshes.len()),
        None,
        None,
    );
    assert_eq!(code, 404);
    for p in [
        "/api/mesh/-1",
        "/api/mesh/",
        "/api/mesh/0x1",
        "/api/mesh/..%2F..%2Foutside.stl",
        "/api/mesh/../../outside.stl",
        "/api/mesh/0/../1",
        "/api/mesh/abb_irb6640_support/meshes/irb6640_185_280/collision/link_1.stl",
        "/api/mesh/99999999999999999999",
    ] {
        let (code, body) = http(&addr, "GET", p, None, None);
        assert!(code == 400 || code == 404, "{p}: {code} {body}");
        assert!(!body.contains("solid"), "{p}: a file's bytes: {body}");
    }
    let (code, _) = http(&addr, "POST", "/api/mesh/0", Some(b"{}"), None);
    assert_eq!(code, 405);
    let _ = std::fs::remove_dir_all(&dir);
}
