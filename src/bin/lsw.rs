//! The `lsw` command-line tool: see `lsw --help`.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    use clap::Parser;
    let cli = lsw::cli::Cli::parse();
    match lsw::cli::run(cli) {
        Ok(json) => println!("{json}"),
        Err(msg) => {
            eprintln!("lsw: error: {msg}");
            std::process::exit(1);
        }
    }
}

/// The CLI is native only; the wasm build of this target is an empty program.
#[cfg(target_arch = "wasm32")]
fn main() {}
