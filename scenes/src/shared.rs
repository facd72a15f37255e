//! `Shared<T>`: what tests and benches record from inside a callback.
//!
//! The engine's callbacks (collision handlers, post-step callbacks,
//! integrators) are `Send + Sync`, so that a `Space` is; a test that counts
//! calls or logs pairs needs a shared cell that is too. This is
//! `Arc<Mutex<T>>` with the `Cell`/`RefCell` calls the tests read best.
#![allow(clippy::unwrap_used)]

use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

/// A value shared between a test and the callbacks it registers.
#[derive(Debug, Default)]
pub struct Shared<T>(Arc<Mutex<T>>);

impl<T> Clone for Shared<T> {
    fn clone(&self) -> Shared<T> {
        Shared(Arc::clone(&self.0))
    }
}

impl<T> Shared<T> {
    /// A new shared value.
    pub fn new(value: T) -> Shared<T> {
        Shared(Arc::new(Mutex::new(value)))
    }

    /// Borrows the value (a lock held until the guard drops).
    pub fn borrow(&self) -> MutexGuard<'_, T> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Borrows the value mutably (the same lock).
    pub fn borrow_mut(&self) -> MutexGuard<'_, T> {
        self.borrow()
    }

    /// Replaces the value.
    pub fn set(&self, value: T) {
        *self.borrow() = value;
    }
}

impl<T: Copy> Shared<T> {
    /// A copy of the value.
    pub fn get(&self) -> T {
        *self.borrow()
    }
}
