//! Which sensors steer the robot in autonomous mode: a word shared by the steer thread
//! (which decides it, core/src/steer/sources.rs), the supervisor (which says each change and
//! faults when nothing steers) and the operator's views.

/// Which sensors steer now.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Steering {
    /// The camera alone ([steer] source = camera), through the row filter.
    #[default]
    Camera,
    /// The row filter, fed by the camera and GNSS.
    Fused,
    /// The row filter, fed by the camera alone (no trusted GNSS fix).
    FilterCamera,
    /// The row filter, fed by GNSS alone (no usable camera row, or [steer] source =
    /// gnss); with source = fused at reduced speed.
    FilterGnss,
    /// Nothing usable: the robot stops.
    Nothing,
}

/// Every value, for reading a record's word back.
const ALL: [Steering; 5] = [
    Steering::Camera,
    Steering::Fused,
    Steering::FilterCamera,
    Steering::FilterGnss,
    Steering::Nothing,
];

impl Steering {
    /// One word, as the record writes it.
    pub fn name(self) -> &'static str {
        match self {
            Steering::Camera => "camera",
            Steering::Fused => "fused",
            Steering::FilterCamera => "camera_alone",
            Steering::FilterGnss => "gnss_alone",
            Steering::Nothing => "nothing",
        }
    }

    /// The value a record's word names, or None.
    pub fn from_name(name: &str) -> Option<Steering> {
        ALL.into_iter().find(|s| s.name() == name)
    }

    /// In words, for the GUI, the console and the record.
    pub fn words(self) -> &'static str {
        match self {
            Steering::Camera => "the camera",
            Steering::Fused => "camera and GNSS, fused",
            // Why it came to this is the notice's (SourceHealth::why): "lost" said of a
            // camera that sends frames which show no row misled.
            Steering::FilterCamera => "the camera alone",
            Steering::FilterGnss => "GNSS alone",
            Steering::Nothing => "nothing: neither the camera nor GNSS",
        }
    }
}
