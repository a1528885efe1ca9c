//! Unit tests: the generator, frame kinds, burst loss and RSU times.

use super::rsu_files::rsu_time;
use super::{ConfigError, FrameError, LossChannel, LossModel, Message, MessageKind, Prng};

#[test]
fn prng_is_seeded_and_uniform() {
    let mut a = Prng::new(7);
    let mut b = Prng::new(7);
    assert_eq!(a.next_u64(), b.next_u64());
    assert_ne!(Prng::new(8).next_u64(), Prng::new(7).next_u64());
    let mut rng = Prng::new(1);
    let n = 100_000;
    let mean = (0..n).map(|_| rng.next_f64()).sum::<f64>() / n as f64;
    assert!((mean - 0.5).abs() < 0.01, "{mean}");
    assert!((0..1000).all(|_| rng.below(10) < 10));
    assert_eq!(rng.below(0), 0);
}

#[test]
fn message_kinds_from_frames() {
    assert_eq!(
        MessageKind::of_frame(&[0x00, 0x12, 0x34]),
        Some(MessageKind::Map)
    );
    assert_eq!(MessageKind::of_frame(&[0x00, 0x1f]), Some(MessageKind::Tim));
    assert_eq!(MessageKind::of_frame(&[0x00]), None);
    assert_eq!(
        Message::new(vec![0x03, 0x80, 0x01, 0x00]),
        Err(FrameError::Enveloped)
    );
    assert_eq!(Message::new(vec![0x80, 0x12]), Err(FrameError::Extended));
    assert_eq!(Message::new(vec![]), Err(FrameError::TooShort { len: 0 }));
}

#[test]
fn bursts_have_the_asked_rate_and_length() {
    let model = LossModel::bursts(0.2, 4.0).unwrap();
    assert!((model.mean_loss_rate() - 0.2).abs() < 1e-12);
    let mut rng = Prng::new(42);
    let mut ch = LossChannel::new(model, &mut rng);
    let (mut lost, mut bursts, mut prev) = (0u32, 0u32, false);
    let n = 200_000;
    for _ in 0..n {
        let l = ch.drops(&mut rng);
        lost += u32::from(l);
        bursts += u32::from(l && !prev);
        prev = l;
    }
    let rate = f64::from(lost) / f64::from(n);
    let mean_burst = f64::from(lost) / f64::from(bursts);
    assert!((rate - 0.2).abs() < 0.01, "{rate}");
    assert!((mean_burst - 4.0).abs() < 0.2, "{mean_burst}");
    assert!(matches!(
        LossModel::bursts(0.9, 2.0),
        Err(ConfigError::BurstsTooShort { .. })
    ));
    assert!(LossModel::bursts(0.5, 0.5).is_err() && LossModel::independent(1.5).is_err());
}

#[test]
fn rsu_times() {
    // 2026-11-22T10:00:00Z.
    assert_eq!(rsu_time(1_795_341_600_000), "11/22/2026, 10:00");
}
