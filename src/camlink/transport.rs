//! Where the camera link's bytes travel: a serial device (the robot's RS-232 port, a
//! USB adapter, or a pseudo-terminal) through the serialport crate, or TCP to a camera
//! computer on Ethernet. The bytes are the same on both (camera-link.md).

use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::time::Duration;

/// Baud rates the camera computer can be set to (camera-link.md).
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
}

impl CameraPort {
    /// Read the [camera] port setting: `sim`, a device path, or `tcp://HOST:PORT`.
    pub fn parse(text: &str, baud: u32) -> Result<CameraPort, String> {
        if text == "sim" {
            return Ok(CameraPort::Sim);
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
        Err(format!(
            "'{text}' is not sim, a device such as /dev/ttyS0, or tcp://HOST:PORT"
        ))
    }

    /// For messages.
    pub fn describe(&self) -> String {
        match self {
            CameraPort::Sim => "the simulated camera computer".to_string(),
            CameraPort::Serial { path, baud } => format!("{path} at {baud} baud"),
            CameraPort::Tcp { address } => format!("tcp://{address}"),
        }
    }
}

/// A byte stream to the camera computer, with reads that time out.
pub trait ByteStream: Read + Write + Send {}
impl<T: Read + Write + Send> ByteStream for T {}

/// Open the transport; reads wait at most `read_timeout` for a byte.
pub fn open(port: &CameraPort, read_timeout: Duration) -> io::Result<Box<dyn ByteStream>> {
    match port {
        CameraPort::Sim => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the simulated camera computer is reached through its pseudo-terminal",
        )),
        CameraPort::Serial { path, baud } => {
            // 8 data bits, no parity, 1 stop bit, no flow control: serialport's defaults.
            let serial = serialport::new(path.as_str(), *baud)
                .timeout(read_timeout)
                .open()?;
            Ok(Box::new(serial))
        }
        CameraPort::Tcp { address } => {
            let target = address.to_socket_addrs()?.next().ok_or_else(|| {
                io::Error::new(io::ErrorKind::NotFound, "the address resolves to nothing")
            })?;
            // Short, so the link thread keeps beating while a camera computer is away.
            let stream = TcpStream::connect_timeout(&target, Duration::from_millis(250))?;
            stream.set_read_timeout(Some(read_timeout))?;
            stream.set_nodelay(true)?;
            Ok(Box::new(stream))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_three_kinds_and_rejects_the_rest() {
        assert_eq!(CameraPort::parse("sim", 115200), Ok(CameraPort::Sim));
        assert_eq!(
            CameraPort::parse("/dev/ttyUSB0", 9600),
            Ok(CameraPort::Serial {
                path: "/dev/ttyUSB0".into(),
                baud: 9600
            })
        );
        assert_eq!(
            CameraPort::parse("tcp://127.0.0.1:5000", 115200),
            Ok(CameraPort::Tcp {
                address: "127.0.0.1:5000".into()
            })
        );
        assert!(CameraPort::parse("tcp://127.0.0.1", 115200).is_err());
        assert!(CameraPort::parse("ttyS0", 115200).is_err());
    }

    #[test]
    fn a_missing_device_is_a_clear_error() {
        let port = CameraPort::Serial {
            path: "/dev/does-not-exist".into(),
            baud: 115200,
        };
        let err = open(&port, Duration::from_millis(10))
            .err()
            .expect("no such device");
        assert_eq!(err.kind(), io::ErrorKind::NotFound, "{err}");
    }
}
