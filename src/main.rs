//! The `footslam` command: parse, run, exit code.

mod cli;

/// mimalloc's `mi_option_purge_delay` (its `mimalloc.h`, the same in versions 2 and 3; the
/// bindings leave options unnamed).
const MI_OPTION_PURGE_DELAY: libmimalloc_sys::mi_option_t = 15;

fn main() -> std::process::ExitCode {
    // Freed memory goes back to the system after a second, not mimalloc's 10 ms: a tracker
    // frees and allocates generations of up to a million particles at every step, and each
    // return cost the kernel zeroing their pages again (an unknown-start walk on a mall
    // floor: 2.2 s of system time of 6.9 s, 0.4 s after; same peak memory).
    // SAFETY: set once, before any other thread exists (the option is not thread safe).
    unsafe { libmimalloc_sys::mi_option_set(MI_OPTION_PURGE_DELAY, 1000) };
    cli::main()
}

/// mimalloc: particle filters allocate and free many small map nodes from all threads.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;
