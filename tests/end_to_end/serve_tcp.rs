//! `trustcbr serve --listen` with many controllers at once: 32 controllers on loopback
//! run their episodes concurrently while one more connects and says nothing and another
//! sends requests without ever reading a reply; all 32 finish. Beyond the connection
//! limit a controller gets one clear error line.

use serde_json::Value;
use std::io::{BufRead, BufReader, Write};
use std::net::TcpStream;
use std::process::Command;
use std::time::{Duration, Instant};

use crate::support;

const CONTROLLERS: usize = 32;
const EPISODES_EACH: usize = 5;

/// Starts a TCP server with `extra` options on a case base in `dir`; returns it and the
/// address it listens on.
fn start(dir: &std::path::Path, extra: &[&str]) -> (support::Server, String) {
    let domain = dir.join("quick.ron");
    std::fs::write(&domain, support::quick_domain(true)).unwrap();
    support::listening(
        Command::new(env!("CARGO_BIN_EXE_trustcbr"))
            .args(["serve", "--domain"])
            .arg(&domain)
            .arg("--cases")
            .arg(dir.join("cases.db"))
            .args(["--listen", "127.0.0.1:0"])
            .args(extra),
    )
}

/// A controller connection: one request, one reply.
struct Controller {
    stream: TcpStream,
    reader: BufReader<TcpStream>,
}

impl Controller {
    fn connect(addr: &str) -> Self {
        let stream = TcpStream::connect(addr).unwrap();
        stream
            .set_read_timeout(Some(Duration::from_secs(60)))
            .unwrap();
        let reader = BufReader::new(stream.try_clone().unwrap());
        Self { stream, reader }
    }

    fn ask(&mut self, request: &str) -> Value {
        // A refused connection may be closed before the request is written; its refusal
        // line is still there to read.
        writeln!(self.stream, "{request}").ok();
        self.read()
    }

    fn read(&mut self) -> Value {
        let mut line = String::new();
        self.reader.read_line(&mut line).unwrap();
        serde_json::from_str(&line).unwrap()
    }
}

#[test]
fn thirty_two_controllers_finish_beside_a_stalled_and_a_non_reading_one() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, addr) = start(dir.path(), &["--write-timeout", "2"]);
    // Connects and says nothing, for the whole test.
    let staller = TcpStream::connect(&addr).unwrap();
    // Sends a stream of requests and never reads a reply: the server's writes to it block
    // until the write timeout closes it.
    let flooder = TcpStream::connect(&addr).unwrap();
    let flood = std::thread::spawn(move || {
        let mut writer = &flooder;
        let deadline = Instant::now() + Duration::from_secs(60);
        let mut sent = 0;
        while Instant::now() < deadline {
            if writeln!(writer, r#"{{"request": "config"}}"#).is_err() {
                return Some(sent);
            }
            sent += 1;
        }
        None
    });
    let started = Instant::now();
    let finished: Vec<usize> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..CONTROLLERS)
            .map(|k| {
                let addr = &addr;
                scope.spawn(move || {
                    let mut c = Controller::connect(addr);
                    let mut settled = 0;
                    for episode in 0..EPISODES_EACH {
                        let id = format!("c{k}-e{episode}");
                        let begun =
                            c.ask(&format!(r#"{{"request": "begin", "id": "{id}"}}"#));
                        assert_eq!(begun["ok"], "begun", "{begun}");
                        assert_eq!(begun["id"], id.as_str());
                        c.ask(r#"{"outcome": "interrupted", "weight": 1, "duration_s": 3, "observed": ["stuck"]}"#);
                        let end = c.ask(r#"{"outcome": "completed", "weight": 1, "duration_s": 5}"#);
                        assert_eq!(end["ok"], "settled", "{end}");
                        settled += 1;
                    }
                    settled
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    let elapsed = started.elapsed();
    assert_eq!(finished, vec![EPISODES_EACH; CONTROLLERS]);
    // The flooder is cut off by the write timeout (its writes then fail) rather than
    // served for ever.
    let sent = flood
        .join()
        .unwrap()
        .expect("the non-reading controller was never cut off");
    eprintln!(
        "{CONTROLLERS} controllers x {EPISODES_EACH} episodes in {:.2} s beside a stalled connection and a non-reader cut off after {sent} requests",
        elapsed.as_secs_f64()
    );
    drop(staller);
}

#[test]
fn a_controller_beyond_the_limit_is_refused_with_a_clear_line() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, addr) = start(dir.path(), &["--max-connections", "1"]);
    let mut first = Controller::connect(&addr);
    assert_eq!(first.ask(r#"{"request": "state"}"#)["ok"], "state");
    let mut second = Controller::connect(&addr);
    let refused = second.read();
    assert_eq!(
        refused["error"],
        "the server is serving 1 controllers, its limit: try again later"
    );
    // The first is still served, and once it leaves another is welcome.
    assert_eq!(first.ask(r#"{"request": "state"}"#)["ok"], "state");
    drop(first);
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let mut third = Controller::connect(&addr);
        let reply = third.ask(r#"{"request": "state"}"#);
        if reply["ok"] == "state" {
            break;
        }
        assert!(Instant::now() < deadline, "{reply}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[test]
fn a_slow_drip_is_closed_once_its_line_is_overdue() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, addr) = start(
        dir.path(),
        &["--max-connections", "1", "--idle-timeout", "1"],
    );
    // One byte every 0.3 s: never silent for the idle timeout, never a whole line.
    let mut dripper = TcpStream::connect(&addr).unwrap();
    dripper
        .set_read_timeout(Some(Duration::from_millis(300)))
        .unwrap();
    let started = Instant::now();
    let request = br#"{"request": "state"}"#;
    let closed = request.iter().cycle().take(40).any(|byte| {
        if dripper.write_all(&[*byte]).is_err() {
            return true;
        }
        let mut reply = [0u8; 256];
        match std::io::Read::read(&mut dripper, &mut reply) {
            Ok(0) => true,
            Ok(_) => panic!("a reply before the line was finished"),
            Err(e) => !matches!(
                e.kind(),
                std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
            ),
        }
    });
    let held = started.elapsed();
    assert!(closed, "the dripping connection was never closed");
    assert!(
        held < Duration::from_secs(5),
        "it held its slot for {held:?}"
    );
    // Its slot is free again: the next controller is served.
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        let mut next = Controller::connect(&addr);
        let reply = next.ask(r#"{"request": "state"}"#);
        if reply["ok"] == "state" {
            break;
        }
        assert!(Instant::now() < deadline, "{reply}");
        std::thread::sleep(Duration::from_millis(20));
    }
}
