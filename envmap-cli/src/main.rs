//! The `envmap` command; see [`envmap_cli`] for what it does and its
//! exit codes.

/// jemalloc keeps freed memory for the next allocation, where glibc's
/// malloc returned each batch of an EXR's blocks to the system and took
/// page faults to get it back.
#[cfg(not(target_env = "msvc"))]
#[global_allocator]
static ALLOCATOR: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

fn main() -> std::process::ExitCode {
    envmap_cli::main()
}
