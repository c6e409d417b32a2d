//! The plan's worker threads: a pool of [`PlanConfig::threads`] threads, or rayon's global
//! pool.

use super::config::{PlanConfig, PlanError};

/// The pool `cfg.threads` asks for; `None` runs on rayon's global pool.
pub(super) fn build(cfg: &PlanConfig) -> Result<Option<rayon::ThreadPool>, PlanError> {
    Ok(match cfg.threads {
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| PlanError::Threads(e.to_string()))?,
        ),
        None => None,
    })
}

/// Runs `f` on `pool`, or on rayon's global pool when there is none.
pub(super) fn in_pool<R: Send>(
    pool: Option<&rayon::ThreadPool>,
    f: impl FnOnce() -> R + Send,
) -> R {
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}
