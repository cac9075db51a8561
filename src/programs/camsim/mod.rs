//! Where `mechweed camsim` speaks: a serial device (or a new pseudo-terminal), or a TCP
//! port that takes one robot computer at a time. It prints every command it receives, and
//! once a second what it sent.

mod bus;
pub mod computer;

use std::net::TcpListener;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use serialport::{SerialPort, TTYPort};

use crate::config::BAUD_RATES;
use crate::programs::camsim::computer::{CamSim, CamSimOptions, Pattern, Sent, serve};

/// A read waits at most this long, so frames go out on time.
const POLL: Duration = Duration::from_millis(5);

fn print_command(t_s: f64, name: &'static str) {
    println!("{t_s:8.3} s  received {name}");
}

/// A line a second of what went out and came in during that second.
fn each_second_printer() -> impl FnMut(f64, &CamSim) {
    let mut before = Sent::default();
    move |t_s, sim| {
        let s = sim.sent.since(&before);
        before = sim.sent;
        let state = if sim.is_streaming() {
            "streaming"
        } else {
            "not streaming (waiting for START)"
        };
        println!(
            "{t_s:8.3} s  {state}: sent {} ROW frames ({} left out by --drop), {} PONGs; received {} commands",
            s.row_frames, s.dropped, s.pongs, s.commands_received
        );
    }
}

/// A serial device, or for DEVICE = "pty" a new pseudo-terminal whose path is said with
/// the setting that points the robot program at it (`what` is the simulated device).
pub(crate) fn serial_or_pty(
    device: &str,
    baud: u32,
    what: &str,
    setting: &str,
) -> Result<Box<dyn SerialPort>, String> {
    if device != "pty" {
        return serialport::new(device, baud)
            .open()
            .map_err(|e| format!("cannot open {device}: {e}"));
    }
    let (master, slave) =
        TTYPort::pair().map_err(|e| format!("cannot make a pseudo-terminal: {e}"))?;
    let path = slave.name().unwrap_or_default();
    println!("{what} on {path}: try  mechweed run --headless --set {setting}={path}");
    // The far end stays open here so the robot computer may open and close it.
    std::mem::forget(slave);
    Ok(Box::new(master))
}

/// Serve on a serial device, or on a new pseudo-terminal for DEVICE = "pty".
pub(crate) fn on_serial(device: &str, baud: u32, options: CamSimOptions) -> Result<(), String> {
    let mut port = serial_or_pty(device, baud, "simulated camera computer", "camera.port")?;
    port.set_timeout(POLL).map_err(|e| e.to_string())?;
    println!("simulated camera computer on {device}, waiting for START");
    let mut sim = CamSim::new(options);
    let stop = AtomicBool::new(false);
    serve(
        &mut sim,
        &mut port,
        Instant::now(),
        &stop,
        &mut print_command,
        &mut each_second_printer(),
    )
    .map_err(|e| format!("{device}: {e}"))
}

/// "PORT" alone means 127.0.0.1:PORT: a stand-in listens on this computer unless told.
pub(crate) fn tcp_address(address: &str) -> String {
    if address.contains(':') {
        address.to_string()
    } else {
        format!("127.0.0.1:{address}")
    }
}

/// Serve robot computers on a TCP port, one at a time. "PORT" alone means 127.0.0.1:PORT.
pub(crate) fn on_tcp(address: &str, options: CamSimOptions) -> Result<(), String> {
    let address = tcp_address(address);
    let listener =
        TcpListener::bind(&address).map_err(|e| format!("cannot listen on {address}: {e}"))?;
    let local = listener.local_addr().map_err(|e| e.to_string())?;
    println!("simulated camera computer listening on {local}");
    let clock = Instant::now();
    let stop = AtomicBool::new(false);
    for client in listener.incoming() {
        let mut stream = match client {
            Ok(stream) => stream,
            Err(e) => {
                eprintln!("a connection failed: {e}");
                continue;
            }
        };
        let peer = stream
            .peer_addr()
            .map(|a| a.to_string())
            .unwrap_or_default();
        println!("robot computer connected from {peer}");
        let _ = stream.set_read_timeout(Some(POLL));
        let _ = stream.set_nodelay(true);
        // A new connection is a new conversation: the camera waits for START again.
        let mut sim = CamSim::new(options);
        match serve(
            &mut sim,
            &mut stream,
            clock,
            &stop,
            &mut print_command,
            &mut each_second_printer(),
        ) {
            Ok(()) => println!("robot computer at {peer} closed the connection"),
            Err(e) => println!("robot computer at {peer}: {e}"),
        }
    }
    Ok(())
}

/// The command line of `mechweed camsim`.
#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("where").required(true).args(["port", "listen", "bus"])))]
pub struct CamsimArgs {
    /// Serial device to speak on, or "pty" to make a pseudo-terminal and print its path.
    #[arg(long, value_name = "DEVICE")]
    pub port: Option<String>,
    /// TCP address to listen on, one robot computer at a time: ADDR:PORT, or PORT alone
    /// for 127.0.0.1:PORT.
    #[arg(long, value_name = "ADDR:PORT")]
    pub listen: Option<String>,
    /// Publish the rows on the bus (ROBOT/camera/row), for a robot program with
    /// [camera] port = bus.
    #[arg(long)]
    pub bus: bool,
    /// With --bus: where the robot program listens.
    #[arg(long, value_name = "ENDPOINT", default_value = crate::programs::bus::tools::DEFAULT_ENDPOINT, requires = "bus")]
    pub connect: String,
    /// With --bus: the robot's name on the bus ([bus] robot).
    #[arg(
        long,
        value_name = "NAME",
        default_value = "mechweed",
        requires = "bus"
    )]
    pub robot: String,
    /// With --bus: this program's identity on a secured bus (--keys DIR --as camera).
    #[command(flatten)]
    pub identity: crate::programs::keys::IdentityArgs,
    /// Serial line speed.
    #[arg(long, default_value_t = 115200, value_parser = parse_baud)]
    pub baud: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[arg(long, value_enum, default_value = "straight")]
    pub pattern: Pattern,
    /// Share of frames not sent (0..1).
    #[arg(long, default_value_t = 0.0, value_parser = parse_share)]
    pub drop: f64,
    /// Probability that a byte is damaged (0..1).
    #[arg(long, default_value_t = 0.0, value_parser = parse_share)]
    pub corrupt: f64,
}

fn parse_baud(text: &str) -> Result<u32, String> {
    let baud: u32 = text
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if BAUD_RATES.contains(&baud) {
        Ok(baud)
    } else {
        Err(format!("the camera computer speaks at {BAUD_RATES:?} baud"))
    }
}

fn parse_share(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(p) if (0.0..=1.0).contains(&p) => Ok(p),
        _ => Err(format!("'{text}' is not a number from 0 to 1")),
    }
}

/// `mechweed camsim`: serve on the port or address given.
pub fn run(args: CamsimArgs) -> Result<(), String> {
    let options = CamSimOptions {
        pattern: args.pattern,
        seed: args.seed,
        drop: args.drop,
        corrupt: args.corrupt,
    };
    if args.bus {
        // The robot program may start after the camera: its session keeps trying.
        return bus::publish_rows(&args.connect, &args.robot, args.identity.files(), options);
    }
    match (args.port, args.listen) {
        (Some(device), _) => on_serial(&device, args.baud, options),
        (None, Some(address)) => on_tcp(&address, options),
        (None, None) => Err("say where to speak: --port DEVICE or --listen ADDR:PORT".to_string()),
    }
}
