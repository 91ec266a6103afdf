//! A counting global allocator: the binary installs it so `bench` can report the heap a
//! measured piece of work takes. It forwards to mimalloc, which serves the engine's many small
//! short-lived vectors in a fraction of the system allocator's instructions.
//!
//! Counting is on only inside a measuring window ([`start_counting`] .. [`stop_counting`]):
//! outside it an allocation costs one relaxed load more than mimalloc's own, where an atomic
//! read-modify-write on every allocation and free cost about a tenth of an engine step.

use mimalloc::MiMalloc as Inner;
use std::alloc::{GlobalAlloc, Layout};
use std::sync::atomic::{AtomicBool, AtomicIsize, Ordering};

/// mimalloc, counting net and peak bytes while a window is open.
pub struct CountingAllocator;

static COUNTING: AtomicBool = AtomicBool::new(false);
/// Bytes allocated minus bytes freed since the window opened (frees of older blocks count too,
/// so this can go below zero).
static NET: AtomicIsize = AtomicIsize::new(0);
static PEAK: AtomicIsize = AtomicIsize::new(0);

fn count(delta: isize) {
    let net = NET.fetch_add(delta, Ordering::Relaxed) + delta;
    // A plain load first: most allocations do not set a new peak.
    if delta > 0 && net > PEAK.load(Ordering::Relaxed) {
        PEAK.fetch_max(net, Ordering::Relaxed);
    }
}

fn counting() -> bool {
    COUNTING.load(Ordering::Relaxed)
}

/// Every mimalloc block is aligned to at least a word, so an allocation that asks no more can
/// skip mimalloc's aligned path (about a third of an allocation's instructions).
const WORD_ALIGN: usize = std::mem::size_of::<usize>();

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: mimalloc's malloc for word alignment (its blocks are word aligned), else
        // forwarded unchanged.
        let p = unsafe {
            if layout.align() <= WORD_ALIGN {
                libmimalloc_sys::mi_malloc(layout.size()).cast::<u8>()
            } else {
                Inner.alloc(layout)
            }
        };
        if counting() && !p.is_null() {
            count(layout.size() as isize);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to mimalloc.
        unsafe { Inner.dealloc(ptr, layout) };
        if counting() {
            count(-(layout.size() as isize));
        }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as in `alloc`; `ptr` came from mimalloc either way.
        let p = unsafe {
            if layout.align() <= WORD_ALIGN {
                libmimalloc_sys::mi_realloc(ptr.cast(), new_size).cast::<u8>()
            } else {
                Inner.realloc(ptr, layout, new_size)
            }
        };
        if counting() && !p.is_null() {
            count(new_size as isize - layout.size() as isize);
        }
        p
    }
}

/// Opens a measuring window: the net and peak counts restart from zero. Windows do not nest,
/// and allocations on every thread count.
pub fn start_counting() {
    NET.store(0, Ordering::Relaxed);
    PEAK.store(0, Ordering::Relaxed);
    COUNTING.store(true, Ordering::SeqCst);
}

/// Closes the window.
pub fn stop_counting() {
    COUNTING.store(false, Ordering::SeqCst);
}

/// Bytes allocated minus freed since the window opened (0 when the counting allocator is not
/// installed or no window was opened).
pub fn counted_bytes() -> isize {
    NET.load(Ordering::Relaxed)
}

/// The most bytes held at once, counted from the window's start.
pub fn peak_counted_bytes() -> isize {
    PEAK.load(Ordering::Relaxed)
}

/// mimalloc's option `purge_delay`: its index in `mi_option_t`, the same in mimalloc 3 (which
/// `libmimalloc-sys` 0.1.49 builds without its `v2` feature) and mimalloc 2.
const MI_OPTION_PURGE_DELAY: std::ffi::c_int = 15;

unsafe extern "C" {
    /// mimalloc's own setter of its runtime options.
    fn mi_option_set(option: std::ffi::c_int, value: std::ffi::c_long);
}

/// Keeps the memory the process frees for its own reuse instead of handing it back to the OS
/// (mimalloc's purging off; by default mimalloc 3 hands freed pages back a second after they
/// are freed). A seek makes a checkpoint's map live: a grid of tens of MB, allocated afresh;
/// when the pages freed before had gone back to the OS, faulting them in again made the worst
/// seek on the 100,000-snapshot `paper` lap run 52–57 ms instead of 40–43 ms
/// (docs/performance.md, stop 32). The process then keeps the memory of its peak. A purge delay
/// set in the environment (`MIMALLOC_PURGE_DELAY`, or its old name `MIMALLOC_RESET_DELAY`) wins.
pub fn keep_freed_memory() {
    let set = |name: &str| std::env::var_os(name).is_some();
    if set("MIMALLOC_PURGE_DELAY") || set("MIMALLOC_RESET_DELAY") {
        return;
    }
    // SAFETY: a plain setter of a process-wide option, valid before or after allocating.
    unsafe { mi_option_set(MI_OPTION_PURGE_DELAY, -1) }
}
