//! Sets `cfg(shared_data)` when `LSW_SHARED_DATA` names a folder, so that tests reading the
//! shared inputs report *ignored* without them instead of passing.

fn main() {
    println!("cargo::rustc-check-cfg=cfg(shared_data)");
    println!("cargo::rerun-if-env-changed=LSW_SHARED_DATA");
    let present =
        std::env::var_os("LSW_SHARED_DATA").is_some_and(|dir| std::path::Path::new(&dir).is_dir());
    if present {
        println!("cargo::rustc-cfg=shared_data");
    }
}
