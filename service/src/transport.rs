//! Running sessions over byte streams: one on stdin/stdout, or one per loopback TCP
//! connection, concurrently.
//!
//! Every line read gets exactly one reply line, flushed at once. Lines longer than
//! [`MAX_LINE_BYTES`] are discarded without being held in memory and answered with an
//! error; the conversation then goes on. Only a failed case-base save ends the server
//! (see [`SessionError::Save`]).
//!
//! Over TCP every connection gets its own thread and its own [`Session`] (its own episode)
//! over the server's one [`SharedCases`]. A connection idle longer than its read timeout,
//! that takes longer than the read timeout to send a line once it has begun it (a slow
//! drip of bytes), or that does not take its replies within the write timeout, is closed,
//! so a stalled, slow or non-reading controller holds its slot for a bounded time; beyond
//! [`Limits::max_connections`] a new connection gets one error line and is closed.

use crate::domain::DomainDefinition;
use crate::lines::{LineRead, read_line};
use crate::reply::{self, Reply};
use crate::session::{Session, SessionError};
use crate::shared::SharedCases;
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The longest request line accepted, newline excluded.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// Why serving stopped.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ServeError {
    /// Reading requests or writing replies failed (shown in the message, so not chained
    /// as a source).
    #[error("connection: {0}")]
    Io(io::Error),
    /// The session must stop.
    #[error(transparent)]
    Session(#[from] SessionError),
    /// `--listen` named an address other than loopback.
    #[error(
        "refusing to listen on {0}: only loopback addresses (127.0.0.0/8 or ::1) are allowed, as the protocol has no authentication"
    )]
    NotLoopback(SocketAddr),
    /// The address could not be bound.
    #[error("cannot listen on {addr}: {reason}")]
    Bind {
        /// The address.
        addr: SocketAddr,
        /// Why binding failed (shown in the message, so not chained as a source).
        reason: io::Error,
    },
}

impl From<io::Error> for ServeError {
    fn from(reason: io::Error) -> Self {
        Self::Io(reason)
    }
}

/// Serves requests from `input` until it ends, writing replies to `output`.
pub fn serve<R: BufRead, W: Write>(
    session: &mut Session,
    mut input: R,
    output: W,
) -> Result<(), ServeError> {
    // Each reply goes out when it is flushed; a case listing may take several writes.
    let mut output = BufWriter::new(output);
    let mut line = Vec::new();
    while let Some(read) = read_line(&mut input, MAX_LINE_BYTES, &mut line)? {
        let (answer, stop) = match read {
            LineRead::TooLong => (
                Reply::Json(reply::error(format_args!(
                    "line too long: a request line may hold at most {MAX_LINE_BYTES} bytes; it was discarded"
                )))
                .with_id(None),
                None,
            ),
            LineRead::Line => match session.handle_line(&line) {
                Ok(answer) => (answer, None),
                Err(e) => (Reply::Json(reply::error(&e)).with_id(None), Some(e)),
            },
        };
        answer.write_line(&mut output)?;
        output.flush()?;
        if let Some(e) = stop {
            return Err(e.into());
        }
    }
    Ok(())
}

/// Binds a loopback address; any other address is refused.
pub fn listen(addr: SocketAddr) -> Result<TcpListener, ServeError> {
    if !addr.ip().is_loopback() {
        return Err(ServeError::NotLoopback(addr));
    }
    TcpListener::bind(addr).map_err(|reason| ServeError::Bind { addr, reason })
}

/// The longest [`Limits::read_timeout`] and [`Limits::write_timeout`] a server is given
/// (`serve --idle-timeout`, `--write-timeout`): a day. A silent controller keeps its slot
/// that long at most, and every deadline (now plus a timeout) stays far from where an
/// `Instant` overflows.
pub const MAX_TIMEOUT: Duration = Duration::from_secs(86_400);

/// The bounds that keep one controller from holding up the others.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Connections served at once; more are refused with an error line.
    pub max_connections: usize,
    /// How long a connection may stay silent before it is closed.
    pub read_timeout: Duration,
    /// How long a reply may wait for the controller to read it before the connection is
    /// closed.
    pub write_timeout: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_connections: 64,
            read_timeout: Duration::from_secs(300),
            write_timeout: Duration::from_secs(10),
        }
    }
}

/// What the connection threads share with the accepting loop.
struct Server {
    domain: DomainDefinition,
    cases: Arc<SharedCases>,
    seed: u64,
    limits: Limits,
    open: AtomicUsize,
    /// Set by a connection whose session must stop the server.
    failed: Mutex<Option<SessionError>>,
    stopping: AtomicBool,
    log: Box<dyn Fn(&str) + Send + Sync>,
}

/// Serves controllers connecting to `listener`, each on its own thread with its own
/// session (connection `k`, counting from 0, seeded with `seed + k`) over the shared case
/// memory `cases`, for ever or until a session must stop. `log` hears of connections
/// opening, closing and being refused.
pub fn serve_tcp(
    domain: DomainDefinition,
    cases: Arc<SharedCases>,
    seed: u64,
    listener: &TcpListener,
    limits: Limits,
    log: Box<dyn Fn(&str) + Send + Sync>,
) -> Result<(), ServeError> {
    let local = listener.local_addr()?;
    let server = Arc::new(Server {
        domain,
        cases,
        seed,
        limits,
        open: AtomicUsize::new(0),
        failed: Mutex::new(None),
        stopping: AtomicBool::new(false),
        log,
    });
    for (k, stream) in (0u64..).zip(listener.incoming()) {
        if server.stopping.load(Ordering::SeqCst) {
            break;
        }
        let stream = match stream {
            Ok(s) => s,
            Err(e) => {
                (server.log)(&format!("accept failed: {e}"));
                continue;
            }
        };
        let peer = stream
            .peer_addr()
            .map_or_else(|_| "unknown peer".to_owned(), |a| a.to_string());
        if server.open.fetch_add(1, Ordering::SeqCst) >= limits.max_connections {
            server.open.fetch_sub(1, Ordering::SeqCst);
            (server.log)(&format!(
                "controller {peer} refused: {} connections already open",
                limits.max_connections
            ));
            refuse(&stream, limits);
            continue;
        }
        let worker = server.clone();
        let name = peer.clone();
        let spawned = std::thread::Builder::new()
            .name(format!("controller {peer}"))
            .spawn(move || {
                worker.connection(stream, &peer, k);
                worker.open.fetch_sub(1, Ordering::SeqCst);
                if worker.stopping.load(Ordering::SeqCst) {
                    // Wake the accepting loop so it sees the server must stop.
                    TcpStream::connect(local).ok();
                }
            });
        if let Err(e) = spawned {
            server.open.fetch_sub(1, Ordering::SeqCst);
            (server.log)(&format!("cannot start a thread for {name}: {e}"));
        }
    }
    match server
        .failed
        .lock()
        .expect("no thread panics holding it")
        .take()
    {
        Some(e) => Err(e.into()),
        None => Ok(()),
    }
}
impl Server {
    /// Serves one controller until it disconnects, times out or its session must stop.
    fn connection(&self, stream: TcpStream, peer: &str, k: u64) {
        (self.log)(&format!("controller connected from {peer}"));
        let served = (|| {
            stream.set_read_timeout(Some(self.limits.read_timeout))?;
            stream.set_write_timeout(Some(self.limits.write_timeout))?;
            let mut session = Session::new(
                self.domain.clone(),
                self.cases.clone(),
                self.seed.wrapping_add(k),
            )?;
            let reader = BufReader::new(LineDeadline::new(
                stream.try_clone()?,
                self.limits.read_timeout,
            ));
            serve(&mut session, reader, &stream)
        })();
        match served {
            Ok(()) => (self.log)(&format!("controller {peer} disconnected")),
            Err(ServeError::Io(e))
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) =>
            {
                (self.log)(&format!(
                    "controller {peer} timed out (silent for {} s, a line unfinished {0} s after it began, or not reading its replies for {} s): closed",
                    self.limits.read_timeout.as_secs_f64(),
                    self.limits.write_timeout.as_secs_f64()
                ));
            }
            Err(ServeError::Io(e)) => (self.log)(&format!("controller {peer} dropped: {e}")),
            Err(ServeError::Session(e)) => {
                (self.log)(&format!("controller {peer}: {e}"));
                self.failed
                    .lock()
                    .expect("no thread panics holding it")
                    .get_or_insert(e);
                self.stopping.store(true, Ordering::SeqCst);
            }
            Err(e) => (self.log)(&format!("controller {peer}: {e}")),
        }
    }
}

/// A connection's reading side that gives each line `timeout` from its first byte to its
/// newline, and the wait for a line to begin the same: a peer sending a byte now and then
/// is closed like a silent one.
struct LineDeadline {
    stream: TcpStream,
    timeout: Duration,
    /// When the line under way must be complete; `None` between lines.
    deadline: Option<Instant>,
}

impl LineDeadline {
    fn new(stream: TcpStream, timeout: Duration) -> Self {
        Self {
            stream,
            timeout,
            deadline: None,
        }
    }
}

impl io::Read for LineDeadline {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let wait = match self.deadline {
            None => self.timeout,
            Some(deadline) => deadline
                .checked_duration_since(Instant::now())
                .filter(|left| !left.is_zero())
                .ok_or_else(|| io::Error::from(io::ErrorKind::TimedOut))?,
        };
        self.stream.set_read_timeout(Some(wait))?;
        let n = io::Read::read(&mut self.stream, buf)?;
        // A line is under way unless the bytes read end with a newline.
        self.deadline = match buf[..n].iter().rposition(|&b| b == b'\n') {
            Some(last) if last + 1 == n => None,
            Some(_) => Some(Instant::now() + self.timeout),
            None if n > 0 => self
                .deadline
                .or_else(|| Some(Instant::now() + self.timeout)),
            None => self.deadline,
        };
        Ok(n)
    }
}

/// Tells a controller beyond the connection limit why it is closed.
fn refuse(stream: &TcpStream, limits: Limits) {
    stream.set_write_timeout(Some(limits.write_timeout)).ok();
    let answer = reply::error(format_args!(
        "the server is serving {} controllers, its limit: try again later",
        limits.max_connections
    ));
    let mut writer = stream;
    Reply::Json(answer).write_line(&mut writer).ok();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_loopback_addresses_are_refused() {
        let err = listen("0.0.0.0:0".parse().unwrap()).unwrap_err();
        assert!(matches!(err, ServeError::NotLoopback(_)));
        assert!(err.to_string().contains("only loopback"));
        assert!(matches!(
            listen("192.0.2.1:7000".parse().unwrap()),
            Err(ServeError::NotLoopback(_))
        ));
    }
}
