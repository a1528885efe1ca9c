//! The classes of road users an instance-segmentation detector reports, and their sizes.

/// What kind of road user a detection is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RoadUserClass {
    /// Passenger car.
    Car,
    /// Van or light commercial vehicle.
    Van,
    /// Bus.
    Bus,
    /// Truck (lorry).
    Truck,
    /// A person on foot: pedestrian or road worker.
    Pedestrian,
    /// A person on a bicycle.
    Cyclist,
    /// Motorcycle and rider.
    Motorcycle,
}

/// The extent of a road user's box, metres: along the road, across it and up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// Along the road (a vehicle's length).
    pub length_m: f64,
    /// Across the road (a vehicle's width).
    pub width_m: f64,
    /// Height.
    pub height_m: f64,
}

/// What a class's size is before a road user of it is seen: mean and 1-sigma per side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizePrior {
    /// Mean length, width and height, metres.
    pub mean: Extent,
    /// 1-sigma spread of each, metres.
    pub sigma: Extent,
}

impl RoadUserClass {
    /// Every class, in order.
    pub const ALL: [Self; 7] = [
        Self::Car,
        Self::Van,
        Self::Bus,
        Self::Truck,
        Self::Pedestrian,
        Self::Cyclist,
        Self::Motorcycle,
    ];

    /// The class of a detector's class name (case-insensitive): car, van, bus, truck,
    /// pedestrian / person / worker, cyclist / bicycle / bicyclist, motorcycle / motorbike /
    /// motorcyclist; `None` for anything else.
    pub fn from_name(name: &str) -> Option<Self> {
        let name = name.trim().to_ascii_lowercase();
        Some(match name.as_str() {
            "car" => Self::Car,
            "van" => Self::Van,
            "bus" => Self::Bus,
            "truck" => Self::Truck,
            "pedestrian" | "person" | "worker" => Self::Pedestrian,
            "cyclist" | "bicycle" | "bicyclist" => Self::Cyclist,
            "motorcycle" | "motorbike" | "motorcyclist" => Self::Motorcycle,
            _ => return None,
        })
    }

    /// Lower-case name: "car", "van", "bus", "truck", "pedestrian", "cyclist", "motorcycle".
    pub fn name(self) -> &'static str {
        match self {
            Self::Car => "car",
            Self::Van => "van",
            Self::Bus => "bus",
            Self::Truck => "truck",
            Self::Pedestrian => "pedestrian",
            Self::Cyclist => "cyclist",
            Self::Motorcycle => "motorcycle",
        }
    }

    /// True for people on foot.
    pub fn is_person(self) -> bool {
        matches!(self, Self::Pedestrian)
    }

    /// The class's size on the road as a prior: the mean and the 1-sigma spread of each
    /// side, from the fleets and people on roads (not from any one scene): cars 4.6 m long
    /// (superminis 3.8 m to large saloons 5.2 m), city and coach buses 10-14 m, rigid trucks
    /// 6-11 m, adults 0.45 m across the shoulders and 1.72 m tall. A measured side is fused
    /// with it by inverse variance, so the prior decides only what the view cannot measure.
    pub fn size_prior(self) -> SizePrior {
        let (mean, sigma) = match self {
            Self::Car => ((4.6, 1.82, 1.5), (0.4, 0.1, 0.12)),
            Self::Van => ((5.3, 2.0, 2.2), (0.5, 0.1, 0.3)),
            Self::Bus => ((12.0, 2.55, 3.2), (1.2, 0.06, 0.2)),
            Self::Truck => ((8.5, 2.5, 3.4), (1.8, 0.08, 0.4)),
            Self::Pedestrian => ((0.45, 0.45, 1.72), (0.1, 0.1, 0.1)),
            Self::Cyclist => ((1.75, 0.6, 1.7), (0.15, 0.1, 0.1)),
            Self::Motorcycle => ((2.1, 0.8, 1.4), (0.2, 0.1, 0.1)),
        };
        let extent = |(length_m, width_m, height_m)| Extent {
            length_m,
            width_m,
            height_m,
        };
        SizePrior {
            mean: extent(mean),
            sigma: extent(sigma),
        }
    }

    /// The class's mean size ([`RoadUserClass::size_prior`]).
    pub fn typical(self) -> Extent {
        self.size_prior().mean
    }

    /// The largest plausible box of the class: a constructed box beyond it is a wrong
    /// construction (merged detections, a wrong tangent), not a road user.
    pub fn largest(self) -> Extent {
        let t = self.typical();
        let (l, w, h) = match self {
            Self::Pedestrian => (1.2, 1.2, 2.3),
            Self::Cyclist | Self::Motorcycle => (3.0, 1.5, 2.3),
            _ => (
                t.length_m * 1.6,
                t.width_m * 1.4 + 0.3,
                t.height_m * 1.4 + 0.3,
            ),
        };
        Extent {
            length_m: l,
            width_m: w,
            height_m: h,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_aliases() {
        for c in RoadUserClass::ALL {
            assert_eq!(RoadUserClass::from_name(c.name()), Some(c));
            let t = c.typical();
            let l = c.largest();
            assert!(t.length_m < l.length_m && t.width_m < l.width_m && t.height_m < l.height_m);
        }
        assert_eq!(
            RoadUserClass::from_name(" Worker"),
            Some(RoadUserClass::Pedestrian)
        );
        assert_eq!(
            RoadUserClass::from_name("BICYCLE"),
            Some(RoadUserClass::Cyclist)
        );
        assert_eq!(RoadUserClass::from_name("traffic cone"), None);
    }
}
