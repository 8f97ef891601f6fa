//! The `lsw` command-line tool: see `lsw --help`.

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    use clap::Parser;
    let cli = lsw::cli::Cli::parse();
    match lsw::cli::run(cli) {
        Ok(json) => {
            // What a valid result still shows (`lsw wrap`'s `warnings`: a genus unlike the
            // target's…) is said on stderr too, where a script that reads only `valid` sees it.
            let report: Option<serde_json::Value> = serde_json::from_str(&json).ok();
            let warnings = report
                .as_ref()
                .and_then(|r| r.get("warnings")?.as_array().cloned());
            for w in warnings.unwrap_or_default() {
                eprintln!("lsw: warning: {}", w.as_str().unwrap_or_default());
            }
            // A closed pipe (`lsw info X | head`) ends the output quietly instead of panicking.
            use std::io::Write;
            let mut out = std::io::stdout().lock();
            match writeln!(out, "{json}").and_then(|_| out.flush()) {
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    eprintln!("lsw: error: writing the output: {e}");
                    std::process::exit(1);
                }
                _ => {}
            }
        }
        Err(failure) => {
            if let Some(report) = failure.report {
                println!("{report}");
            }
            eprintln!("lsw: error: {}", failure.message);
            std::process::exit(1);
        }
    }
}

/// The CLI is native only; the wasm build of this target is an empty program.
#[cfg(target_arch = "wasm32")]
fn main() {}
