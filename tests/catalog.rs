//! The one list of formats stays in sync with what users read: the README names every extension
//! of the catalog, the CLI's help lists every format LSW reads, and the CLI prints the core
//! error's hint. Native only (runs the `lsw` binary).
#![cfg(not(target_arch = "wasm32"))]

use lsw::io::FORMATS;
use std::process::Command;

/// True if `text` holds `.ext` as a whole token (not followed by a letter, digit or `_`, so
/// `.nii` in `.nii.gz` counts but `.gl` in `.glb` would not).
fn mentions(text: &str, ext: &str) -> bool {
    let needle = format!(".{ext}");
    text.match_indices(&needle).any(|(i, _)| {
        text[i + needle.len()..]
            .chars()
            .next()
            .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
    })
}

#[test]
fn readme_names_every_extension_of_the_catalog() {
    let readme = include_str!("../README.md");
    let missing: Vec<String> = FORMATS
        .iter()
        .flat_map(|f| f.extensions.iter().map(move |e| format!("{} .{e}", f.name)))
        .filter(|s| !mentions(readme, s.split_once(" .").unwrap().1))
        .collect();
    assert!(
        missing.is_empty(),
        "README.md does not mention these extensions of lsw::io::FORMATS: {missing:?}"
    );
    assert!(mentions("a `.nii.gz` b", "nii") && !mentions("a `.glb`", "gl"));
}

fn lsw(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_lsw"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_help_lists_the_catalog() {
    for sub in ["info", "sdf", "wrap", "metrics"] {
        let out = lsw(&[sub, "--help"]);
        assert!(out.status.success());
        let help = String::from_utf8_lossy(&out.stdout);
        for f in FORMATS.iter().filter(|f| f.read) {
            assert!(help.contains(f.label), "lsw {sub} --help lacks {}", f.label);
        }
    }
    let help = String::from_utf8_lossy(&lsw(&["wrap", "--help"]).stdout).into_owned();
    for f in FORMATS.iter().filter(|f| f.write) {
        assert!(mentions(&help, f.extensions[0]), "{}", f.name);
    }
    for p in lsw::flow::Preset::ALL {
        assert!(help.contains(p.name()), "{}", p.name());
    }
}

/// A failing command prints `error: <message>` and `hint: <hint>` on stderr, nothing on stdout.
#[test]
fn cli_errors_carry_the_hint() {
    let dir = std::env::temp_dir().join(format!("lsw_catalog_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("notes");
    std::fs::write(&file, "hello\n").unwrap();
    let out = lsw(&["info", file.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(out.stdout.is_empty());
    let err = String::from_utf8_lossy(&out.stderr);
    let e = lsw::io::IoError::UnknownFormat { reason: "-".into() };
    let hint = lsw::error::Explain::hint(&e);
    assert!(
        err.contains("error: unrecognised file format") && err.contains(&format!("\nhint: {hint}")),
        "{err}"
    );
    let out = lsw(&["mcf", "--level", "9"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("too high") && err.contains("\nhint: Use a subdivision level"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A refused wrap (here a solver that cannot converge: the first step diverges) exits non-zero,
/// writes no mesh, and still prints its JSON report on stdout, with the reason under `error`, so
/// that `lsw wrap … > report.json` over a folder of scans keeps why each one was refused.
#[test]
fn a_refused_wrap_still_reports_on_stdout() {
    let dir = std::env::temp_dir().join(format!("lsw_refused_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (input, output) = (dir.join("torus.ply"), dir.join("wrap.ply"));
    assert!(
        lsw(&["demo", "torus-sparse-cloud", "-o", input.to_str().unwrap()])
            .status
            .success()
    );
    let out = lsw(&[
        "wrap",
        input.to_str().unwrap(),
        "-o",
        output.to_str().unwrap(),
        "--set",
        "solver.max_iterations=1",
        "--set",
        "solver.tolerance=1e-30",
        "--set",
        "flow.max_retries=0",
    ]);
    assert!(!out.status.success());
    assert!(!output.exists(), "a refused wrap wrote its mesh");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["written"], false);
    let why = report["error"].as_str().unwrap();
    assert!(why.contains("diverged"), "{why}");
    assert!(report["certificate"]["valid"].is_boolean());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.starts_with("lsw: error: the wrap stopped early"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
