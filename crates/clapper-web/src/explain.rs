//! hyper's own answers given a body that says what was wrong.
//!
//! A request line or headers past hyper's limits never reach the router:
//! hyper answers 414 (URI too long), 431 (headers too large) or 400 (not
//! HTTP/1.1) itself, with an empty body, and its HTTP/1 builder has no hook
//! to change that. So the connection's bytes pass through [`Explained`],
//! which knows such an answer by its status and its `content-length: 0`
//! (every answer of the router has a body) and writes it again with the
//! reason as the router's errors give theirs, `{"error": "one line"}`.

use std::io;
use std::pin::Pin;
use std::task::{ready, Context, Poll};

use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

/// The body for hyper's answer with status line `status` (its first
/// bytes), if it is one of hyper's own.
fn reason(status: &[u8]) -> Option<&'static str> {
    match status {
        b"HTTP/1.1 414 " => {
            Some("the request's URI is too long: at most 65,534 bytes (send long input as a JSON body with POST)")
        }
        b"HTTP/1.1 431 " => Some(
            "the request's headers are too large: at most 100 headers, and the request line and headers \
             together at most about 400 KiB",
        ),
        b"HTTP/1.1 400 " => Some("the request is not well-formed HTTP/1.1"),
        _ => None,
    }
}

/// hyper's bodiless answer `head` (the whole head, up to its blank line)
/// with a JSON body saying why; `None` for any other bytes.
fn with_body(head: &[u8]) -> Option<Vec<u8>> {
    let why = reason(head.get(..13)?)?;
    if !head.ends_with(b"\r\n\r\n") {
        return None;
    }
    let text = std::str::from_utf8(head).ok()?;
    let zero = text
        .find("content-length: 0\r\n")
        .or_else(|| text.find("Content-Length: 0\r\n"))?;
    let body = serde_json::json!({ "error": why }).to_string();
    let mut out = String::with_capacity(head.len() + body.len() + 64);
    out.push_str(&text[..zero]);
    out.push_str(&format!(
        "content-type: application/json\r\ncontent-length: {}\r\n",
        body.len()
    ));
    out.push_str(&text[zero + "content-length: 0\r\n".len()..]);
    out.push_str(&body);
    Some(out.into_bytes())
}

/// A connection whose bodiless error answers from hyper get a body.
pub(crate) struct Explained<T> {
    inner: T,
    /// A rewritten answer not yet all written (hyper was told it was).
    pending: Vec<u8>,
}

impl<T> Explained<T> {
    pub(crate) fn new(inner: T) -> Self {
        Explained {
            inner,
            pending: Vec::new(),
        }
    }
}

impl<T: AsyncWrite + Unpin> Explained<T> {
    /// Write what is pending.
    fn drain(&mut self, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        while !self.pending.is_empty() {
            let n = ready!(Pin::new(&mut self.inner).poll_write(cx, &self.pending))?;
            if n == 0 {
                return Poll::Ready(Err(io::ErrorKind::WriteZero.into()));
            }
            self.pending.drain(..n);
        }
        Poll::Ready(Ok(()))
    }
}

impl<T: AsyncRead + Unpin> AsyncRead for Explained<T> {
    fn poll_read(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_read(cx, buf)
    }
}

impl<T: AsyncWrite + Unpin> AsyncWrite for Explained<T> {
    fn poll_write(mut self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        ready!(self.drain(cx))?;
        if let Some(answer) = with_body(buf) {
            self.pending = answer;
            // Taken whole: the rest is written by later calls or the flush.
            let _ = self.drain(cx)?;
            return Poll::Ready(Ok(buf.len()));
        }
        Pin::new(&mut self.inner).poll_write(cx, buf)
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        ready!(self.drain(cx))?;
        Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        ready!(self.drain(cx))?;
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }

    // Not vectored: hyper then writes each answer's head in one buffer,
    // which is where a bodiless answer is known.
    fn is_write_vectored(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_hypers_bodiless_errors_are_given_a_body() {
        let head = b"HTTP/1.1 431 Request Header Fields Too Large\r\nconnection: close\r\ncontent-length: 0\r\ndate: x\r\n\r\n";
        let out = String::from_utf8(with_body(head).unwrap()).unwrap();
        let (h, body) = out.split_once("\r\n\r\n").unwrap();
        assert!(h.contains(&format!("content-length: {}", body.len())), "{out}");
        assert!(body.contains("headers are too large"), "{out}");
        // An answer of the router, with its body, is left alone.
        assert!(with_body(b"HTTP/1.1 400 Bad Request\r\ncontent-length: 12\r\n\r\n").is_none());
        assert!(with_body(b"HTTP/1.1 200 OK\r\ncontent-length: 0\r\n\r\n").is_none());
    }
}
