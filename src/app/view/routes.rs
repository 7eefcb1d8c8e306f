//! Which request gets which answer. The table is fixed: a path is compared
//! literally with the few the viewer serves, and no part of a request is ever
//! turned into a file name. The page, its script and style are compiled into
//! the binary; the texture was read, when the scene was loaded, from the
//! path the scene names.
//! Everything else is `404`.

use super::api::{Command, Status};
use super::http::{Method, Request, Response};
use super::image;
use super::simulation_thread::{Message, Reply, SceneAssets, Shared};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

const PAGE: &str = include_str!("assets/viewer.html");
const SCRIPT: &str = include_str!("assets/viewer.js");
const BACKEND: &str = include_str!("assets/backend.js");
const PLOT: &str = include_str!("assets/plot.js");
const STYLE: &str = include_str!("assets/viewer.css");

/// The page may load only what this server serves: no network beyond it.
const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'self'; \
     style-src 'self'; img-src 'self' data:; connect-src 'self'; base-uri 'none'; \
     form-action 'none'; frame-ancestors 'none'";

/// How long a command waits for the simulation thread's answer before the
/// page is told (`202`) that it is being applied, or waits for the work in
/// progress (a long step, a precomputation), and will be applied after it.
const ANSWER_WITHIN: Duration = Duration::from_millis(400);

/// Work that will not end within this is not waited for: a command queued
/// behind it is answered (`202`) at once.
const SOON: Duration = Duration::from_millis(100);

/// How often a command waiting for its answer looks again whether the
/// work ahead of it will end soon.
const LOOK_AGAIN: Duration = Duration::from_millis(10);

/// Commands that may wait for the simulation thread at once; one more is
/// refused (`503`, not applied), but a cancel, which always goes through.
const MAX_QUEUED: usize = 32;

/// Everything a request can be answered from.
pub struct Routes {
    pub shared: Arc<Shared>,
    /// The simulation thread's inbox.
    pub commands: Sender<Message>,
    /// The `Host` values accepted (`127.0.0.1:8080`, `localhost:8080`, …),
    /// or `None` to accept any (when serving beyond loopback). Refusing other
    /// names stops a web page elsewhere from reaching the viewer by DNS
    /// rebinding.
    pub allowed_hosts: Option<Vec<String>>,
}

impl Routes {
    /// The answer to `request`.
    pub fn respond(&self, request: &Request) -> Response {
        if !self.host_allowed(request.header("host")) {
            return Response::error(403, "unexpected Host");
        }
        let read_only = matches!(request.method, Method::Get | Method::Head);
        match request.path.as_str() {
            "/" | "/index.html" if read_only => {
                Response::new(200, "text/html; charset=utf-8", PAGE)
                    .with_header("Content-Security-Policy", CONTENT_SECURITY_POLICY)
            }
            "/viewer.js" if read_only => script(SCRIPT),
            "/backend.js" if read_only => script(BACKEND),
            "/plot.js" if read_only => script(PLOT),
            "/viewer.css" if read_only => Response::new(200, "text/css; charset=utf-8", STYLE),
            "/texture.png" if read_only => match self.scene_assets().1 {
                Some(png) => Response::new(200, "image/png", png.to_vec()),
                None => Response::error(404, "this scene has no texture"),
            },
            "/api/scene" if read_only => {
                let json = self.scene_assets().0;
                Response::new(200, "application/json", json.as_bytes().to_vec())
            }
            "/api/status" if read_only => json_status(&self.status()),
            "/api/frame" if read_only => self.frame(request.query.as_deref()),
            "/api/image" if read_only => image::respond(&self.shared, request.query.as_deref()),
            "/api/command" if request.method == Method::Post => self.command(request),
            "/" | "/index.html" | "/viewer.js" | "/backend.js" | "/plot.js" | "/viewer.css"
            | "/texture.png" | "/api/scene" | "/api/status" | "/api/frame" | "/api/image" => {
                Response::error(405, "use GET").with_header("Allow", "GET, HEAD")
            }
            "/api/command" => Response::error(405, "use POST").with_header("Allow", "POST"),
            _ => Response::error(404, "no such page"),
        }
    }

    fn host_allowed(&self, host: Option<&str>) -> bool {
        match (&self.allowed_hosts, host) {
            (None, _) | (_, None) => true,
            (Some(allowed), Some(host)) => allowed.iter().any(|name| name == host),
        }
    }

    /// The published status, with the work in progress as it is now.
    fn status(&self) -> Status {
        let mut status = Shared::lock(&self.shared.status).clone();
        if let Some(busy) = Shared::lock(&self.shared.busy).clone() {
            status.busy_ms = Some(1e3 * busy.since.elapsed().as_secs_f64());
            status.busy = Some(busy.what);
        }
        status.queued = self.shared.queued.load(Ordering::SeqCst);
        status
    }

    /// The scene's JSON and texture (shared, not copied).
    fn scene_assets(&self) -> (Arc<str>, Option<Arc<[u8]>>) {
        let assets: std::sync::MutexGuard<'_, SceneAssets> = Shared::lock(&self.shared.scene);
        (Arc::clone(&assets.json), assets.texture.clone())
    }

    /// The latest frame, or `204` when it is still serial `since`. Counts
    /// the asking page (`page=ID`) as watching.
    fn frame(&self, query: Option<&str>) -> Response {
        let parameter = |name: &str| {
            query.and_then(|q| {
                q.split('&')
                    .find_map(|pair| pair.strip_prefix(name)?.strip_prefix('='))
            })
        };
        let since = parameter("since").and_then(|value| value.parse::<u32>().ok());
        let page = parameter("page").and_then(|value| value.parse::<u64>().ok());
        self.shared
            .watchers
            .lock()
            .expect("no thread panics holding it")
            .seen(page);
        let frame = self
            .shared
            .frame
            .lock()
            .expect("no thread panics holding it");
        if since == Some(frame.serial()) {
            return Response::new(204, "application/octet-stream", Vec::new());
        }
        Response::new(200, "application/octet-stream", frame.bytes().to_vec())
    }

    /// Parses a command and hands it to the simulation thread; answers
    /// with its result, or that it is accepted (`202`, the status as it is
    /// now, and the header `X-Command: applying` when it is the work in
    /// progress, `waiting` when it waits for it: it is applied after it,
    /// and a refusal then shows in the status's note): at once when it
    /// waits for work that will not end [`SOON`], after [`ANSWER_WITHIN`]
    /// otherwise. A cancel sets the flag the step in progress looks at
    /// first.
    fn command(&self, request: &Request) -> Response {
        let media_type = request.header("content-type").unwrap_or("");
        let media_type = media_type.split(';').next().unwrap_or("").trim();
        // Requiring JSON also means a page of another origin cannot post a
        // command without the browser asking this server first (CORS), which
        // it never allows.
        if !media_type.eq_ignore_ascii_case("application/json") {
            return Response::error(415, "send application/json");
        }
        let command = match Command::from_json(&request.body) {
            Ok(command) => command,
            Err(why) => return json_error(400, &why),
        };
        let cancel = command == (Command::Cancel {});
        if cancel {
            self.shared.cancel.store(true, Ordering::SeqCst);
        }
        let waiting = self.shared.queued.load(Ordering::SeqCst);
        if waiting >= MAX_QUEUED && !cancel {
            let why = format!(
                "{waiting} commands already wait for the simulation ({}); not applied",
                self.status().busy.unwrap_or_else(|| "busy".into())
            );
            return json_error(503, &why);
        }
        self.shared.queued.fetch_add(1, Ordering::SeqCst);
        let (reply_to, reply) = mpsc::channel::<Reply>();
        let taken = Arc::new(AtomicBool::new(false));
        let message = Message::Command(command, reply_to, Arc::clone(&taken));
        if self.commands.send(message).is_err() {
            self.shared.queued.fetch_sub(1, Ordering::SeqCst);
            return json_error(503, "the simulation has stopped");
        }
        let asked = Instant::now();
        loop {
            let taken = taken.load(Ordering::SeqCst);
            let left = ANSWER_WITHIN.saturating_sub(asked.elapsed());
            if left.is_zero() || (!taken && self.work_ends_late()) {
                return self.accepted(taken);
            }
            match reply.recv_timeout(left.min(LOOK_AGAIN)) {
                Ok(Ok(())) => return json_status(&self.status()),
                Ok(Err(why)) => return json_error(409, &why),
                Err(RecvTimeoutError::Timeout) => continue,
                Err(RecvTimeoutError::Disconnected) => {
                    return json_error(503, "the simulation has stopped")
                }
            }
        }
    }

    /// Will the work in progress run beyond [`SOON`]? Past the time such
    /// work takes (or with no such time known), it is taken to run as long
    /// again as it has.
    fn work_ends_late(&self) -> bool {
        let Some(busy) = Shared::lock(&self.shared.busy).clone() else {
            return false;
        };
        let elapsed = busy.since.elapsed();
        let left = match busy.expected {
            Some(expected) if elapsed < expected => expected - elapsed,
            _ => elapsed,
        };
        left > SOON
    }

    /// `202`: the command is being applied (`taken`), or waits its turn.
    fn accepted(&self, taken: bool) -> Response {
        let state = match taken {
            true => "applying",
            false => "waiting",
        };
        let mut accepted = json_status(&self.status()).with_header("X-Command", state);
        accepted.status = 202;
        accepted
    }
}

/// One of the page's scripts.
fn script(text: &'static str) -> Response {
    Response::new(200, "text/javascript; charset=utf-8", text)
}

fn json_status(status: &Status) -> Response {
    let body = serde_json::to_vec(status).expect("plain data serialises");
    Response::new(200, "application/json", body)
}

fn json_error(status: u16, message: &str) -> Response {
    let body = serde_json::json!({ "error": message }).to_string();
    Response::new(status, "application/json", body)
}
