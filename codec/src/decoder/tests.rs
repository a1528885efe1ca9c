use super::*;
use crate::MessageFrameValue;

/// Oracle vectors (pycrate bytes, `codec/tests/vectors/oracle_vectors.jsonl`).
const BSM_MINIMAL: &str =
    "00142504468acf136848a7603a059cae1b0f0d4b140c8fa021166978817ad7dc7f7f6903485c8f00";
const BSM_CORE_MAX: &str =
    "0014251ffffffffffffff5a4e900eb49d2007ffffffffffffffff080fdfa1fa1fefffefff7fffff8";
const SPAT_MINIMAL: &str = "00130b0000003281000000002003";
const MAP_MINIMAL: &str = "0012020000";

fn bytes(hex: &str) -> std::vec::Vec<u8> {
    let mut out = std::vec![0u8; hex.len() / 2];
    crate::hex::decode_into(hex, &mut out).unwrap();
    out
}

fn msg_cnt(f: &MessageFrame) -> u8 {
    match &f.value {
        MessageFrameValue::BasicSafetyMessage(b) => b.core_data.msg_cnt.get(),
        _ => panic!("not a BSM"),
    }
}

fn on_big_stack(f: impl FnOnce() + Send + 'static) {
    // Without `alloc` a kept MessageFrame is megabytes: the decoder is built on a test
    // thread with room for it, then boxed.
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

#[test]
fn frames_of_one_type_reuse_one_kept_value() {
    on_big_stack(|| {
        let mut d = std::boxed::Box::new(Decoder::<2>::new());
        assert_eq!(msg_cnt(d.decode(&bytes(BSM_MINIMAL)).unwrap()), 17);
        assert_eq!(msg_cnt(d.decode(&bytes(BSM_CORE_MAX)).unwrap()), 127);
        assert_eq!(d.kept(), 1);
    });
}

#[test]
fn a_new_type_takes_a_free_value_then_the_least_recently_used() {
    on_big_stack(|| {
        let mut d = std::boxed::Box::new(Decoder::<2>::new());
        let (bsm, spat, map) = (bytes(BSM_MINIMAL), bytes(SPAT_MINIMAL), bytes(MAP_MINIMAL));
        assert!(d.decode(&bsm).is_ok());
        assert!(matches!(
            d.decode(&spat).unwrap().value,
            MessageFrameValue::SPAT(_)
        ));
        assert_eq!(d.kept(), 2);
        assert_eq!(msg_cnt(d.decode(&bsm).unwrap()), 17);
        // Both values are taken: the MAP replaces the SPaT, used least recently.
        assert!(matches!(
            d.decode(&map).unwrap().value,
            MessageFrameValue::MapData(_)
        ));
        assert_eq!(d.kept(), 2);
        assert_eq!(d.ids[..2], [20, 18]);
        assert_eq!(msg_cnt(d.decode(&bsm).unwrap()), 17);
    });
}

#[test]
fn errors_are_returned_and_the_decoder_goes_on() {
    on_big_stack(|| {
        let mut d = std::boxed::Box::new(Decoder::<4>::new());
        let bsm = bytes(BSM_MINIMAL);
        assert!(d.decode(&bsm[..10]).is_err());
        assert!(d.decode(&[]).is_err());
        let mut longer = bsm.clone();
        longer.push(0);
        assert_eq!(
            d.decode(&longer).unwrap_err().kind,
            DecodeErrorKind::TrailingBytes
        );
        assert_eq!(msg_cnt(d.decode(&bsm).unwrap()), 17);
        assert_eq!(d.kept(), 1);
    });
}
