//! Agreement with the independent oracle (pycrate, `../shared/oracle`): a sample of random
//! valid MessageFrames of MAP, TIM, BSM and SPaT encoded by us is decoded by the oracle, and
//! the oracle's re-encoding is the same bytes. Needs feature `shared-corpus` (and Python; the
//! oracle's setup script makes its environment).
#![cfg(feature = "shared-corpus")]

mod common;

use j2735::uper;

#[test]
fn random_frames_agree_with_the_oracle_byte_for_byte() {
    let ours: Vec<String> = common::big_stack(|| {
        let mut buf = vec![0u8; 1 << 17];
        (0..160u64)
            .map(|i| {
                let frame = common::random_frame((i % 4) as u8, 0x5eed_0000 + i);
                let n = uper::encode(&frame, &mut buf).unwrap();
                common::to_hex(&buf[..n])
            })
            .collect()
    });
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/oracle_roundtrip.py");
    let answer = test_support::oracle::run_script(
        std::path::Path::new(script),
        [common::shared_dir()],
        &(ours.join("\n") + "\n"),
    );
    let theirs: Vec<&str> = answer.lines().collect();
    assert_eq!(theirs.len(), ours.len(), "the oracle answered every frame");
    let kinds = ["MAP", "TIM", "BSM", "SPaT"];
    let mut differ = Vec::new();
    for (i, (a, b)) in ours.iter().zip(&theirs).enumerate() {
        if a != b {
            differ.push(format!("{} #{i}: ours {a}\n  oracle {b}", kinds[i % 4]));
        }
    }
    println!(
        "{}/{} random frames agree with the oracle",
        ours.len() - differ.len(),
        ours.len()
    );
    assert!(
        differ.is_empty(),
        "{} differ:\n{}",
        differ.len(),
        differ.join("\n")
    );
}
