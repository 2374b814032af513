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
    let o = Command::new(env!("CARGO_BIN_EXE_printwatt"))
        .args(["energy", "--no-csv", "--at", at])
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

struct Driver {
    addr: String,
    session: String,
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

fn start_driver(chromium: &Path, driver: &Path) -> (Kill, Driver) {
    let port = free_port();
    let child = Command::new(driver)
        .arg(format!("--port={port}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromedriver starts");
    let guard = Kill(child);
    let addr = format!("127.0.0.1:{port}");
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
    let session = v["value"]["sessionId"].as_str().unwrap().to_string();
    (guard, Driver { addr, session })
}

#[test]
fn the_view_follows_a_drag_with_the_energy_of_energy_at_shows_why_not_and_exports() {
    let Some((chromium, driver)) = browser_or_skip() else {
        return;
    };
    let export = std::env::temp_dir().join(format!("pw-view-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&export);
    let (_view, addr) = start_view(&["--export", export.to_str().unwrap()]);
    let (_drv, d) = start_driver(&chromium, &driver);
    d.call("POST", "/url", json!({"url": format!("http://{addr}/")}));
    let first = d.settled();
    assert_eq!(first["status"], "feasible", "the start placement: {first}");

    // The scene renders: the WebGL canvas holds many colours, not a blank fill.
    let colours = d.js(
        "const c = document.querySelector('#scene canvas'); const s = document.createElement('canvas'); \
         s.width = 200; s.height = 120; const g = s.getContext('2d'); g.drawImage(c, 0, 0, 200, 120); \
         const px = g.getImageData(0, 0, 200, 120).data; const set = new Set(); \
         for (let i = 0; i < px.length; i += 4) set.add(px[i] << 16 | px[i+1] << 8 | px[i+2]); return set.size;",
    );
    assert!(
        colours.as_u64().unwrap() > 50,
        "the canvas is (nearly) blank: {colours} colours"
    );

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
    let _ = http(
        &d.addr,
        "DELETE",
        &format!("/session/{}", d.session),
        None,
        None,
    );
    let _ = std::fs::remove_dir_all(&export);
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
