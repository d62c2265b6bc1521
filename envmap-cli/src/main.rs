//! The `envmap` command; see [`envmap_cli`] for what it does and its
//! exit codes.

/// jemalloc keeps freed memory for the next allocation, where glibc's
/// malloc returned each batch of an EXR's blocks to the system and took
/// page faults to get it back: a conversion of a 100 MB EXR to a 150 MB
/// cube took 80 000–118 000 page faults with it, 66 000 with jemalloc
/// (the input's and output's own pages are 61 500 of those).
#[cfg(not(target_env = "msvc"))]
#[global_allocator]
static ALLOCATOR: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

fn main() -> std::process::ExitCode {
    envmap_cli::main()
}
