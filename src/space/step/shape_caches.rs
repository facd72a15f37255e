//! [`Stage::ShapeCaches`](super::Stage::ShapeCaches): the world-space geometry and bounding box of
//! every shape that moved, and the lists of moving and sleeping boxes the
//! broadphase reads. A level's static shapes are skipped while it is
//! unchanged (`space::level`). In pieces between the threads.

use crate::arena::Arena;
use crate::body::{Body, BodyType};
use crate::broadphase::{BroadphaseCache, Proxy};
use crate::math::BB;
use crate::shape::{Geometry, Shape};

use super::super::level::LevelIndex;
use super::super::state::WorldState;

/// Per-shape world-space cache: rewritten each step for shapes of
/// non-static bodies, only when statics changed for static ones.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShapeCache {
    pub(crate) geometry: Geometry,
    pub(crate) bb: BB,
    /// Written for a shape of a static body.
    pub(crate) is_static: bool,
}

/// [`Stage::ShapeCaches`](super::Stage::ShapeCaches): world-space geometry
/// and bounding box of every shape of a non-static body into `caches`
/// (indexed by shape slot); static shapes' entries are rewritten only when
/// `bp.statics_dirty` says statics changed (the API calls that can add,
/// remove, move or reshape a static shape, `restore_state` and a new space
/// set it), otherwise kept from the step that wrote them. A live slot whose
/// body is static but whose entry was not written for a static body (a
/// body replaced in place through `body_mut`) is written now and marks the
/// statics dirty (and forgets the `level`). Lists the moving and sleeping
/// shapes' boxes, in slot order, in `bp` for the broadphase.
///
/// One path for any thread count: the slots outside the level in
/// [`SHAPE_PIECE`]s, halves in parallel where there are threads (inline on
/// one), each piece listing its own boxes, joined in slot order.
pub(crate) fn update_shape_caches(
    state: &WorldState,
    caches: &mut Vec<Option<ShapeCache>>,
    bp: &mut BroadphaseCache,
    level_cache: &crate::space::level::LevelCache,
    pieces: &mut Vec<CachePiece>,
) {
    let rewrite = Rewrite {
        statics: bp.statics_dirty,
        sleepers: bp.sleepers_dirty,
    };
    bp.sleepers.clear();
    bp.proxies.clear();
    let (bodies, shapes) = (&state.bodies, &state.shapes);
    let slots = shapes.capacity_slots();
    caches.resize(slots, None);
    // While the statics are clean, every level slot holds its static entry
    // already: walk the other slots only, so a big level costs nothing here
    // (`space::level`; a change to the level flags the statics, and the
    // walk is then complete).
    let level = if rewrite.statics {
        None
    } else {
        Some(level_cache.take().unwrap_or_else(|| LevelIndex::of(state)))
    };
    let skip: &[(u32, u32)] = level.as_ref().map_or(&[], |l| &l.shape_runs);
    // The pieces are kept from step to step with their lists, so that a
    // warm step allocates nothing: only their ranges are rewritten.
    let mut count = 0;
    for gap in crate::arena::gaps(skip, slots as u32) {
        let mut start = gap.start;
        while start < gap.end {
            let end = start.saturating_add(SHAPE_PIECE).min(gap.end);
            match pieces.get_mut(count) {
                Some(piece) => piece.slots = start..end,
                None => pieces.push(CachePiece {
                    slots: start..end,
                    ..CachePiece::default()
                }),
            }
            count = count.saturating_add(1);
            start = end;
        }
    }
    pieces.truncate(count);
    let view = (shapes, bodies, rewrite);
    update_caches_split(&view, caches, 0, pieces);
    let mut statics_changed = false;
    for piece in pieces.iter() {
        bp.proxies.extend_from_slice(&piece.proxies);
        bp.sleepers.extend_from_slice(&piece.sleepers);
        statics_changed |= piece.statics_changed;
    }
    if statics_changed {
        bp.statics_dirty = true;
        // Also a body made static in place (`body_mut`): the level changed.
        level_cache.set(None);
    } else if let Some(level) = level {
        level_cache.set(Some(level));
    }
}

/// Which cache entries the shape-cache stage rewrites even if written before.
#[derive(Clone, Copy)]
struct Rewrite {
    /// Static shapes' (the statics changed).
    statics: bool,
    /// Sleeping shapes' (bodies fell asleep or woke).
    sleepers: bool,
}

/// What the shape-cache stage did with a shape slot: whether it wrote a static
/// shape's entry (the statics changed), and the list its box goes to.
struct Written {
    static_entry: bool,
    listed: Listed,
}

/// The list a written entry's box goes to.
enum Listed {
    /// None: nothing written, the slot cleared, or a static shape.
    Neither,
    /// A moving shape's: the sweep's.
    Moving(Proxy),
    /// A sleeping shape's: the sleeping tree's.
    Sleeping(Proxy),
}

impl Written {
    const NOTHING: Written = Written {
        static_entry: false,
        listed: Listed::Neither,
    };
}

/// [`Stage::ShapeCaches`](super::Stage::ShapeCaches) for shape slot `i` and its cache `entry`.
#[inline]
fn update_cache_entry(
    entry: &mut Option<ShapeCache>,
    i: u32,
    shapes: &Arena<Shape>,
    bodies: &Arena<Body>,
    rewrite: Rewrite,
) -> Written {
    let Some((s, body)) = shapes
        .get_by_index(i)
        .and_then(|(_, s)| Some((s, bodies.get(s.body)?)))
    else {
        *entry = None;
        return Written::NOTHING;
    };
    let is_static = body.body_type() == BodyType::Static;
    if is_static && !rewrite.statics && entry.as_ref().is_some_and(|c| c.is_static) {
        return Written::NOTHING;
    }
    // A sleeping body has not moved since its entry was written
    // (anything that could move it wakes it and sets the flag).
    let sleeping = body.is_sleeping();
    if sleeping && !rewrite.sleepers && entry.as_ref().is_some_and(|c| !c.is_static) {
        return Written::NOTHING;
    }
    let (pos, rot) = (body.position(), body.rotation());
    // Written over last step's entry where there is one.
    let bb = match entry {
        Some(c) => {
            s.geometry.write_world_into(pos, rot, &mut c.geometry);
            c.bb = c.geometry.bb();
            c.is_static = is_static;
            c.bb
        }
        None => {
            let geometry = s.geometry.to_world(pos, rot);
            let bb = geometry.bb();
            *entry = Some(ShapeCache {
                geometry,
                bb,
                is_static,
            });
            bb
        }
    };
    let proxy = Proxy { index: i, bb };
    Written {
        static_entry: is_static,
        listed: if sleeping {
            Listed::Sleeping(proxy)
        } else if !is_static {
            Listed::Moving(proxy)
        } else {
            Listed::Neither
        },
    }
}

/// Shape slots per piece of the split shape-cache stage (a few µs of work).
const SHAPE_PIECE: usize = 256;

/// A piece of the split shape-cache stage: its slots, and what it found.
#[derive(Clone, Debug, Default)]
pub(crate) struct CachePiece {
    slots: core::ops::Range<usize>,
    proxies: Vec<Proxy>,
    sleepers: Vec<Proxy>,
    statics_changed: bool,
}

/// [`Stage::ShapeCaches`](super::Stage::ShapeCaches) for `pieces` (in slot order), whose slots lie in `caches`
/// from slot `base` on: halves in parallel, each piece writing its own
/// entries and lists.
fn update_caches_split(
    view: &(&Arena<Shape>, &Arena<Body>, Rewrite),
    caches: &mut [Option<ShapeCache>],
    base: usize,
    pieces: &mut [CachePiece],
) {
    let (shapes, bodies, rewrite) = *view;
    if let [piece] = pieces {
        piece.proxies.clear();
        piece.sleepers.clear();
        piece.statics_changed = false;
        let range = piece.slots.start.wrapping_sub(base)..piece.slots.end.wrapping_sub(base);
        let Some(entries) = caches.get_mut(range) else {
            return;
        };
        for (k, entry) in entries.iter_mut().enumerate() {
            // Slots are counted in u32 (the arena's indices).
            let i = piece.slots.start.wrapping_add(k) as u32;
            let written = update_cache_entry(entry, i, shapes, bodies, rewrite);
            piece.statics_changed |= written.static_entry;
            match written.listed {
                Listed::Neither => {}
                Listed::Moving(p) => piece.proxies.push(p),
                Listed::Sleeping(p) => piece.sleepers.push(p),
            }
        }
        return;
    }
    if pieces.is_empty() {
        return;
    }
    let mid = pieces.len() / 2;
    let (left, right) = pieces.split_at_mut(mid);
    let cut = right.first().map_or(base, |p| p.slots.start);
    let Some((caches_l, caches_r)) = caches.split_at_mut_checked(cut.wrapping_sub(base)) else {
        return;
    };
    crate::threads::join(
        || update_caches_split(view, caches_l, base, left),
        || update_caches_split(view, caches_r, cut, right),
    );
}
