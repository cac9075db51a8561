//! [ros2]: how `mechweed ros2` shows the robot to ROS 2 tools (docs/ros2.md). The
//! section is optional: a settings file from before it gives the shipped values, which
//! the program says at its start.

use super::bus::parse_endpoints;
use super::reader::Reader;

/// The ROS 2 releases whose wire format the bridge speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Distro {
    Jazzy,
    Kilted,
    Rolling,
}

impl Distro {
    pub const ALL: [Distro; 3] = [Distro::Jazzy, Distro::Kilted, Distro::Rolling];
    pub const NAMES: [&str; 3] = ["jazzy", "kilted", "rolling"];

    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    pub fn from_name(name: &str) -> Option<Distro> {
        Self::ALL.into_iter().find(|d| d.name() == name)
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Ros2Settings {
    /// ROS_DOMAIN_ID of the ROS machines: the first part of every key.
    pub domain_id: u32,
    /// The namespace of the node and its topics, e.g. /mechweed.
    pub namespace: String,
    /// The ROS router's (rmw_zenohd's) endpoint, e.g. tcp/127.0.0.1:7447.
    pub connect: String,
    pub distro: Distro,
    /// Radius of the drive wheels, m: wheel speeds in rad/s on /joint_states.
    pub wheel_radius_m: f64,
    /// Put before every frame id (odom, base_link, row, gnss): "" or e.g. "robot2/".
    pub frame_prefix: String,
    /// Offer the HALT service /NAMESPACE/halt (std_srvs/srv/Trigger) to ROS.
    pub halt_service: bool,
}

impl Ros2Settings {
    /// The values shipped in config/robot.ini, for a file without [ros2].
    pub fn shipped() -> Ros2Settings {
        Ros2Settings {
            domain_id: 0,
            namespace: "/mechweed".to_string(),
            connect: "tcp/127.0.0.1:7447".to_string(),
            distro: Distro::Jazzy,
            wheel_radius_m: 0.2,
            frame_prefix: String::new(),
            halt_service: false,
        }
    }
}

/// The largest domain id ROS 2 takes (its DDS port arithmetic; rmw_zenoh keeps it).
pub const MAX_DOMAIN_ID: u64 = 232;

/// A ROS namespace: `/`, or `/` and names of letters, digits and `_` that do not start
/// with a digit, joined by `/`, with no `/` at the end.
pub fn parse_namespace(text: &str) -> Result<String, String> {
    let bad = |why: &str| Err(format!("'{text}' is not a ROS namespace: {why}"));
    let Some(rest) = text.strip_prefix('/') else {
        return bad("it must start with /");
    };
    if rest.is_empty() {
        return Ok(text.to_string());
    }
    for part in rest.split('/') {
        let mut chars = part.chars();
        match chars.next() {
            None => return bad("it has an empty name (// or a / at the end)"),
            Some(c) if c.is_ascii_digit() => return bad("a name starts with a digit"),
            Some(_) => {}
        }
        if !part.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
            return bad("use only letters, digits and _ between the /");
        }
    }
    Ok(text.to_string())
}

/// A frame prefix: empty, or letters, digits, `_` and `/` that do not start with `/`
/// (tf2 takes no frame id that starts with one), such as `robot2/`.
pub fn parse_frame_prefix(text: &str) -> Result<String, String> {
    let plain = (text.chars()).all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '/');
    if text.starts_with('/') || !plain {
        return Err(format!(
            "'{text}' is not a frame prefix: letters, digits, _ and /, not starting with / (for example robot2/), or nothing"
        ));
    }
    Ok(text.to_string())
}

/// One endpoint of the ROS router.
pub fn parse_router(text: &str) -> Result<String, String> {
    match parse_endpoints(text)?.as_slice() {
        [one] => Ok(one.clone()),
        _ => Err(format!(
            "'{text}' is not one endpoint: the ROS machines have one router"
        )),
    }
}

/// [ros2], or None when the file has no such section.
pub(super) fn load(r: &mut Reader) -> Option<Ros2Settings> {
    let s = "ros2";
    if !r.sections().iter().any(|name| name == s) {
        return None;
    }
    Some(Ros2Settings {
        domain_id: r.u64(s, "domain_id", 0, MAX_DOMAIN_ID) as u32,
        namespace: r
            .parsed(s, "namespace", parse_namespace)
            .unwrap_or_default(),
        connect: r.parsed(s, "connect", parse_router).unwrap_or_default(),
        distro: Distro::ALL[r.choice(s, "distro", &Distro::NAMES)],
        wheel_radius_m: r.f64(s, "wheel_radius_m", 0.01, 2.0),
        frame_prefix: (r.parsed(s, "frame_prefix", parse_frame_prefix)).unwrap_or_default(),
        halt_service: r.choice(s, "halt_service", &["yes", "no"]) == 0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_prefix_is_a_frame_ids_beginning() {
        for good in ["", "robot2/", "farm_1/robot_a/"] {
            assert_eq!(parse_frame_prefix(good).as_deref(), Ok(good));
        }
        for bad in ["/robot2/", "robot 2/", "robot-2/"] {
            let why = parse_frame_prefix(bad).unwrap_err();
            assert!(why.contains(&format!("'{bad}'")), "{why}");
        }
    }

    #[test]
    fn namespaces_follow_ros_names() {
        assert!(parse_namespace("/mechweed").is_ok());
        assert!(parse_namespace("/farm_2/robot_a").is_ok());
        assert!(parse_namespace("/").is_ok());
        for bad in ["mechweed", "/mechweed/", "/a//b", "/2robot", "/weed-er"] {
            let why = parse_namespace(bad).unwrap_err();
            assert!(why.contains(bad), "{why}");
        }
    }

    #[test]
    fn one_router_endpoint() {
        assert_eq!(
            parse_router("tcp/127.0.0.1:7447").unwrap(),
            "tcp/127.0.0.1:7447"
        );
        assert!(parse_router("tcp/127.0.0.1:7447, tcp/10.0.0.2:7447").is_err());
    }
}
