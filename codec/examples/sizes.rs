//! Prints the in-memory size of the largest generated types in this build's storage mode.
use core::mem::size_of;
use j2735::msg::common::{NodeAttributeSetXY, NodeXY};
use j2735::msg::map_data::{GenericLane, IntersectionGeometry};
use j2735::msg::traveler_information::{GeographicalPath, TravelerDataFrame};
use j2735::{BasicSafetyMessage, MapData, MessageFrame, TravelerInformation, SPAT};

fn main() {
    let mode = if cfg!(feature = "alloc") {
        "alloc"
    } else {
        "no-heap"
    };
    println!("storage: {mode}");
    println!(
        "MessageFrame          {:>10} bytes",
        size_of::<MessageFrame>()
    );
    println!("MapData               {:>10} bytes", size_of::<MapData>());
    println!(
        "IntersectionGeometry  {:>10} bytes",
        size_of::<IntersectionGeometry>()
    );
    println!(
        "GenericLane           {:>10} bytes",
        size_of::<GenericLane>()
    );
    println!("NodeXY                {:>10} bytes", size_of::<NodeXY>());
    println!(
        "NodeAttributeSetXY    {:>10} bytes",
        size_of::<NodeAttributeSetXY>()
    );
    println!(
        "TravelerInformation   {:>10} bytes",
        size_of::<TravelerInformation>()
    );
    println!(
        "TravelerDataFrame     {:>10} bytes",
        size_of::<TravelerDataFrame>()
    );
    println!(
        "GeographicalPath      {:>10} bytes",
        size_of::<GeographicalPath>()
    );
    println!(
        "BasicSafetyMessage    {:>10} bytes",
        size_of::<BasicSafetyMessage>()
    );
    println!("SPAT                  {:>10} bytes", size_of::<SPAT>());
    println!(
        "MAX_UPER_BITS MessageFrame {:?}",
        <MessageFrame as j2735::uper::Uper>::MAX_UPER_BITS
    );
}
