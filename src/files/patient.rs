//! Pipes that cannot hang a command: a FIFO (named pipe) or a terminal is
//! opened without blocking, and reading or writing it waits for the other
//! side at most [`PATIENCE`] without progress, then fails with a sentence
//! saying so.
//!
//! Opening a FIFO the ordinary way blocks until a program opens its other
//! end, and reading it blocks while that program writes nothing: a FIFO
//! nobody writes to would hang the command forever. Opened with
//! `O_NONBLOCK`, a read returns at once (`EAGAIN` while the writer is
//! quiet, 0 bytes while no writer has come yet or after it left), and a
//! write either goes through or returns `EAGAIN` (reader slow) or `ENXIO`
//! at opening (no reader). These types turn those answers into waiting with
//! a deadline.

use std::fs::{File, OpenOptions};
use std::io::{self, Read, Write};
use std::path::Path;
use std::time::{Duration, Instant};

/// The longest a pipe may stay silent (no byte read or written) before the
/// command gives up on it.
pub const PATIENCE: Duration = Duration::from_secs(5);

/// How long to sleep between two tries.
const POLL: Duration = Duration::from_millis(5);

/// `O_NONBLOCK` of this platform (the standard library does not export it);
/// `None` where not known here, and a pipe is then opened the ordinary way.
#[cfg(unix)]
const O_NONBLOCK: Option<i32> = if cfg!(any(target_os = "linux", target_os = "android")) {
    if cfg!(any(
        target_arch = "mips",
        target_arch = "mips64",
        target_arch = "sparc",
        target_arch = "sparc64"
    )) {
        None
    } else {
        Some(0o4000)
    }
} else if cfg!(any(
    target_os = "macos",
    target_os = "ios",
    target_os = "freebsd",
    target_os = "openbsd",
    target_os = "netbsd",
    target_os = "dragonfly"
)) {
    Some(4)
} else {
    None
};

/// The regular file at `path`, opened for reading, or `None` when there is
/// none (a FIFO, a device, a folder, nothing): opened without blocking, so
/// a FIFO put where a file was expected is never waited for, and checked
/// on the open file, so it cannot be swapped in between.
pub fn open_regular(path: &Path) -> Option<File> {
    let file = open_without_blocking(path, OpenOptions::new().read(true)).ok()?;
    file.metadata().is_ok_and(|m| m.is_file()).then_some(file)
}

fn open_without_blocking(path: &Path, options: &mut OpenOptions) -> io::Result<File> {
    #[cfg(unix)]
    if let Some(flag) = O_NONBLOCK {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(flag);
    }
    options.open(path)
}

/// Tries `attempt` until it answers (`Ok(Some)`) or fails, sleeping
/// between tries; `Ok(None)` and the "try again" errors (`EAGAIN`, `EINTR`)
/// mean not yet. After [`PATIENCE`] since `since`, the error `silent` says
/// what did not happen.
fn patiently<T>(
    since: Instant,
    silent: &str,
    mut attempt: impl FnMut() -> io::Result<Option<T>>,
) -> io::Result<T> {
    loop {
        match attempt() {
            Ok(Some(answer)) => return Ok(answer),
            Ok(None) => {}
            Err(error)
                if matches!(
                    error.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                ) => {}
            Err(error) => return Err(error),
        }
        if since.elapsed() > PATIENCE {
            return Err(io::Error::new(
                io::ErrorKind::TimedOut,
                format!(
                    "{silent} for {} s; gave up (a pipe or terminal is waited for at most that \
                     long)",
                    since.elapsed().as_secs()
                ),
            ));
        }
        std::thread::sleep(POLL);
    }
}

/// A non-regular input (a FIFO, a terminal, a device) read without ever
/// blocking for longer than [`PATIENCE`].
pub struct PatientReader {
    file: File,
    /// A FIFO reads 0 bytes before its writer came as after it left: until
    /// the first byte, 0 means "not yet".
    fifo: bool,
    got_data: bool,
    last_progress: Instant,
}

impl PatientReader {
    /// Opens `path` for reading without blocking.
    ///
    /// # Errors
    /// The error of opening.
    pub fn open(path: &Path, fifo: bool) -> io::Result<PatientReader> {
        let file = open_without_blocking(path, OpenOptions::new().read(true))?;
        Ok(PatientReader {
            file,
            fifo,
            got_data: false,
            last_progress: Instant::now(),
        })
    }
}

impl Read for PatientReader {
    fn read(&mut self, buffer: &mut [u8]) -> io::Result<usize> {
        let silent = if self.got_data {
            "the pipe sent nothing more"
        } else {
            "nothing was written to the pipe"
        };
        let waiting_for_writer = self.fifo && !self.got_data && !buffer.is_empty();
        let file = &mut self.file;
        let count = patiently(self.last_progress, silent, || match file.read(buffer)? {
            0 if waiting_for_writer => Ok(None),
            count => Ok(Some(count)),
        })?;
        self.got_data |= count > 0;
        self.last_progress = Instant::now();
        Ok(count)
    }
}

/// A FIFO written without ever blocking for longer than [`PATIENCE`]: it
/// waits that long for a reader to open the other end, and for a reader
/// that stopped reading.
pub struct PatientWriter {
    file: File,
    last_progress: Instant,
}

impl PatientWriter {
    /// Opens the FIFO at `path` for writing, waiting for a reader.
    ///
    /// # Errors
    /// No reader came within [`PATIENCE`], or the error of opening.
    pub fn open(path: &Path) -> io::Result<PatientWriter> {
        let silent = "no program opened the FIFO to read it";
        let file = patiently(Instant::now(), silent, || {
            match open_without_blocking(path, OpenOptions::new().write(true)) {
                Ok(file) => Ok(Some(file)),
                // ENXIO (6 on Linux and the BSDs): no process has the FIFO
                // open for reading yet.
                Err(error) if error.raw_os_error() == Some(6) => Ok(None),
                Err(error) => Err(error),
            }
        })?;
        Ok(PatientWriter {
            file,
            last_progress: Instant::now(),
        })
    }
}

impl Write for PatientWriter {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        let silent = "the program reading the FIFO read nothing";
        let file = &mut self.file;
        let count = patiently(self.last_progress, silent, || file.write(bytes).map(Some))?;
        self.last_progress = Instant::now();
        Ok(count)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}
