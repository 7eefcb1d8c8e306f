//! `masssprings view` as a client sees it: the program is started as a child
//! process on a free port, and every request is written by hand over raw TCP,
//! so that malformed and hostile requests can be sent too.
//!
//! Checked: the page, script, style and texture with their content types;
//! the status; the keys' commands (space advances exactly one step, R resets,
//! W, A and L toggle); dragging; path traversal and unknown paths leak
//! nothing; garbage, oversized and unfinished requests get a 4xx and the
//! server goes on; two clients at once; Ctrl-C (SIGINT) exits with status 0.

use serde_json::{json, Value};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::process::{Child, ChildStdout, Command, ExitStatus, Stdio};
use std::sync::mpsc;
use std::thread;
use std::time::{Duration, Instant};

/// A running `masssprings view`, killed when dropped (whatever the test did).
struct Viewer {
    child: Child,
    address: SocketAddr,
    /// Kept open so the program can still write to its stdout.
    _stdout: BufReader<ChildStdout>,
}

impl Viewer {
    /// Starts `masssprings view data/SCENE --port 0` and reads the URL it
    /// prints.
    fn start(scene: &str) -> Viewer {
        Viewer::start_with(scene, &[], None)
    }

    /// [`Viewer::start`] with more flags, and a memory limit (GB) if given.
    fn start_with(scene: &str, flags: &[&str], memory_limit_gb: Option<&str>) -> Viewer {
        let mut command = Command::new(env!("CARGO_BIN_EXE_masssprings"));
        command
            .args(["view", &data(scene), "--port", "0"])
            .args(flags);
        Viewer::spawn(command, memory_limit_gb)
    }

    /// `masssprings view SCENE --port 0` run in `folder`, `scene` as given.
    fn start_in(folder: &std::path::Path, scene: &str) -> Viewer {
        let mut command = Command::new(env!("CARGO_BIN_EXE_masssprings"));
        command
            .args(["view", scene, "--port", "0"])
            .current_dir(folder);
        Viewer::spawn(command, None)
    }

    fn spawn(mut command: Command, memory_limit_gb: Option<&str>) -> Viewer {
        if let Some(limit) = memory_limit_gb {
            command.env(masssprings::memory::LIMIT_VARIABLE, limit);
        }
        let child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("the binary runs");
        let mut viewer = ViewerStarting { child: Some(child) };
        let stdout = viewer.child().stdout.take().expect("piped");
        let (sender, receiver) = mpsc::channel();
        thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            let mut line = String::new();
            let _ = reader.read_line(&mut line);
            let _ = sender.send((line, reader));
        });
        let (line, stdout) = receiver
            .recv_timeout(Duration::from_secs(30))
            .expect("the URL within 30 s");
        let url = line.trim();
        let authority = url
            .strip_prefix("http://")
            .and_then(|rest| rest.strip_suffix('/'))
            .unwrap_or_else(|| panic!("not a URL: {line:?}"));
        assert!(authority.starts_with("127.0.0."), "{url}");
        Viewer {
            child: viewer.child.take().expect("still there"),
            address: authority.parse().expect("ip:port"),
            _stdout: stdout,
        }
    }

    /// Sends `raw` on a fresh connection and reads the answer until the
    /// server closes it (`None` when it answered nothing).
    fn exchange(&self, raw: &[u8]) -> Option<HttpResponse> {
        let mut stream = self.connect();
        // The server may close before reading all of an oversized request.
        let _ = stream.write_all(raw);
        let mut bytes = Vec::new();
        let _ = stream.read_to_end(&mut bytes);
        HttpResponse::parse(&bytes)
    }

    fn connect(&self) -> TcpStream {
        let stream = TcpStream::connect_timeout(&self.address, Duration::from_secs(5))
            .expect("the server accepts connections");
        stream
            .set_read_timeout(Some(Duration::from_secs(15)))
            .unwrap();
        stream
    }

    /// `GET path` with `Connection: close`.
    fn get(&self, path: &str) -> HttpResponse {
        let request = format!(
            "GET {path} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
            self.address
        );
        self.exchange(request.as_bytes()).expect("an answer")
    }

    /// `POST /api/command` with a JSON body.
    fn post_command(&self, body: &Value) -> HttpResponse {
        let body = body.to_string();
        let request = format!(
            "POST /api/command HTTP/1.1\r\nHost: {}\r\nContent-Type: application/json\r\n\
             Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
            self.address,
            body.len()
        );
        self.exchange(request.as_bytes()).expect("an answer")
    }

    /// A command that must succeed; returns the new status.
    fn command(&self, name: &str) -> Value {
        let response = self.post_command(&json!({ "command": name }));
        assert_eq!(response.status, 200, "{name}: {}", response.text());
        response.json()
    }

    fn status(&self) -> Value {
        let response = self.get("/api/status");
        assert_eq!(response.status, 200);
        assert_eq!(response.header("content-type"), Some("application/json"));
        response.json()
    }

    /// The positions of the latest frame.
    fn positions(&self) -> Vec<[f32; 3]> {
        let frame = self.get("/api/frame");
        assert_eq!(frame.status, 200);
        frame.body[16..]
            .chunks_exact(12)
            .map(|xyz| [0, 4, 8].map(|at| f32::from_le_bytes(xyz[at..at + 4].try_into().unwrap())))
            .collect()
    }

    /// Pauses the animation (it starts animating).
    fn pause(&self) -> Value {
        let status = self.status();
        if status["animating"] == true {
            let paused = self.command("toggle_animation");
            assert_eq!(paused["animating"], false);
            return paused;
        }
        status
    }

    /// Waits up to `limit` for the program to exit.
    fn wait_for_exit(&mut self, limit: Duration) -> Option<ExitStatus> {
        let deadline = Instant::now() + limit;
        while Instant::now() < deadline {
            if let Some(status) = self.child.try_wait().expect("try_wait") {
                return Some(status);
            }
            thread::sleep(Duration::from_millis(20));
        }
        None
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Kills the child if `Viewer::start` panics before it returns.
struct ViewerStarting {
    child: Option<Child>,
}

impl ViewerStarting {
    fn child(&mut self) -> &mut Child {
        self.child.as_mut().expect("still there")
    }
}

impl Drop for ViewerStarting {
    fn drop(&mut self) {
        if let Some(child) = &mut self.child {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// One HTTP response as read off the wire.
#[derive(Debug)]
struct HttpResponse {
    status: u16,
    headers: Vec<(String, String)>,
    body: Vec<u8>,
}

impl HttpResponse {
    /// The first response in `bytes` (head, then `Content-Length` bytes).
    fn parse(bytes: &[u8]) -> Option<HttpResponse> {
        Self::parse_with_body(bytes, true)
    }

    /// The first response, with its body unless `with_body` is false (the
    /// answer to `HEAD`).
    fn parse_with_body(bytes: &[u8], with_body: bool) -> Option<HttpResponse> {
        let head_end = bytes.windows(4).position(|w| w == b"\r\n\r\n")? + 4;
        let head = std::str::from_utf8(&bytes[..head_end]).expect("an ASCII head");
        let mut lines = head.split("\r\n");
        let status_line = lines.next()?;
        assert!(status_line.starts_with("HTTP/1.1 "), "{status_line}");
        let status = status_line[9..12].parse().expect("a status code");
        let headers: Vec<(String, String)> = lines
            .filter_map(|line| line.split_once(": "))
            .map(|(name, value)| (name.to_ascii_lowercase(), value.to_string()))
            .collect();
        let length: usize = headers
            .iter()
            .find(|(name, _)| name == "content-length")
            .map(|(_, value)| value.parse().expect("a length"))
            .unwrap_or(0);
        let body_length = if with_body { length } else { 0 };
        let body = bytes.get(head_end..head_end + body_length)?.to_vec();
        Some(HttpResponse {
            status,
            headers,
            body,
        })
    }

    fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(key, _)| key == name)
            .map(|(_, value)| value.as_str())
    }

    fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }

    fn json(&self) -> Value {
        serde_json::from_slice(&self.body).expect("a JSON body")
    }
}

fn data(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
        .display()
        .to_string()
}

/// Reads one whole response from a kept-alive connection.
fn read_one_response(stream: &mut TcpStream) -> HttpResponse {
    let mut bytes = Vec::new();
    let mut chunk = [0u8; 8192];
    loop {
        if let Some(response) = HttpResponse::parse(&bytes) {
            return response;
        }
        let count = stream.read(&mut chunk).expect("the rest of the response");
        assert!(count > 0, "the server closed mid-response");
        bytes.extend_from_slice(&chunk[..count]);
    }
}

#[test]
fn the_page_script_style_and_scene_are_served_with_their_content_types() {
    let viewer = Viewer::start("net.json");
    let page = viewer.get("/");
    assert_eq!(page.status, 200);
    assert_eq!(
        page.header("content-type"),
        Some("text/html; charset=utf-8")
    );
    assert!(page.text().contains("<canvas"));
    let policy = page.header("content-security-policy").expect("a CSP");
    assert!(policy.contains("default-src 'none'") && policy.contains("connect-src 'self'"));
    assert_eq!(viewer.get("/index.html").body, page.body);

    let script = viewer.get("/viewer.js");
    assert_eq!(script.status, 200);
    assert_eq!(
        script.header("content-type"),
        Some("text/javascript; charset=utf-8")
    );
    assert!(script.text().contains("getContext('webgl2'"));
    let style = viewer.get("/viewer.css");
    assert_eq!(
        (style.status, style.header("content-type")),
        (200, Some("text/css; charset=utf-8"))
    );

    let scene = viewer.get("/api/scene");
    assert_eq!(scene.header("content-type"), Some("application/json"));
    let scene = scene.json();
    assert_eq!(scene["n"], 81);
    assert_eq!(scene["springs"].as_array().unwrap().len(), 2 * 144);
    assert_eq!(scene["pinned"], json!([0, 4, 8, 36, 44, 72, 76, 80]));
    assert_eq!(scene["texture"], Value::Null);
    assert_eq!(scene["triangles"], json!([]), "the net is made of springs");

    let status = viewer.status();
    assert_eq!(
        (status["n"].clone(), status["springs"].clone()),
        (json!(81), json!(144))
    );
    assert_eq!(status["scene"], "net");
    assert_eq!(status["backend"], "sparse");
    for key in ["steps", "time", "ms_per_step", "steps_per_second"] {
        assert!(status[key].is_number(), "{key}");
    }
    for key in ["animating", "wind", "show_springs"] {
        assert!(status[key].is_boolean(), "{key}");
    }
    assert_eq!(status["dragged"], Value::Null);

    let frame = viewer.get("/api/frame");
    assert_eq!(
        frame.header("content-type"),
        Some("application/octet-stream")
    );
    assert_eq!(frame.body.len(), 16 + 12 * 81);
    assert_eq!(&frame.body[..4], &81u32.to_le_bytes());
    assert_eq!(
        viewer.get("/texture.png").status,
        404,
        "the net has no texture"
    );
}

#[test]
fn the_scenes_texture_is_served_as_the_png_the_scene_names() {
    let viewer = Viewer::start("flag.json");
    let texture = viewer.get("/texture.png");
    assert_eq!(texture.status, 200);
    assert_eq!(texture.header("content-type"), Some("image/png"));
    assert_eq!(texture.body, std::fs::read(data("flag.png")).unwrap());
    let scene = viewer.get("/api/scene").json();
    assert_eq!(scene["texture"], "/texture.png");
    assert_eq!(scene["triangles"].as_array().unwrap().len(), 3 * 2 * 3081);
    let mut stream = viewer.connect();
    let request = format!(
        "HEAD /texture.png HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
        viewer.address
    );
    stream.write_all(request.as_bytes()).unwrap();
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).unwrap();
    let head = HttpResponse::parse_with_body(&bytes, false).expect("an answer to HEAD");
    assert_eq!(head.status, 200);
    assert!(bytes.ends_with(b"\r\n\r\n"), "no body after the head");
    assert_eq!(
        head.header("content-length"),
        Some(texture.body.len().to_string().as_str())
    );
}

#[test]
fn space_steps_once_r_resets_and_a_w_l_toggle() {
    let viewer = Viewer::start("net.json");
    assert_eq!(viewer.status()["animating"], false, "it starts paused");
    assert_eq!(viewer.status()["steps"], 0, "at rest");
    let paused = viewer.pause();
    let steps = paused["steps"].as_u64().unwrap();

    let stepped = viewer.command("step");
    assert_eq!(
        stepped["steps"],
        steps + 1,
        "space advances exactly one step"
    );
    assert_eq!(stepped["animating"], false, "space pauses");
    assert_eq!(viewer.command("step")["steps"], steps + 2);
    thread::sleep(Duration::from_millis(200));
    assert_eq!(viewer.status()["steps"], steps + 2, "no steps while paused");

    let reset = viewer.command("reset");
    assert_eq!(
        (reset["steps"].clone(), reset["time"].clone()),
        (json!(0), json!(0.0))
    );
    let rest: Vec<[f32; 3]> = viewer.positions();
    assert_eq!(rest[1], [0.15, 0.0, 0.0], "back at the rest positions");

    let wind = viewer.status()["wind"].clone();
    assert_eq!(
        viewer.command("toggle_wind")["wind"],
        json!(!wind.as_bool().unwrap())
    );
    assert_eq!(viewer.command("toggle_wind")["wind"], wind);

    let springs = viewer.status()["show_springs"].as_bool().unwrap();
    assert!(springs, "a scene of springs shows them");
    assert_eq!(viewer.command("toggle_springs")["show_springs"], false);
    assert_eq!(viewer.command("toggle_springs")["show_springs"], true);

    assert_eq!(viewer.command("toggle_animation")["animating"], true);
    let deadline = Instant::now() + Duration::from_secs(10);
    while viewer.status()["steps"].as_u64().unwrap() < 3 {
        assert!(Instant::now() < deadline, "the animation steps on its own");
        viewer.get("/api/frame?page=1"); // a page watching
        thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(viewer.command("toggle_animation")["animating"], false);
}

#[test]
fn it_animates_only_while_a_page_asks_for_frames() {
    let viewer = Viewer::start("net.json");
    let animating = viewer.command("toggle_animation");
    assert_eq!(animating["animating"], true);
    thread::sleep(Duration::from_millis(1500)); // nobody watching
    let idle = viewer.status();
    assert_eq!(
        (idle["steps"].clone(), idle["watched"].clone()),
        (json!(0), json!(false))
    );
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        viewer.get("/api/frame?page=42");
        let status = viewer.status();
        if status["steps"].as_u64().unwrap() >= 3 {
            assert_eq!(
                (status["watched"].clone(), status["pages"].clone()),
                (json!(true), json!(1))
            );
            break;
        }
        assert!(Instant::now() < deadline, "a watching page starts it");
        thread::sleep(Duration::from_millis(20));
    }
    // Watched for over a second, it counts its steps per second.
    let deadline = Instant::now() + Duration::from_secs(10);
    while viewer.status()["steps_per_second"].as_f64().unwrap() <= 0.0 {
        viewer.get("/api/frame?page=42");
        assert!(Instant::now() < deadline, "the overlay's rate");
        thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn new_parameters_refactor_q_and_change_the_motion() {
    let viewer = Viewer::start("net.json");
    let before = viewer.status();
    assert_eq!(before["refactor_ms"], Value::Null);
    assert_eq!(
        (before["k"].clone(), before["iterations"].clone()),
        (json!(1000.0), json!(50))
    );
    viewer.command("step");
    let original = viewer.positions();
    viewer.command("reset");
    let change = json!({"command": "set_parameters", "k": 50.0, "delta_t": 0.05,
        "mass_scale": 2.0, "iterations": 10});
    let changed = viewer.post_command(&change);
    assert_eq!(changed.status, 200, "{}", changed.text());
    let status = changed.json();
    assert!(status["refactor_ms"].as_f64().unwrap() > 0.0, "{status}");
    assert_eq!(
        [
            &status["k"],
            &status["delta_t"],
            &status["mass_scale"],
            &status["iterations"]
        ],
        [&json!(50.0), &json!(0.05), &json!(2.0), &json!(10)]
    );
    let stepped = viewer.command("step");
    assert_eq!(stepped["history"][0]["iterations"], 10);
    assert_ne!(
        viewer.positions(),
        original,
        "a softer, heavier net moves otherwise"
    );
    for bad in [
        json!({"command": "set_parameters", "k": -1.0, "delta_t": 0.05, "mass_scale": 1.0, "iterations": 10}),
        json!({"command": "set_parameters", "k": 1.0, "delta_t": 5.0, "mass_scale": 1.0, "iterations": 10}),
        json!({"command": "set_parameters", "k": 1.0, "delta_t": 0.05, "mass_scale": 0.0, "iterations": 10}),
        json!({"command": "set_parameters", "k": 1.0, "delta_t": 0.05, "mass_scale": 1.0, "iterations": 0}),
    ] {
        assert_eq!(viewer.post_command(&bad).status, 409, "{bad}");
    }
    assert_eq!(
        viewer.status()["k"],
        json!(50.0),
        "refused values change nothing"
    );
}

#[test]
fn the_page_can_switch_to_another_bundled_scene() {
    let viewer = Viewer::start("net.json");
    let status = viewer.status();
    let scenes: Vec<String> = serde_json::from_value(status["scenes"].clone()).unwrap();
    assert_eq!(scenes[0], "net", "the scene given comes first");
    for bundled in [
        "flag",
        "skirt",
        "horizontal-chain",
        "single-spring-horizontal",
    ] {
        assert!(
            scenes.iter().any(|s| s == bundled),
            "{bundled} in {scenes:?}"
        );
    }
    let chain = scenes.iter().position(|s| s == "horizontal-chain").unwrap();
    viewer.command("step");
    let loaded = viewer.post_command(&json!({"command": "load_scene", "scene": chain}));
    assert_eq!(loaded.status, 200, "{}", loaded.text());
    let loaded = loaded.json();
    assert_eq!(
        [
            &loaded["scene"],
            &loaded["n"],
            &loaded["steps"],
            &loaded["scene_index"],
            &loaded["animating"]
        ],
        [
            &json!("horizontal-chain"),
            &json!(11),
            &json!(0),
            &json!(chain),
            &json!(false)
        ]
    );
    assert_ne!(loaded["scene_serial"], status["scene_serial"]);
    let scene = viewer.get("/api/scene").json();
    assert_eq!(
        (scene["name"].clone(), scene["n"].clone()),
        (json!("horizontal-chain"), json!(11))
    );
    assert_eq!(viewer.positions().len(), 11);
    assert_eq!(
        viewer.get("/texture.png").status,
        404,
        "the chain has no texture"
    );
    let missing = viewer.post_command(&json!({"command": "load_scene", "scene": 999}));
    assert_eq!(missing.status, 409);
    assert_eq!(viewer.status()["scene"], "horizontal-chain");
}

#[test]
fn a_bare_scene_name_lists_the_scenes_beside_it_as_a_path_does() {
    let folder = std::env::temp_dir().join(format!("masssprings-viewer-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    for name in ["mine.json", "mine.obj", "other.json", "other.obj"] {
        let source = if name.ends_with("json") {
            "net.json"
        } else {
            "net.obj"
        };
        let text = std::fs::read_to_string(data(source)).unwrap();
        std::fs::write(
            folder.join(name),
            text.replace("net.obj", &name.replace("json", "obj")),
        )
        .unwrap();
    }
    for given in ["mine.json", "./mine.json"] {
        let viewer = Viewer::start_in(&folder, given);
        let scenes: Vec<String> =
            serde_json::from_value(viewer.status()["scenes"].clone()).unwrap();
        assert_eq!(scenes[0], "mine");
        assert!(scenes.iter().any(|s| s == "other"), "{given}: {scenes:?}");
    }
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn switching_scenes_on_the_dense_path_checks_its_memory_as_the_command_line_does() {
    let viewer = Viewer::start_with("net.json", &["--dense"], Some("4"));
    let scenes: Vec<String> = serde_json::from_value(viewer.status()["scenes"].clone()).unwrap();
    let skirt = scenes.iter().position(|s| s == "skirt").unwrap();
    let refused = viewer.post_command(&json!({"command": "load_scene", "scene": skirt}));
    assert_eq!(refused.status, 409, "{}", refused.text());
    let text = refused.text();
    assert!(
        text.contains("the dense path for n = 9,840") && text.contains("use the sparse path"),
        "{text}"
    );
    assert_eq!(viewer.status()["scene"], "net", "the scene shown stays");
}

#[test]
fn a_frame_is_sent_again_only_when_it_changed() {
    let viewer = Viewer::start("net.json");
    viewer.pause();
    let frame = viewer.get("/api/frame");
    let serial = u32::from_le_bytes(frame.body[4..8].try_into().unwrap());
    let same = viewer.get(&format!("/api/frame?since={serial}"));
    assert_eq!((same.status, same.body.len()), (204, 0));
    viewer.command("step");
    let next = viewer.get(&format!("/api/frame?since={serial}"));
    assert_eq!(next.status, 200);
    assert_ne!(next.body[4..8], frame.body[4..8]);
}

#[test]
fn dragging_pulls_a_free_vertex_to_its_target_through_the_solver() {
    let viewer = Viewer::start("net.json");
    viewer.pause();
    viewer.command("reset");
    let centre = 40; // the middle of the 9 × 9 net, not pinned
    let rest = viewer.positions()[centre];
    let target = [f64::from(rest[0]), 0.5, f64::from(rest[2])];
    let start =
        viewer.post_command(&json!({"command": "drag_start", "vertex": centre, "target": target}));
    assert_eq!(start.status, 200, "{}", start.text());
    assert_eq!(start.json()["dragged"], centre);
    viewer.command("step");
    let pulled = viewer.positions()[centre];
    assert!((f64::from(pulled[1]) - 0.5).abs() < 1e-4, "{pulled:?}");

    let moved = [target[0], -0.5, target[2]];
    let to = viewer.post_command(&json!({"command": "drag_to", "target": moved}));
    assert_eq!(to.status, 200, "{}", to.text());
    viewer.command("step");
    assert!((f64::from(viewer.positions()[centre][1]) + 0.5).abs() < 1e-4);

    assert_eq!(viewer.command("drag_end")["dragged"], Value::Null);
    let after = viewer.post_command(&json!({"command": "drag_to", "target": moved}));
    assert_eq!(after.status, 409, "nothing is dragged any more");
    let pinned =
        viewer.post_command(&json!({"command": "drag_start", "vertex": 0, "target": target}));
    assert_eq!(pinned.status, 409, "a pinned vertex stays put");
    assert!(pinned.json()["error"].as_str().unwrap().contains("pinned"));
    let beyond =
        viewer.post_command(&json!({"command": "drag_start", "vertex": 81, "target": target}));
    assert_eq!(beyond.status, 409);
    let far = viewer
        .post_command(&json!({"command": "drag_start", "vertex": centre, "target": [1e300, 0, 0]}));
    assert_eq!(far.status, 409, "a target far from the scene is refused");
    assert_eq!(viewer.status()["dragged"], Value::Null);
}

#[test]
fn malformed_commands_are_refused_and_change_nothing() {
    let viewer = Viewer::start("net.json");
    let before = viewer.pause();
    for body in [
        json!({"command": "explode"}),
        json!({"command": "drag_to", "target": [1, 2]}),
        json!({"command": "step", "extra": 1}),
        json!(["step"]),
    ] {
        let response = viewer.post_command(&body);
        assert_eq!(response.status, 400, "{body}: {}", response.text());
        assert!(response.json()["error"].is_string());
    }
    let not_json = format!(
        "POST /api/command HTTP/1.1\r\nHost: {}\r\nContent-Type: text/plain\r\nContent-Length: 18\r\n\
         Connection: close\r\n\r\n{{\"command\":\"step\"}}",
        viewer.address
    );
    assert_eq!(viewer.exchange(not_json.as_bytes()).unwrap().status, 415);
    assert_eq!(viewer.get("/api/command").status, 405);
    let post_page = format!(
        "POST / HTTP/1.1\r\nHost: {}\r\nContent-Length: 0\r\nConnection: close\r\n\r\n",
        viewer.address
    );
    assert_eq!(viewer.exchange(post_page.as_bytes()).unwrap().status, 405);
    assert_eq!(viewer.status()["steps"], before["steps"]);
}

#[test]
fn path_traversal_and_unknown_paths_get_4xx_and_leak_no_file() {
    let viewer = Viewer::start("flag.json");
    let long = format!("/{}", "a/".repeat(3000));
    let targets = [
        "/../Cargo.toml",
        "/%2e%2e/Cargo.toml",
        "/%2E%2E%2FCargo.toml",
        "/..%2fCargo.toml",
        "//etc/passwd",
        "/../../../../etc/passwd",
        "/Cargo.toml",
        "/src/main.rs",
        "/data/flag.json",
        "/flag.png",
        "/texture.png/../../Cargo.toml",
        "/viewer.js/",
        "/api/",
        "/api/status/../../Cargo.toml",
        "http://127.0.0.1/Cargo.toml",
        "*",
        "C:\\Windows\\win.ini",
        long.as_str(),
    ];
    for target in targets {
        let request = format!(
            "GET {target} HTTP/1.1\r\nHost: {}\r\nConnection: close\r\n\r\n",
            viewer.address
        );
        let response = viewer.exchange(request.as_bytes()).expect("an answer");
        assert!(
            (400..500).contains(&response.status),
            "{target}: {}",
            response.status
        );
        let text = response.text();
        assert!(
            !text.contains("[package]") && !text.contains("root:") && !text.contains("fn main"),
            "{target} leaked a file"
        );
        assert!(response.body.len() < 200, "{target}: only a short error");
    }
    assert_eq!(viewer.get("/../Cargo.toml").status, 404);
    assert_eq!(viewer.get(&long).status, 414);
    assert_eq!(viewer.get("/api/status").status, 200, "still serving");
}

#[test]
fn requests_for_another_host_name_are_refused() {
    let viewer = Viewer::start("net.json");
    let port = viewer.address.port();
    for host in [format!("evil.example:{port}"), "127.0.0.1:1".to_string()] {
        let request =
            format!("GET /api/status HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n");
        assert_eq!(
            viewer.exchange(request.as_bytes()).unwrap().status,
            403,
            "{host}"
        );
    }
    let localhost =
        format!("GET / HTTP/1.1\r\nHost: localhost:{port}\r\nConnection: close\r\n\r\n");
    assert_eq!(viewer.exchange(localhost.as_bytes()).unwrap().status, 200);
}

#[test]
fn malformed_requests_get_4xx_and_the_server_goes_on() {
    let viewer = Viewer::start("net.json");
    let huge_header = format!(
        "GET / HTTP/1.1\r\nHost: {}\r\nX-Filler: {}\r\n\r\n",
        viewer.address,
        "x".repeat(20_000)
    );
    let huge_body = format!(
        "POST /api/command HTTP/1.1\r\nHost: {}\r\nContent-Type: application/json\r\n\
         Content-Length: 10000000\r\n\r\n{}",
        viewer.address,
        "{".repeat(10_000)
    );
    let cases: Vec<(Vec<u8>, u16)> = vec![
        ((0..=255u8).cycle().take(3000).collect(), 400),
        (b"\r\n\r\n".to_vec(), 400),
        (b"GET\r\n\r\n".to_vec(), 400),
        (b"BREW / HTTP/1.1\r\nHost: x\r\n\r\n".to_vec(), 405),
        (b"GET / HTTP/9.9\r\nHost: x\r\n\r\n".to_vec(), 505),
        (b"GET / HTTP/1.1\r\n\r\n".to_vec(), 400),
        (
            b"GET / HTTP/1.1\r\nHost: x\r\nBad Header\r\n\r\n".to_vec(),
            400,
        ),
        (
            b"POST /api/command HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n".to_vec(),
            501,
        ),
        (huge_header.into_bytes(), 431),
        (huge_body.into_bytes(), 413),
    ];
    for (request, expected) in cases {
        let preview = String::from_utf8_lossy(&request[..request.len().min(40)]).into_owned();
        if let Some(response) = viewer.exchange(&request) {
            assert_eq!(response.status, expected, "{preview:?}");
        } // else the server closed the connection, which is also fine
        assert_eq!(viewer.get("/api/status").status, 200, "after {preview:?}");
    }
}

#[test]
fn an_unfinished_request_times_out_without_blocking_others() {
    let viewer = Viewer::start("net.json");
    let mut slow = viewer.connect();
    slow.write_all(b"GET /api/status HTTP/1.1\r\nHost: 127.0.0.1\r\n")
        .unwrap();
    let mut idle = viewer.connect(); // connects and says nothing
    let started = Instant::now();
    for _ in 0..5 {
        assert_eq!(
            viewer.get("/api/status").status,
            200,
            "others are served meanwhile"
        );
    }
    // A slow-loris client keeps trickling bytes; it is cut off all the same.
    for _ in 0..3 {
        thread::sleep(Duration::from_millis(500));
        let _ = slow.write_all(b"X-Trickle: 1\r\n");
    }
    let mut answer = Vec::new();
    let _ = slow.read_to_end(&mut answer);
    let waited = started.elapsed();
    let response = HttpResponse::parse(&answer).expect("an answer before the close");
    assert_eq!(response.status, 408);
    assert!(waited < Duration::from_secs(10), "cut off after {waited:?}");
    let _ = idle.write_all(b"GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
    assert_eq!(viewer.get("/api/status").status, 200);
}

#[test]
fn five_hundred_idle_connections_and_a_client_reopening_them_do_not_starve_the_status() {
    use std::collections::VecDeque;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let viewer = Viewer::start("net.json");
    // 500 connections that say nothing (the pool holds 64: the server
    // closes the oldest waiting one for each new one).
    let mut idle: VecDeque<TcpStream> = (0..500).map(|_| viewer.connect()).collect();
    // A client that keeps reopening them, one a millisecond, for 4 s at most.
    let stop = Arc::new(AtomicBool::new(false));
    let reopener = {
        let (address, stop) = (viewer.address, Arc::clone(&stop));
        thread::spawn(move || {
            let deadline = Instant::now() + Duration::from_secs(4);
            let mut reopened = 0;
            while Instant::now() < deadline && !stop.load(Ordering::SeqCst) {
                idle.pop_front();
                if let Ok(stream) = TcpStream::connect_timeout(&address, Duration::from_secs(1)) {
                    idle.push_back(stream);
                    reopened += 1;
                }
                thread::sleep(Duration::from_millis(1));
            }
            reopened
        })
    };
    thread::sleep(Duration::from_millis(200));
    for _ in 0..10 {
        let asked = Instant::now();
        let response = viewer.get("/api/status");
        let waited = asked.elapsed();
        assert_eq!(response.status, 200);
        assert!(waited < Duration::from_secs(1), "answered after {waited:?}");
        thread::sleep(Duration::from_millis(150));
    }
    stop.store(true, Ordering::SeqCst);
    let reopened = reopener.join().unwrap();
    assert!(
        reopened > 100,
        "the hostile client reopened only {reopened}"
    );
}

#[test]
fn two_clients_on_kept_alive_connections_both_get_frames() {
    let viewer = Viewer::start("net.json");
    viewer.command("toggle_animation"); // it starts paused
    let address = viewer.address;
    let clients: Vec<_> = (0..2)
        .map(|_| {
            thread::spawn(move || {
                let mut stream = TcpStream::connect(address).unwrap();
                stream
                    .set_read_timeout(Some(Duration::from_secs(15)))
                    .unwrap();
                let mut serials = Vec::new();
                for _ in 0..30 {
                    let request = format!("GET /api/frame HTTP/1.1\r\nHost: {address}\r\n\r\n");
                    stream.write_all(request.as_bytes()).unwrap();
                    let response = read_one_response(&mut stream);
                    assert_eq!(response.status, 200);
                    assert_eq!(response.header("connection"), Some("keep-alive"));
                    assert_eq!(response.body.len(), 16 + 12 * 81);
                    serials.push(u32::from_le_bytes(response.body[4..8].try_into().unwrap()));
                    thread::sleep(Duration::from_millis(10));
                }
                serials
            })
        })
        .collect();
    for client in clients {
        let serials = client.join().expect("the client succeeded");
        assert!(
            serials.windows(2).all(|w| w[0] <= w[1]),
            "frames move forward"
        );
        assert!(
            serials.last() > serials.first(),
            "the animation ran meanwhile"
        );
    }
}

#[test]
fn sigint_stops_the_server_with_status_0() {
    let mut viewer = Viewer::start("net.json");
    assert_eq!(viewer.get("/api/status").status, 200);
    let mut open = viewer.connect(); // a connection left open does not hold it up
    let _ = open.write_all(b"GET / HT");
    let killed = Command::new("kill")
        .args(["-INT", &viewer.child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let status = viewer
        .wait_for_exit(Duration::from_secs(3))
        .expect("exits within 3 s of SIGINT");
    assert_eq!(status.code(), Some(0), "{status:?}");
    assert!(
        TcpStream::connect_timeout(&viewer.address, Duration::from_secs(1)).is_err(),
        "no longer listening"
    );
}

/// Sends `POST /api/command` with `command` on a new connection and
/// returns the connection without reading the answer.
fn send_command(viewer: &Viewer, command: &str) -> TcpStream {
    let body = json!({ "command": command }).to_string();
    let request = format!(
        "POST /api/command HTTP/1.1\r\nHost: {}\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        viewer.address,
        body.len()
    );
    let mut stream = viewer.connect();
    stream.write_all(request.as_bytes()).unwrap();
    stream
}

#[test]
fn sigterm_stops_the_viewer_within_a_second_even_in_the_middle_of_a_step() {
    // 1000 Newton iterations on the skirt: a step of minutes.
    let flags = ["--method", "newton", "--iterations", "1000"];
    let mut viewer = Viewer::start_with("skirt.json", &flags, None);
    let _stepping = send_command(&viewer, "step");
    thread::sleep(Duration::from_millis(1000));
    let killed = Command::new("kill")
        .args(["-TERM", &viewer.child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let status = viewer
        .wait_for_exit(Duration::from_millis(1000))
        .expect("exits within 1 s of SIGTERM, mid-step");
    assert_eq!(status.code(), Some(0), "{status:?}");
}

/// Waits up to `limit` for `condition` on the status; returns it.
fn wait_for(viewer: &Viewer, limit: Duration, condition: impl Fn(&Value) -> bool) -> Value {
    let deadline = Instant::now() + limit;
    loop {
        let status = viewer.status();
        if condition(&status) {
            return status;
        }
        assert!(Instant::now() < deadline, "timed out: {status}");
        thread::sleep(Duration::from_millis(50));
    }
}

/// The skirt with 1000 Newton iterations a step: a step of minutes,
/// started and seen in progress.
fn viewer_in_a_long_step() -> Viewer {
    let flags = ["--method", "newton", "--iterations", "1000"];
    let viewer = Viewer::start_with("skirt.json", &flags, None);
    let _stepping = send_command(&viewer, "step");
    wait_for(&viewer, Duration::from_secs(30), |s| {
        s["busy"].as_str().is_some_and(|b| b.starts_with("step 1"))
    });
    viewer
}

#[test]
fn a_command_during_a_long_step_is_answered_at_once_and_applied_after_it() {
    let viewer = viewer_in_a_long_step();
    let started = Instant::now();
    let wind = viewer.post_command(&json!({"command": "toggle_wind"}));
    let answered = started.elapsed();
    assert_eq!(wind.status, 202, "{}", wind.text());
    // Queued behind a step that will not end soon, it is answered as soon
    // as it is queued: a few milliseconds, where a fixed wait for the step
    // (400 ms) used to be.
    assert!(
        answered < Duration::from_millis(250),
        "answered after {answered:?}"
    );
    let waiting = wind.json();
    assert_eq!(waiting["wind"], false, "not applied yet");
    assert!(waiting["busy_ms"].as_f64().unwrap() > 0.0, "{waiting}");
    assert_eq!(waiting["queued"], 1, "{waiting}");
    // The step is cancelled (below); the wind waited for it and then blew.
    let started = Instant::now();
    let cancel = viewer.post_command(&json!({"command": "cancel"}));
    assert!(matches!(cancel.status, 200 | 202), "{}", cancel.text());
    assert!(started.elapsed() < Duration::from_millis(500));
    // The step ends first, then the queue is worked through: the status
    // may show the one without the other for a moment.
    let after = wait_for(&viewer, Duration::from_secs(5), |s| {
        s["busy"].is_null() && s["wind"] == true
    });
    assert_eq!(
        after["steps"], 0,
        "the cancelled step is not counted: {after}"
    );
}

#[test]
fn a_cancelled_step_leaves_the_simulation_at_its_last_completed_step() {
    let viewer = Viewer::start_with("skirt.json", &["--iterations", "5"], None);
    let first = viewer.command("step");
    assert_eq!(first["steps"], 1);
    let before = viewer.positions();
    let long = json!({"command": "set_method", "method": "newton", "tolerance": null});
    assert_eq!(viewer.post_command(&long).status, 200);
    let budget = json!({"command": "set_parameters", "k": first["k"], "delta_t": first["delta_t"],
        "mass_scale": 1.0, "iterations": 1000});
    assert_eq!(viewer.post_command(&budget).status, 200);
    let _stepping = send_command(&viewer, "step");
    wait_for(&viewer, Duration::from_secs(30), |s| !s["busy"].is_null());
    thread::sleep(Duration::from_millis(300));
    let started = Instant::now();
    assert_ne!(
        viewer.post_command(&json!({"command": "cancel"})).status,
        503
    );
    let after = wait_for(&viewer, Duration::from_secs(5), |s| s["busy"].is_null());
    assert!(
        started.elapsed() < Duration::from_secs(3),
        "{:?}",
        started.elapsed()
    );
    assert_eq!(after["steps"], 1, "{after}");
    assert_eq!(after["animating"], false);
    let note = after["note"].as_str().unwrap_or("");
    assert!(
        note.contains("step 2 cancelled") && note.contains("stays at step 1"),
        "{after}"
    );
    assert_eq!(
        viewer.positions(),
        before,
        "the last completed step's positions"
    );
    assert_eq!(viewer.status()["history"].as_array().unwrap().len(), 1);
    // The next step runs (the cancel is over), from there.
    let short = json!({"command": "set_parameters", "k": first["k"], "delta_t": first["delta_t"],
        "mass_scale": 1.0, "iterations": 2});
    assert_eq!(viewer.post_command(&short).status, 200);
    let plain = json!({"command": "set_method", "method": "plain", "tolerance": null});
    assert_eq!(viewer.post_command(&plain).status, 200);
    assert_eq!(viewer.command("step")["steps"], 2);
}

#[test]
fn commands_beyond_the_queue_are_refused_with_a_reason_and_never_applied() {
    let viewer = viewer_in_a_long_step();
    let answers: Vec<u16> = thread::scope(|scope| {
        let sent: Vec<_> = (0..32)
            .map(|_| scope.spawn(|| viewer.post_command(&json!({"command": "toggle_springs"}))))
            .collect();
        sent.into_iter().map(|h| h.join().unwrap().status).collect()
    });
    assert!(answers.iter().all(|&status| status == 202), "{answers:?}");
    let refused = viewer.post_command(&json!({"command": "toggle_springs"}));
    assert_eq!(refused.status, 503, "{}", refused.text());
    assert!(refused.text().contains("not applied"), "{}", refused.text());
    let shown = viewer.status()["show_springs"].clone();
    viewer.post_command(&json!({"command": "cancel"}));
    let after = wait_for(&viewer, Duration::from_secs(10), |s| s["queued"] == 0);
    assert_eq!(
        after["show_springs"], shown,
        "32 toggles applied, the refused one not"
    );
}

#[test]
fn the_url_printed_for_another_loopback_address_answers() {
    let viewer = Viewer::start_with("net.json", &["--address", "127.0.0.2"], None);
    assert!(viewer.address.to_string().starts_with("127.0.0.2:"));
    let page = viewer.get("/");
    assert_eq!(page.status, 200, "{}", page.text());
    assert_eq!(viewer.get("/api/status").status, 200);
}

#[test]
fn the_scene_picker_lists_each_name_once_when_the_scenes_are_a_copy_of_the_bundled_ones() {
    let folder = std::env::temp_dir().join(format!("masssprings-copy-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    for entry in std::fs::read_dir(data("")).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, folder.join(path.file_name().unwrap())).unwrap();
    }
    let viewer = Viewer::start_in(&folder, "flag.json");
    let mut scenes: Vec<String> =
        serde_json::from_value(viewer.status()["scenes"].clone()).unwrap();
    assert_eq!(scenes[0], "flag");
    let listed = scenes.len();
    scenes.sort();
    scenes.dedup();
    assert_eq!(scenes.len(), listed, "{scenes:?}");
    assert!(scenes.contains(&"skirt".to_string()), "{scenes:?}");
    drop(viewer);
    let _ = std::fs::remove_dir_all(&folder);
}

#[test]
fn an_accuracy_viewer_keeps_its_accuracy_through_changes_of_its_rules() {
    let viewer = Viewer::start_with("flag.json", &["--accuracy", "assignment"], None);
    let start = viewer.status();
    assert_eq!(start["solver"], "accuracy-assignment", "{start}");
    assert_eq!(start["plain_first"], true);
    let rules = |start: &str| {
        json!({"command": "set_method", "method": "lbfgs", "tolerance": null,
            "energy_tolerance": start_value(&viewer, "energy_tolerance"),
            "at_least_plain": 50, "start": start})
    };
    let inertial = viewer.post_command(&rules("inertial")).json();
    assert_eq!(
        (inertial["solver"].clone(), inertial["plain_first"].clone()),
        (Value::Null, json!(true))
    );
    let back = viewer.post_command(&rules("current")).json();
    assert_eq!(back["solver"], "accuracy-assignment", "{back}");
    assert_eq!(back["energy_tolerance"], start["energy_tolerance"]);
    let budget = json!({"command": "set_parameters", "k": back["k"], "delta_t": back["delta_t"],
        "mass_scale": 1.0, "iterations": 40});
    assert_eq!(
        viewer.post_command(&budget).json()["solver"],
        "accuracy-assignment"
    );
    // Another method is the expert's: L-BFGS picked again runs without plain first.
    viewer.post_command(&json!({"command": "set_method", "method": "newton", "tolerance": null}));
    let lbfgs = viewer.post_command(&rules("current")).json();
    assert_eq!(
        (lbfgs["solver"].clone(), lbfgs["plain_first"].clone()),
        (Value::Null, json!(false))
    );
    let solver = json!({"command": "set_solver", "solver": "accuracy-assignment"});
    assert_eq!(
        viewer.post_command(&solver).json()["solver"],
        "accuracy-assignment"
    );
}

/// The status's `name`, now.
fn start_value(viewer: &Viewer, name: &str) -> Value {
    viewer.status()[name].clone()
}

#[test]
fn the_solve_picker_switches_paths_by_the_command_lines_rules() {
    let viewer = Viewer::start("net.json");
    let status = viewer.status();
    assert_eq!(status["solver"], "assignment");
    let solvers: Vec<String> = serde_json::from_value(status["solvers"].clone()).unwrap();
    assert_eq!(solvers, ["assignment", "textbook", "accuracy-assignment"]);
    viewer.command("step");
    for (solver, backend, functions) in [
        ("textbook", "dense", "fast_mass_springs_step_dense"),
        ("textbook", "sparse", "fast_mass_springs_step_sparse"),
        ("accuracy-assignment", "sparse", "plain_then_lbfgs"),
        ("assignment", "dense", "methods/plain.rs"),
    ] {
        let command = json!({"command": "set_solver", "solver": solver, "backend": backend});
        let set = viewer.post_command(&command);
        assert_eq!(set.status, 200, "{}", set.text());
        let set = set.json();
        assert_eq!(
            (set["solver"].as_str(), set["backend"].as_str()),
            (Some(solver), Some(backend))
        );
        assert!(
            set["functions"].as_str().unwrap().contains(functions),
            "{set}"
        );
        assert_eq!(set["steps"], 1, "it goes on from where it was");
        assert_eq!(viewer.command("step")["steps"], 2);
        viewer.command("reset");
        viewer.command("step");
    }
    viewer.post_command(&json!({"command": "set_solver", "solver": "textbook"}));
    let method = json!({"command": "set_method", "method": "plain", "tolerance": null,
        "start": "inertial"});
    let refused = viewer.post_command(&method);
    assert_eq!(refused.status, 409);
    assert!(
        refused
            .text()
            .contains("the textbook path runs the handout's step"),
        "{}",
        refused.text()
    );
    let unknown = viewer.post_command(&json!({"command": "set_solver", "solver": "magic"}));
    assert_eq!(unknown.status, 409);
    assert!(
        unknown.text().contains("unknown solver"),
        "{}",
        unknown.text()
    );
}

#[test]
fn a_comparison_steps_both_from_the_same_start_and_commands_act_on_both() {
    let viewer = Viewer::start("flag.json");
    viewer.command("step");
    let compare = json!({"command": "compare", "with": "accuracy-assignment"});
    let started = viewer.post_command(&compare);
    assert_eq!(started.status, 200, "{}", started.text());
    assert_eq!(started.json()["compare"]["solver"], "accuracy-assignment");
    let frame = viewer.get("/api/frame");
    let n = 3200;
    assert_eq!(frame.body.len(), 16 + 2 * 12 * n, "both sets of positions");
    assert_eq!(
        frame.body[16..16 + 12 * n],
        frame.body[16 + 12 * n..],
        "the same start"
    );
    viewer.command("toggle_wind");
    for _ in 0..3 {
        viewer.command("step");
    }
    let status = viewer.status();
    let compare = &status["compare"];
    assert_eq!(compare["history"].as_array().unwrap().len(), 3, "{status}");
    let (first, second) = (&status["history"][3], &compare["history"][2]);
    assert_eq!(
        (first["step"].clone(), second["step"].clone()),
        (json!(4), json!(4))
    );
    for record in [first, second] {
        assert!(
            record["energy_decrease"].as_f64().unwrap() > 0.0,
            "{record}"
        );
        assert!(record["ms"].as_f64().unwrap() > 0.0, "{record}");
    }
    let drag = json!({"command": "drag_start", "vertex": 3199, "target": [2.0, 1.0, 0.5]});
    assert_eq!(viewer.post_command(&drag).status, 200);
    viewer.command("step");
    let frame = viewer.get("/api/frame");
    let at = |set: usize| {
        let start = 16 + 12 * (set * n + 3199);
        [0, 4, 8]
            .map(|k| f32::from_le_bytes(frame.body[start + k..start + k + 4].try_into().unwrap()))
    };
    for set in [0, 1] {
        let p = at(set);
        assert!(
            (p[0] - 2.0).abs() < 1e-3 && (p[2] - 0.5).abs() < 1e-3,
            "set {set}: {p:?}"
        );
    }
    viewer.command("drag_end");
    let stop = viewer
        .post_command(&json!({"command": "compare", "with": null}))
        .json();
    assert_eq!(stop["compare"], Value::Null);
    assert_eq!(viewer.get("/api/frame").body.len(), 16 + 12 * n);
}

#[test]
fn the_image_of_a_frame_is_a_png_drawn_for_the_pages_camera() {
    let viewer = Viewer::start("flag.json");
    let query = "w=200&h=120&tx=1&ty=0.5&tz=0&az=0.5&el=0.35&d=4&fov=0.61&sx=0&sy=0&springs=0&ox=0";
    let image = viewer.get(&format!("/api/image?{query}"));
    assert_eq!(image.status, 200, "{}", image.text());
    assert_eq!(image.header("content-type"), Some("image/png"));
    assert!(image.body.starts_with(b"\x89PNG\r\n\x1a\n"));
    let width = u32::from_be_bytes(image.body[16..20].try_into().unwrap());
    let height = u32::from_be_bytes(image.body[20..24].try_into().unwrap());
    assert_eq!((width, height), (200, 120));
    let bad = viewer.get(&format!("/api/image?{}", query.replace("w=200", "w=1e9")));
    assert_eq!(bad.status, 400);
    assert!(bad.text().contains("w="), "{}", bad.text());
    assert_eq!(viewer.get("/api/image").status, 400);
}

#[test]
fn clients_that_do_not_read_are_evicted_like_idle_ones() {
    let viewer = Viewer::start("skirt.json");
    let request = format!(
        "GET /api/scene HTTP/1.1\r\nHost: {}\r\n\r\n",
        viewer.address
    );
    let silent: Vec<TcpStream> = (0..64)
        .map(|_| {
            let mut stream = viewer.connect();
            stream.write_all(request.as_bytes()).unwrap();
            stream
        })
        .collect();
    thread::sleep(Duration::from_millis(500));
    let started = Instant::now();
    assert_eq!(viewer.get("/api/status").status, 200);
    assert!(
        started.elapsed() < Duration::from_secs(2),
        "{:?}",
        started.elapsed()
    );
    drop(silent);
}

#[test]
fn wrong_command_lines_exit_with_2_and_bad_scenes_with_1() {
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_masssprings"))
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .unwrap()
            .code()
    };
    assert_eq!(run(&["view"]), Some(2));
    assert_eq!(run(&["view", &data("net.json"), "--port", "http"]), Some(2));
    assert_eq!(
        run(&["view", &data("net.json"), "--address", "nowhere"]),
        Some(2)
    );
    assert_eq!(run(&["view", &data("net.json"), "--bogus"]), Some(2));
    assert_eq!(run(&["view", &data("no-such-scene.json")]), Some(1));
}

#[test]
fn the_method_and_tolerance_apply_to_later_steps_and_show_in_the_history() {
    let viewer = Viewer::start("net.json");
    let before = viewer.status();
    assert_eq!(before["method"], "plain");
    assert_eq!(before["tolerance"], Value::Null);
    let methods: Vec<String> = serde_json::from_value(before["methods"].clone()).unwrap();
    assert_eq!(
        methods,
        ["plain", "chebyshev", "anderson", "lbfgs", "newton"]
    );
    let set = viewer
        .post_command(&json!({"command": "set_method", "method": "newton", "tolerance": 1e-6}));
    assert_eq!(set.status, 200, "{}", set.text());
    assert_eq!(
        (
            set.json()["method"].clone(),
            set.json()["tolerance"].clone()
        ),
        (json!("newton"), json!(1e-6))
    );
    let stepped = viewer.command("step");
    let record = &stepped["history"][0];
    assert!(
        record["relative_gradient"].as_f64().unwrap() <= 1e-6,
        "{record}"
    );
    assert!(record["iterations"].as_u64().unwrap() < 50, "{record}");
    assert_eq!(record["converged"], true);
    assert!(record["energy_decrease"].as_f64().unwrap() >= 0.0);
    for bad in [
        json!({"command": "set_method", "method": "magic", "tolerance": null}),
        json!({"command": "set_method", "method": "plain", "tolerance": 2.0}),
    ] {
        assert_eq!(viewer.post_command(&bad).status, 409, "{bad}");
    }
    assert_eq!(viewer.status()["method"], "newton");
}

#[test]
fn the_energy_tolerance_applies_to_later_steps_and_shows_in_the_status() {
    let viewer = Viewer::start("flag.json");
    assert_eq!(viewer.status()["energy_tolerance"], Value::Null);
    let command = json!({"command": "set_method", "method": "chebyshev", "tolerance": null,
        "energy_tolerance": 0.1});
    let set = viewer.post_command(&command);
    assert_eq!(set.status, 200, "{}", set.text());
    assert_eq!(set.json()["energy_tolerance"], json!(0.1));
    let stepped = viewer.command("step");
    let record = &stepped["history"][0];
    // the rule stops the flag's first step long before 50 iterations
    assert!(record["iterations"].as_u64().unwrap() < 50, "{record}");
    assert_eq!(record["converged"], true, "{record}");
    let bad = json!({"command": "set_method", "method": "plain", "tolerance": null,
        "energy_tolerance": 1.5});
    assert_eq!(viewer.post_command(&bad).status, 409, "{bad}");
    // absent: no such rule
    let plain = viewer.post_command(&json!({"command": "set_method", "method": "plain",
        "tolerance": null}));
    assert_eq!(plain.json()["energy_tolerance"], Value::Null);
}

#[test]
fn the_floor_of_at_least_plain_applies_to_later_steps_and_shows_in_the_status() {
    let viewer = Viewer::start("flag.json");
    assert_eq!(viewer.status()["at_least_plain"], Value::Null);
    let command = json!({"command": "set_method", "method": "lbfgs", "tolerance": null,
        "at_least_plain": 5});
    let set = viewer.post_command(&command);
    assert_eq!(set.status, 200, "{}", set.text());
    assert_eq!(set.json()["at_least_plain"], json!(5.0));
    let stepped = viewer.command("step");
    let record = &stepped["history"][0];
    // five first plain decreases: L-BFGS gets there long before 50 iterations
    assert!(record["iterations"].as_u64().unwrap() < 50, "{record}");
    assert_eq!(record["converged"], true, "{record}");
    for bad in [0.5, 2e6] {
        let bad = json!({"command": "set_method", "method": "plain", "tolerance": null,
            "at_least_plain": bad});
        assert_eq!(viewer.post_command(&bad).status, 409, "{bad}");
    }
    // absent: no floor
    let plain = viewer.post_command(&json!({"command": "set_method", "method": "plain",
        "tolerance": null}));
    assert_eq!(plain.json()["at_least_plain"], Value::Null);
}

#[test]
fn serving_beyond_loopback_warns_that_anyone_can_drive_it() {
    for (address, warns) in [("0.0.0.0", true), ("127.0.0.1", false)] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_masssprings"))
            .args([
                "view",
                &data("net.json"),
                "--port",
                "0",
                "--address",
                address,
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the binary runs");
        // the URL on standard output: it is serving
        let mut url = String::new();
        BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut url)
            .unwrap();
        assert!(url.starts_with("http://"), "{address}: {url:?}");
        child.kill().unwrap();
        child.wait().unwrap();
        let mut errors = String::new();
        child
            .stderr
            .take()
            .expect("piped")
            .read_to_string(&mut errors)
            .unwrap();
        assert_eq!(
            errors.contains("no authentication") && errors.contains("anyone who can reach"),
            warns,
            "{address}: {errors}"
        );
    }
}

#[test]
fn the_dense_setup_names_what_it_takes_and_stops_on_a_cancel() {
    let viewer = Viewer::start("flag.json");
    let before = viewer.status();
    assert_eq!(before["dense_fits"], true, "{before}");
    let need = before["dense_memory"].as_str().unwrap().to_string();
    assert!(
        need.starts_with(
            "the dense path for n = 3,200 (12,442 springs; five n × n matrices of f64): 0.7"
        ) && need.ends_with(" GB"),
        "{need}"
    );
    // Minutes of work: answered while it runs, and shown with its memory.
    let dense = json!({"command": "set_solver", "solver": "textbook", "backend": "dense"});
    assert_eq!(viewer.post_command(&dense).status, 202);
    let busy = viewer.status()["busy"].as_str().unwrap_or("").to_string();
    assert_eq!(
        busy,
        format!(
            "precomputing for textbook (dense): {}",
            need.replace("): ", "), ")
        )
    );
    thread::sleep(Duration::from_millis(200));
    let started = Instant::now();
    let springs = viewer.post_command(&json!({"command": "toggle_springs"}));
    assert_eq!(springs.status, 202, "{}", springs.text());
    assert!(
        started.elapsed() < Duration::from_millis(250),
        "{:?}",
        started.elapsed()
    );
    let cancel = viewer.post_command(&json!({"command": "cancel"}));
    assert!(matches!(cancel.status, 200 | 202), "{}", cancel.text());
    let after = wait_for(&viewer, Duration::from_secs(10), |s| {
        s["busy"].is_null() && s["queued"] == 0
    });
    let note = after["note"].as_str().unwrap_or("");
    assert!(
        note.starts_with("precomputing for textbook (dense)")
            && note.contains(": cancelled after ")
            && note.ends_with("s; nothing changed"),
        "{after}"
    );
    assert_eq!(after["solver"], "assignment");
    assert_eq!(after["backend"], "sparse");
    assert_eq!(after["show_springs"], true, "the command queued behind it");
    // The next steps run: the cancel is over.
    assert_eq!(viewer.command("step")["steps"], 1);
}

#[test]
fn reset_returns_to_the_scene_as_it_loaded_and_restart_keeps_the_settings() {
    let viewer = Viewer::start("net.json");
    let loaded = viewer.status();
    let changed = json!({"command": "set_parameters", "k": 50.0, "delta_t": 0.01,
        "mass_scale": 2.0, "iterations": 7});
    assert_eq!(viewer.post_command(&changed).status, 200);
    viewer.command("toggle_wind");
    viewer.command("step");
    viewer.command("toggle_animation");
    let restarted = viewer.command("restart");
    assert_eq!(restarted["steps"], 0);
    assert_eq!(restarted["time"], 0.0);
    assert_eq!(restarted["animating"], true, "restart keeps playing");
    let kept = |s: &Value| {
        (
            s["k"].clone(),
            s["delta_t"].clone(),
            s["mass_scale"].clone(),
        )
    };
    assert_eq!(kept(&restarted), (json!(50.0), json!(0.01), json!(2.0)));
    assert_eq!(
        (restarted["iterations"].clone(), restarted["wind"].clone()),
        (json!(7), json!(true))
    );
    let reset = viewer.command("reset");
    assert_eq!(reset["animating"], false, "reset pauses");
    assert_eq!(reset["steps"], 0);
    assert_eq!(kept(&reset), kept(&loaded));
    assert_eq!(reset["iterations"], loaded["iterations"]);
    assert_eq!(reset["wind"], false);
    assert_eq!(reset["solver"], "assignment");
}

#[test]
fn the_simulated_time_adds_each_steps_own_time_step() {
    let viewer = Viewer::start("net.json");
    for _ in 0..3 {
        viewer.command("step");
    }
    let status = viewer.status();
    let shorter = json!({"command": "set_parameters", "k": status["k"], "delta_t": 0.01,
        "mass_scale": 1.0, "iterations": status["iterations"]});
    assert_eq!(viewer.post_command(&shorter).status, 200);
    viewer.command("step");
    let time = viewer.command("step")["time"].as_f64().unwrap();
    assert!((time - (3.0 / 30.0 + 0.02)).abs() < 1e-12, "t = {time}");
}

/// `masssprings simulate data/SCENE --steps N --out DIR`, in a new folder
/// under the system's temporary one.
fn frames_of(scene: &str, steps: usize, name: &str) -> std::path::PathBuf {
    let folder =
        std::env::temp_dir().join(format!("masssprings-frames-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&folder);
    let written = Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args([
            "simulate",
            &data(scene),
            "--steps",
            &steps.to_string(),
            "--out",
        ])
        .arg(&folder)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(written.success());
    folder
}

#[test]
fn frames_written_by_simulate_play_beside_the_viewers_at_distance_zero() {
    let folder = frames_of("net.json", 8, "same");
    let mut command = Command::new(env!("CARGO_BIN_EXE_masssprings"));
    command
        .args(["view", &data("net.json"), "--port", "0", "--frames"])
        .arg(&folder);
    let viewer = Viewer::spawn(command, None);
    let status = viewer.status();
    assert_eq!(status["compare"]["solver"], "frames", "{status}");
    assert_eq!(status["frames"]["steps"], 8);
    for step in 1..=8 {
        assert_eq!(viewer.command("step")["steps"], step);
    }
    let history = viewer.status()["compare"]["history"].clone();
    let distances: Vec<f64> = history
        .as_array()
        .unwrap()
        .iter()
        .map(|record| record["distance"].as_f64().unwrap())
        .collect();
    assert_eq!(distances, vec![0.0; 8]);
    let past = viewer.command("step");
    assert_eq!(past["compare"]["ended"], true);
    assert_eq!(past["compare"]["history"][8]["distance"], Value::Null);
    let _ = std::fs::remove_dir_all(&folder);
}

/// `masssprings view data/SCENE --frames FOLDER`: its exit code and what
/// it says on standard error.
fn view_frames(scene: &str, folder: &Path) -> (Option<i32>, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_masssprings"))
        .args(["view", &data(scene), "--port", "0", "--frames"])
        .arg(folder)
        .stdout(Stdio::null())
        .output()
        .unwrap();
    (
        output.status.code(),
        String::from_utf8_lossy(&output.stderr).into_owned(),
    )
}

#[test]
fn frames_of_another_scene_or_with_a_gap_are_refused_naming_why() {
    let net = frames_of("net.json", 3, "other");
    let (code, said) = view_frames("flag.json", &net);
    assert_eq!(code, Some(1), "{said}");
    assert!(
        said.contains("frame-000000.obj: 81 vertices, but the scene")
            && said.contains("flag.json has 3,200"),
        "{said}"
    );
    std::fs::remove_file(net.join("frame-000002.obj")).unwrap();
    let (code, said) = view_frames("net.json", &net);
    assert_eq!(code, Some(1), "{said}");
    assert!(
        said.contains("a gap in the numbering: frame-000003.obj follows frame-000001.obj"),
        "{said}"
    );
    std::fs::copy(net.join("frame-000001.obj"), net.join("mine_1.obj")).unwrap();
    let (code, said) = view_frames("net.json", &net);
    assert_eq!(code, Some(1), "{said}");
    assert!(
        said.contains("numbered OBJ files of 2 kinds (frame-N.obj, mine_N.obj)"),
        "{said}"
    );
    for entry in std::fs::read_dir(&net).unwrap() {
        std::fs::remove_file(entry.unwrap().path()).unwrap();
    }
    let (code, said) = view_frames("net.json", &net);
    assert_eq!(code, Some(1), "{said}");
    assert!(said.contains("no numbered OBJ files"), "{said}");
    let _ = std::fs::remove_dir_all(&net);
}

#[test]
fn a_programs_own_numbered_frames_are_read_in_the_order_of_their_numbers() {
    let written = frames_of("net.json", 11, "renamed");
    let folder = written.with_file_name(format!(
        "{}-mine",
        written.file_name().unwrap().to_string_lossy()
    ));
    std::fs::create_dir_all(&folder).unwrap();
    for step in 0..=11 {
        let from = written.join(format!("frame-{step:06}.obj"));
        std::fs::copy(from, folder.join(format!("cloth{}.obj", step + 1))).unwrap();
    }
    let mut command = Command::new(env!("CARGO_BIN_EXE_masssprings"));
    command
        .args(["view", &data("net.json"), "--port", "0", "--frames"])
        .arg(&folder);
    let viewer = Viewer::spawn(command, None);
    for step in 1..=11 {
        assert_eq!(viewer.command("step")["steps"], step);
    }
    let history = viewer.status()["compare"]["history"].clone();
    assert!(
        history
            .as_array()
            .unwrap()
            .iter()
            .all(|record| record["distance"] == 0.0),
        "{history}"
    );
    let _ = std::fs::remove_dir_all(&folder);
    let _ = std::fs::remove_dir_all(&written);
}
