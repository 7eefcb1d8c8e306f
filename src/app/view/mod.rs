//! `masssprings view SCENE.json`: the interactive viewer. The simulation
//! runs in this process; a browser page draws it with WebGL.
//!
//! Threads:
//!
//! * the **simulation thread** ([`simulation_thread`]) owns the simulation
//!   (two when comparing solvers, [`solver`]), steps it in real time (Δt =
//!   1/30 s) while animating ([`stepping`]), applies commands
//!   ([`commands`]), and publishes the positions and the status
//!   ([`publish`]);
//! * the **acceptor** (this file) takes connections and gives each its own
//!   **connection thread** (at most [`MAX_CONNECTIONS`] at once: when full,
//!   the connection waiting longest is closed to make room, see [`pool`]),
//!   which reads requests with [`http`] and answers them with [`routes`];
//! * the **main thread** waits for Ctrl-C (SIGINT, or SIGTERM), then stops
//!   the other two and returns, so the program exits with status 0 (within
//!   [`STOP_GRACE`] even in the middle of a long step, which it cancels).
//!
//! The page polls `GET /api/frame` once per animation frame of the browser
//! and posts key presses and drags to `POST /api/command` ([`api`]);
//! without WebGL it shows `GET /api/image`, the frame drawn by the crate's
//! own renderer ([`image`]).

mod api;
mod commands;
mod display_mesh;
mod facing;
mod http;
mod image;
mod pool;
mod publish;
mod recording;
mod routes;
mod rules;
mod simulation_thread;
mod solver;
mod stepping;
mod watchers;

use super::error::AppError;
use super::file_plan::load_scene;
use super::flags::{whole, SimulationFlags};
use api::{Frame, Status};
use http::{Connection, Method, ReadError};
use masssprings::mesh::Scene;
use masssprings::sim::simulation::SimulationOptions;
use pool::{Member, Pool};
use recording::{read_frames, Frames};
use routes::Routes;
use simulation_thread::{Message, SceneAssets, Shared, Shown, SimulationThread, MAX_ITERATIONS};
use solver::{Backend, NotBuilt};
use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
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
and a page shows it; the page draws it with WebGL (without WebGL, as images
drawn by this program's renderer), with buttons, a scene picker, a solve
picker (the assignment, the handout's code dense or sparse, the fast mode:
the assignment's energy, not its motion), compare (a second simulation from
the same start, or your own program's frames with --frames, beside the
first or as a wireframe over it), sliders for k, Δt, mass scale and
iterations, a method picker and a plot. Esc stops whatever runs: a long
step, the dense setup, the animation. Large print (Aa) for a projector; on
a phone the panels fold into a drawer. Keys, whatever control has focus:
space step, A play, L springs, R reset (to the scene as it loaded),
shift-R restart (keeping the settings), W wind, F fit, M method, ? help;
drag to orbit, right-drag to pan, wheel to zoom, shift-drag to pull a
vertex; by touch, one finger orbits, two zoom and pan, a long press pulls.
Ctrl-C stops it.

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
    /// A folder of frames your own program wrote, one OBJ per step from rest (frame-000000.obj, … or any numbered NAME0.obj, NAME1.obj, …): played back beside the simulation, the plot showing the distance between the two at each step.
    #[arg(long, value_name = "DIR")]
    frames: Option<PathBuf>,
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
    let backend = match args.simulation.backend.dense {
        true => Backend::Dense,
        false => Backend::Sparse,
    };
    let frames = match &args.frames {
        Some(folder) => Some(Arc::new(read_frames(folder, &scene, &args.scene)?)),
        None => None,
    };
    let start = Given {
        scene,
        scenes,
        backend,
        options,
        frames,
    };
    serve(start, address)
}

/// What the command line gives the viewer to show.
struct Given {
    scene: Scene,
    scenes: Vec<PathBuf>,
    backend: Backend,
    options: SimulationOptions,
    frames: Option<Arc<Frames>>,
}

/// The scenes the page can switch to: the one given first, then the
/// others beside it and the bundled ones in the project's `data/` folder
/// (when it is there), each name once (the picker lists names: a copy of
/// `data/` elsewhere would list every bundled scene twice), the given
/// folder's first.
fn scene_list(given: &Path) -> Vec<PathBuf> {
    let bundled = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    // `net.json`'s parent is the empty path, which names no folder to list.
    let beside = match given.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let mut scenes = vec![given.to_path_buf()];
    let mut names = vec![simulation_thread::scene_name(given)];
    for folder in [beside, bundled] {
        for path in scene_files(&folder) {
            let name = simulation_thread::scene_name(&path);
            if !names.contains(&name) && scenes.len() < MAX_SCENES {
                names.push(name);
                scenes.push(path);
            }
        }
    }
    scenes
}

/// The `.json` files of `folder`, sorted (none when it cannot be read).
fn scene_files(folder: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(folder) else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = entries
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .filter(|path| path.extension().is_some_and(|e| e == "json"))
        .collect();
    found.sort();
    found
}

/// Starts the threads, prints the URL, and serves until Ctrl-C.
fn serve(given: Given, address: SocketAddr) -> Result<(), AppError> {
    let Given {
        scene,
        scenes,
        backend,
        options,
        frames,
    } = given;
    let cancel = Arc::new(AtomicBool::new(false));
    let run = first_simulation(&scene, &scenes[0], backend, options, &cancel)?;
    let listener = TcpListener::bind(address).map_err(|e| bind_error(address, &e))?;
    let local = listener.local_addr()?;
    let stop_requested = stop_signal()?;
    let shared = Arc::new(shared_state(&scene, backend, cancel));
    let (commands, inbox) = mpsc::channel();
    let start = simulation_thread::Start {
        main: Shown::new(run, backend),
        scene,
        scenes,
        scene_index: 0,
        initial: options,
        frames,
    };
    let simulation_thread = SimulationThread::new(start, Arc::clone(&shared));
    let simulation_handle = thread::Builder::new()
        .name("simulation".into())
        .spawn(move || simulation_thread.run(inbox))?;
    let routes = Arc::new(Routes {
        shared: Arc::clone(&shared),
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
    println!("{}", url_of(local));
    std::io::stdout().flush()?;

    // Blocks until Ctrl-C; an error means the handler is gone, so stop too.
    let _ = stop_requested.recv();
    eprintln!("masssprings: stopping");
    stopping.store(true, Ordering::SeqCst);
    shared.cancel.store(true, Ordering::SeqCst); // the step in progress ends
    let _ = commands.send(Message::Quit);
    if wake_acceptor(local) {
        let _ = acceptor.join();
    }
    // The simulation thread sees Quit after the step or the precomputation
    // it is in, which the flag ends at its next iteration or row; whatever
    // is still running after the grace ends with the process.
    let grace = std::time::Instant::now() + STOP_GRACE;
    while !simulation_handle.is_finished() && std::time::Instant::now() < grace {
        thread::sleep(Duration::from_millis(10));
    }
    Ok(())
}

/// The simulation the viewer starts with, refused as the command line
/// refuses it.
fn first_simulation(
    scene: &Scene,
    path: &Path,
    backend: Backend,
    options: SimulationOptions,
    cancel: &Arc<AtomicBool>,
) -> Result<Box<dyn solver::Run>, AppError> {
    solver::build(scene, path, backend, options, cancel).map_err(|not| {
        AppError::Failed(match not {
            NotBuilt::Refused(why) => why,
            NotBuilt::Cancelled => "the precomputation was cancelled".into(),
        })
    })
}

/// What the threads share, for `scene` at rest on `backend`.
fn shared_state(scene: &Scene, backend: Backend, cancel: Arc<AtomicBool>) -> Shared {
    Shared {
        frame: Mutex::new(Frame::new(scene.vertices.len(), 1)),
        status: Mutex::new(Status {
            scene: scene.name.clone(),
            backend: backend.name(),
            n: scene.vertices.len(),
            springs: scene.springs.len(),
            ..Status::default()
        }),
        scene: Mutex::new(SceneAssets::of(scene, backend.name())),
        watchers: Mutex::new(Watchers::default()),
        cancel,
        busy: Mutex::new(None),
        queued: AtomicUsize::new(0),
        drawing: Mutex::new(()),
    }
}

/// The URL a browser opens for a server listening on `local`.
fn url_of(local: SocketAddr) -> String {
    format!("http://{local}/")
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

/// The `Host` values a browser sends for a loopback server: the address
/// it listens on (the one its printed URL names: `127.0.0.2` as well as
/// `127.0.0.1`), `localhost` and the usual loopback names; `None` (accept
/// any) when serving on another address.
fn allowed_hosts(local: SocketAddr) -> Option<Vec<String>> {
    if !local.ip().is_loopback() {
        return None;
    }
    let port = local.port();
    let own = SocketAddr::new(local.ip(), 80).to_string();
    let own = own.strip_suffix(":80").expect("an address and port 80");
    let mut names = vec!["127.0.0.1", "localhost", "[::1]"];
    if !names.contains(&own) {
        names.push(own);
    }
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
