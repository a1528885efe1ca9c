//! The bench's IEEE 1609.2 PKI (`hil-sim/pki/bench`, see its README): the trust anchors
//! every bench daemon is configured with (and the firmware is built with), and the signer
//! of the bench roadside, so that bench runs are signed end to end like the product.

use roadside::pki::read_key_text;
use roadside::signer::RsuSigner;
use std::path::Path;
use std::sync::Arc;

/// The root certificate (COER).
pub const ROOT: &[u8] = include_bytes!("../pki/bench/root.oer");
/// The issuing CA certificate (COER).
pub const CA: &[u8] = include_bytes!("../pki/bench/ca.oer");
/// The RSU certificate (COER).
pub const RSU: &[u8] = include_bytes!("../pki/bench/rsu.oer");
/// The RSU's private key (hexadecimal text; public, test only).
const RSU_KEY: &str = include_str!("../pki/bench/rsu.key");

/// The bench roadside's signer (certificate in every message, 60 s lifetime).
///
/// # Errors
///
/// A message when the committed key does not parse (a damaged checkout).
pub fn signer() -> Result<Arc<RsuSigner>, String> {
    let key = read_key_text(RSU_KEY).map_err(|e| format!("pki/bench/rsu.key: {e}"))?;
    Ok(Arc::new(RsuSigner::new(RSU.to_vec(), key, None, 60_000)))
}

/// Writes the roadside's certificate and key into `dir` (`rsu.oer`, `rsu.key`: a PKI
/// folder as `roadside` site files name it).
///
/// # Errors
///
/// The file system's error.
pub fn write_rsu(dir: &Path) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for (name, bytes) in [("rsu.oer", RSU), ("rsu.key", RSU_KEY.as_bytes())] {
        let path = dir.join(name);
        std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(())
}

/// Writes the anchors into `dir` and returns their paths, root first (the daemon's
/// `security.trust_anchors`).
///
/// # Errors
///
/// The file system's error.
pub fn write_anchors(dir: &Path) -> Result<Vec<std::path::PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let root = dir.join("root.oer");
    let ca = dir.join("ca.oer");
    for (path, bytes) in [(&root, ROOT), (&ca, CA)] {
        std::fs::write(path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    }
    Ok(vec![root, ca])
}

#[cfg(test)]
mod tests {
    use super::*;
    use j2735::envelope::Psid;
    use roadside::pki::{Pki, PkiSpec};

    #[test]
    fn the_committed_pki_is_what_its_command_makes() {
        let pki = Pki::create(&PkiSpec {
            seed: Some("hil-sim bench".into()),
            start_unix_s: 1_735_689_600, // 2025-01-01
            root_years: 20,
            ca_years: 15,
            rsu_hours: 2730 * 24,
            region: None,
            psids: vec![Psid::TIM, Psid::MAP, Psid::PSM],
            rsu_name: "rsu.bench.hil-sim.example".into(),
        })
        .unwrap();
        assert_eq!(pki.root.cert, ROOT);
        assert_eq!(pki.ca.cert, CA);
        assert_eq!(pki.rsu.cert, RSU);
        assert_eq!(signer().unwrap().certificate(), RSU);
    }
}
