//! `lsw demo --list` and `lsw demo NAME -o FILE`: the deterministic test shapes of
//! [`crate::demo::shapes`], listed as JSON or written to a file (format from the extension;
//! point clouds need a format that stores bare points, such as PLY).

use crate::demo::shapes::{generate, SHAPES};
use crate::io::{write_path, WriteInput};
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `lsw demo`.
#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// The shape to write (one of `lsw demo --list`).
    #[arg(required_unless_present = "list")]
    pub name: Option<String>,
    /// Output file; the format follows the extension (a writable format of
    /// [`crate::io::FORMATS`]; use .ply for point clouds).
    #[arg(
        short,
        long,
        required_unless_present = "list",
        help = super::output_help("Output file (use .ply for point clouds)")
    )]
    pub output: Option<PathBuf>,
    /// Print every shape as JSON: [{name, description}], in suite order.
    #[arg(long, conflicts_with_all = ["name", "output"])]
    pub list: bool,
}

/// The JSON of `lsw demo --list`: an array of {name, description}.
pub fn list_json() -> serde_json::Value {
    SHAPES
        .iter()
        .map(|(name, description)| json!({"name": name, "description": description}))
        .collect()
}

/// Runs `lsw demo`. Writing prints {name, output, kind ("points" or "mesh"), vertices, faces}.
pub fn run(a: &DemoArgs) -> Result<String, String> {
    if a.list {
        return Ok(serde_json::to_string_pretty(&list_json()).expect("JSON"));
    }
    let (Some(name), Some(output)) = (&a.name, &a.output) else {
        return Err("give a shape NAME and -o FILE, or --list".into());
    };
    let (points, triangles) = generate(name).map_err(|e| format!("{e} (see lsw demo --list)"))?;
    write_path(output, &WriteInput::new(&points, &triangles)).map_err(super::explained)?;
    let kind = if triangles.is_empty() {
        "points"
    } else {
        "mesh"
    };
    Ok(serde_json::to_string_pretty(&json!({
        "name": name,
        "output": output.display().to_string(),
        "kind": kind,
        "vertices": points.len(),
        "faces": triangles.len(),
    }))
    .expect("JSON"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn list_names_every_shape() {
        let v = list_json();
        let arr = v.as_array().unwrap();
        assert_eq!(arr.len(), SHAPES.len());
        assert_eq!(arr[0]["name"], SHAPES[0].0);
        assert!(arr.iter().all(|e| e["description"].is_string()));
    }

    #[test]
    fn writes_a_cloud_and_a_mesh_that_read_back() {
        let dir = std::env::temp_dir().join(format!("lsw-demo-cli-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, file, faces) in [
            ("coplanar-cloud", "c.ply", 0usize),
            ("cube-hole", "h.obj", generate("cube-hole").unwrap().1.len()),
        ] {
            let out = dir.join(file);
            let args = DemoArgs {
                name: Some(name.into()),
                output: Some(out.clone()),
                list: false,
            };
            let v: serde_json::Value = serde_json::from_str(&run(&args).unwrap()).unwrap();
            assert_eq!(v["faces"], faces);
            let back = crate::io::read_path(&out).unwrap();
            assert_eq!(back.target.triangles.len(), faces);
        }
        let bad = DemoArgs {
            name: Some("nope".into()),
            output: Some(dir.join("x.ply")),
            list: false,
        };
        assert!(run(&bad).unwrap_err().contains("unknown demo shape"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
