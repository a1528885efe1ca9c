//! Puts memory.x where cortex-m-rt's link.x finds it, and turns the codec's committed oracle
//! vectors of MAP and TIM into a Rust table for the on-target tests.
use std::{env, fs, path::PathBuf};

const VECTORS: &str = "../../codec/tests/vectors/oracle_vectors.jsonl";

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed={VECTORS}");
    let text = fs::read_to_string(VECTORS).expect("oracle vectors");
    let mut table =
        String::from("/// (name, MessageFrame UPER) of the oracle vectors of MAP and TIM.\n");
    table.push_str("pub static MAP_TIM_VECTORS: &[(&str, &[u8])] = &[\n");
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let v: serde_json::Value = serde_json::from_str(line).expect("vector line");
        let id = v["jer"]["messageId"].as_u64().unwrap_or(0);
        if id != 18 && id != 31 {
            continue;
        }
        let name = v["name"].as_str().expect("name");
        let hex = v["uper"].as_str().expect("uper");
        let bytes: Vec<String> = (0..hex.len() / 2)
            .map(|i| format!("0x{}", &hex[2 * i..2 * i + 2]))
            .collect();
        table.push_str(&format!("    ({name:?}, &[{}]),\n", bytes.join(", ")));
    }
    table.push_str("];\n");
    fs::write(out.join("vectors.rs"), table).expect("vectors.rs");
}
