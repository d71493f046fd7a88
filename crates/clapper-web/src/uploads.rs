//! Request bodies bounded in size, rate and total: a body announced larger
//! than its route takes is refused before it is read (413); a body that
//! arrives slower than [`Limits::min_upload_rate`] after
//! [`Limits::body_timeout`] is cut off (408), so a client sending a byte now
//! and then cannot hold a connection; and the recordings being received at
//! once hold at most [`Limits::max_upload_bytes_in_flight`] between them
//! (503 beyond it), so many large uploads cannot fill the server's memory.

use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};
use std::time::Duration;

use axum::body::{Body, Bytes};
use axum::extract::{Request, State};
use axum::http::header::{CONTENT_LENGTH, HOST};
use axum::http::StatusCode;
use axum::middleware::Next;
use axum::response::{IntoResponse, Response};
use http_body::{Frame, SizeHint};
use tokio::sync::Semaphore;
// tokio's clock, so that tests can run it paused.
use tokio::time::Instant;

use crate::{ApiError, Limits};

/// The route that takes recordings (its bodies are up to
/// [`Limits::max_recording_bytes`]; every other route's up to
/// [`Limits::max_body_bytes`]).
pub(crate) const RECORDING_ROUTE: &str = "/api/strikes";

/// Bytes of recordings being received, counted in KiB (a semaphore's
/// permits are `u32`; 4 TiB in KiB fits).
#[derive(Clone)]
pub(crate) struct Uploads {
    kib: Arc<Semaphore>,
    limits: Limits,
}

impl Uploads {
    pub fn new(limits: Limits) -> Self {
        Self {
            kib: Arc::new(Semaphore::new(kib(limits.max_upload_bytes_in_flight) as usize)),
            limits,
        }
    }
}

fn kib(bytes: usize) -> u32 {
    u32::try_from(bytes.div_ceil(1024)).unwrap_or(u32::MAX).max(1)
}

/// A body arriving slower than the server's least rate.
#[derive(Debug, thiserror::Error)]
#[error(
    "upload too slow: {bytes} bytes in {secs:.0} s; this server takes a request body at {min_kib} KiB/s at least \
     (after the first {grace_s} s)"
)]
pub(crate) struct SlowUpload {
    bytes: u64,
    secs: f64,
    min_kib: u64,
    grace_s: u64,
}

/// The message for a body that could not be read: a slow upload is a 408
/// with its reason, a body over its limit a 413; anything else keeps its
/// status (a stalled body's 408, say).
pub(crate) fn body_rejection(
    r: axum::extract::rejection::BytesRejection,
    too_large: impl FnOnce() -> String,
) -> ApiError {
    let mut source: Option<&(dyn std::error::Error + 'static)> = Some(&r);
    while let Some(e) = source {
        if let Some(slow) = e.downcast_ref::<SlowUpload>() {
            return ApiError::Limit(StatusCode::REQUEST_TIMEOUT, slow.to_string());
        }
        source = e.source();
    }
    let status = r.status();
    if status == StatusCode::PAYLOAD_TOO_LARGE {
        ApiError::Limit(status, too_large())
    } else {
        ApiError::Limit(status, r.body_text().replace('\n', " "))
    }
}

/// A body that must keep up the least rate once its grace time is past.
struct MinRate {
    inner: Body,
    start: Instant,
    bytes: u64,
    grace: Duration,
    min_rate: u64,
}

impl http_body::Body for MinRate {
    type Data = Bytes;
    type Error = axum::Error;

    fn poll_frame(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Option<Result<Frame<Bytes>, axum::Error>>> {
        let this = self.get_mut();
        let polled = Pin::new(&mut this.inner).poll_frame(cx);
        if let Poll::Ready(Some(Ok(frame))) = &polled {
            if let Some(data) = frame.data_ref() {
                this.bytes += data.len() as u64;
            }
            // Checked as each part arrives; a pause between parts is the
            // body timeout's to end.
            let t = this.start.elapsed();
            if let Some(past) = t.checked_sub(this.grace) {
                let owed = (past.as_secs_f64() * this.min_rate as f64) as u64;
                if this.bytes < owed {
                    return Poll::Ready(Some(Err(axum::Error::new(SlowUpload {
                        bytes: this.bytes,
                        secs: t.as_secs_f64(),
                        min_kib: this.min_rate / 1024,
                        grace_s: this.grace.as_secs(),
                    }))));
                }
            }
        }
        polled
    }

    fn is_end_stream(&self) -> bool {
        self.inner.is_end_stream()
    }

    fn size_hint(&self) -> SizeHint {
        self.inner.size_hint()
    }
}

/// The middleware, outermost of the routes: one Host header, the announced
/// length against the route's limit, recordings' share of the in-flight
/// budget (held until the answer is made), and the least rate on every body.
pub(crate) async fn gate(State(uploads): State<Uploads>, req: Request, next: Next) -> Response {
    let limits = uploads.limits;
    let hosts = req.headers().get_all(HOST).iter().count();
    if hosts > 1 {
        return ApiError::BadRequest(format!("a request has one Host header; this one has {hosts}")).into_response();
    }
    let recording = req.uri().path() == RECORDING_ROUTE;
    let max = if recording {
        limits.max_recording_bytes
    } else {
        limits.max_body_bytes
    };
    let announced = req
        .headers()
        .get(CONTENT_LENGTH)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.trim().parse::<u64>().ok());
    if let Some(n) = announced {
        if n > max as u64 {
            return ApiError::Limit(
                StatusCode::PAYLOAD_TOO_LARGE,
                format!(
                    "request body too large: {n} bytes announced, {} takes at most {max} bytes{}",
                    req.uri().path(),
                    if recording {
                        " (longer recordings belong to clapper strikes)"
                    } else {
                        ""
                    }
                ),
            )
            .into_response();
        }
    }
    // A recording's share: what it announced, or the most it may be.
    let _held = if recording {
        let want = kib(announced.map_or(max, |n| n as usize));
        match uploads.kib.clone().try_acquire_many_owned(want) {
            Ok(p) => Some(p),
            Err(_) => {
                return ApiError::Unavailable(format!(
                    "server busy: {} MiB of recordings are being received; try again shortly",
                    limits.max_upload_bytes_in_flight >> 20
                ))
                .into_response()
            }
        }
    } else {
        None
    };
    let (parts, body) = req.into_parts();
    let body = Body::new(MinRate {
        inner: body,
        start: Instant::now(),
        bytes: 0,
        grace: limits.body_timeout,
        min_rate: limits.min_upload_rate,
    });
    next.run(Request::from_parts(parts, body)).await
}

#[cfg(test)]
mod tests {
    use super::*;
    use http_body_util::BodyExt;

    /// A body that gives a byte each `every`, `n` times.
    fn trickle(n: usize, every: Duration) -> Body {
        let s = tokio_stream::iter(0..n).then(move |_| async move {
            tokio::time::sleep(every).await;
            Ok::<_, std::io::Error>(Bytes::from_static(b"x"))
        });
        Body::from_stream(s)
    }
    use tokio_stream::StreamExt;

    #[tokio::test(start_paused = true)]
    async fn a_trickle_is_cut_after_the_grace_and_a_steady_body_is_not() {
        let slow = MinRate {
            inner: trickle(10, Duration::from_secs(3)),
            start: Instant::now(),
            bytes: 0,
            grace: Duration::from_secs(5),
            min_rate: 1024,
        };
        let err = slow.collect().await.expect_err("a trickle is cut");
        let msg = err.to_string();
        assert!(msg.contains("upload too slow") && msg.contains("1 KiB/s"), "{msg}");

        let steady = MinRate {
            inner: Body::from(vec![0u8; 4096]),
            start: Instant::now(),
            bytes: 0,
            grace: Duration::from_secs(5),
            min_rate: 1024,
        };
        assert_eq!(steady.collect().await.unwrap().to_bytes().len(), 4096);
    }

    #[test]
    fn budgets_are_counted_in_whole_kib() {
        assert_eq!(kib(0), 1);
        assert_eq!(kib(1025), 2);
        assert_eq!(kib(usize::MAX), u32::MAX);
    }
}
