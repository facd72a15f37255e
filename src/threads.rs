//! The threads a step may use (the `parallel` feature), and the one
//! primitive the parallel stages split work with.
//!
//! Nothing a step computes depends on the thread count: work is split in
//! halves down to pieces whose boundaries depend only on the item count,
//! and every piece writes only what no other piece of the same stage
//! reads or writes (see [`solver::sweep`](crate::solver)). Without the
//! feature, or with one thread, the halves run one after the other. With
//! threads, the thread that steps is one of them ([`join`]), and the
//! others spin through the step ([`Threads::awake`]).

/// The most threads a space may ask for: far beyond the cores of any
/// machine a step would gain from, low enough that a mistaken count does
/// not start a thread per body.
pub(crate) const MAX_THREADS: usize = 256;

/// The default least work a step shares between threads
/// ([`Space::set_parallel_threshold`](crate::space::Space::set_parallel_threshold)):
/// below it, on the project's 2-core machine,
/// handing stages to the other thread cost more than it saved
/// (`pyramid_20`, work about 1,210, and `bowl_circles_500`, 1,260, ran
/// at 0.90–0.97× the speed of one thread; `bowl_hexagons_500`, 1,400
/// and up, at 1.16–1.20×).
pub const DEFAULT_PARALLEL_THRESHOLD: u32 = 1350;

/// A space's threads: a count, and with the `parallel` feature and more
/// than one thread, the pool of the other `count - 1` (the thread that
/// steps is the first: it takes part, see [`join`]), shared by the space's
/// clones.
#[derive(Clone, Debug)]
pub(crate) struct Threads {
    count: usize,
    /// The least work a step shares ([`Threads::engage`]).
    threshold: u32,
    /// Whether this step shares its stages: set by [`Threads::engage`]
    /// before the step's first stage.
    engaged: bool,
    #[cfg(feature = "parallel")]
    pool: Option<std::sync::Arc<rayon::ThreadPool>>,
}

impl Default for Threads {
    fn default() -> Self {
        Threads {
            count: 1,
            threshold: DEFAULT_PARALLEL_THRESHOLD,
            engaged: false,
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
                    .num_threads(count.saturating_sub(1))
                    .thread_name(|i| format!("tamias2d-{}", i.saturating_add(1)))
                    .build()
                    .map_err(|_| "threads: the operating system refused to start the threads")?;
                Some(std::sync::Arc::new(pool))
            } else {
                None
            };
            Ok(Threads {
                count,
                pool,
                ..Threads::default()
            })
        }
        #[cfg(not(feature = "parallel"))]
        Ok(Threads {
            count,
            ..Threads::default()
        })
    }

    /// These threads with the threshold of `other` (a new count keeps the
    /// space's threshold).
    pub(crate) fn with_threshold_of(self, other: &Threads) -> Threads {
        Threads {
            threshold: other.threshold,
            ..self
        }
    }

    /// The least work a step shares.
    pub(crate) fn threshold(&self) -> u32 {
        self.threshold
    }

    /// Sets the least work a step shares (0: every step).
    pub(crate) fn set_threshold(&mut self, work: u32) {
        self.threshold = work;
    }

    /// Decides, before a step's first stage, whether its stages split
    /// between the threads: when `work` (an estimate from the step
    /// before, [`Space`](crate::space::Space)'s) reaches the threshold.
    /// Either way gives the same bits; only the time differs.
    pub(crate) fn engage(&mut self, work: u32) {
        self.engaged = work >= self.threshold;
    }

    /// The thread count asked for.
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// Whether stages split between threads (the feature, more than one
    /// thread, a step [`engage`](Self::engage)d): otherwise they take the
    /// cheaper in-place serial paths.
    pub(crate) fn parallel(&self) -> bool {
        #[cfg(feature = "parallel")]
        return self.engaged && self.pool.is_some();
        #[cfg(not(feature = "parallel"))]
        false
    }

    /// Runs `f` on this thread with the pool's workers kept awake, and
    /// [`join`] handing work to them: each worker spins, picking up work
    /// as it comes, until `f` returns. Parallel stages a few milliseconds
    /// apart then start at once instead of waking sleeping threads, and
    /// the calling thread works on its share with its caches warm instead
    /// of sleeping while the pool works. Without a pool, just `f()`.
    pub(crate) fn awake<R>(&self, f: impl FnOnce() -> R) -> R {
        #[cfg(feature = "parallel")]
        if let Some(pool) = self.pool.as_ref().filter(|_| self.engaged) {
            use core::sync::atomic::{AtomicBool, Ordering};
            let done = AtomicBool::new(false);
            return pool.in_place_scope(|scope| {
                // One spinner on every worker (a spinner spawned into the
                // pool's queue could be picked up by a worker that already
                // spins, inside its own loop, leaving another asleep).
                scope.spawn_broadcast(|_, _| {
                    // A worker may take its spinner while waiting inside a
                    // piece of work (rayon runs any job then, and a worker
                    // can take a piece before its spinner): spinning there
                    // would never finish the piece the step waits for.
                    if main::is_working() {
                        return;
                    }
                    while !done.load(Ordering::Acquire) {
                        // Run the pool's work if there is any, else give
                        // the core to whoever needs it.
                        if rayon::yield_now() != Some(rayon::Yield::Executed) {
                            std::thread::yield_now();
                        }
                    }
                });
                // Ends the spinning and the hand-over when dropped: also
                // if `f` panics (a handler's panic), which would otherwise
                // leave the scope waiting for spinners that never stop.
                let _stepping = main::Stepping::enter(pool, self.count.saturating_sub(1), &done);
                f()
            });
        }
        f()
    }
}

/// Runs `a` and `b`, in parallel where there are threads to share them:
/// on a pool's worker by `rayon::join`; on the thread that steps, inside
/// [`Threads::awake`], by handing `b` to a worker while it runs `a` (and
/// runs `b` itself if no worker has taken it by then); elsewhere one after
/// the other. Which thread runs which half never changes what they compute.
#[inline]
pub(crate) fn join<A: FnOnce() + Send, B: FnOnce() + Send>(a: A, b: B) {
    #[cfg(feature = "parallel")]
    match main::free_worker() {
        // The stepping thread (even if it is a worker of some other pool,
        // a game's own, that steps the space inside a task).
        Some(Some(pool)) => return main::join(&pool, a, b),
        Some(None) => {}
        // A worker of the step's pool (outside a pool rayon would start
        // its global one: never).
        None if rayon::current_thread_index().is_some() => {
            rayon::join(|| main::working(a), || main::working(b));
            return;
        }
        None => {}
    }
    a();
    b();
}

/// Runs `blocks.len()` stages in order: stage `s`'s `blocks[s]` blocks
/// (`block(s, k)` for `k < blocks[s]`, each once, on any thread), then
/// `serial(s)` on this thread alone, before stage `s + 1` starts. Inside
/// [`Threads::awake`], the pool's workers take part in every stage,
/// claiming blocks as they go: one hand-over for all the stages, and a
/// spin on a counter between them, where a [`join`] per stage would hand
/// over (and wait) once per stage. Elsewhere, in order on this thread.
/// Blocks must not [`join`] (the workers are busy in the stages).
/// Which thread runs which block never changes what they compute.
pub(crate) fn stages(
    blocks: &[u32],
    block: &(impl Fn(usize, u32) + Sync),
    mut serial: impl FnMut(usize),
) {
    #[cfg(feature = "parallel")]
    if let Some(Some(pool)) = main::free_worker() {
        main::stages(&pool, blocks, block, serial);
        return;
    }
    for (s, &n) in blocks.iter().enumerate() {
        for k in 0..n {
            block(s, k);
        }
        serial(s);
    }
}

/// `f(src[i], dst[i])` for every `i` of both, halves in parallel (through
/// [`join`]) down to pieces of `piece` (at least 1): for work on each pair
/// alone, which gives the same result however it is split.
pub(crate) fn zip_split<S: Sync, D: Send>(
    src: &[S],
    dst: &mut [D],
    piece: usize,
    f: &(impl Fn(&S, &mut D) + Sync),
) {
    let len = src.len().min(dst.len());
    if len <= piece.max(1) {
        src.iter().zip(dst.iter_mut()).for_each(|(s, d)| f(s, d));
        return;
    }
    let (Some((src_l, src_r)), Some((dst_l, dst_r))) = (
        src.split_at_checked(len / 2),
        dst.split_at_mut_checked(len / 2),
    ) else {
        return;
    };
    join(
        || zip_split(src_l, dst_l, piece, f),
        || zip_split(src_r, dst_r, piece, f),
    );
}

/// [`zip_split`] with both slices written: `f(a[i], b[i])` for every `i`
/// of both, halves in parallel down to pieces of `piece` (at least 1).
pub(crate) fn zip_mut_split<A: Send, B: Send>(
    a: &mut [A],
    b: &mut [B],
    piece: usize,
    f: &(impl Fn(&mut A, &mut B) + Sync),
) {
    let len = a.len().min(b.len());
    if len <= piece.max(1) {
        a.iter_mut().zip(b.iter_mut()).for_each(|(x, y)| f(x, y));
        return;
    }
    let (Some((a_l, a_r)), Some((b_l, b_r))) = (
        a.split_at_mut_checked(len / 2),
        b.split_at_mut_checked(len / 2),
    ) else {
        return;
    };
    join(
        || zip_mut_split(a_l, b_l, piece, f),
        || zip_mut_split(a_r, b_r, piece, f),
    );
}

/// The thread that steps, taking part in the parallel stages.
#[cfg(feature = "parallel")]
mod main {
    use core::cell::RefCell;
    use core::sync::atomic::{AtomicBool, AtomicU32, AtomicUsize, Ordering};
    use std::sync::{Arc, Mutex, PoisonError};

    /// While a step's parallel stages run on this thread: its pool, how
    /// many workers it has, and how many halves [`join`] has handed to
    /// them that are not yet done.
    struct Handover {
        pool: Arc<rayon::ThreadPool>,
        workers: usize,
        outstanding: usize,
    }

    std::thread_local! {
        static HANDOVER: RefCell<Option<Handover>> = const { RefCell::new(None) };
        /// How deep this thread is in pieces of a step's work.
        static WORKING: core::cell::Cell<u32> = const { core::cell::Cell::new(0) };
    }

    /// Runs `f`, a piece of a step's work, marked as such on this thread
    /// (also if it unwinds).
    pub(super) fn working<R>(f: impl FnOnce() -> R) -> R {
        struct Depth;
        impl Drop for Depth {
            fn drop(&mut self) {
                WORKING.with(|w| w.set(w.get().saturating_sub(1)));
            }
        }
        WORKING.with(|w| w.set(w.get().saturating_add(1)));
        let _depth = Depth;
        f()
    }

    /// Whether this thread is inside a piece of a step's work.
    pub(super) fn is_working() -> bool {
        WORKING.with(|w| w.get() > 0)
    }

    /// Marks this thread as stepping with `pool` until dropped; the drop
    /// also stops the spinners (`done`) and gives back the hand-over of the
    /// step this one was nested in, if any: a thread that waits inside a
    /// step (a worker of a game's own pool, stepping a world in a task) may
    /// be given another world's step to run meanwhile, and the outer step
    /// keeps its pool when that one ends.
    pub(super) struct Stepping<'a> {
        done: &'a AtomicBool,
        outer: Option<Handover>,
    }

    impl<'a> Stepping<'a> {
        pub(super) fn enter(
            pool: &Arc<rayon::ThreadPool>,
            workers: usize,
            done: &'a AtomicBool,
        ) -> Stepping<'a> {
            let outer = HANDOVER.with(|h| {
                h.borrow_mut().replace(Handover {
                    pool: Arc::clone(pool),
                    workers,
                    outstanding: 0,
                })
            });
            Stepping { done, outer }
        }
    }

    impl Drop for Stepping<'_> {
        fn drop(&mut self) {
            let outer = self.outer.take();
            HANDOVER.with(|h| *h.borrow_mut() = outer);
            self.done.store(true, Ordering::Release);
        }
    }

    /// `None` if this thread is not stepping; else the pool if a worker
    /// may be free (fewer halves handed over than workers: counted as one
    /// more), `Some(None)` if all are busy (this thread then runs both
    /// halves itself).
    pub(super) fn free_worker() -> Option<Option<Arc<rayon::ThreadPool>>> {
        HANDOVER.with(|h| {
            let mut h = h.borrow_mut();
            let h = h.as_mut()?;
            Some((h.outstanding < h.workers).then(|| {
                h.outstanding = h.outstanding.saturating_add(1);
                Arc::clone(&h.pool)
            }))
        })
    }

    /// [`super::stages`] with the pool's workers: the caller counted one
    /// of them as outstanding ([`free_worker`]), and this takes the others
    /// too until the stages end. This thread moves the stages on. Each of
    /// the team (this thread first, then each worker as it arrives) owns
    /// the same share of every stage's blocks, a run of them, and takes
    /// them in order; then it takes what is left of the others' shares. A
    /// block thus runs on the same thread from stage to stage while all
    /// keep up (its data stays in that core's cache), and a worker that
    /// comes late (or never) only leaves more blocks to the others. Each
    /// stage has its own counters, so a worker that still looks at a
    /// finished stage claims nothing of the next.
    pub(super) fn stages(
        pool: &rayon::ThreadPool,
        blocks: &[u32],
        block: &(impl Fn(usize, u32) + Sync),
        mut serial: impl FnMut(usize),
    ) {
        let workers = HANDOVER.with(|h| {
            h.borrow_mut().as_mut().map_or(0, |h| {
                let free = h.workers.saturating_sub(h.outstanding).saturating_add(1);
                h.outstanding = h.workers;
                free
            })
        });
        let team = workers.saturating_add(1);
        // Blocks claimed, per stage and share; blocks done, per stage.
        let claimed: Vec<AtomicU32> = (0..blocks.len().saturating_mul(team))
            .map(|_| AtomicU32::new(0))
            .collect();
        let done: Vec<AtomicU32> = blocks.iter().map(|_| AtomicU32::new(0)).collect();
        // The stage the workers follow (`OVER` once every stage is done).
        let current = AtomicUsize::new(0);
        const OVER: usize = usize::MAX;
        let arrived = AtomicUsize::new(1);
        // Runs stage `s`'s blocks, the share of member `me` first, until
        // none is left.
        let work = |s: usize, me: usize| {
            let (Some(&n), Some(finished)) = (blocks.get(s), done.get(s)) else {
                return;
            };
            let base = s.saturating_mul(team);
            for j in (me..team).chain(0..me) {
                let Some(counter) = claimed.get(base.saturating_add(j)) else {
                    continue;
                };
                let (first, end) = (
                    share_start(n, team, j),
                    share_start(n, team, j.saturating_add(1)),
                );
                loop {
                    let k = counter.fetch_add(1, Ordering::Relaxed);
                    let Some(b) = first.checked_add(k).filter(|&b| b < end) else {
                        break;
                    };
                    // Counted as done also if it unwinds (never waited on
                    // for ever; the scope passes the panic on).
                    let _done = CountOnDrop(finished);
                    block(s, b);
                }
            }
        };
        pool.in_place_scope(|scope| {
            for _ in 0..workers {
                scope.spawn(|_| {
                    let me = arrived.fetch_add(1, Ordering::Relaxed);
                    working(|| {
                        let mut seen = OVER;
                        let mut spins = 0u32;
                        loop {
                            let s = current.load(Ordering::Acquire);
                            if s == OVER {
                                return;
                            }
                            if s != seen {
                                work(s, me);
                                seen = s;
                                spins = 0;
                            } else {
                                wait_a_little(&mut spins);
                            }
                        }
                    });
                });
            }
            // Sends the workers home when dropped: also if this thread
            // unwinds, which would otherwise leave the scope waiting on
            // them.
            let _over = SetOnDrop(&current, OVER);
            for (s, (finished, &n)) in done.iter().zip(blocks).enumerate() {
                current.store(s, Ordering::Release);
                work(s, 0);
                let mut spins = 0u32;
                while finished.load(Ordering::Acquire) < n {
                    wait_a_little(&mut spins);
                }
                serial(s);
            }
        });
        HANDOVER.with(|h| {
            if let Some(h) = h.borrow_mut().as_mut() {
                h.outstanding = h.outstanding.saturating_sub(workers);
            }
        });
    }

    /// The first of `n` blocks in share `j` of `team` (the end of share
    /// `team - 1` is `n`): shares differ by at most one block.
    fn share_start(n: u32, team: usize, j: usize) -> u32 {
        let team = team.max(1) as u64;
        let at = u64::from(n)
            .saturating_mul(j as u64)
            .checked_div(team)
            .unwrap_or(0);
        u32::try_from(at).unwrap_or(n)
    }

    /// One round of a wait on another thread: a spin, or after 128 of
    /// them, the core given away (with more threads than cores, the one
    /// waited for may need it).
    #[inline]
    fn wait_a_little(spins: &mut u32) {
        if *spins < 128 {
            *spins = spins.wrapping_add(1);
            core::hint::spin_loop();
        } else {
            std::thread::yield_now();
        }
    }

    /// Sets its flag when dropped: when its half is done, or unwinding.
    struct FlagOnDrop<'a>(&'a AtomicBool);

    impl Drop for FlagOnDrop<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }

    /// Sets its word to a value when dropped.
    struct SetOnDrop<'a>(&'a AtomicUsize, usize);

    impl Drop for SetOnDrop<'_> {
        fn drop(&mut self) {
            self.0.store(self.1, Ordering::Release);
        }
    }

    /// Counts one more when dropped: when its block is done, or unwinding.
    struct CountOnDrop<'a>(&'a AtomicU32);

    impl Drop for CountOnDrop<'_> {
        fn drop(&mut self) {
            self.0.fetch_add(1, Ordering::Release);
        }
    }

    /// `b` handed to `pool`, `a` here, then `b` here too if no worker has
    /// claimed it yet; returns when both are done. The caller counted `b`
    /// as outstanding ([`free_worker`]).
    pub(super) fn join<A: FnOnce() + Send, B: FnOnce() + Send>(
        pool: &rayon::ThreadPool,
        a: A,
        b: B,
    ) {
        let b = Mutex::new(Some(b));
        let claimed = AtomicBool::new(false);
        let done = AtomicBool::new(false);
        let run_b = || {
            let f = b.lock().unwrap_or_else(PoisonError::into_inner).take();
            if let Some(f) = f {
                f();
            }
        };
        pool.in_place_scope(|scope| {
            scope.spawn(|_| {
                let _done = FlagOnDrop(&done);
                if !claimed.swap(true, Ordering::AcqRel) {
                    working(run_b);
                }
            });
            a();
            if !claimed.swap(true, Ordering::AcqRel) {
                run_b();
            } else {
                // A worker has it: wait.
                let mut spins = 0u32;
                while !done.load(Ordering::Acquire) {
                    wait_a_little(&mut spins);
                }
            }
            HANDOVER.with(|h| {
                if let Some(h) = h.borrow_mut().as_mut() {
                    h.outstanding = h.outstanding.saturating_sub(1);
                }
            });
        });
    }
}
