//! IEEE 1609.2 verification on the host: one signed TIM through the core's trust policy
//! (`obu::security::Trust::check`) with the signer certificate cached, and with a chain of
//! two certificates to verify first (only the root trusted), beside OpenSSL's ECDSA P-256
//! verify (`openssl speed ecdsap256`, run here on the same machine); prints the ratios.
//!
//! `cargo bench -p obu --bench verify` (OpenSSL's `openssl` command on the PATH).

use obu::security::{CheckContext, SecurityConfig, Trust};
use std::hint::black_box;
use std::process::Command;
use std::time::Instant;
use test_support::signed_vectors::{all, SignedVector};

/// Median over rounds of the mean time of `f`, microseconds.
fn time_us(rounds: usize, per_round: usize, mut f: impl FnMut()) -> f64 {
    let mut means: Vec<f64> = (0..rounds)
        .map(|_| {
            let t = Instant::now();
            for _ in 0..per_round {
                f();
            }
            t.elapsed().as_secs_f64() * 1e6 / per_round as f64
        })
        .collect();
    means.sort_by(f64::total_cmp);
    means[rounds / 2]
}

/// OpenSSL's ECDSA P-256 verifications per second (`openssl speed -seconds 3 ecdsap256`).
fn openssl_verify_us() -> Option<f64> {
    let out = Command::new("openssl")
        .args(["speed", "-seconds", "3", "ecdsap256"])
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text.lines().find(|l| l.contains("ecdsa (nistp256)"))?;
    let per_s: f64 = line.split_whitespace().last()?.parse().ok()?;
    Some(1e6 / per_s)
}

fn context(v: &SignedVector) -> CheckContext {
    CheckContext {
        message_id: j2735::frame::peek_message_id(&v.frame).unwrap(),
        now_us: Some(v.now),
        position: None,
    }
}

fn main() {
    let v = all()
        .into_iter()
        .find(|v| v.name == "valid_tim_certificate_chain_x_only")
        .expect("vector");
    let data = j2735::envelope::ieee1609dot2::Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let signed = *data.signed_data().unwrap();
    let ctx = context(&v);
    // Cached: the first check verifies the chain and caches the RSU certificate; every
    // later one verifies the message's signature in full, then finds it a replay.
    let mut cached = Trust::new(SecurityConfig::DEFAULT);
    cached.add_anchor(&v.root).unwrap();
    cached.add_anchor(&v.ca).unwrap();
    cached.check(&signed, &ctx).unwrap();
    let cached_us = time_us(7, 2000, || {
        let r = cached.check(black_box(&signed), &ctx);
        assert!(r.is_err(), "a replay after the full check");
    });
    // Chain of two: only the root trusted, nothing cached: CA under root, RSU under CA,
    // then the message (three ECDSA verifications, two keys prepared, the hashes). The
    // template has made its generator table (a check of a frame it then refuses).
    let mut fresh = Trust::new(SecurityConfig::DEFAULT);
    fresh.add_anchor(&v.root).unwrap();
    let untrusted = all()
        .into_iter()
        .find(|v| v.name == "untrusted_root")
        .unwrap();
    let other = j2735::envelope::ieee1609dot2::Ieee1609Dot2Data::parse(&untrusted.coer).unwrap();
    assert!(fresh.check(other.signed_data().unwrap(), &ctx).is_err());
    let chain_us = time_us(7, 300, || {
        let mut t = fresh.clone();
        t.check(black_box(&signed), &ctx).unwrap();
    });
    println!("verify one signed TIM, signer certificate cached: {cached_us:.1} us (1 ECDSA verification)");
    println!(
        "verify one signed TIM with a chain of 2 (CA, RSU) under the root, nothing cached: \
         {chain_us:.1} us (3 ECDSA verifications)"
    );
    match openssl_verify_us() {
        Some(ssl) => {
            println!("openssl speed ecdsap256 verify: {ssl:.1} us");
            println!(
                "ratio cached / openssl: {:.2}x; chain / (3 x openssl): {:.2}x",
                cached_us / ssl,
                chain_us / (3.0 * ssl)
            );
        }
        None => println!("openssl speed ecdsap256: not available (no ratio)"),
    }
}
