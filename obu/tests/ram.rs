//! Static RAM of the core with the default capacities.

use obu::capacity::*;
use obu::lane::{Lane, LaneModel, MapStore};
use obu::zone::{WorkZone, ZoneStore};
use obu::Obu;

#[test]
fn static_ram_budget() {
    let obu = core::mem::size_of::<Obu>();
    println!(
        "RAM: Obu {} B ({:.1} KiB) for {} maps x {} lanes x {} nodes and {} zones",
        obu,
        obu as f64 / 1024.0,
        MAX_MAPS,
        MAX_LANES,
        MAX_NODES,
        MAX_ZONES
    );
    println!(
        "  Lane {} B, LaneModel {} B, MapStore {} B, WorkZone {} B, ZoneStore {} B, HmiState {} B",
        core::mem::size_of::<Lane>(),
        core::mem::size_of::<LaneModel>(),
        core::mem::size_of::<MapStore>(),
        core::mem::size_of::<WorkZone>(),
        core::mem::size_of::<ZoneStore>(),
        core::mem::size_of::<obu::HmiState>()
    );
    assert!(obu < 64 * 1024, "goal: < 64 KiB, got {obu}");
}
