//! Where the camera computer is: robot.ini [camera] port and baud.

use super::reader::Reader;

/// Read [camera] port and baud.
pub(super) fn load(r: &mut Reader) -> CameraPort {
    let names = BAUD_RATES.map(|b| b.to_string());
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let baud = BAUD_RATES[r.choice("camera", "baud", &names)];
    r.parsed("camera", "port", |text| CameraPort::parse(text, baud))
        .unwrap_or(CameraPort::Sim)
}

/// Baud rates the camera computer can be set to (function_spec.md section 7).
pub const BAUD_RATES: [u32; 5] = [9600, 19200, 38400, 57600, 115200];

/// Where to find the camera computer: robot.ini [camera] port.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CameraPort {
    /// The simulated camera computer of the simulated robot, on a pseudo-terminal.
    Sim,
    /// A serial device such as /dev/ttyS0 or /dev/ttyUSB0.
    Serial { path: String, baud: u32 },
    /// A camera computer's TCP port, as HOST:PORT.
    Tcp { address: String },
    /// Row estimates from a vision program on the bus (`ROBOT/camera/row`, src/bus/).
    Bus,
}

impl CameraPort {
    /// Read the [camera] port setting: `sim`, a device path, or `tcp://HOST:PORT`.
    pub fn parse(text: &str, baud: u32) -> Result<CameraPort, String> {
        if text == "sim" {
            return Ok(CameraPort::Sim);
        }
        if text == "bus" {
            return Ok(CameraPort::Bus);
        }
        if let Some(address) = text.strip_prefix("tcp://") {
            let port_ok = address.rsplit_once(':').is_some_and(|(host, port)| {
                !host.is_empty() && port.parse::<u16>().is_ok_and(|p| p > 0)
            });
            if !port_ok {
                return Err(format!(
                    "'{text}' is not tcp://HOST:PORT (for example tcp://192.168.1.20:5000)"
                ));
            }
            return Ok(CameraPort::Tcp {
                address: address.to_string(),
            });
        }
        if text.starts_with('/') {
            return Ok(CameraPort::Serial {
                path: text.to_string(),
                baud,
            });
        }
        // HOST:PORT is how camsim --listen is written: the likely slip is the missing tcp://.
        let looks_like_tcp = text.rsplit_once(':').is_some_and(|(host, port)| {
            !host.is_empty() && port.parse::<u16>().is_ok_and(|p| p > 0)
        });
        if looks_like_tcp {
            return Err(format!(
                "'{text}' lacks tcp://: a camera computer on the network is written tcp://{text}"
            ));
        }
        Err(format!(
            "'{text}' is not sim, bus, a device such as /dev/ttyS0, or tcp://HOST:PORT"
        ))
    }

    /// A camera outside this program (camsim, a camera computer) while the robot is the
    /// simulated one: the camera's rows are not the simulated field's, so the field's
    /// cross-track says nothing about the steering.
    pub(crate) fn is_outside_of(&self, backend: super::Backend) -> bool {
        backend == super::Backend::Sim && *self != CameraPort::Sim
    }

    /// For messages.
    pub fn describe(&self) -> String {
        match self {
            CameraPort::Sim => "the simulated camera computer".to_string(),
            CameraPort::Serial { path, baud } => format!("{path} at {baud} baud"),
            CameraPort::Tcp { address } => format!("tcp://{address}"),
            CameraPort::Bus => "the bus (row estimates on camera/row)".to_string(),
        }
    }
}
