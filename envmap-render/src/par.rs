//! Data parallelism: rayon's with the `parallel` feature (the default), or
//! without it the same iterator chains run in order on the calling thread.
//! The results are the same either way: every parallel sum in the crate
//! adds fixed blocks in a fixed order, and every parallel map writes each
//! output where its index says.
//!
//! Threads: rayon's global pool, or the caller's
//! (`rayon::ThreadPool::install` around a call runs it in that pool).

#[cfg(feature = "parallel")]
pub(crate) use rayon::{current_num_threads, join, prelude::*};

#[cfg(not(feature = "parallel"))]
pub(crate) use serial::*;

/// rayon's iterator methods as plain iterators, for builds without it.
#[cfg(not(feature = "parallel"))]
mod serial {
    /// One thread: the caller's.
    pub(crate) fn current_num_threads() -> usize {
        1
    }

    /// `a` then `b`, on the calling thread.
    pub(crate) fn join<A, B, RA, RB>(a: A, b: B) -> (RA, RB)
    where
        A: FnOnce() -> RA,
        B: FnOnce() -> RB,
    {
        let ra = a();
        (ra, b())
    }

    /// `into_par_iter`: the plain iterator.
    pub(crate) trait IntoParallelIterator: IntoIterator + Sized {
        /// The plain iterator.
        fn into_par_iter(self) -> Self::IntoIter {
            self.into_iter()
        }
    }

    impl<I: IntoIterator> IntoParallelIterator for I {}

    /// `par_iter` and `par_chunks` of a slice: the plain ones.
    pub(crate) trait ParallelSlice<T> {
        /// `iter`.
        fn par_iter(&self) -> std::slice::Iter<'_, T>;
        /// `chunks`.
        fn par_chunks(&self, n: usize) -> std::slice::Chunks<'_, T>;
    }

    impl<T> ParallelSlice<T> for [T] {
        fn par_iter(&self) -> std::slice::Iter<'_, T> {
            self.iter()
        }

        fn par_chunks(&self, n: usize) -> std::slice::Chunks<'_, T> {
            self.chunks(n)
        }
    }

    /// `par_chunks_mut` of a slice: the plain one.
    pub(crate) trait ParallelSliceMut<T> {
        /// `chunks_mut`.
        fn par_chunks_mut(&mut self, n: usize) -> std::slice::ChunksMut<'_, T>;
    }

    impl<T> ParallelSliceMut<T> for [T] {
        fn par_chunks_mut(&mut self, n: usize) -> std::slice::ChunksMut<'_, T> {
            self.chunks_mut(n)
        }
    }

    /// rayon's adapters that std's iterators spell otherwise.
    pub(crate) trait ParallelIterator: Iterator + Sized {
        /// `par_bridge`: the iterator itself.
        fn par_bridge(self) -> Self {
            self
        }

        /// `flat_map_iter`: `flat_map`.
        fn flat_map_iter<U, F>(self, f: F) -> std::iter::FlatMap<Self, U, F>
        where
            U: IntoIterator,
            F: FnMut(Self::Item) -> U,
        {
            self.flat_map(f)
        }

        /// `for_each_init`: one state for every item.
        fn for_each_init<S, I, F>(self, init: I, mut f: F)
        where
            I: FnOnce() -> S,
            F: FnMut(&mut S, Self::Item),
        {
            let mut state = init();
            for item in self {
                f(&mut state, item);
            }
        }
    }

    impl<I: Iterator> ParallelIterator for I {}
}
