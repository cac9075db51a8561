//! `mechweed bench ros2`: what the ROS 2 bridge costs and how late its messages are,
//! on this computer. It starts a Zenoh router here (as rmw_zenohd is on a ROS
//! machine), the robot program on the simulated robot driving autonomous, and `mechweed
//! ros2` between them, all on loopback; a ROS-side client then takes
//! /mechweed/joint_states for the time asked. Its figures:
//!
//! - latency: from the robot's tick (its stamp, the supervisor's time on the robot's
//!   wall clock) to the sample's arrival at the ROS client, through the robot's bus
//!   thread, the bridge and the router; median, 99th percentile (nearest rank, as
//!   `bench loop` takes them) and worst;
//! - the bridge's CPU: its user and system time over the same time, as a share of one
//!   core (from /proc), beside the robot program's.

use std::process::{Child, Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

use zenoh::Wait;

use crate::ros2::cdr::decode;
use crate::ros2::msgs::JointState;
use crate::ros2::topics::Topic;
use crate::ros2::wire::Node;

#[derive(clap::Args)]
pub struct Ros2BenchArgs {
    /// How long to measure, after 5 s for the robot to drive and the bridge to join.
    #[arg(long, value_name = "SECONDS", default_value_t = 30.0)]
    pub seconds: f64,
    /// The robot publishes every Nth tick ([bus] tick_every_n; shipped 10: 10 a second).
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub tick_every_n: u64,
}

/// A child process, ended when dropped.
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> Result<u16, String> {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    Ok(listener.local_addr().map_err(|e| e.to_string())?.port())
}

/// User and system time of process `pid` so far, s.
fn cpu_s(pid: u32) -> Result<f64, String> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat"))
        .map_err(|e| format!("cannot read the CPU time of process {pid}: {e}"))?;
    // After the command's name in brackets: state, then 10 more fields, then utime
    // and stime, in clock ticks.
    let after = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |i: usize| {
        fields
            .get(i)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    // SAFETY: sysconf reads a constant of the system and touches no memory of ours.
    let per_s = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    Ok((ticks(11) + ticks(12)) / per_s)
}

fn zenoh_config(
    mode: &str,
    listen: &[String],
    connect: &[String],
) -> Result<zenoh::Config, String> {
    let mut config = zenoh::Config::default();
    let json = |items: &[String]| serde_json::to_string(items).unwrap_or_default();
    for (key, value) in [
        ("mode", format!("\"{mode}\"")),
        ("listen/endpoints", json(listen)),
        ("connect/endpoints", json(connect)),
        ("scouting/multicast/enabled", "false".to_string()),
    ] {
        config
            .insert_json5(key, &value)
            .map_err(|e| e.to_string())?;
    }
    Ok(config)
}

fn measure(args: &Ros2BenchArgs) -> Result<String, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    let folder = std::env::temp_dir().join(format!("mechweed-bench-ros2-{}", std::process::id()));
    let (router_at, robot_at) = (
        format!("tcp/127.0.0.1:{}", free_port()?),
        format!("tcp/127.0.0.1:{}", free_port()?),
    );
    let router = zenoh::open(zenoh_config(
        "router",
        std::slice::from_ref(&router_at),
        &[],
    )?)
    .wait()
    .map_err(|e| format!("cannot start the router: {e}"))?;
    let total_s = args.seconds + 5.0;
    let quiet = |cmd: &mut Command| -> Result<Running, String> {
        cmd.stdout(Stdio::null()).stderr(Stdio::null());
        cmd.spawn().map(Running).map_err(|e| e.to_string())
    };
    let robot = quiet(
        Command::new(&exe)
            .args(["run", "--headless", "--mode", "autonomous"])
            .args(["--duration", &(total_s + 5.0).to_string()])
            .args(["--set", &format!("bus.listen={robot_at}")])
            .args(["--set", "bus.enabled=yes"])
            .args(["--set", &format!("bus.tick_every_n={}", args.tick_every_n)])
            .args(["--set", &format!("record.folder={}", folder.display())]),
    )?;
    // The shipped domain and namespace, whatever robot.ini here says: the client below
    // listens there. What the bridge says goes to a file, for when it does not run.
    let shipped = crate::config::Ros2Settings::shipped();
    let said_path = folder.join("bridge.txt");
    std::fs::create_dir_all(&folder).map_err(|e| e.to_string())?;
    let said = std::fs::File::create(&said_path).map_err(|e| e.to_string())?;
    let bridge = Command::new(&exe)
        .args([
            "ros2",
            "--connect",
            &router_at,
            "--robot-connect",
            &robot_at,
        ])
        .args(["--domain-id", &shipped.domain_id.to_string()])
        .args(["--namespace", &shipped.namespace])
        .args(["--seconds", &total_s.to_string()])
        .stdout(Stdio::null())
        .stderr(said)
        .spawn()
        .map(Running)
        .map_err(|e| e.to_string())?;
    let client = zenoh::open(zenoh_config(
        "client",
        &[],
        std::slice::from_ref(&router_at),
    )?)
    .wait()
    .map_err(|e| format!("cannot reach the router: {e}"))?;
    let node = Node {
        domain_id: shipped.domain_id,
        zid: String::new(),
        namespace: shipped.namespace,
        distro: shipped.distro,
    };
    let (tx, rx) = crossbeam_channel::unbounded();
    let _subscriber = client
        .declare_subscriber(node.data_key(Topic::JointStates))
        .callback(move |sample| {
            let arrived_s = crate::bus::payload::wall_s();
            let _ = tx.send((arrived_s, sample.payload().to_bytes().into_owned()));
        })
        .wait()
        .map_err(|e| e.to_string())?;
    println!(
        "bench ros2: robot, bridge and router on loopback; 5 s to start, then {} s measured",
        args.seconds
    );
    std::thread::sleep(Duration::from_secs(5));
    while rx.try_recv().is_ok() {}
    let start = Instant::now();
    let (bridge_cpu0, robot_cpu0) = (cpu_s(bridge.0.id())?, cpu_s(robot.0.id())?);
    let mut latency_ms = Vec::new();
    while start.elapsed().as_secs_f64() < args.seconds {
        if let Ok((arrived_s, bytes)) = rx.recv_timeout(Duration::from_millis(200)) {
            let joints: JointState = decode(&bytes)?;
            let stamp_s = joints.header.stamp.unix_ns() as f64 / 1e9;
            latency_ms.push((arrived_s - stamp_s) * 1e3);
        }
    }
    let wall_s = start.elapsed().as_secs_f64();
    let bridge_cpu = (cpu_s(bridge.0.id())? - bridge_cpu0) / wall_s;
    let robot_cpu = (cpu_s(robot.0.id())? - robot_cpu0) / wall_s;
    drop((bridge, robot, client, router));
    let bridge_said = std::fs::read_to_string(&said_path).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&folder);
    if latency_ms.is_empty() {
        return Err(format!(
            "no /mechweed/joint_states arrived; the bridge said: {}",
            bridge_said.trim()
        ));
    }
    latency_ms.sort_by(f64::total_cmp);
    Ok(format!(
        "bench ros2: {} samples of /mechweed/joint_states in {wall_s:.1} s; latency from the robot's tick to the ROS client: median {:.2} ms, p99 {:.2} ms, worst {:.2} ms; CPU of one core: bridge {:.1} %, robot program {:.1} %",
        latency_ms.len(),
        super::nearest_rank(&latency_ms, 0.5),
        super::nearest_rank(&latency_ms, 0.99),
        latency_ms.last().copied().unwrap_or(f64::NAN),
        100.0 * bridge_cpu,
        100.0 * robot_cpu,
    ))
}

pub fn program(args: Ros2BenchArgs) -> ExitCode {
    crate::programs::said(measure(&args))
}
