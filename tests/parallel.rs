//! The parallel step (`parallel` feature, `Space::set_threads`) gives the
//! bits of one thread: every golden scene, with the canonical and with the
//! colored order of the sequential solver and on the soft step, stepped on
//! 1, 2, 3, 4 and 8 threads (more threads than
//! this machine's cores is fine), has the same checksum at every step; on
//! one thread it is the committed golden (`scenes/tests/golden.rs`, which
//! the cross-platform script runs without the feature on every target, and
//! which also holds the colored solver's goldens).
//!
//! The root crate's tests build the engine with the feature (see the
//! dev-dependencies). A debug build checks the first 60 steps of each
//! scene on 1 and 3 threads (every step validated costs time there);
//! release, the whole golden run on every count. Also here, with threads:
//! Box2D's benchmark scenes made small (they have no golden), GGRS SyncTest, snapshot
//! continuation across thread counts, a panicking handler, and handlers and
//! a custom integrator with threads.
use tamias2d::space::Kernels;
use tamias2d_scenes::REGISTRY;

const THREADS: [usize; 5] = [1, 2, 3, 4, 8];

/// The thread counts this build compares: [`THREADS`] when optimised (CI
/// runs this file in release too); 1 and 3 in a debug build, where every
/// step is validated: 3 splits each color more ways than 2 and runs more
/// threads than CI's two cores, which wait on each other.
fn thread_counts() -> &'static [usize] {
    if cfg!(debug_assertions) {
        &[1, 3]
    } else {
        &THREADS
    }
}

/// The solver orders compared: the sequential solver's canonical and
/// colored orders, and the soft step (always colored).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Order {
    Canonical,
    Colored,
    Soft,
    /// The soft step with the narrow contact kernels.
    Narrow,
}

/// The checksum after each of `steps` steps of scene `name`.
fn checksums(name: &str, order: Order, threads: usize, steps: u32) -> Vec<u64> {
    checksums_on(name, order, threads, Kernels::Auto, steps)
}

/// [`checksums`] on `kernels` (`Space::set_kernels`).
fn checksums_on(
    name: &str,
    order: Order,
    threads: usize,
    kernels: Kernels,
    steps: u32,
) -> Vec<u64> {
    let mut desc = tamias2d_scenes::builtin(name).expect("a registered scene");
    desc.settings.colored_solver = order == Order::Colored;
    if order == Order::Soft {
        desc.settings.use_soft_step();
    }
    if order == Order::Narrow {
        desc.settings.use_narrow_soft_step();
    }
    let mut world = desc.build().expect("a valid scene");
    world.space.set_threads(threads).expect("threads start");
    world.space.set_parallel_threshold(0);
    assert_eq!(world.space.threads(), threads);
    world.space.set_kernels(kernels);
    (0..steps)
        .map(|n| {
            world
                .step()
                .unwrap_or_else(|e| panic!("{name}, {threads} threads, step {n}: {e}"));
            world.space.checksum()
        })
        .collect()
}

#[test]
fn the_feature_is_on_in_these_tests() {
    // Otherwise the test below would compare one thread with itself.
    const { assert!(tamias2d::space::PARALLEL) };
}

/// Aborts the test binary, naming the run in progress (`at`), if the test
/// holding this has not dropped it after `limit`: a hang of the parallel
/// step shows as that message, not as CI's timeout.
struct Watchdog {
    at: std::sync::Arc<std::sync::Mutex<String>>,
    _done: std::sync::mpsc::Sender<()>,
}

impl Watchdog {
    fn new(limit: std::time::Duration) -> Watchdog {
        let (done, wait) = std::sync::mpsc::channel::<()>();
        let at = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
        let seen = std::sync::Arc::clone(&at);
        std::thread::spawn(move || {
            // The test's end drops the sender: the wait ends, no abort.
            if let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = wait.recv_timeout(limit) {
                let at = seen.lock().map(|s| s.clone()).unwrap_or_default();
                // Past the test harness's capture of `eprintln!`, which the
                // abort would swallow.
                let message = format!("tests/parallel.rs: no end in {limit:?}; at {at}: a hang\n");
                let _ = std::io::Write::write_all(&mut std::io::stderr(), message.as_bytes());
                std::process::abort();
            }
        });
        Watchdog { at, _done: done }
    }

    fn at(&self, what: String) {
        if let Ok(mut at) = self.at.lock() {
            *at = what;
        }
    }
}

/// Every golden scene in `order` on every thread count has the bits of
/// one thread at every step; on the canonical order, one thread's last
/// checksum is the golden. One test per order, so that the test harness
/// runs them side by side (about 25 s each in debug on 2 cores).
fn every_thread_count_gives_the_bits_of_one_thread(order: Order) {
    let watchdog = Watchdog::new(std::time::Duration::from_secs(900));
    for info in REGISTRY {
        let Some(golden) = info.golden else { continue };
        let steps = if cfg!(debug_assertions) {
            golden.steps.min(60)
        } else {
            golden.steps
        };
        let one = checksums(info.name, order, 1, steps);
        if order == Order::Canonical && steps == golden.steps {
            assert_eq!(one.last(), Some(&golden.checksum), "{}: golden", info.name);
        }
        for &threads in &thread_counts()[1..] {
            watchdog.at(format!("{} ({order:?}) on {threads} threads", info.name));
            let many = checksums(info.name, order, threads, steps);
            if let Some(n) = one.iter().zip(&many).position(|(a, b)| a != b) {
                panic!(
                    "{} ({order:?}): {threads} threads differ from 1 at step {}",
                    info.name,
                    n + 1
                );
            }
        }
    }
}

#[test]
fn every_thread_count_gives_the_bits_of_one_thread_in_the_canonical_order() {
    every_thread_count_gives_the_bits_of_one_thread(Order::Canonical);
}

#[test]
fn every_thread_count_gives_the_bits_of_one_thread_in_the_colored_order() {
    every_thread_count_gives_the_bits_of_one_thread(Order::Colored);
}

#[test]
fn every_thread_count_gives_the_bits_of_one_thread_on_the_soft_step() {
    every_thread_count_gives_the_bits_of_one_thread(Order::Soft);
}

/// Every kernel form of `order` (the wide kernels as this processor runs
/// them, AVX2 where it has it, and compiled for the build's instruction
/// set) gives the bits of `reference` on one thread at every step, on 1,
/// 2, 3 and 4 threads: in release every golden scene, in a debug build
/// (where lanes run about 60 times slower) the short `debug_scenes` on
/// the wide kernels as this processor runs them.
fn every_form_gives_the_reference_bits(
    order: Order,
    reference: Kernels,
    debug_scenes: &[(&'static str, u32)],
) {
    let watchdog = Watchdog::new(std::time::Duration::from_secs(900));
    let scenes: Vec<(&str, u32)> = if cfg!(debug_assertions) {
        debug_scenes.to_vec()
    } else {
        REGISTRY
            .iter()
            .filter_map(|info| Some((info.name, info.golden?.steps)))
            .collect()
    };
    for (name, steps) in scenes {
        let want = checksums_on(name, order, 1, reference, steps);
        let forms: &[Kernels] = if cfg!(debug_assertions) {
            &[Kernels::Wide]
        } else {
            &[Kernels::Wide, Kernels::Portable]
        };
        for &kernels in forms {
            for &threads in thread_counts().iter().take(4) {
                watchdog.at(format!(
                    "{name} ({order:?}, {kernels:?}) on {threads} threads"
                ));
                let got = checksums_on(name, order, threads, kernels, steps);
                if let Some(n) = want.iter().zip(&got).position(|(a, b)| a != b) {
                    panic!(
                        "{name} ({order:?}): {kernels:?} kernels on {threads} threads differ \
                         from one thread's {reference:?} ones at step {}",
                        n + 1
                    );
                }
            }
        }
    }
}

/// The soft step's wide kernels, forced on, give the scalar kernels' bits
/// at every step on 1, 2, 3 and 4 threads (a step that splits its passes
/// between threads runs the scalar ones; one with fewer manifolds than a
/// split needs runs them in place).
#[test]
fn wide_kernels_give_the_scalar_bits_on_every_thread_count() {
    every_form_gives_the_reference_bits(Order::Soft, Kernels::Scalar, &[("pyramid_20", 6)]);
}

/// The narrow contact kernels give the same bits on every kernel form
/// (the scalar choice runs the portable lanes) and thread count: each
/// color's batches split between threads, the overflow color's run in
/// order. In debug a stack (two-point manifolds) and a bowl of circles
/// (one-point ones).
#[test]
fn narrow_kernels_give_the_same_bits_on_every_form_and_thread_count() {
    every_form_gives_the_reference_bits(
        Order::Narrow,
        Kernels::Scalar,
        &[("pyramid_20", 6), ("bowl_circles_100", 8)],
    );
}

/// A handler that panics while the pool's workers are kept awake: the
/// panic reaches the caller (the workers stop spinning), never a hang.
#[test]
fn a_panicking_handler_with_threads_unwinds_and_does_not_hang() {
    let mut world = tamias2d_scenes::builtin("pyramid_20")
        .expect("a registered scene")
        .build()
        .expect("a valid scene");
    world.space.set_threads(2).expect("threads start");
    world.space.set_parallel_threshold(0);
    world
        .space
        .add_wildcard_handler(Default::default())
        .pre_solve = Some(Box::new(|_| panic!("a game's bug")));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| world.step()));
    assert!(result.is_err(), "the handler's panic reached the caller");
}

/// The colored solver on 2 threads under GGRS rollback: a `SyncTestSession`
/// re-simulating the last 7 frames every frame agrees with itself and ends
/// where a straight run on one thread ends.
#[test]
fn ggrs_synctest_on_two_threads_agrees_with_a_straight_run_on_one() {
    use tamias2d_scenes::ggrs_game::{run_straight_on, run_synctest, Game};
    let colored = |threads: usize| {
        let mut game = Game::new();
        let settings = tamias2d::space::Settings {
            colored_solver: true,
            ..*game.space.settings()
        };
        game.space.set_settings(settings).expect("valid settings");
        game.space.set_threads(threads).expect("threads start");
        game.space.set_parallel_threshold(0);
        game
    };
    let frames = if cfg!(debug_assertions) { 120 } else { 600 };
    let mut game = colored(2);
    run_synctest(&mut game, frames, 7, 3).expect("deterministic under rollback on 2 threads");
    let straight = run_straight_on(colored(1), frames, 3, 0);
    assert_eq!(game.space.checksum(), straight.space.checksum());
}

/// A frame snapshot saved on 2 threads and loaded into another space on 3
/// continues exactly as the straight run on 1 (colored solver).
#[test]
fn snapshot_continuation_across_thread_counts() {
    let build = |threads: usize| {
        let mut desc = tamias2d_scenes::builtin("bowl_boxes_100").expect("a registered scene");
        desc.settings.colored_solver = true;
        let mut world = desc.build().expect("a valid scene");
        world.space.set_threads(threads).expect("threads start");
        world.space.set_parallel_threshold(0);
        world
    };
    let mut straight = build(1);
    straight.step_n(120).expect("steps");
    let mut first = build(2);
    first.step_n(60).expect("steps");
    let frame = tamias2d::snapshot::save_frame(&first.space);
    let mut second = build(3);
    second
        .space
        .load_frame_snapshot(&frame)
        .expect("the frame loads");
    second.step_n(60).expect("steps");
    assert_eq!(second.space.checksum(), straight.space.checksum());
}

#[test]
fn thread_counts_out_of_range_are_refused_or_clamped() {
    let mut space = tamias2d::space::Space::new();
    space.set_threads(0).expect("0 counts as 1");
    assert_eq!(space.threads(), 1);
    let err = space
        .set_threads(100_000)
        .expect_err("far too many threads");
    assert!(err.to_string().contains("at most 256"), "{err}");
    assert_eq!(space.threads(), 1, "an error changes nothing");
}

/// A game that steps its world inside a task of its own rayon pool (a
/// worker thread of another pool): the step ends and gives the bits of one
/// thread. Two worlds are stepped at once from two tasks of the game's
/// pool, each with its own step pool; while one waits inside its step, its
/// thread may be given the other world's step to run (rayon runs the
/// game's pending tasks then), a nested step that hands the outer one its
/// pool back when it ends (`threads::main::Stepping`).
#[test]
fn stepping_inside_another_rayon_pool_gives_the_bits_of_one_thread() {
    let watchdog = Watchdog::new(std::time::Duration::from_secs(300));
    let steps = if cfg!(debug_assertions) { 30 } else { 120 };
    let run = |colored: bool, threads: usize| {
        let order = if colored {
            Order::Colored
        } else {
            Order::Canonical
        };
        checksums("pyramid_20", order, threads, steps)
    };
    let one = [run(false, 1), run(true, 1)];
    let game_pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("the game's pool starts");
    watchdog.at("pyramid_20 on 2 and 3 threads inside a 2-thread game pool".into());
    let (canonical, colored) = game_pool.install(|| rayon::join(|| run(false, 2), || run(true, 3)));
    assert_eq!(
        canonical, one[0],
        "canonical order, 2 threads in a foreign pool"
    );
    assert_eq!(
        colored, one[1],
        "colored order, 3 threads in a foreign pool"
    );
}

/// The stages split between threads that also have a one-thread form for
/// games' closures (a custom velocity integrator on one body: the others
/// still integrate in pieces) and the arbiters' update ahead of the merge
/// (handlers that reject pairs and change the arbiter they see) give the
/// bits of one thread on the soft step, step by step.
#[test]
fn handlers_and_custom_integrators_give_the_bits_of_one_thread() {
    use tamias2d::math::{Real, Vect};
    let run = |threads: usize| -> Vec<u64> {
        let mut desc = tamias2d_scenes::builtin("pyramid_20").expect("a registered scene");
        desc.settings.use_soft_step();
        let mut world = desc.build().expect("a valid scene");
        world.space.set_threads(threads).expect("threads start");
        world.space.set_parallel_threshold(0);
        let handler = world.space.add_wildcard_handler(Default::default());
        // A pair whose second shape's slot is 3 modulo 7 never collides;
        // the others solve with a friction set by their contact count.
        handler.begin = Some(Box::new(|ctx| ctx.arbiter.shapes().1.index() % 7 != 3));
        handler.pre_solve = Some(Box::new(|ctx| {
            ctx.arbiter.friction = Real::from_bits(ctx.arbiter.count() as i64 * (1 << 30));
            true
        }));
        let dynamic: Vec<_> = world
            .space
            .bodies()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, _)| h)
            .collect();
        let h = dynamic[dynamic.len() / 2];
        world
            .space
            .set_velocity_update_func(
                h,
                Some(Box::new(|body, g, damping, dt| {
                    body.update_velocity(Vect::new(g.y, g.x), damping, dt);
                })),
            )
            .expect("a live body");
        (0..90)
            .map(|n| {
                world
                    .step()
                    .unwrap_or_else(|e| panic!("{threads} threads, step {n}: {e}"));
                world.space.checksum()
            })
            .collect()
    };
    every_thread_count_agrees_with_one(run);
}

/// The soft step keeps the solver bodies shared between threads from the
/// first sub-step to the last when no joint or custom integrator comes
/// between them, and fuses the body stages: forces re-applied in every
/// sub-step, damping, a torque, and a force on a static body (the level
/// changes) give the bits of one thread, step by step.
#[test]
fn forces_and_damping_on_shared_sub_steps_give_the_bits_of_one_thread() {
    use tamias2d::math::{Real, Vect};
    let run = |threads: usize| -> Vec<u64> {
        let mut desc = tamias2d_scenes::builtin("pyramid_20").expect("a registered scene");
        desc.settings.use_narrow_soft_step();
        desc.settings.damping = Real::lit("0.97");
        let mut world = desc.build().expect("a valid scene");
        world.space.set_threads(threads).expect("threads start");
        world.space.set_parallel_threshold(0);
        let handles: Vec<_> = world.space.bodies().map(|(h, _)| h).collect();
        (0..60u32)
            .map(|n| {
                for (k, &h) in handles.iter().enumerate() {
                    let Some(body) = world.space.body_mut(h) else {
                        continue;
                    };
                    if !body.is_dynamic() {
                        if n % 20 == 5 {
                            body.apply_force(Vect::new(Real::ONE, Real::ZERO));
                        }
                    } else if k % 3 == 0 {
                        body.apply_force(Vect::from_ints((k % 7) as i32, 2));
                        body.set_torque(Real::from_int((k % 5) as i32 - 2));
                    }
                }
                world
                    .step()
                    .unwrap_or_else(|e| panic!("{threads} threads, step {n}: {e}"));
                world.space.checksum()
            })
            .collect()
    };
    every_thread_count_agrees_with_one(run);
}

/// Panics at the first step where `run(threads)`'s checksums differ from
/// `run(1)`'s, for every thread count above one.
fn every_thread_count_agrees_with_one(run: impl Fn(usize) -> Vec<u64>) {
    let one = run(1);
    for &threads in thread_counts().iter().filter(|&&t| t > 1) {
        let got = run(threads);
        if let Some(n) = one.iter().zip(&got).position(|(a, b)| a != b) {
            panic!("{threads} threads differ from one at step {}", n + 1);
        }
    }
}

/// Warm starting off on the narrow soft step (the impulses start from 0
/// in every sub-step, between the shared passes) gives the bits of one
/// thread, step by step.
#[test]
fn warm_starting_off_on_the_soft_step_gives_the_bits_of_one_thread() {
    every_thread_count_agrees_with_one(|threads| {
        let mut desc = tamias2d_scenes::builtin("pyramid_20").expect("a registered scene");
        desc.settings.use_narrow_soft_step();
        desc.settings.warm_starting = false;
        let mut world = desc.build().expect("a valid scene");
        world.space.set_threads(threads).expect("threads start");
        world.space.set_parallel_threshold(0);
        (0..40u32)
            .map(|n| {
                world
                    .step()
                    .unwrap_or_else(|e| panic!("{threads} threads, step {n}: {e}"));
                world.space.checksum()
            })
            .collect()
    });
}

/// With no handler, threads split the narrowphase's arbiter merge; pairs
/// that come and go (elastic circles), cached arbiters that expire after
/// two idle steps, sensors (kept, never solved) and shapes removed in the
/// middle of the run give one thread's snapshot bytes, step by step.
#[test]
fn arbiters_coming_and_going_give_the_bytes_of_one_thread() {
    let run = |threads: usize| -> Vec<u64> {
        let mut desc = tamias2d_scenes::builtin("bouncy_circles_500").expect("a registered scene");
        desc.settings.collision_persistence = 2;
        let mut world = desc.build().expect("a valid scene");
        world.space.set_threads(threads).expect("threads start");
        world.space.set_parallel_threshold(0);
        let shapes: Vec<_> = world.space.shapes().map(|(h, _)| h).collect();
        (0..50u32)
            .map(|n| {
                if n == 10 {
                    // Every 7th shape becomes a sensor in a new slot.
                    for &h in shapes.iter().step_by(7) {
                        let mut shape = world.space.remove_shape(h).expect("a live shape");
                        shape.sensor = true;
                        world.space.add_shape(shape).expect("shape added back");
                    }
                }
                if n == 30 {
                    for &h in shapes.iter().skip(3).step_by(11) {
                        let _ = world.space.remove_shape(h);
                    }
                }
                world
                    .step()
                    .unwrap_or_else(|e| panic!("{threads} threads, step {n}: {e}"));
                let space = &world.space;
                let is_sensor = |h| space.shape(h).is_some_and(|s| s.sensor);
                let sensor_pairs = space
                    .arbiters()
                    .iter()
                    .filter(|a| is_sensor(a.shapes().0) || is_sensor(a.shapes().1))
                    .count();
                assert!(n < 12 || sensor_pairs > 0, "step {n}: no sensor touches");
                let mut hasher = std::hash::DefaultHasher::new();
                std::hash::Hash::hash(&tamias2d::snapshot::save(space), &mut hasher);
                std::hash::Hasher::finish(&hasher)
            })
            .collect()
    };
    every_thread_count_agrees_with_one(run);
}

/// Box2D's benchmark scenes, made small (the full ones have no golden, so
/// the tests above do not step them): on every order, every thread count
/// gives one thread's bits at every step, the first after a frame load
/// among them. The spinner holds the case that once broke: its bar starts
/// among a few hundred bodies, held by a pivot and turned by a motor, so
/// the contacts split between threads from the very first step beside
/// joints whose rows were not built yet (a first step, a load, a joint
/// whose bodies wake up).
#[test]
fn box2d_scenes_made_small_give_the_bits_of_one_thread() {
    use tamias2d_scenes::box2d;
    type Build = fn() -> tamias2d_scenes::SceneDesc;
    let scenes: [(&str, Build); 6] = [
        ("spinner", || box2d::spinner(300)),
        ("tumbler", || box2d::tumbler(12)),
        ("joint_grid", || box2d::joint_grid(12)),
        ("smash", || box2d::smash(16, 12)),
        ("many_pyramids", || box2d::many_pyramids(2, 2)),
        ("large_pyramid", || box2d::large_pyramid(16)),
    ];
    for (name, scene) in scenes {
        for order in [Order::Colored, Order::Soft, Order::Narrow] {
            eprintln!("{name} ({order:?})");
            every_thread_count_agrees_with_one(|threads| {
                let mut desc = scene();
                desc.settings.colored_solver = order == Order::Colored;
                match order {
                    Order::Soft => desc.settings.use_soft_step(),
                    Order::Narrow => desc.settings.use_narrow_soft_step(),
                    Order::Canonical | Order::Colored => {}
                }
                let mut world = desc.build().expect("a valid scene");
                world.space.set_threads(threads).expect("threads start");
                world.space.set_parallel_threshold(0);
                let mut sums = Vec::new();
                for n in 0..24u32 {
                    if n == 8 {
                        let frame = tamias2d::snapshot::save_frame(&world.space);
                        world
                            .space
                            .load_frame_snapshot(&frame)
                            .expect("the frame loads");
                    }
                    world
                        .step()
                        .unwrap_or_else(|e| panic!("{name}, {threads} threads, step {n}: {e}"));
                    sums.push(world.space.checksum());
                }
                sums
            });
        }
    }
}

/// A step below the parallel threshold runs on the calling thread, one at
/// or above it splits; the two paths share the arbiters' caches, so a run
/// that switches between them gives one thread's bits: the threshold
/// switched between 0 and `u32::MAX` in a changing pattern, then a
/// threshold the scene's work grows through (the rain piles up: about
/// 175 at step 60, 400 at step 110). The threshold is kept by a new
/// thread count.
#[test]
fn steps_switching_between_split_and_serial_give_the_bits_of_one_thread() {
    let mut space = tamias2d::space::Space::new();
    assert_eq!(
        space.parallel_threshold(),
        tamias2d::space::DEFAULT_PARALLEL_THRESHOLD
    );
    space.set_parallel_threshold(7);
    space.set_threads(2).expect("threads start");
    assert_eq!(space.parallel_threshold(), 7);
    for narrow in [false, true] {
        every_thread_count_agrees_with_one(|threads| {
            let mut desc = tamias2d_scenes::builtin("rain_1000").expect("a registered scene");
            if narrow {
                desc.settings.use_narrow_soft_step();
            }
            let mut world = desc.build().expect("a valid scene");
            world.space.set_threads(threads).expect("threads start");
            (0..120u32)
                .map(|n| {
                    let threshold = match n {
                        0..60 if n % 5 < 2 || n % 7 == 3 => u32::MAX,
                        0..60 => 0,
                        _ => 300,
                    };
                    world.space.set_parallel_threshold(threshold);
                    world
                        .step()
                        .unwrap_or_else(|e| panic!("{threads} threads, step {n}: {e}"));
                    world.space.checksum()
                })
                .collect()
        });
    }
}
