//! `mechweed gnsssim`: a stand-alone simulated RTK GNSS receiver, for bench-testing a
//! robot computer's GNSS link (and the row map) without a receiver. Ten times a second it
//! writes GGA, RMC, VTG and GST for an antenna standing at `--origin`, or driving east
//! from it at `--speed`, with the simulated receiver's errors (hw/src/sim/gnss_model.rs);
//! `--state` chooses the solution. It only writes: a receiver needs no commands.

use std::io::{self, Write};
use std::net::TcpListener;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use mechweed_hw::geo::{Geodetic, LocalFrame};
use mechweed_hw::nmea::encode::NmeaEncoder;
use mechweed_hw::sim::gnss::epoch_of;
use mechweed_hw::sim::gnss_model::{GnssState, ReceiverModel};

/// The receiver's solution, as `--state` names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum StateArg {
    Fixed,
    Float,
    Dgps,
    Lost,
}

#[derive(Debug, Clone, Copy)]
pub struct GnssSimOptions {
    pub seed: u64,
    pub state: StateArg,
    pub origin: Geodetic,
    /// Driving east from the origin, m/s (0: standing).
    pub speed_mps: f64,
    pub rate_hz: f64,
}

/// The simulated day starts at 10:00 UTC.
const START_UTC_S: f64 = 36_000.0;

pub struct GnssSim {
    opts: GnssSimOptions,
    model: ReceiverModel,
    frame: LocalFrame,
    encoder: NmeaEncoder,
    next_epoch_s: f64,
    /// Epochs written, and those with a position.
    pub epochs: u64,
    pub fixes: u64,
}

impl GnssSim {
    pub fn new(opts: GnssSimOptions) -> GnssSim {
        let mut model = ReceiverModel::new(opts.seed);
        model.set_state(
            match opts.state {
                StateArg::Fixed => GnssState::Fixed,
                StateArg::Float => GnssState::Float,
                StateArg::Dgps => GnssState::Dgps,
                StateArg::Lost => GnssState::Lost,
            },
            0.0,
        );
        GnssSim {
            model,
            frame: LocalFrame::new(opts.origin),
            encoder: NmeaEncoder::default(),
            next_epoch_s: 0.0,
            epochs: 0,
            fixes: 0,
            opts,
        }
    }

    /// The lines of every epoch due by `now_s`, appended to `out`.
    pub fn poll(&mut self, now_s: f64, out: &mut Vec<u8>) {
        while self.next_epoch_s <= now_s {
            let t_s = self.next_epoch_s;
            self.next_epoch_s += 1.0 / self.opts.rate_hz;
            self.epochs += 1;
            let east_m = self.opts.speed_mps * t_s;
            let measured = self.model.measure(t_s, east_m, east_m, 0.0);
            if measured.is_some() {
                self.fixes += 1;
            }
            // Driving east: course 90 degrees.
            let motion = (self.opts.speed_mps, 90.0);
            let epoch = epoch_of(START_UTC_S + t_s, measured.as_ref(), &self.frame, motion);
            // An epoch the encoder cannot write is left out, as a receiver sends nothing then.
            if let Ok(lines) = self.encoder.epoch(&epoch) {
                for line in &lines {
                    out.extend_from_slice(line.as_bytes());
                }
            }
        }
    }
}

/// Write epochs into `stream` until it fails or `stop` is set; a line a second says
/// what went out.
pub fn serve(
    sim: &mut GnssSim,
    stream: &mut dyn Write,
    clock: Instant,
    stop: &AtomicBool,
) -> io::Result<()> {
    let mut out = Vec::with_capacity(1024);
    let mut next_line_s = 1.0;
    while !stop.load(Ordering::Relaxed) {
        let now_s = clock.elapsed().as_secs_f64();
        out.clear();
        sim.poll(now_s, &mut out);
        stream.write_all(&out)?;
        stream.flush()?;
        if now_s >= next_line_s {
            next_line_s += 1.0;
            println!(
                "{now_s:8.3} s  sent {} epochs, {} with a position",
                sim.epochs, sim.fixes
            );
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    Ok(())
}

/// Serve on a serial device, or on a new pseudo-terminal for DEVICE = "pty".
pub(crate) fn on_serial(device: &str, baud: u32, opts: GnssSimOptions) -> Result<(), String> {
    let mut port = crate::programs::camsim::serial_or_pty(
        device,
        baud,
        "simulated GNSS receiver",
        "gnss.port",
    )?;
    let stop = AtomicBool::new(false);
    serve(&mut GnssSim::new(opts), &mut port, Instant::now(), &stop)
        .map_err(|e| format!("{device}: {e}"))
}

/// Serve robot computers on a TCP port, one at a time. "PORT" alone means 127.0.0.1:PORT.
pub(crate) fn on_tcp(address: &str, opts: GnssSimOptions) -> Result<(), String> {
    let address = crate::programs::camsim::tcp_address(address);
    let listener =
        TcpListener::bind(&address).map_err(|e| format!("cannot listen on {address}: {e}"))?;
    println!(
        "simulated GNSS receiver listening on {address}: try  mechweed run --headless --set gnss.port=tcp://{address}"
    );
    loop {
        let (mut stream, peer) = listener.accept().map_err(|e| e.to_string())?;
        println!("robot computer {peer} connected");
        let stop = AtomicBool::new(false);
        // Each connection starts a new receiver: a robot computer that comes back gets
        // a fresh stream, as from a receiver switched on again.
        match serve(&mut GnssSim::new(opts), &mut stream, Instant::now(), &stop) {
            Ok(()) => println!("robot computer {peer} left"),
            Err(e) => println!("robot computer {peer} left: {e}"),
        }
    }
}

/// The command line of `mechweed gnsssim`.
#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("where").required(true).args(["port", "listen"])))]
pub struct GnssSimArgs {
    /// Serial device to write on, or "pty" to make a pseudo-terminal and print its path.
    #[arg(long, value_name = "DEVICE")]
    pub port: Option<String>,
    /// TCP address to listen on, one robot computer at a time: ADDR:PORT, or PORT alone
    /// for 127.0.0.1:PORT.
    #[arg(long, value_name = "ADDR:PORT")]
    pub listen: Option<String>,
    /// Serial line speed.
    #[arg(long, default_value_t = 115200, value_parser = parse_baud)]
    pub baud: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The solution: RTK fixed, RTK float, DGPS, or no position at all.
    #[arg(long, value_enum, default_value = "fixed")]
    pub state: StateArg,
    /// Where the antenna starts: LAT,LON in degrees.
    #[arg(long, value_name = "LAT,LON", default_value = "52.0,5.66", value_parser = parse_origin)]
    pub origin: Geodetic,
    /// Drive east from there at this speed, m/s (0: stand).
    #[arg(long, default_value_t = 0.0, value_parser = parse_speed)]
    pub speed: f64,
    /// Epochs a second.
    #[arg(long, default_value_t = 10.0, value_parser = parse_rate)]
    pub rate: f64,
}

fn parse_baud(text: &str) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(baud) if crate::config::BAUD_RATES.contains(&baud) => Ok(baud),
        _ => Err(format!(
            "'{text}' is not one of {:?} baud",
            crate::config::BAUD_RATES
        )),
    }
}

fn parse_origin(text: &str) -> Result<Geodetic, String> {
    let bad = || format!("'{text}' is not LAT,LON in degrees (for example 52.0,5.66)");
    let (lat, lon) = text.split_once(',').ok_or_else(bad)?;
    let (lat_deg, lon_deg): (f64, f64) = (
        lat.trim().parse().map_err(|_| bad())?,
        lon.trim().parse().map_err(|_| bad())?,
    );
    if !(-85.0..=85.0).contains(&lat_deg) || !(-180.0..=180.0).contains(&lon_deg) {
        return Err(format!(
            "{text}: latitude must be -85..85 and longitude -180..180 degrees"
        ));
    }
    Ok(Geodetic {
        lat_deg,
        lon_deg,
        height_m: 0.0,
    })
}

fn parse_speed(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.0..=10.0).contains(&v) => Ok(v),
        _ => Err(format!("'{text}' is not a speed of 0 to 10 m/s")),
    }
}

fn parse_rate(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(v) if (0.1..=100.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "'{text}' is not a rate of 0.1 to 100 epochs a second"
        )),
    }
}

/// `mechweed gnsssim`.
pub fn run(args: GnssSimArgs) -> Result<(), String> {
    let opts = GnssSimOptions {
        seed: args.seed,
        state: args.state,
        origin: args.origin,
        speed_mps: args.speed,
        rate_hz: args.rate,
    };
    match (args.port, args.listen) {
        (Some(device), _) => on_serial(&device, args.baud, opts),
        (None, Some(address)) => on_tcp(&address, opts),
        (None, None) => Err("say where: --port DEVICE or --listen ADDR:PORT".to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mechweed_hw::nmea::{Epoch, FixAssembler, FixQuality, NmeaDecoder};

    fn options(state: StateArg, speed_mps: f64) -> GnssSimOptions {
        GnssSimOptions {
            seed: 1,
            state,
            origin: Geodetic {
                lat_deg: 52.0,
                lon_deg: 5.66,
                height_m: 0.0,
            },
            speed_mps,
            rate_hz: 10.0,
        }
    }

    fn epochs(sim: &mut GnssSim, seconds: f64) -> Vec<Epoch> {
        let mut bytes = Vec::new();
        sim.poll(seconds, &mut bytes);
        let (mut decoder, mut assembler, mut out) =
            (NmeaDecoder::new(), FixAssembler::new(), Vec::new());
        decoder.push(&bytes, |s| assembler.push(s, |e| out.push(e)));
        assert_eq!(
            decoder.counters().checksum_errors + decoder.counters().malformed,
            0
        );
        out
    }

    #[test]
    fn ten_rtk_fixes_a_second_along_its_way_east() {
        let mut sim = GnssSim::new(options(StateArg::Fixed, 1.0));
        let got = epochs(&mut sim, 10.0);
        assert!((99..=101).contains(&got.len()), "{} epochs", got.len());
        let frame = LocalFrame::new(options(StateArg::Fixed, 1.0).origin);
        let Some(Epoch::Fix(last)) = got.last() else {
            panic!("{:?}", got.last())
        };
        assert_eq!(last.quality, FixQuality::RtkFixed);
        let e = frame.to_enu(Geodetic {
            lat_deg: last.lat_deg,
            lon_deg: last.lon_deg,
            height_m: 0.0,
        });
        // 9.9 or 10 s east at 1 m/s, within RTK's centimetres.
        assert!(
            (9.8..10.1).contains(&e.east_m) && e.north_m.abs() < 0.05,
            "{e:?}"
        );
    }

    #[test]
    fn a_lost_receiver_sends_epochs_without_a_position() {
        let mut sim = GnssSim::new(options(StateArg::Lost, 0.0));
        let got = epochs(&mut sim, 2.0);
        assert!(got.len() >= 19);
        assert!(
            got.iter().all(|e| matches!(e, Epoch::NoFix { .. })),
            "{got:?}"
        );
    }
}
