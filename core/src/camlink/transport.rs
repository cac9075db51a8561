//! Where the camera link's bytes travel: a serial device (the robot's RS-232 port, a
//! USB adapter, or a pseudo-terminal) through the serialport crate, or TCP to a camera
//! computer on Ethernet. The bytes are the same on both (function_spec.md section 7).

use std::io::{self, Read, Write};
use std::net::{SocketAddr, TcpStream, ToSocketAddrs};
use std::time::Duration;

use super::OpenStep;
use crate::config::CameraPort;

/// A byte stream to the camera computer, with reads that time out.
pub trait ByteStream: Read + Write + Send {}
impl<T: Read + Write + Send> ByteStream for T {}

/// Turns "HOST:PORT" into addresses. A plain function, so that a test can put in one
/// that hangs as a name look-up does without a network.
pub type Resolver = fn(&str) -> io::Result<Vec<SocketAddr>>;

/// The system's name look-up (/etc/hosts, DNS): it may block for seconds.
pub fn system_resolver(address: &str) -> io::Result<Vec<SocketAddr>> {
    Ok(address.to_socket_addrs()?.collect())
}

/// A camera computer that does not answer gives up after this long. The connect runs
/// off the link thread (opener.rs), so this can allow for a slow network.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(1);

/// Open the transport; reads wait at most `read_timeout` for a byte. This blocks (a
/// name look-up, a connect): the link thread calls it through opener.rs. `step` hears
/// what it is waiting for.
pub fn open(
    port: &CameraPort,
    resolve: Resolver,
    read_timeout: Duration,
    step: &dyn Fn(OpenStep),
) -> io::Result<Box<dyn ByteStream>> {
    match port {
        CameraPort::Sim => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "the simulated camera computer is reached through its pseudo-terminal",
        )),
        CameraPort::Bus => Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "row estimates on the bus come through the bus thread, not a camera port",
        )),
        CameraPort::Serial { path, baud } => {
            step(OpenStep::Opening);
            // 8 data bits, no parity, 1 stop bit, no flow control: serialport's defaults.
            let serial = serialport::new(path.as_str(), *baud)
                .timeout(read_timeout)
                .open()?;
            Ok(Box::new(serial))
        }
        CameraPort::Tcp { address } => {
            step(OpenStep::LookingUp);
            let targets = resolve(address)?;
            step(OpenStep::Opening);
            // A name may stand for several addresses ("localhost": ::1 and 127.0.0.1):
            // the first that answers is the camera computer.
            let mut why =
                io::Error::new(io::ErrorKind::NotFound, "the address resolves to nothing");
            for target in targets {
                match TcpStream::connect_timeout(&target, CONNECT_TIMEOUT) {
                    Ok(stream) => {
                        stream.set_read_timeout(Some(read_timeout))?;
                        stream.set_nodelay(true)?;
                        return Ok(Box::new(stream));
                    }
                    Err(e) => why = e,
                }
            }
            Err(why)
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
        let err = open(&port, system_resolver, Duration::from_millis(10), &|_| {})
            .err()
            .expect("no such device");
        assert_eq!(err.kind(), io::ErrorKind::NotFound, "{err}");
    }

    #[test]
    fn a_name_with_several_addresses_connects_to_the_one_that_answers() {
        let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
        let port = listener.local_addr().unwrap().port();
        // Nothing listens on the first address (the listener's port on IPv6 loopback,
        // or refused where there is none).
        fn two_addresses(address: &str) -> io::Result<Vec<SocketAddr>> {
            let port = address.rsplit_once(':').unwrap().1;
            Ok(vec![
                format!("[::1]:{port}").parse().unwrap(),
                format!("127.0.0.1:{port}").parse().unwrap(),
            ])
        }
        let tcp = CameraPort::Tcp {
            address: format!("camera:{port}"),
        };
        let steps = std::cell::RefCell::new(Vec::new());
        let opened = open(&tcp, two_addresses, Duration::from_millis(10), &|s| {
            steps.borrow_mut().push(s)
        });
        assert!(opened.is_ok(), "{:?}", opened.err());
        assert_eq!(*steps.borrow(), [OpenStep::LookingUp, OpenStep::Opening]);
    }
}
