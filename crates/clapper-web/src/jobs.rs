//! Computations off the async threads, a bounded number at once, each
//! with a time limit.

use std::sync::Arc;

use tokio::sync::{OwnedSemaphorePermit, Semaphore};

use crate::{ApiError, Limits};

/// The computation slots.
#[derive(Clone)]
pub(crate) struct Jobs {
    slots: Arc<Semaphore>,
    limits: Limits,
}

impl Jobs {
    pub fn new(limits: Limits) -> Self {
        Self {
            slots: Arc::new(Semaphore::new(limits.max_jobs.max(1))),
            limits,
        }
    }

    /// A slot, waiting at most the queue time.
    pub async fn slot(&self) -> Result<OwnedSemaphorePermit, ApiError> {
        match tokio::time::timeout(self.limits.queue_wait, self.slots.clone().acquire_owned()).await {
            Ok(Ok(p)) => Ok(p),
            Ok(Err(_)) => Err(ApiError::Internal("the server is shutting down".into())),
            Err(_) => Err(ApiError::Unavailable(format!(
                "server busy: {} computations running and none finished within {} s; try again",
                self.limits.max_jobs,
                self.limits.queue_wait.as_secs()
            ))),
        }
    }

    /// Run `work` on a blocking thread in a slot, within the time limit.
    /// Past the limit the client gets 503 at once; the work, bounded by
    /// the solver's own step and event limits, finishes in the background
    /// and only then frees its slot, so runaway work cannot pile up.
    pub async fn run<T, F>(&self, work: F) -> Result<T, ApiError>
    where
        T: Send + 'static,
        F: FnOnce() -> Result<T, ApiError> + Send + 'static,
    {
        let permit = self.slot().await?;
        let handle = tokio::task::spawn_blocking(move || {
            let _slot = permit;
            work()
        });
        match tokio::time::timeout(self.limits.job_time, handle).await {
            Ok(Ok(r)) => r,
            Ok(Err(e)) => Err(ApiError::Internal(format!("computation failed: {e}"))),
            Err(_) => Err(ApiError::Unavailable(format!(
                "the computation took longer than this server's limit of {} s",
                self.limits.job_time.as_secs()
            ))),
        }
    }
}
