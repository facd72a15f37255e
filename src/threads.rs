//! The threads a step may use (the `parallel` feature), and the one
//! primitive the parallel stages split work with.
//!
//! Nothing a step computes depends on the thread count: work is split in
//! halves down to pieces whose boundaries depend only on the item count,
//! and every piece writes only what no other piece of the same stage
//! reads or writes (see [`solver::sweep`](crate::solver)). Without the
//! feature, or with one thread, the halves run one after the other.

/// The most threads a space may ask for: far beyond the cores of any
/// machine a step would gain from, low enough that a mistaken count does
/// not start a thread per body.
pub(crate) const MAX_THREADS: usize = 256;

/// A space's threads: a count, and with the `parallel` feature and more
/// than one thread, the pool that runs them (shared by the space's clones).
#[derive(Clone, Debug)]
pub(crate) struct Threads {
    count: usize,
    #[cfg(feature = "parallel")]
    pool: Option<std::sync::Arc<rayon::ThreadPool>>,
}

impl Default for Threads {
    fn default() -> Self {
        Threads {
            count: 1,
            #[cfg(feature = "parallel")]
            pool: None,
        }
    }
}

impl Threads {
    /// `n` threads (0 counts as 1; more than [`MAX_THREADS`] is an error).
    /// Without the `parallel` feature the count is kept and the step runs
    /// on the calling thread.
    pub(crate) fn new(n: usize) -> Result<Threads, &'static str> {
        if n > MAX_THREADS {
            return Err("threads: at most 256 (Space::set_threads)");
        }
        let count = n.max(1);
        #[cfg(feature = "parallel")]
        {
            let pool = if count > 1 {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(count)
                    .thread_name(|i| format!("tamias2d-{i}"))
                    .build()
                    .map_err(|_| "threads: the operating system refused to start the threads")?;
                Some(std::sync::Arc::new(pool))
            } else {
                None
            };
            Ok(Threads { count, pool })
        }
        #[cfg(not(feature = "parallel"))]
        Ok(Threads { count })
    }

    /// The thread count asked for.
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// Whether stages split between threads (the feature, more than one
    /// thread): otherwise they take the cheaper in-place serial paths.
    pub(crate) fn parallel(&self) -> bool {
        #[cfg(feature = "parallel")]
        return self.pool.is_some();
        #[cfg(not(feature = "parallel"))]
        false
    }

    /// Runs `f` (on this thread) with the pool's workers kept awake: each
    /// spins, picking up the pool's work as it comes, until `f` returns.
    /// Parallel stages a few milliseconds apart then start at once instead
    /// of waking sleeping threads. Without a pool, just `f()`.
    pub(crate) fn awake<R>(&self, f: impl FnOnce() -> R) -> R {
        #[cfg(feature = "parallel")]
        if let Some(pool) = &self.pool {
            use core::sync::atomic::{AtomicBool, Ordering};
            /// Ends the spinning when dropped: also if `f` panics (a
            /// handler's panic), which would otherwise leave the scope
            /// waiting for spinners that never stop.
            struct Done<'a>(&'a AtomicBool);
            impl Drop for Done<'_> {
                fn drop(&mut self) {
                    self.0.store(true, Ordering::Release);
                }
            }
            let done = AtomicBool::new(false);
            return pool.in_place_scope(|scope| {
                for _ in 0..self.count {
                    scope.spawn(|_| {
                        while !done.load(Ordering::Acquire) {
                            // Run the pool's work if there is any, else
                            // give the core to whoever needs it.
                            if rayon::yield_now() != Some(rayon::Yield::Executed) {
                                std::thread::yield_now();
                            }
                        }
                    });
                }
                let _done = Done(&done);
                f()
            });
        }
        f()
    }

    /// Runs `f` in the pool (its [`join`]s then use the pool's threads),
    /// or on this thread.
    pub(crate) fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        #[cfg(feature = "parallel")]
        if let Some(pool) = &self.pool {
            return pool.install(f);
        }
        f()
    }
}

/// Runs `a` and `b`, in parallel inside a pool's [`Threads::install`]
/// (`rayon::join`), else one after the other.
#[inline]
pub(crate) fn join<A: FnOnce() + Send, B: FnOnce() + Send>(a: A, b: B) {
    // Outside a pool rayon would start its global one: never.
    #[cfg(feature = "parallel")]
    if rayon::current_thread_index().is_some() {
        rayon::join(a, b);
        return;
    }
    a();
    b();
}
