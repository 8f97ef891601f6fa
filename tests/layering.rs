//! The layering of `src/`: data flows one way, so no module may name a module of a higher layer.
//! Reads every `crate::…` path in the sources (production code only: everything from a file's
//! `#[cfg(test)]` on is test code, which may use fixtures from anywhere). The same table is
//! drawn in the README's "What is where".

use std::path::Path;

/// Top-level modules by layer, bottom first. A module may use its own layer and those below.
const LAYERS: &[&[&str]] = &[
    &["clock", "fmath", "parallel", "progress", "solve"],
    &["mesh"],
    &["geometry"],
    &["io", "target"],
    &["field"],
    &["metrics"],
    &["remesh"],
    &["flow"],
    &["pipeline", "catalog"],
    &["demo"],
    &["error", "cli", "wasm", "bin", "lib"],
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|l| l.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("src/ is readable") {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level modules named as `crate::name` in the production part of `src`.
fn crate_paths(src: &str) -> Vec<String> {
    let code = src.split("#[cfg(test)]").next().unwrap_or("");
    let mut out = Vec::new();
    for line in code.lines() {
        let line = line.trim_start();
        if line.starts_with("//") {
            continue; // doc links may point anywhere
        }
        let mut rest = line;
        while let Some(i) = rest.find("crate::") {
            let tail = &rest[i + 7..];
            let name: String = tail
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() {
                out.push(name);
            }
            rest = tail;
        }
    }
    out
}

#[test]
fn no_module_uses_a_higher_layer() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    assert!(files.len() > 50, "found only {} source files", files.len());
    let mut violations = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        let own = layer_of(&module)
            .unwrap_or_else(|| panic!("src/{module} is in no layer: add it to LAYERS"));
        let text = std::fs::read_to_string(file).unwrap();
        for used in crate_paths(&text) {
            let Some(theirs) = layer_of(&used) else {
                continue; // a crate-root item (a macro or re-export), not a module
            };
            if theirs > own {
                violations.push(format!("src/{} uses crate::{used}", rel.display()));
            }
        }
    }
    assert!(
        violations.is_empty(),
        "imports against the layers (bottom first: {LAYERS:?}):\n{}",
        violations.join("\n")
    );
}

#[test]
fn the_scanner_sees_paths_and_skips_comments_and_tests() {
    let src = "use crate::mesh::X;\n// crate::flow in a comment\nfn f() { crate::geometry::aabb::Aabb::EMPTY; }\n#[cfg(test)]\nmod tests { use crate::demo::Rng; }\n";
    assert_eq!(crate_paths(src), vec!["mesh", "geometry"]);
    assert!(layer_of("flow") > layer_of("remesh"));
}

/// The module a source file defines, as path components below `src/` (`flow/evolver/mod.rs` is
/// `[flow, evolver]`, `lib.rs` is `[]`).
fn module_of(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .components()
        .map(|c| {
            c.as_os_str()
                .to_string_lossy()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The modules (their first two path components) that `src` names, from `crate::a::b` and
/// `super::x` paths in its production part.
fn named_modules(src: &str, module: &[String]) -> Vec<Vec<String>> {
    let code = src.split("#[cfg(test)]").next().unwrap_or("");
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for line in code.lines().map(str::trim_start) {
        if line.starts_with("//") {
            continue;
        }
        for (i, _) in line.match_indices("crate::") {
            let tail = &line[i + 7..];
            let first = ident(tail);
            let second = tail[first.len()..].strip_prefix("::").map(ident);
            out.push([Some(first), second].into_iter().flatten().collect());
        }
        for (i, _) in line.match_indices("super::") {
            if i > 0 && line[..i].ends_with("::") {
                continue; // super::super: left to the layers
            }
            let mut path = module[..module.len().saturating_sub(1)].to_vec();
            path.push(ident(&line[i + 7..]));
            out.push(path);
        }
    }
    out.into_iter()
        .map(|mut p| {
            p.truncate(2);
            p
        })
        .collect()
}

#[test]
fn no_two_modules_import_each_other() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let mut edges = std::collections::BTreeSet::new();
    for file in &files {
        let module = module_of(file.strip_prefix(&root).unwrap());
        let from: Vec<String> = module.iter().take(2).cloned().collect();
        let text = std::fs::read_to_string(file).unwrap();
        for to in named_modules(&text, &module) {
            if to != from && !to.is_empty() {
                edges.insert((from.join("::"), to.join("::")));
            }
        }
    }
    let circles: Vec<String> = edges
        .iter()
        .filter(|(a, b)| a < b && edges.contains(&(b.clone(), a.clone())))
        .map(|(a, b)| format!("{a} <-> {b}"))
        .collect();
    assert!(
        circles.is_empty(),
        "modules that import each other:\n{}",
        circles.join("\n")
    );
}

/// Receivers of `.triangles` that are no target: the writers' `WriteInput` (a mesh to write).
const NOT_TARGETS: &[&str] = &["input"];

/// Whether a line of code tests a target's kind by hand: `x.triangles.is_empty()` (a cloud),
/// `x.sampled` (a volume's iso-surface) or a `TargetKind::` variant.
fn tests_kind(line: &str) -> bool {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let empty = line.match_indices(".triangles.is_empty()").any(|(i, _)| {
        let before = &line[..i];
        let receiver = &before[before.trim_end_matches(ident).len()..];
        !NOT_TARGETS.contains(&receiver)
    });
    let sampled = line
        .match_indices(".sampled")
        .any(|(i, m)| !line[i + m.len()..].starts_with(ident));
    empty || sampled || line.contains("TargetKind::")
}

/// What a target's kind means (point cloud, triangle mesh or soup, volume iso-surface) is asked
/// of its oracle (`Target::oracle`): no code outside `src/target/` tests the kind by hand.
#[test]
fn no_kind_test_outside_the_target_oracles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let mut found = Vec::new();
    for file in &files {
        let rel = file.strip_prefix(&root).unwrap();
        if rel.starts_with("target") {
            continue;
        }
        let text = std::fs::read_to_string(file).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.trim_start();
            if !code.starts_with("//") && tests_kind(code) {
                found.push(format!("src/{}:{}: {code}", rel.display(), n + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "kind tests outside src/target/ (ask target.oracle() instead):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_kind_scanner_sees_targets_only() {
    assert!(tests_kind("if !target.triangles.is_empty() {"));
    assert!(tests_kind("let v = t.sampled;"));
    assert!(tests_kind("if t.kind() == TargetKind::Mesh {"));
    assert!(!tests_kind("if triangles.is_empty() {"));
    assert!(!tests_kind("if !input.triangles.is_empty() {"));
    assert!(!tests_kind("let s = g.sampled_nodes; sampled: true,"));
}
