//! The OBU's GNSS reader: NMEA sentences and UBX frames with any bytes between.
//! The checks: `j2735_fuzz::gnss`.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    j2735_fuzz::gnss::check(data);
});
