//! The plots of a scenario run: its records and the simulated truth handed to [`crate::plot`].

use crate::drive::Sample;
use crate::expect::Record;
use crate::plot::{write_plots, PlotInput, PlotLane, TrackPoint};
use crate::scenario::Scenario;
use roadside::messages::WorkZone;
use roadside::road::Road;
use std::path::{Path, PathBuf};

/// Writes the plots of a run into `out`; returns the files.
pub fn write(
    s: &Scenario,
    road: &Road,
    zones: &[WorkZone],
    samples: &[Sample],
    records: &[Record],
    out: &Path,
) -> Result<Vec<PathBuf>, String> {
    let track: Vec<TrackPoint> = records
        .iter()
        .filter_map(|r| {
            let truth = samples.get(r.sample?)?;
            Some(TrackPoint {
                t_s: r.t_s,
                true_point: truth.point,
                true_lane: truth.lane,
                true_distance_m: r.distance_m,
                speed_mps: r.state.speed_mps.map(f64::from),
                limit_mps: r.state.speed_limit_mps.map(f64::from),
                zone_state: format!("{:?}", r.state.zone_state),
                primary: r.state.primary.map(|a| format!("{:?}", a.kind)),
                matched_lane: r.state.lane.map(|l| l.lane),
            })
        })
        .collect();
    let lanes: Vec<PlotLane> = road
        .lanes
        .iter()
        .map(|l| PlotLane {
            id: l.id,
            centre: l.centre.clone(),
            width_m: l.width_m,
        })
        .collect();
    let pieces: Vec<Vec<[f64; 2]>> = zones
        .iter()
        .flat_map(|z| {
            let first = z.closed_lanes.first().and_then(|id| road.lane(*id));
            z.closed_lanes.iter().filter_map(move |id| {
                let lane = road.lane(*id)?;
                let (a, b) = match first {
                    Some(f) if f.id != lane.id => (
                        lane.project(f.at(z.start_m)?.point)?.0,
                        lane.project(f.at(z.end_m)?.point)?.0,
                    ),
                    _ => (z.start_m, z.end_m),
                };
                Some(lane.slice(a, b))
            })
        })
        .collect();
    write_plots(
        out,
        &PlotInput {
            title: &s.name,
            track: &track,
            lanes: &lanes,
            zones: &pieces,
            warning_distance_m: Some(s.settings.warning_distance_m),
        },
    )
}
