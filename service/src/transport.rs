//! Running a [`Session`] over a byte stream: stdin/stdout, or one loopback TCP connection
//! at a time.
//!
//! Every line read gets exactly one reply line, flushed at once. Lines longer than
//! [`MAX_LINE_BYTES`] are discarded without being held in memory and answered with an
//! error; the conversation then goes on. Only a failed case-base save ends the session
//! (see [`SessionError::Save`]).

use crate::lines::{LineRead, read_line};
use crate::reply;
use crate::session::{Session, SessionError};
use std::io::{self, BufRead, BufReader, BufWriter, Write};
use std::net::{SocketAddr, TcpListener};

/// The longest request line accepted, newline excluded.
pub const MAX_LINE_BYTES: usize = 64 * 1024;

/// Why serving stopped.
#[derive(Debug, thiserror::Error)]
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
    // Each reply goes out whole, in one write, when it is flushed.
    let mut output = BufWriter::new(output);
    let mut line = Vec::new();
    while let Some(read) = read_line(&mut input, MAX_LINE_BYTES, &mut line)? {
        let (answer, stop) = match read {
            LineRead::TooLong => (
                reply::error(format_args!(
                    "line too long: a request line may hold at most {MAX_LINE_BYTES} bytes; it was discarded"
                )),
                None,
            ),
            LineRead::Line => match session.handle_line(&line) {
                Ok(answer) => (answer, None),
                Err(e) => (reply::error(&e), Some(e)),
            },
        };
        serde_json::to_writer(&mut output, &answer).map_err(io::Error::from)?;
        output.write_all(b"\n")?;
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

/// Serves controllers connecting to `listener`, one connection at a time, for ever (or
/// until the session must stop). The adapter's state carries over from one connection to
/// the next. `log` hears of connections opening and closing.
pub fn serve_tcp(
    session: &mut Session,
    listener: &TcpListener,
    log: &mut dyn FnMut(&str),
) -> Result<(), ServeError> {
    for stream in listener.incoming() {
        let stream = match stream {
            Ok(s) => s,
            Err(e) => {
                log(&format!("accept failed: {e}"));
                continue;
            }
        };
        let peer = stream
            .peer_addr()
            .map_or_else(|_| "unknown peer".to_owned(), |a| a.to_string());
        log(&format!("controller connected from {peer}"));
        let reader = BufReader::new(stream.try_clone()?);
        match serve(session, reader, &stream) {
            Ok(()) => log(&format!("controller {peer} disconnected")),
            Err(ServeError::Io(e)) => log(&format!("controller {peer} dropped: {e}")),
            Err(e) => return Err(e),
        }
    }
    Ok(())
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
