//! One zeroed static per type, sized by `size_of` on the target: `nm -S` reads the sizes.
#![no_std]
#![forbid(unsafe_code)]

use core::mem::size_of;

macro_rules! size_of_static {
    ($name:ident, $t:ty) => {
        /// Zeros, as many as the type's size on this target.
        pub static $name: [u8; size_of::<$t>()] = [0; size_of::<$t>()];
    };
}

size_of_static!(SIZE_OF_OBU, obu::Obu);
size_of_static!(SIZE_OF_MAP_STORE, obu::lane::MapStore);
size_of_static!(SIZE_OF_ZONE_STORE, obu::zone::ZoneStore);
size_of_static!(SIZE_OF_LANE, obu::lane::Lane);
size_of_static!(SIZE_OF_WORK_ZONE, obu::zone::WorkZone);
size_of_static!(SIZE_OF_HMI_STATE, obu::HmiState);
