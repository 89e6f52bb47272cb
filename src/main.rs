//! The `footslam` command: parse, run, exit code.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}

/// mimalloc: particle filters allocate and free many small map nodes from all threads.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;
