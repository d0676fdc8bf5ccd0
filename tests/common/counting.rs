//! The tests' one heap-counting allocator: every call goes to `System` unchanged; beside it
//! the bytes in use, their peak since [`Counting::mark`], and the calls that took memory.
//! A test binary installs it as `#[global_allocator]` (the fuzz loop, `translate_1mb`).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Counts the bytes allocated now and the peak since the last mark.
pub struct Counting;

static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// Calls that took memory (allocations and reallocations).
static CALLS: AtomicUsize = AtomicUsize::new(0);

/// Where the counters stood at [`Counting::mark`].
pub struct Mark {
    base: usize,
    calls: usize,
}

impl Counting {
    /// Starts a measure: the peak is set back to what is in use now.
    pub fn mark() -> Mark {
        let base = NOW.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        Mark {
            base,
            calls: CALLS.load(Ordering::Relaxed),
        }
    }
}

impl Mark {
    /// The peak heap above what was in use at the mark, bytes.
    pub fn peak(&self) -> usize {
        PEAK.load(Ordering::Relaxed).saturating_sub(self.base)
    }

    /// The calls that took memory since the mark.
    #[allow(dead_code)]
    pub fn calls(&self) -> usize {
        CALLS.load(Ordering::Relaxed) - self.calls
    }
}

fn grew(n: usize) {
    CALLS.fetch_add(1, Ordering::Relaxed);
    let now = NOW.fetch_add(n, Ordering::Relaxed) + n;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

// SAFETY: every call is passed to `System` unchanged; only counters are kept beside it.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            grew(l.size());
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        NOW.fetch_sub(l.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, l, new) };
        if !q.is_null() {
            if new >= l.size() {
                grew(new - l.size());
            } else {
                NOW.fetch_sub(l.size() - new, Ordering::Relaxed);
            }
        }
        q
    }
}
