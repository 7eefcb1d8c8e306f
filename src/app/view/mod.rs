//! `masssprings view SCENE.json`: the interactive viewer. The simulation
//! runs in this process; a browser page draws it with WebGL.
//!
//! Threads:
//!
//! * the **simulation thread** ([`simulation_thread`]) owns the simulation,
//!   steps it in real time (Δt = 1/30 s) while animating, applies commands,
//!   and publishes the positions and the status;
//! * the **acceptor** (this file) takes connections and gives each its own
//!   **connection thread** (at most [`MAX_CONNECTIONS`] at once), which
//!   reads requests with [`http`] and answers them with [`routes`];
//! * the **main thread** waits for Ctrl-C (SIGINT, or SIGTERM), then stops
//!   the other two and returns, so the program exits with status 0.
//!
//! The page polls `GET /api/frame` once per animation frame of the browser
//! and posts key presses and drags to `POST /api/command` ([`api`]).

mod api;
mod display_mesh;
mod http;
mod routes;
mod simulation_thread;

use super::args::Args;
use super::convergence_flags;
use super::factorization_flags;
use super::AppError;
use api::{Frame, Status};
use http::{Connection, Method, ReadError};
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, Sparse};
use routes::Routes;
use simulation_thread::{Message, Shared, SimulationThread};
use std::io::Write;
use std::net::{IpAddr, Ipv4Addr, Ipv6Addr, SocketAddr, TcpListener, TcpStream};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc, Mutex};
use std::thread;
use std::time::Duration;

/// The port when `--port` is not given.
const DEFAULT_PORT: u16 = 8080;
/// Connections served at once; more are closed at once (a few tabs need a
/// handful each).
const MAX_CONNECTIONS: usize = 64;
/// The first bytes of every PNG file.
const PNG_SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";

pub fn run(args: &[String]) -> Result<(), AppError> {
    let mut options = vec!["port", "address"];
    options.extend(convergence_flags::OPTIONS);
    options.extend(factorization_flags::OPTIONS);
    let args = Args::parse(args, &options, &["dense"])?;
    let mut simulation_options = SimulationOptions::default();
    convergence_flags::apply(&args, &mut simulation_options)?;
    factorization_flags::apply(&args, &mut simulation_options)?;
    let scene_path = PathBuf::from(args.single_positional("SCENE.json")?);
    let port: u16 = args.value_or("port", DEFAULT_PORT)?;
    let ip: IpAddr = args.value_or("address", IpAddr::V4(Ipv4Addr::LOCALHOST))?;
    let scene = load_scene(&scene_path)?;
    let texture = read_texture(&scene);
    let address = SocketAddr::new(ip, port);
    if args.switch("dense") {
        serve::<Dense>(&scene, texture, address, simulation_options)
    } else {
        serve::<Sparse>(&scene, texture, address, simulation_options)
    }
}

/// The scene's PNG texture, read from the path the scene names; `None`
/// (with a warning) when it cannot be read or is not a PNG.
fn read_texture(scene: &Scene) -> Option<Vec<u8>> {
    let path = scene.texture.as_ref()?;
    match std::fs::read(path) {
        Ok(bytes) if bytes.starts_with(PNG_SIGNATURE) => Some(bytes),
        Ok(_) => {
            eprintln!(
                "masssprings: warning: {} is not a PNG file; drawing without texture",
                path.display()
            );
            None
        }
        Err(error) => {
            eprintln!(
                "masssprings: warning: {}: {error}; drawing without texture",
                path.display()
            );
            None
        }
    }
}

/// Starts the threads, prints the URL, and serves until Ctrl-C.
fn serve<B>(
    scene: &Scene,
    texture: Option<Vec<u8>>,
    address: SocketAddr,
    options: SimulationOptions,
) -> Result<(), AppError>
where
    B: LinearAlgebra + 'static,
    Simulation<B>: Send,
{
    let simulation = Simulation::<B>::from_scene(scene, options)?;
    let listener = TcpListener::bind(address)
        .map_err(|e| AppError::Failed(format!("cannot listen on {address}: {e}")))?;
    let local = listener.local_addr()?;
    let stop_requested = stop_signal()?;

    let shared = Arc::new(Shared {
        frame: Mutex::new(Frame::new(scene.vertices.len())),
        status: Mutex::new(Status {
            scene: scene.name.clone(),
            backend: B::NAME,
            n: scene.vertices.len(),
            springs: scene.springs.len(),
            ..Status::default()
        }),
    });
    let mesh = display_mesh::display_mesh(scene, texture.is_some(), B::NAME);
    // A cloth shows its surface; a scene made only of springs, its springs.
    let show_springs = mesh.triangles.is_empty();
    let (commands, inbox) = mpsc::channel();
    let simulation_thread = SimulationThread::new(simulation, Arc::clone(&shared), show_springs);
    let simulation_handle = thread::Builder::new()
        .name("simulation".into())
        .spawn(move || simulation_thread.run(inbox))?;

    let routes = Arc::new(Routes {
        shared,
        commands: commands.clone(),
        scene_json: serde_json::to_string(&mesh).expect("plain data serialises"),
        texture,
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
    let _ = simulation_handle.join();
    Ok(())
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

/// Accepts connections until `stopping`, one thread each.
fn accept_connections(listener: TcpListener, routes: Arc<Routes>, stopping: &AtomicBool) {
    let active = Arc::new(AtomicUsize::new(0));
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
        if active.load(Ordering::SeqCst) >= MAX_CONNECTIONS {
            continue; // dropping the stream closes it
        }
        let routes = Arc::clone(&routes);
        let count = ActiveConnection::new(Arc::clone(&active));
        let spawned = thread::Builder::new()
            .name("connection".into())
            .spawn(move || {
                let _count = count;
                serve_connection(stream, &routes);
            });
        if let Err(error) = spawned {
            eprintln!("masssprings: cannot start a connection thread: {error}");
        }
    }
}

/// Counts a connection as active while it lives.
struct ActiveConnection(Arc<AtomicUsize>);

impl ActiveConnection {
    fn new(active: Arc<AtomicUsize>) -> Self {
        active.fetch_add(1, Ordering::SeqCst);
        ActiveConnection(active)
    }
}

impl Drop for ActiveConnection {
    fn drop(&mut self) {
        self.0.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Answers requests on one connection until it closes, times out, asks to
/// close, or sends something malformed (answered with a 4xx, then closed).
fn serve_connection(stream: TcpStream, routes: &Routes) {
    let Ok(mut connection) = Connection::new(stream) else {
        return;
    };
    loop {
        match connection.read_request() {
            Ok(request) => {
                let response = routes.respond(&request);
                let head_only = request.method == Method::Head;
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
