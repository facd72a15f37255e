//! Generational arenas: the storage of bodies and shapes.
//!
//! A handle is `(index, generation)`. Removing an object bumps its slot's
//! generation and pushes the slot on a free list, so a stale handle never
//! reaches the object that later reuses the slot. The free list is part of the
//! simulation state (and of snapshots): a world restored from a snapshot hands
//! out exactly the handles the original would have handed out.
//!
//! An arena split in two (a world's level and its frame: [`ArenaPart`],
//! the runs of slots and the walks around them) is `arena/parts.rs`'s.
mod parts;

use core::marker::PhantomData;

use serde::{Deserialize, Serialize};

pub use parts::ArenaPart;
pub(crate) use parts::{gaps, outside_runs};

/// A generational handle to an object of type `T` in an [`Arena`].
///
/// Besides slot and generation, every handle a
/// [`Space`](crate::space::Space) hands out (from `add_body`, iteration,
/// queries, arbiters, handler contexts, a shape's `body()`, error values)
/// carries the space's *origin tag*, so that a handle of one world given to
/// another is an error or `None`, not a silent alias of whatever lives in
/// the same slot there. The tag is not simulation state: it is not
/// serialized, compared or hashed (0 means "unknown" and is accepted by
/// every space: a handle built by `from_raw_parts` or deserialised by the
/// game).
#[derive(Serialize, Deserialize)]
#[serde(bound = "")]
pub struct Handle<T> {
    index: u32,
    generation: u32,
    #[serde(skip)]
    origin: u32,
    #[serde(skip)]
    _marker: PhantomData<fn() -> T>,
}

impl<T> Handle<T> {
    /// A handle from its raw parts (for deserialisation and tests; a wrong
    /// generation simply resolves to nothing).
    pub const fn from_raw_parts(index: u32, generation: u32) -> Handle<T> {
        Handle {
            index,
            generation,
            origin: 0,
            _marker: PhantomData,
        }
    }

    /// The same handle tagged with the origin `tag` of the space that made it.
    pub(crate) const fn with_origin(self, tag: u32) -> Handle<T> {
        Handle {
            origin: tag,
            ..self
        }
    }

    /// The origin tag (0: unknown, e.g. after deserialisation).
    pub(crate) const fn origin(self) -> u32 {
        self.origin
    }

    /// The slot index. Stable for the object's lifetime; used to order pairs
    /// canonically.
    pub const fn index(self) -> u32 {
        self.index
    }

    /// The slot's generation when the object was inserted.
    pub const fn generation(self) -> u32 {
        self.generation
    }
}

impl<T> Clone for Handle<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Handle<T> {}
impl<T> PartialEq for Handle<T> {
    fn eq(&self, o: &Self) -> bool {
        // Every field named: a new one must be compared or said not to be.
        let Handle {
            index,
            generation,
            origin: _, // not state (see the type's docs)
            _marker,
        } = self;
        *index == o.index && *generation == o.generation
    }
}
impl<T> Eq for Handle<T> {}
impl<T> PartialOrd for Handle<T> {
    fn partial_cmp(&self, o: &Self) -> Option<core::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl<T> Ord for Handle<T> {
    fn cmp(&self, o: &Self) -> core::cmp::Ordering {
        (self.index, self.generation).cmp(&(o.index, o.generation))
    }
}
impl<T> core::hash::Hash for Handle<T> {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named, as in `eq`.
        let Handle {
            index,
            generation,
            origin: _, // not state
            _marker,
        } = self;
        // One word: the checksum's per-word cost is what counts.
        h.write_u64(u64::from(*index) | u64::from(*generation) << 32);
    }
}
impl<T> core::fmt::Debug for Handle<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "#{}v{}", self.index, self.generation)
    }
}

/// One arena slot.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

/// Error of an arena operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ArenaError {
    /// The arena already holds `u32::MAX` slots.
    Full,
}

/// A generational arena with a LIFO free list.
///
/// An arena of a [`Space`](crate::space::Space) carries the space's origin
/// tag (see [`Handle`]): every handle it makes (`insert`, `iter`, …) has
/// it, and lookups (`get`, `remove`, …) treat a handle of another origin as
/// stale. Like the handle's, the arena's tag is not simulation state: it is
/// not serialized, compared or hashed (0: unknown, accepts every handle).
#[derive(Debug, Serialize, Deserialize)]
pub struct Arena<T> {
    slots: Vec<Slot<T>>,
    /// Free slot indices; the last one is reused first.
    free: Vec<u32>,
    len: u32,
    #[serde(skip)]
    origin: u32,
}

/// `clone_from` reuses the buffers (a per-frame copy into a kept arena
/// allocates nothing once grown; the derive's would allocate anew).
impl<T: Clone> Clone for Arena<T> {
    fn clone(&self) -> Self {
        Arena {
            slots: self.slots.clone(),
            free: self.free.clone(),
            len: self.len,
            origin: self.origin,
        }
    }
    fn clone_from(&mut self, o: &Self) {
        // Every field named: a new one must be copied too.
        let Arena {
            slots,
            free,
            len,
            origin,
        } = self;
        slots.clone_from(&o.slots);
        free.clone_from(&o.free);
        *len = o.len;
        *origin = o.origin;
    }
}

/// Compares the contents; the origin tag is not state.
impl<T: PartialEq> PartialEq for Arena<T> {
    fn eq(&self, o: &Self) -> bool {
        let Arena {
            slots,
            free,
            len,
            origin: _, // not state
        } = self;
        *slots == o.slots && *free == o.free && *len == o.len
    }
}
impl<T: Eq> Eq for Arena<T> {}

/// Hashes value by value: `Hash` for a `[u32]` slice would feed the hasher
/// native-endian bytes, which differ between platforms.
impl<T: core::hash::Hash> core::hash::Hash for Arena<T> {
    fn hash<H: core::hash::Hasher>(&self, h: &mut H) {
        // Every field named: a new one is a compile error until it is hashed
        // (the world checksum must cover the whole state).
        let Arena {
            slots,
            free,
            len,
            origin: _, // not state (see the type's docs)
        } = self;
        h.write_u64(slots.len() as u64);
        for slot in slots {
            hash_slot(slot, h);
        }
        h.write_u64(free.len() as u64);
        for &i in free {
            h.write_u32(i);
        }
        h.write_u32(*len);
    }
}

/// A slot as the checksum sees it: generation and occupancy in one word,
/// then the value (the derive's `Hash` of [`Slot`] spends a word on each).
#[inline(always)]
fn hash_slot<T: core::hash::Hash, H: core::hash::Hasher>(slot: &Slot<T>, h: &mut H) {
    // Every field named: a new one is a compile error until it is hashed.
    let Slot { generation, value } = slot;
    h.write_u64(u64::from(*generation) << 1 | u64::from(value.is_some()));
    if let Some(value) = value {
        value.hash(h);
    }
}

impl<T> Default for Arena<T> {
    fn default() -> Self {
        Arena {
            slots: Vec::new(),
            free: Vec::new(),
            len: 0,
            origin: 0,
        }
    }
}

impl<T> Arena<T> {
    /// An empty arena.
    pub fn new() -> Self {
        Self::default()
    }

    /// The origin tag put on the handles this arena makes (0: none).
    pub(crate) fn origin(&self) -> u32 {
        self.origin
    }

    /// Sets the origin tag (a space adopting the arena).
    pub(crate) fn set_origin(&mut self, origin: u32) {
        self.origin = origin;
    }

    /// The handle `(index, generation)` with this arena's origin tag.
    fn handle(&self, index: u32, generation: u32) -> Handle<T> {
        Handle::from_raw_parts(index, generation).with_origin(self.origin)
    }

    /// False for a handle made by an arena of another origin (tag 0 on
    /// either side: unknown, accepted).
    fn admits(&self, h: Handle<T>) -> bool {
        h.origin == 0 || self.origin == 0 || h.origin == self.origin
    }

    /// Number of live objects.
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// True if there is no live object.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Number of slots (live and free): one past the largest index ever used.
    pub fn capacity_slots(&self) -> usize {
        self.slots.len()
    }

    /// Inserts `value`, reusing the most recently freed slot first.
    pub fn insert(&mut self, value: T) -> Result<Handle<T>, ArenaError> {
        if let Some(index) = self.free.pop() {
            if let Some(slot) = self.slots.get_mut(index as usize) {
                slot.value = Some(value);
                // `len` counts live slots, fewer than `u32::MAX` (the slot
                // count's limit below): never saturates unless forged.
                self.len = self.len.saturating_add(1);
                let generation = slot.generation;
                return Ok(self.handle(index, generation));
            }
        }
        let index = u32::try_from(self.slots.len()).map_err(|_| ArenaError::Full)?;
        if index == u32::MAX {
            return Err(ArenaError::Full);
        }
        self.slots.push(Slot {
            generation: 0,
            value: Some(value),
        });
        // At most `index + 1 < u32::MAX` live slots: never saturates.
        self.len = self.len.saturating_add(1);
        Ok(self.handle(index, 0))
    }

    /// Removes and returns the object, or `None` for a stale handle.
    pub fn remove(&mut self, h: Handle<T>) -> Option<T> {
        if !self.admits(h) {
            return None;
        }
        let slot = self.slots.get_mut(h.index as usize)?;
        if slot.generation != h.generation || slot.value.is_none() {
            return None;
        }
        // Generations wrap after 2^32 reuses of one slot; documented limit.
        slot.generation = slot.generation.wrapping_add(1);
        // The slot was live, so `len ≥ 1` in a valid arena; a forged one
        // (deserialised without `validate`) stays at 0 instead of wrapping.
        self.len = self.len.saturating_sub(1);
        self.free.push(h.index);
        slot.value.take()
    }

    /// The object, or `None` for a stale handle (or one of another origin).
    pub fn get(&self, h: Handle<T>) -> Option<&T> {
        if !self.admits(h) {
            return None;
        }
        let slot = self.slots.get(h.index as usize)?;
        if slot.generation == h.generation {
            slot.value.as_ref()
        } else {
            None
        }
    }

    /// The object mutably, or `None` for a stale handle (or one of another
    /// origin).
    pub fn get_mut(&mut self, h: Handle<T>) -> Option<&mut T> {
        if !self.admits(h) {
            return None;
        }
        let slot = self.slots.get_mut(h.index as usize)?;
        if slot.generation == h.generation {
            slot.value.as_mut()
        } else {
            None
        }
    }

    /// True if the handle refers to a live object.
    pub fn contains(&self, h: Handle<T>) -> bool {
        self.get(h).is_some()
    }

    /// The live object in slot `index`, with its handle.
    pub fn get_by_index(&self, index: u32) -> Option<(Handle<T>, &T)> {
        let slot = self.slots.get(index as usize)?;
        slot.value
            .as_ref()
            .map(|v| (self.handle(index, slot.generation), v))
    }

    /// The live object in slot `index`, mutably, with its handle.
    pub fn get_by_index_mut(&mut self, index: u32) -> Option<(Handle<T>, &mut T)> {
        let origin = self.origin;
        let slot = self.slots.get_mut(index as usize)?;
        let generation = slot.generation;
        slot.value.as_mut().map(|v| {
            (
                Handle::from_raw_parts(index, generation).with_origin(origin),
                v,
            )
        })
    }

    /// Live objects in slot order (the canonical iteration order).
    pub fn iter(&self) -> impl Iterator<Item = (Handle<T>, &T)> {
        let origin = self.origin;
        self.slots.iter().enumerate().filter_map(move |(i, s)| {
            s.value.as_ref().map(|v| {
                (
                    Handle::from_raw_parts(i as u32, s.generation).with_origin(origin),
                    v,
                )
            })
        })
    }

    /// Live objects mutably, in slot order.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = (Handle<T>, &mut T)> {
        let origin = self.origin;
        self.slots.iter_mut().enumerate().filter_map(move |(i, s)| {
            let g = s.generation;
            s.value
                .as_mut()
                .map(|v| (Handle::from_raw_parts(i as u32, g).with_origin(origin), v))
        })
    }

    /// Runs `f` on every live object, the slots in pieces of `piece` (at
    /// least 1) split between threads ([`crate::threads::join`]): for work
    /// on each object alone, whose result does not depend on the order.
    pub(crate) fn for_each_value_split<F>(&mut self, piece: usize, f: &F)
    where
        T: Send,
        F: Fn(&mut T) + Sync,
    {
        fn split<T: Send, F: Fn(&mut T) + Sync>(slots: &mut [Slot<T>], piece: usize, f: &F) {
            if slots.len() <= piece {
                slots
                    .iter_mut()
                    .filter_map(|s| s.value.as_mut())
                    .for_each(f);
                return;
            }
            let (left, right) = slots.split_at_mut(slots.len() / 2);
            crate::threads::join(|| split(left, piece, f), || split(right, piece, f));
        }
        split(&mut self.slots, piece.max(1), f);
    }

    /// Runs `f` on every live object and the element of `others` at its
    /// slot (slots past the end of `others` are skipped), in pieces of
    /// `piece` slots split between threads: for work on each object alone.
    pub(crate) fn zip_values_split<U, F>(&self, others: &mut [U], piece: usize, f: &F)
    where
        T: Sync,
        U: Send,
        F: Fn(&T, &mut U) + Sync,
    {
        crate::threads::zip_split(&self.slots, others, piece, &|s: &Slot<T>, u| {
            if let Some(v) = s.value.as_ref() {
                f(v, u);
            }
        });
    }

    /// [`zip_values_split`](Self::zip_values_split) with the objects
    /// mutable and `others` read.
    pub(crate) fn zip_values_mut_split<U, F>(&mut self, others: &[U], piece: usize, f: &F)
    where
        T: Send,
        U: Sync,
        F: Fn(&mut T, &U) + Sync,
    {
        crate::threads::zip_split(others, &mut self.slots, piece, &|u, s: &mut Slot<T>| {
            if let Some(v) = s.value.as_mut() {
                f(v, u);
            }
        });
    }

    /// Runs `f` on every live object, the element of `read` at its slot
    /// and the element of `write` at its slot (slots past the end of
    /// either are skipped), in pieces of `piece` slots split between
    /// threads: for work on each object alone.
    pub(crate) fn zip_values_mut2_split<U, V, F>(
        &mut self,
        read: &[U],
        write: &mut [V],
        piece: usize,
        f: &F,
    ) where
        T: Send,
        U: Sync,
        V: Send,
        F: Fn(&mut T, &U, &mut V) + Sync,
    {
        fn split<T: Send, U: Sync, V: Send, F: Fn(&mut T, &U, &mut V) + Sync>(
            slots: &mut [Slot<T>],
            read: &[U],
            write: &mut [V],
            piece: usize,
            f: &F,
        ) {
            let len = slots.len().min(read.len()).min(write.len());
            if len <= piece {
                for ((s, u), v) in slots.iter_mut().zip(read).zip(write) {
                    if let Some(t) = s.value.as_mut() {
                        f(t, u, v);
                    }
                }
                return;
            }
            let mid = len / 2;
            let (Some((s_l, s_r)), Some((u_l, u_r)), Some((v_l, v_r))) = (
                slots.split_at_mut_checked(mid),
                read.split_at_checked(mid),
                write.split_at_mut_checked(mid),
            ) else {
                return;
            };
            crate::threads::join(
                || split(s_l, u_l, v_l, piece, f),
                || split(s_r, u_r, v_r, piece, f),
            );
        }
        split(&mut self.slots, read, write, piece.max(1), f);
    }

    /// Checks the internal invariants: the free list names exactly the empty
    /// slots, each once, and `len` counts the full ones. Used by snapshot
    /// loading and by tests; returns a description of the first violation.
    pub fn validate(&self) -> Result<(), String> {
        // Every field named: a new one must be checked or said not to need
        // it (a slot's generation may be any value).
        let Arena {
            slots,
            free,
            len,
            origin: _, // any tag is valid: it is not state
        } = self;
        let full = slots.iter().filter(|s| s.value.is_some()).count();
        if full != *len as usize {
            return Err(format!("arena length {} but {} live slots", *len, full));
        }
        let mut seen = vec![false; slots.len()];
        for &i in free {
            let Some(flag) = seen.get_mut(i as usize) else {
                return Err(format!("free list names slot {i} past the end"));
            };
            if *flag {
                return Err(format!("free list names slot {i} twice"));
            }
            *flag = true;
            if self
                .slots
                .get(i as usize)
                .is_some_and(|s| s.value.is_some())
            {
                return Err(format!("free list names live slot {i}"));
            }
        }
        // `full` counts some of the slots: never saturates.
        let empty = slots.len().saturating_sub(full);
        if empty != free.len() {
            return Err(format!(
                "{} empty slots but {} on the free list",
                empty,
                free.len()
            ));
        }
        Ok(())
    }
}

impl<T> Slot<T> {
    /// A free slot of generation 0.
    fn empty() -> Slot<T> {
        Slot {
            generation: 0,
            value: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stale_handle_resolves_to_nothing_after_reuse() {
        let mut a = Arena::new();
        let h1 = a.insert(1).unwrap();
        assert_eq!(a.remove(h1), Some(1));
        let h2 = a.insert(2).unwrap();
        assert_eq!(h1.index(), h2.index());
        assert_ne!(h1, h2);
        assert_eq!(a.get(h1), None);
        assert_eq!(a.get(h2), Some(&2));
        assert_eq!(a.remove(h1), None);
        a.validate().unwrap();
    }

    #[test]
    fn iteration_is_in_slot_order_and_free_list_is_lifo() {
        let mut a = Arena::new();
        let hs: Vec<_> = (0..5).map(|i| a.insert(i).unwrap()).collect();
        a.remove(hs[1]);
        a.remove(hs[3]);
        assert_eq!(a.iter().map(|(_, v)| *v).collect::<Vec<_>>(), vec![0, 2, 4]);
        assert_eq!(a.insert(9).unwrap().index(), 3);
        assert_eq!(a.insert(8).unwrap().index(), 1);
        assert_eq!(a.len(), 5);
        a.validate().unwrap();
    }

    #[test]
    fn clone_hands_out_the_same_handles() {
        let mut a = Arena::new();
        let h = a.insert(1).unwrap();
        a.insert(2).unwrap();
        a.remove(h);
        let mut b = a.clone();
        assert_eq!(a.insert(7).unwrap(), b.insert(7).unwrap());
    }
}
