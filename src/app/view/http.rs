//! A minimal, strict HTTP/1.1 server side over `std::net`: just enough for
//! one page that polls a few endpoints, and nothing a hostile client can
//! use to make it read a file or hang.
//!
//! What it accepts:
//!
//! * `GET`, `HEAD` and `POST`; any other method is `405`.
//! * A request line `METHOD SP /path[?query] SP HTTP/1.x`, target at most
//!   [`MAX_TARGET_BYTES`] long (`414` beyond), starting with `/` (absolute
//!   URLs and `*` are `400`).
//! * A head (request line and headers) of printable ASCII, lines ending in
//!   CRLF, at most [`MAX_HEAD_BYTES`] and [`MAX_HEADERS`] headers (`431`).
//! * A body only with `Content-Length`, at most [`MAX_BODY_BYTES`] (`413`);
//!   `Transfer-Encoding` is `501`.
//! * The whole request must arrive within [`REQUEST_TIMEOUT`] of its first
//!   byte (a slow-loris client gets `408` and the connection is closed); an
//!   idle keep-alive connection is closed after [`IDLE_TIMEOUT`].
//!
//! After any error response the connection is closed. Requests can be kept
//! alive (HTTP/1.1 without `Connection: close`), so a page polling at 60 Hz
//! reuses one connection.

use std::io::{self, Read, Write};
use std::net::{Shutdown, TcpStream};
use std::time::{Duration, Instant};

/// Longest request line plus headers.
pub const MAX_HEAD_BYTES: usize = 8 * 1024;
/// Most headers in one request.
pub const MAX_HEADERS: usize = 64;
/// Longest request target (path and query).
pub const MAX_TARGET_BYTES: usize = 1024;
/// Largest request body (commands are a few dozen bytes).
pub const MAX_BODY_BYTES: usize = 4 * 1024;
/// Time allowed for a whole request, from its first byte.
pub const REQUEST_TIMEOUT: Duration = Duration::from_secs(5);
/// Time an open connection may wait for its next request.
pub const IDLE_TIMEOUT: Duration = Duration::from_secs(15);
/// Time allowed to send one whole response, however many writes it takes.
const WRITE_TIMEOUT: Duration = Duration::from_secs(10);

/// The methods the server knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    Get,
    Head,
    Post,
}

/// One parsed request.
#[derive(Debug)]
pub struct Request {
    pub method: Method,
    /// The target's path, exactly as sent (no decoding: routes match it
    /// literally, so `%2e%2e` is just an unknown path).
    pub path: String,
    /// The part after `?`, if any.
    pub query: Option<String>,
    /// Header names in lower case, values trimmed.
    pub headers: Vec<(String, String)>,
    pub body: Vec<u8>,
    /// May the connection serve another request after this one?
    pub keep_alive: bool,
}

impl Request {
    /// The value of header `name` (lower case).
    pub fn header(&self, name: &str) -> Option<&str> {
        self.headers
            .iter()
            .find(|(key, _)| key == name)
            .map(|(_, value)| value.as_str())
    }
}

/// A response: status, content type, body and a few extra headers.
#[derive(Debug)]
pub struct Response {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
    pub extra_headers: Vec<(&'static str, String)>,
}

impl Response {
    /// A response with `body` of type `content_type`.
    pub fn new(status: u16, content_type: &'static str, body: impl Into<Vec<u8>>) -> Self {
        Response {
            status,
            content_type,
            body: body.into(),
            extra_headers: Vec::new(),
        }
    }

    /// A short plain-text error: the reason phrase and `detail`.
    pub fn error(status: u16, detail: &str) -> Self {
        let text = format!("{status} {}: {detail}\n", reason_phrase(status));
        Response::new(status, "text/plain; charset=utf-8", text)
    }

    /// Adds a header.
    pub fn with_header(mut self, name: &'static str, value: impl Into<String>) -> Self {
        self.extra_headers.push((name, value.into()));
        self
    }
}

/// Why no request could be read.
#[derive(Debug)]
pub enum ReadError {
    /// The peer closed the connection, or it stayed idle too long, before
    /// sending a byte of a new request: close without answering.
    Closed,
    /// A bad or unfinished request: send this response, then close.
    Reject(Response),
}

/// A client connection with the bytes read but not used yet (the start of
/// a pipelined next request).
pub struct Connection {
    stream: TcpStream,
    buffer: Vec<u8>,
}

impl Connection {
    /// Wraps an accepted stream.
    pub fn new(stream: TcpStream) -> io::Result<Self> {
        stream.set_nodelay(true)?;
        stream.set_write_timeout(Some(WRITE_TIMEOUT))?;
        Ok(Connection {
            stream,
            buffer: Vec::with_capacity(1024),
        })
    }

    /// Reads the next request: waits up to [`IDLE_TIMEOUT`] for its first
    /// byte, then up to [`REQUEST_TIMEOUT`] for the rest.
    pub fn read_request(&mut self) -> Result<Request, ReadError> {
        if self.buffer.is_empty() {
            match self.read_more(Instant::now() + IDLE_TIMEOUT) {
                Ok(()) => {}
                Err(_) => return Err(ReadError::Closed),
            }
        }
        let deadline = Instant::now() + REQUEST_TIMEOUT;
        let head_length = self.read_head(deadline)?;
        let head = parse_head(&self.buffer[..head_length]).map_err(ReadError::Reject)?;
        let body_end = head_length + head.content_length;
        while self.buffer.len() < body_end {
            self.read_more(deadline).map_err(unfinished)?;
        }
        let body = self.buffer[head_length..body_end].to_vec();
        self.buffer.drain(..body_end);
        Ok(Request {
            method: head.method,
            path: head.path,
            query: head.query,
            headers: head.headers,
            body,
            keep_alive: head.keep_alive,
        })
    }

    /// Reads until the buffer holds a whole head; returns its length
    /// (including the blank line).
    /// Bytes that cannot be part of a head are refused as soon as they
    /// arrive, without waiting for the rest.
    fn read_head(&mut self, deadline: Instant) -> Result<usize, ReadError> {
        loop {
            let end = find_head_end(&self.buffer);
            let head = &self.buffer[..end.unwrap_or(self.buffer.len())];
            if !head.iter().all(|&byte| is_head_byte(byte)) {
                return Err(ReadError::Reject(Response::error(
                    400,
                    "the head must be printable ASCII",
                )));
            }
            if end.unwrap_or(self.buffer.len()) > MAX_HEAD_BYTES {
                return Err(ReadError::Reject(Response::error(431, "head too large")));
            }
            if let Some(end) = end {
                return Ok(end);
            }
            self.read_more(deadline).map_err(unfinished)?;
        }
    }

    /// Appends what the socket has (at least one byte) to the buffer, or
    /// fails at the deadline or when the peer closes.
    fn read_more(&mut self, deadline: Instant) -> io::Result<()> {
        let remaining = deadline.saturating_duration_since(Instant::now());
        if remaining.is_zero() {
            return Err(io::ErrorKind::TimedOut.into());
        }
        self.stream.set_read_timeout(Some(remaining))?;
        let mut chunk = [0u8; 4096];
        let count = self.stream.read(&mut chunk)?;
        if count == 0 {
            return Err(io::ErrorKind::UnexpectedEof.into());
        }
        self.buffer.extend_from_slice(&chunk[..count]);
        Ok(())
    }

    /// Sends `response` (without its body for `HEAD`), saying whether the
    /// connection stays open.
    pub fn write_response(
        &mut self,
        response: &Response,
        head_only: bool,
        keep_alive: bool,
    ) -> io::Result<()> {
        let mut head = format!(
            "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\n\
             Cache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\nConnection: {}\r\n",
            response.status,
            reason_phrase(response.status),
            response.content_type,
            response.body.len(),
            if keep_alive { "keep-alive" } else { "close" },
        );
        for (name, value) in &response.extra_headers {
            head.push_str(&format!("{name}: {value}\r\n"));
        }
        head.push_str("\r\n");
        let deadline = Instant::now() + WRITE_TIMEOUT;
        self.write_by(head.as_bytes(), deadline)?;
        if !head_only {
            self.write_by(&response.body, deadline)?;
        }
        self.stream.flush()
    }

    /// Writes all of `bytes` by `deadline`, or fails: a client that does
    /// not read cannot hold its connection (and its thread) longer than
    /// that, however the response is split into writes.
    fn write_by(&mut self, mut bytes: &[u8], deadline: Instant) -> io::Result<()> {
        while !bytes.is_empty() {
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(io::Error::new(
                    io::ErrorKind::TimedOut,
                    "the client did not read the response in time",
                ));
            }
            self.stream.set_write_timeout(Some(left))?;
            match self.stream.write(bytes) {
                Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
                Ok(count) => bytes = &bytes[count..],
                Err(error) if error.kind() == io::ErrorKind::Interrupted => {}
                Err(error) => return Err(error),
            }
        }
        Ok(())
    }

    /// Closes after an error response without resetting the connection:
    /// stop sending, then read and drop what the client still sends (for a
    /// moment), so that the client sees the response rather than a reset.
    pub fn close_gracefully(mut self) {
        let _ = self.stream.shutdown(Shutdown::Write);
        let _ = self
            .stream
            .set_read_timeout(Some(Duration::from_millis(200)));
        let mut sink = [0u8; 4096];
        let mut drained = 0;
        while drained < 64 * 1024 {
            match self.stream.read(&mut sink) {
                Ok(0) | Err(_) => break,
                Ok(count) => drained += count,
            }
        }
    }
}

/// An unfinished request: `408` after a timeout, otherwise (the peer gave
/// up halfway) a `400` nobody may read.
fn unfinished(error: io::Error) -> ReadError {
    match error.kind() {
        io::ErrorKind::TimedOut | io::ErrorKind::WouldBlock => {
            ReadError::Reject(Response::error(408, "request not received in time"))
        }
        _ => ReadError::Reject(Response::error(400, "incomplete request")),
    }
}

/// The length of the head (through `\r\n\r\n`), if the buffer holds it all.
pub(crate) fn find_head_end(buffer: &[u8]) -> Option<usize> {
    buffer
        .windows(4)
        .position(|window| window == b"\r\n\r\n")
        .map(|position| position + 4)
}

/// The parts of a head that matter here.
#[derive(Debug)]
pub(crate) struct Head {
    method: Method,
    path: String,
    query: Option<String>,
    headers: Vec<(String, String)>,
    content_length: usize,
    keep_alive: bool,
}

/// Parses the request line and headers (`head` ends with the blank line).
pub(crate) fn parse_head(head: &[u8]) -> Result<Head, Response> {
    if !head.iter().all(|&byte| is_head_byte(byte)) {
        return Err(Response::error(400, "the head must be printable ASCII"));
    }
    let text = std::str::from_utf8(head).expect("ASCII is UTF-8");
    let mut lines = text.strip_suffix("\r\n\r\n").unwrap_or(text).split("\r\n");
    let request_line = lines.next().unwrap_or("");
    let (method, target, http_1_1) = parse_request_line(request_line)?;
    let headers = parse_headers(lines)?;
    let (path, query) = match target.split_once('?') {
        Some((path, query)) => (path.to_string(), Some(query.to_string())),
        None => (target.to_string(), None),
    };
    let find = |name: &'static str| headers.iter().filter(move |(key, _)| key == name);
    if http_1_1 && find("host").count() != 1 {
        return Err(Response::error(
            400,
            "HTTP/1.1 needs exactly one Host header",
        ));
    }
    if find("transfer-encoding").next().is_some() {
        return Err(Response::error(501, "Transfer-Encoding is not supported"));
    }
    let content_length = parse_content_length(find("content-length").map(|(_, v)| v.as_str()))?;
    let close_requested = find("connection").any(|(_, value)| {
        value
            .split(',')
            .any(|token| token.trim().eq_ignore_ascii_case("close"))
    });
    Ok(Head {
        method,
        path,
        query,
        headers,
        content_length,
        keep_alive: http_1_1 && !close_requested,
    })
}

/// `METHOD SP TARGET SP HTTP/1.x` → method, target, and whether it is 1.1.
fn parse_request_line(line: &str) -> Result<(Method, &str, bool), Response> {
    let parts: Vec<&str> = line.split(' ').collect();
    let [method, target, version] = parts.as_slice() else {
        return Err(Response::error(400, "malformed request line"));
    };
    let http_1_1 = match *version {
        "HTTP/1.1" => true,
        "HTTP/1.0" => false,
        other if other.starts_with("HTTP/") => {
            return Err(Response::error(505, "only HTTP/1.0 and 1.1"))
        }
        _ => return Err(Response::error(400, "malformed request line")),
    };
    let method = match *method {
        "GET" => Method::Get,
        "HEAD" => Method::Head,
        "POST" => Method::Post,
        other if !other.is_empty() && other.bytes().all(is_token_byte) => {
            return Err(Response::error(405, "only GET, HEAD and POST")
                .with_header("Allow", "GET, HEAD, POST"))
        }
        _ => return Err(Response::error(400, "malformed request line")),
    };
    if target.len() > MAX_TARGET_BYTES {
        return Err(Response::error(414, "target too long"));
    }
    if !target.starts_with('/') {
        return Err(Response::error(400, "the target must be a path"));
    }
    Ok((method, target, http_1_1))
}

/// `Name: value` lines → (lower-case name, trimmed value).
fn parse_headers<'a>(
    lines: impl Iterator<Item = &'a str>,
) -> Result<Vec<(String, String)>, Response> {
    let mut headers = Vec::new();
    for line in lines {
        if headers.len() == MAX_HEADERS {
            return Err(Response::error(431, "too many headers"));
        }
        let Some((name, value)) = line.split_once(':') else {
            return Err(Response::error(400, "malformed header"));
        };
        if name.is_empty() || !name.bytes().all(is_token_byte) {
            return Err(Response::error(400, "malformed header name"));
        }
        headers.push((name.to_ascii_lowercase(), value.trim().to_string()));
    }
    Ok(headers)
}

/// The body's length: 0 without the header; one decimal number at most
/// [`MAX_BODY_BYTES`]; repeated headers must agree.
fn parse_content_length<'a>(values: impl Iterator<Item = &'a str>) -> Result<usize, Response> {
    let mut length = None;
    for value in values {
        if value.is_empty() || value.len() > 9 || !value.bytes().all(|b| b.is_ascii_digit()) {
            return Err(Response::error(400, "malformed Content-Length"));
        }
        let parsed: usize = value.parse().expect("at most 9 digits");
        if length.is_some_and(|previous| previous != parsed) {
            return Err(Response::error(400, "conflicting Content-Length"));
        }
        length = Some(parsed);
    }
    let length = length.unwrap_or(0);
    if length > MAX_BODY_BYTES {
        return Err(Response::error(413, "body too large"));
    }
    Ok(length)
}

/// A byte that may appear in a head: printable ASCII, tab, CR, LF.
fn is_head_byte(byte: u8) -> bool {
    byte == b'\r' || byte == b'\n' || byte == b'\t' || (32..127).contains(&byte)
}

/// A byte of an HTTP token (method or header name), RFC 9110 §5.6.2.
fn is_token_byte(byte: u8) -> bool {
    byte.is_ascii_alphanumeric() || b"!#$%&'*+-.^_`|~".contains(&byte)
}

/// The standard reason phrase of the statuses this server sends.
pub fn reason_phrase(status: u16) -> &'static str {
    match status {
        200 => "OK",
        202 => "Accepted",
        204 => "No Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        409 => "Conflict",
        413 => "Content Too Large",
        414 => "URI Too Long",
        415 => "Unsupported Media Type",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        501 => "Not Implemented",
        503 => "Service Unavailable",
        505 => "HTTP Version Not Supported",
        _ => "Unknown",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mutate;

    fn status_of(head: &str) -> u16 {
        match parse_head(head.as_bytes()) {
            Ok(_) => 200,
            Err(response) => response.status,
        }
    }

    #[test]
    fn a_plain_get_parses_with_path_query_and_keep_alive() {
        let head = parse_head(b"GET /api/frame?since=3 HTTP/1.1\r\nHost: x\r\n\r\n").unwrap();
        assert_eq!(head.method, Method::Get);
        assert_eq!(head.path, "/api/frame");
        assert_eq!(head.query.as_deref(), Some("since=3"));
        assert!(head.keep_alive);
        assert_eq!(head.content_length, 0);
    }

    #[test]
    fn connection_close_and_http_1_0_end_the_connection() {
        let close = parse_head(b"GET / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
        assert!(!close.unwrap().keep_alive);
        assert!(!parse_head(b"GET / HTTP/1.0\r\n\r\n").unwrap().keep_alive);
    }

    #[test]
    fn malformed_heads_get_the_matching_4xx_or_5xx() {
        assert_eq!(status_of("\u{1}\u{2}garbage\r\n\r\n"), 400);
        assert_eq!(status_of("GET /\r\n\r\n"), 400);
        assert_eq!(status_of("GET http://x/ HTTP/1.1\r\nHost: x\r\n\r\n"), 400);
        assert_eq!(status_of("DELETE / HTTP/1.1\r\nHost: x\r\n\r\n"), 405);
        assert_eq!(status_of("GET / HTTP/2.0\r\nHost: x\r\n\r\n"), 505);
        assert_eq!(status_of("GET / HTTP/1.1\r\n\r\n"), 400);
        assert_eq!(
            status_of("GET / HTTP/1.1\r\nHost: x\r\n folded\r\n\r\n"),
            400
        );
        let long = format!("GET /{} HTTP/1.1\r\nHost: x\r\n\r\n", "a".repeat(2000));
        assert_eq!(status_of(&long), 414);
        let post = "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 99999\r\n\r\n";
        assert_eq!(status_of(post), 413);
        let chunked = "POST / HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
        assert_eq!(status_of(chunked), 501);
        let two = "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: 1\r\nContent-Length: 2\r\n\r\n";
        assert_eq!(status_of(two), 400);
    }

    /// The raw requests of `tests/hostile/requests/`.
    fn request_corpus() -> Vec<Vec<u8>> {
        let folder =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/hostile/requests");
        let mut requests: Vec<Vec<u8>> = std::fs::read_dir(folder)
            .unwrap()
            .map(|entry| std::fs::read(entry.unwrap().path()).unwrap())
            .collect();
        requests.sort();
        assert!(requests.len() >= 5);
        requests
    }

    #[test]
    fn mutated_requests_parse_or_get_a_4xx_or_5xx() {
        let seeds = request_corpus();
        let mut rng = mutate::Rng::new(1996);
        let (mut parsed, mut refused) = (0, 0);
        for case in 0..20_000 {
            let input = mutate::mutate(&seeds[case % seeds.len()], &mut rng);
            let Some(end) = find_head_end(&input) else {
                continue;
            };
            match parse_head(&input[..end]) {
                Ok(head) => {
                    assert!(head.path.starts_with('/'));
                    assert!(head.content_length <= MAX_BODY_BYTES);
                    parsed += 1;
                }
                Err(response) => {
                    assert!(
                        (400..=505).contains(&response.status),
                        "{}",
                        response.status
                    );
                    assert!(!response.body.is_empty());
                    refused += 1;
                }
            }
        }
        assert!(
            parsed > 1000 && refused > 1000,
            "{parsed} parsed, {refused} refused"
        );
    }
}
