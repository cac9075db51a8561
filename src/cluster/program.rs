//! The programs a graph can run and their ports: the mechweed commands, whose ports
//! are the robot's flows on the bus, and any other executable, whose ports are named by
//! the graph.

/// A port takes flows in or sends them out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Direction {
    In,
    Out,
}

#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Program {
    /// `mechweed run`: the controller, the one program that listens for flows.
    Run,
    /// `mechweed camsim --bus`: the simulated camera computer's rows.
    Camsim,
    /// `mechweed watch`: the operator GUI on another machine.
    Watch,
    /// `mechweed record --bus`: the off-board recorder.
    Record,
    /// `mechweed ros2`: the robot's flows as ROS 2 topics on the ROS machines' router.
    Ros2,
    /// Any other executable, by name (on the PATH) or path.
    Executable(String),
}

/// The robot's flows, by port name: (port, key after `ROBOT/`).
const FLOW_KEYS: [(&str, &str); 5] = [
    ("status", "status"),
    ("tick", "tick"),
    ("event", "event"),
    ("rows", "camera/row"),
    ("requests", "request"),
];

impl Program {
    /// `run`, `camsim`, `watch`, `record`, `ros2`, or an executable.
    pub fn parse(text: &str) -> Result<Program, String> {
        Ok(match text {
            "run" => Program::Run,
            "camsim" => Program::Camsim,
            "watch" => Program::Watch,
            "record" => Program::Record,
            "ros2" => Program::Ros2,
            "" => {
                return Err("is empty: run, camsim, watch, record, ros2, or an executable".into());
            }
            other if other.contains(char::is_whitespace) => {
                return Err(format!(
                    "'{other}' is more than one word: put the arguments in args"
                ));
            }
            other => Program::Executable(other.to_string()),
        })
    }

    /// The mechweed command's word, or the executable.
    pub fn name(&self) -> &str {
        match self {
            Program::Run => "run",
            Program::Camsim => "camsim",
            Program::Watch => "watch",
            Program::Record => "record",
            Program::Ros2 => "ros2",
            Program::Executable(path) => path,
        }
    }

    pub(crate) fn is_mechweed(&self) -> bool {
        !matches!(self, Program::Executable(_))
    }

    /// Programs that read robot.ini take `set.SECTION.KEY` overrides.
    pub(crate) fn takes_settings(&self) -> bool {
        matches!(self, Program::Run | Program::Record | Program::Ros2)
    }

    /// The mechweed program's ports in `direction`; None: any port (an executable).
    fn ports(&self, direction: Direction) -> Option<&'static [&'static str]> {
        use Direction::{In, Out};
        Some(match (self, direction) {
            (Program::Run, Out) => &["status", "tick", "event"],
            (Program::Run, In) => &["rows", "requests"],
            (Program::Camsim, Out) => &["rows"],
            (Program::Camsim, In) => &[],
            (Program::Watch, Out) => &["requests"],
            (Program::Watch | Program::Record | Program::Ros2, In) => &["status", "tick", "event"],
            (Program::Record | Program::Ros2, Out) => &[],
            (Program::Executable(_), _) => return None,
        })
    }

    /// Whether `port` is one of this program's ports in `direction`.
    pub(crate) fn check_port(&self, port: &str, direction: Direction) -> Result<(), String> {
        let plain = !port.is_empty()
            && port
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if !plain {
            return Err(format!(
                "'{port}' is not a port name (letters, digits, _ -)"
            ));
        }
        let Some(ports) = self.ports(direction) else {
            return Ok(());
        };
        if ports.contains(&port) {
            return Ok(());
        }
        let (way, other) = match direction {
            Direction::In => ("takes in", Direction::Out),
            Direction::Out => ("sends out", Direction::In),
        };
        let listed = if ports.is_empty() {
            "nothing".to_string()
        } else {
            ports.join(", ")
        };
        let wrong_way = self.ports(other).is_some_and(|p| p.contains(&port));
        let hint = if wrong_way {
            format!(" ({port} goes the other way)")
        } else {
            String::new()
        };
        Err(format!("{} {way} {listed}, not {port}{hint}", self.name()))
    }

    /// Whether a flow can go from `from`'s port to `to`'s: the same kind of message,
    /// and the controller at one end of a flow between mechweed programs (it is the
    /// one that listens; the others connect to it).
    pub(crate) fn check_link(
        from: &Program,
        out: &str,
        to: &Program,
        into: &str,
    ) -> Result<(), String> {
        let robot_flow = |port: &str| FLOW_KEYS.iter().any(|(p, _)| *p == port);
        if (from.is_mechweed() || to.is_mechweed() || robot_flow(out)) && out != into {
            return Err(format!("{out} cannot feed {into}: a flow carries one kind"));
        }
        if from.is_mechweed() && to.is_mechweed() && *from != Program::Run && *to != Program::Run {
            return Err(format!(
                "{} and {} reach each other only through the controller (program = run)",
                from.name(),
                to.name()
            ));
        }
        Ok(())
    }

    /// The bus key of `process`'s output `port`: the robot's flows by their names
    /// (`ROBOT/camera/row`), an executable's other ports under its own name.
    pub fn key(robot: &str, process: &str, port: &str) -> String {
        match FLOW_KEYS.iter().find(|(p, _)| *p == port) {
            Some((_, key)) => format!("{robot}/{key}"),
            None => format!("{robot}/{process}/{port}"),
        }
    }
}
