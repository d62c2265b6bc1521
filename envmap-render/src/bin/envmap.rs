//! The `envmap` command; see [`envmap_render::cli`] for what it does and its
//! exit codes.

fn main() -> std::process::ExitCode {
    envmap_render::cli::main()
}
