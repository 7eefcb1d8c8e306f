//! `masssprings view SCENE.json`: the interactive viewer. The simulation
//! runs in this process; a browser page draws it with WebGL.
//!
//! Threads:
//!
//! * the **simulation thread** ([`simulation_thread`]) owns the simulation,
//!   steps it in real time (Δt = 1/30 s) while animating, applies commands,
//!   and publishes the positions and the status;
//! * the **acceptor** (this file) takes connections and gives each its own
//!   **connection thread** (at most [`MAX_CONNECTIONS`] at once: when full,
//!   the connection waiting longest is closed to make room, see [`pool`]),
//!   which reads requests with [`http`] and answers them with [`routes`];
//! * the **main thread** waits for Ctrl-C (SIGINT, or SIGTERM), then stops
//!   the other two and returns, so the program exits with status 0 (within
//!   [`STOP_GRACE`] even in the middle of a long step, which is dropped).
//!
//! The page polls `GET /api/frame` once per animation frame of the browser
//! and posts key presses and drags to `POST /api/command` ([`api`]).

mod api;
mod display_mesh;
mod http;
mod pool;
mod routes;
mod simulation_thread;
mod watchers;

use super::error::AppError;
use super::file_plan::load_scene;
use super::flags::{whole, SimulationFlags};
use super::limits::precompute;
use api::{Frame, Status};
use http::{Connection, Method, ReadError};
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, Sparse};
use pool::{Member, Pool};
use routes::Routes;
use simulation_thread::{Message, SceneAssets, Shared, SimulationThread, MAX_ITERATIONS};
use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::thread;
use std::time::Duration;
use watchers::Watchers;

/// The port when `--port` is not given.
const DEFAULT_PORT: u16 = 8080;
/// Connections served at once (a few tabs need a handful each); a new one
/// beyond closes the one waiting longest ([`pool`]).
const MAX_CONNECTIONS: usize = 64;
/// Scenes listed in the page's picker at most.
const MAX_SCENES: usize = 32;
/// Serve an interactive viewer of the scene to a web browser.
#[derive(clap::Args, Debug)]
#[command(after_help = "\
Serves an interactive viewer on http://127.0.0.1:P/ and prints its URL. The
simulation runs here, starting paused at rest, and steps only while playing
and a page shows it; the page draws it with WebGL, with buttons, a scene
picker, sliders for k, Δt, mass scale and iterations, a method picker and a
convergence plot. Keys: space step, A play, L springs, R reset, W wind,
F fit, M method, ? help; drag to orbit, right-drag to pan, wheel to zoom,
shift-drag to pull a vertex. Ctrl-C stops it.

The viewer has no authentication: it binds to the loopback address unless
--address says otherwise, and anyone who can reach that port can drive it.")]
pub struct ViewArgs {
    /// The scene: JSON that names an OBJ (data/README.md).
    #[arg(value_name = "SCENE.json")]
    scene: PathBuf,
    /// Port to serve on (0 picks a free one).
    #[arg(long, value_name = "P", default_value_t = DEFAULT_PORT, value_parser = port)]
    port: u16,
    /// Address to serve on (0.0.0.0 serves every network: anyone who reaches it can drive the viewer).
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1", value_parser = address)]
    address: IpAddr,
    #[command(flatten)]
    simulation: SimulationFlags,
}

/// `--port`: 0 to 65535.
fn port(text: &str) -> Result<u16, String> {
    whole(0, usize::from(u16::MAX))(text).map(|port| port as u16)
}

/// `--address`: an IP address.
fn address(text: &str) -> Result<IpAddr, String> {
    text.trim()
        .parse()
        .map_err(|_| format!("expected an IP address such as 127.0.0.1 or ::1, got '{text}'"))
}

pub fn run(args: ViewArgs) -> Result<(), AppError> {
    let scene = load_scene(&args.scene)?;
    let address = SocketAddr::new(args.address, args.port);
    if !args.address.is_loopback() {
        eprintln!(
            "masssprings: warning: serving on {}: the viewer has no authentication, and \
             anyone who can reach this port can drive it (and read the scenes it lists)",
            args.address
        );
    }
    let scenes = scene_list(&args.scene);
    let mut options = SimulationOptions::default();
    args.simulation.apply(&mut options);
    options.step.measure = true; // the viewer plots every step's gradient
    if options.step.iterations > MAX_ITERATIONS {
        return Err(AppError::Usage(format!(
            "--iterations {}: the viewer takes at most {MAX_ITERATIONS} a step (as its slider \
             does), so that every step ends within moments",
            options.step.iterations
        )));
    }
    if args.simulation.backend.dense {
        serve::<Dense>(&scene, scenes, address, options)
    } else {
        serve::<Sparse>(&scene, scenes, address, options)
    }
}

/// The scenes the page can switch to: the one given first, then the
/// bundled ones in the project's `data/` folder (when it is there) and the
/// others beside the given one, each once, by name.
fn scene_list(given: &Path) -> Vec<PathBuf> {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    // `net.json`'s parent is the empty path, which names no folder to list.
    let beside = match given.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mut scenes = vec![given.to_path_buf()];
    let mut seen = vec![std::fs::canonicalize(given).unwrap_or_else(|_| given.to_path_buf())];
    for folder in [bundled, beside] {
        let Ok(entries) = std::fs::read_dir(&folder) else {
            continue;
        };
        let mut found: Vec<PathBuf> = entries
            .filter_map(|entry| entry.ok().map(|e| e.path()))
            .filter(|path| path.extension().is_some_and(|e| e == "json"))
            .collect();
        found.sort();
        for path in found {
            let canonical = std::fs::canonicalize(&path).unwrap_or_else(|_| path.clone());
            if !seen.contains(&canonical) && scenes.len() < MAX_SCENES {
                seen.push(canonical);
                scenes.push(path);
            }
        }
    }
    scenes
}

/// Starts the threads, prints the URL, and serves until Ctrl-C.
fn serve<B>(
    scene: &Scene,
    scenes: Vec<PathBuf>,
    address: SocketAddr,
    options: SimulationOptions,
) -> Result<(), AppError>
where
    B: LinearAlgebra + 'static,
    Simulation<B>: Send,
{
    let simulation = precompute::<B>(scene, &scenes[0], options)?;
    let listener = TcpListener::bind(address).map_err(|e| bind_error(address, &e))?;
    let local = listener.local_addr()?;
    let stop_requested = stop_signal()?;

    let shared = shared_state::<B>(scene);
    // A cloth shows its surface; a scene made only of springs, its springs.
    let show_springs = scene.faces.first().is_none_or(|face| face.len() < 3);
    let (commands, inbox) = mpsc::channel();
    let simulation_thread =
        SimulationThread::new(simulation, Arc::clone(&shared), show_springs, scenes, 0);
    let simulation_handle = thread::Builder::new()
        .name("simulation".into())
        .spawn(move || simulation_thread.run(inbox))?;

    let routes = Arc::new(Routes {
        shared,
        commands: commands.clone(),
        allowed_hosts: allowed_hosts(local),
    });
    let stopping = Arc::new(AtomicBool::new(false));
    let acceptor = {
        let stopping = Arc::clone(&stopping);
        thread::Builder::new()
            .name("acceptor".into())
            .spawn(move || accept_connections(listener, routes, &stopping))?
    };

    println!("http://{local}/");
    std::io::stdout().flush()?;

    // Blocks until Ctrl-C; an error means the handler is gone, so stop too.
    let _ = stop_requested.recv();
    eprintln!("masssprings: stopping");
    stopping.store(true, Ordering::SeqCst);
    let _ = commands.send(Message::Quit);
    if wake_acceptor(local) {
        let _ = acceptor.join();
    }
    // The simulation thread sees Quit after the step it is in; a long step
    // is not waited for: returning ends the process, and the step with it.
    let grace = std::time::Instant::now() + STOP_GRACE;
    while !simulation_handle.is_finished() && std::time::Instant::now() < grace {
        thread::sleep(Duration::from_millis(10));
    }
    Ok(())
}

/// What the simulation thread and the connections share, before the first
/// step: the rest frame, the status, the scene's assets, no watchers.
fn shared_state<B: LinearAlgebra>(scene: &Scene) -> Arc<Shared> {
    Arc::new(Shared {
        frame: Mutex::new(Frame::new(scene.vertices.len())),
        status: Mutex::new(Status {
            scene: scene.name.clone(),
            backend: B::NAME,
            n: scene.vertices.len(),
            springs: scene.springs.len(),
            ..Status::default()
        }),
        scene: Mutex::new(SceneAssets::of(scene, B::NAME)),
        watchers: Mutex::new(Watchers::default()),
    })
}

/// How long a stopping viewer waits for the step in progress to end.
const STOP_GRACE: Duration = Duration::from_millis(500);

/// Why the server cannot listen, in plain words.
fn bind_error(address: SocketAddr, error: &std::io::Error) -> AppError {
    let port = address.port();
    match error.kind() {
        std::io::ErrorKind::AddrInUse => AppError::Failed(format!(
            "port {port} is in use (another viewer?); try --port 0, which picks a free one"
        )),
        std::io::ErrorKind::PermissionDenied if port < 1024 => AppError::Failed(format!(
            "port {port} needs special rights; try a port from 1024, or --port 0"
        )),
        std::io::ErrorKind::AddrNotAvailable => AppError::Failed(format!(
            "{} is not an address of this machine; try 127.0.0.1",
            address.ip()
        )),
        _ => AppError::Failed(format!("cannot listen on {address}: {error}")),
    }
}

/// A channel that receives once when the user presses Ctrl-C (SIGINT) or
/// the process gets SIGTERM.
fn stop_signal() -> Result<mpsc::Receiver<()>, AppError> {
    let (sender, receiver) = mpsc::channel();
    ctrlc::set_handler(move || {
        let _ = sender.send(());
    })
    .map_err(|e| AppError::Failed(format!("cannot install the Ctrl-C handler: {e}")))?;
    Ok(receiver)
}

/// The `Host` values a browser sends for a loopback server; `None` (accept
/// any) when serving on another address.
fn allowed_hosts(local: SocketAddr) -> Option<Vec<String>> {
    if !local.ip().is_loopback() {
        return None;
    }
    let port = local.port();
    let names = ["127.0.0.1", "localhost", "[::1]"];
    let mut hosts: Vec<String> = names.iter().map(|name| format!("{name}:{port}")).collect();
    if port == 80 {
        hosts.extend(names.iter().map(|name| name.to_string()));
    }
    Some(hosts)
}

/// Accepts connections until `stopping`, one thread each, at most
/// [`MAX_CONNECTIONS`] (the pool closes the one waiting longest for a new
/// one).
fn accept_connections(listener: TcpListener, routes: Arc<Routes>, stopping: &AtomicBool) {
    let pool = Pool::new(MAX_CONNECTIONS);
    for stream in listener.incoming() {
        if stopping.load(Ordering::SeqCst) {
            return;
        }
        let stream = match stream {
            Ok(stream) => stream,
            Err(error) => {
                // Out of file descriptors, say: wait a little and go on.
                eprintln!("masssprings: accept: {error}");
                thread::sleep(Duration::from_millis(50));
                continue;
            }
        };
        let Some(member) = pool.admit(&stream) else {
            continue; // every connection is being answered: dropping closes it
        };
        let routes = Arc::clone(&routes);
        let spawned = thread::Builder::new()
            .name("connection".into())
            .spawn(move || serve_connection(stream, &routes, &member));
        if let Err(error) = spawned {
            eprintln!("masssprings: cannot start a connection thread: {error}");
        }
    }
}

/// Answers requests on one connection until it closes, times out, asks to
/// close, is evicted from the pool, or sends something malformed (answered
/// with a 4xx, then closed).
fn serve_connection(stream: TcpStream, routes: &Routes, member: &Member) {
    let Ok(mut connection) = Connection::new(stream) else {
        return;
    };
    loop {
        member.waiting();
        let request = connection.read_request();
        member.answering();
        match request {
            Ok(request) => {
                let response = routes.respond(&request);
                let head_only = request.method == Method::Head;
                // Sending waits on the client, as reading does: a client
                // that does not read may be evicted like an idle one.
                member.waiting();
                if connection
                    .write_response(&response, head_only, request.keep_alive)
                    .is_err()
                {
                    return;
                }
                if !request.keep_alive {
                    connection.close_gracefully();
                    return;
                }
            }
            Err(ReadError::Closed) => return,
            Err(ReadError::Reject(response)) => {
                let _ = connection.write_response(&response, false, false);
                connection.close_gracefully();
                return;
            }
        }
    }
}

/// Unblocks the acceptor's `accept` by connecting to it; false when that
/// failed (the acceptor is then left to end with the process).
fn wake_acceptor(local: SocketAddr) -> bool {
    let ip = match local.ip() {
        IpAddr::V4(ip) if ip.is_unspecified() => IpAddr::V4(Ipv4Addr::LOCALHOST),
        IpAddr::V6(ip) if ip.is_unspecified() => IpAddr::V6(Ipv6Addr::LOCALHOST),
        ip => ip,
    };
    TcpStream::connect_timeout(&SocketAddr::new(ip, local.port()), Duration::from_secs(1)).is_ok()
}
