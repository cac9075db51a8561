//! The graph file's rules, the plans made from it and its picture.

use super::dot::dot;
use super::graph::{Graph, MasterLost, Start};
use super::plan::for_machine;

const FIELD: &str = include_str!("../../config/cluster.ini");
const LOCAL: &str = include_str!("../../config/cluster-local.ini");

fn errors(text: &str) -> Vec<String> {
    match Graph::parse("g.ini", text) {
        Ok(_) => Vec::new(),
        Err(errors) => errors.iter().map(ToString::to_string).collect(),
    }
}

const HEAD: &str = "[cluster]\nrobot = r\nmaster = tcp/127.0.0.1:7450\nmaster_lost = run_on\n\
                    [machine a]\nendpoint = tcp/127.0.0.1:7451\n";

#[test]
fn the_shipped_graphs_are_read_whole() {
    let field = Graph::parse("config/cluster.ini", FIELD).unwrap();
    assert_eq!(field.machines.len(), 3);
    assert_eq!(field.processes.len(), 4);
    assert_eq!(field.flows.len(), 5);
    assert_eq!(field.master_lost, MasterLost::RunOn);
    assert_eq!(field.controller().unwrap().name, "controller");
    assert_eq!(field.controller_endpoint(), Some("tls/192.168.1.10:7510"));
    assert!(field.tls.is_some(), "the field's cluster is secured");
    let local = Graph::parse("config/cluster-local.ini", LOCAL).unwrap();
    let names = |g: &Graph| {
        g.processes
            .iter()
            .map(|p| p.name.clone())
            .collect::<Vec<_>>()
    };
    // The same programs and flows on one computer.
    assert_eq!(names(&field), names(&local));
    assert_eq!(local.process("operator-view").unwrap().start, Start::Manual);
    for machine in &local.machines {
        assert!(
            machine.endpoint.starts_with("tcp/127.0.0.1:"),
            "{machine:?}"
        );
    }
}

#[test]
fn no_shipped_graph_listens_on_a_zenoh_routers_port() {
    // 7447 is the TCP port of zenohd and of rmw_zenohd (ROS 2's router), 7446 Zenoh's
    // UDP scouting port: a controller or master there does not start beside them.
    for (file, text) in [
        ("config/cluster.ini", FIELD),
        ("config/cluster-local.ini", LOCAL),
    ] {
        let graph = Graph::parse(file, text).unwrap();
        let mut endpoints = vec![graph.master.clone()];
        for m in &graph.machines {
            endpoints.extend([m.endpoint.clone(), m.listen.clone()]);
        }
        for endpoint in endpoints {
            let port: u16 = endpoint.rsplit_once(':').unwrap().1.parse().unwrap();
            assert!(![7447, 7446].contains(&port), "{file}: {endpoint}");
        }
    }
}

#[test]
fn a_broken_graph_names_every_error_by_line_and_key() {
    let text = format!(
        "{HEAD}[process cam]\nmachine = b\nprogram = camsim\n\
         [process lost]\nprogram = run\n\
         [process cam]\nmachine = a\n\
         [flow rows]\nfrom = cam.rows\nto = robot.rows\n"
    );
    let found = errors(&text);
    let expect = [
        // An unknown machine.
        "g.ini line 8: [process cam] machine: 'b' is not a machine of this graph (its machines: a)",
        // A process on no machine.
        "g.ini line 10: [process lost] machine is missing",
        // A repeated name.
        "g.ini line 12: [process cam] appears again (first at line 7): put its keys in one section",
        // A flow to a process that does not exist.
        "g.ini line 16: [flow rows] to: 'robot' is not a process of this graph (its processes: cam, lost)",
    ];
    for e in expect {
        assert!(found.iter().any(|f| f == e), "missing {e:?} in {found:#?}");
    }
}

#[test]
fn flows_must_join_ports_that_exist_and_carry_the_same_kind() {
    let base = format!(
        "{HEAD}[process c]\nmachine = a\nprogram = run\n[process cam]\nmachine = a\nprogram = camsim\n\
         [process rec]\nmachine = a\nprogram = record\n"
    );
    let flow =
        |from: &str, to: &str| errors(&format!("{base}[flow f]\nfrom = {from}\nto = {to}\n"));
    assert!(flow("cam.rows", "c.rows").is_empty());
    let wrong_way = flow("c.rows", "cam.rows");
    assert!(
        wrong_way[0]
            .contains("run sends out status, tick, event, not rows (rows goes the other way)"),
        "{wrong_way:?}"
    );
    let kinds = flow("c.status", "rec.tick");
    assert!(kinds[0].contains("status cannot feed tick"), "{kinds:?}");
    let not_through = flow("cam.rows", "rec.status");
    assert!(!not_through.is_empty());
    let twice = flow("c.status", "rec.status, rec.status");
    assert!(twice[0].contains("rec.status is named twice"), "{twice:?}");
}

#[test]
fn one_robot_per_graph_and_no_process_waits_for_itself() {
    let two = errors(&format!(
        "{HEAD}[process c]\nmachine = a\nprogram = run\n[process d]\nmachine = a\nprogram = run\n"
    ));
    assert!(
        two[0].contains("[process d] program: a second robot program"),
        "{two:?}"
    );
    let cycle = errors(&format!(
        "{HEAD}[process c]\nmachine = a\nprogram = run\nafter = d\n\
         [process d]\nmachine = a\nprogram = camsim\nafter = c\n"
    ));
    assert!(
        cycle.iter().any(|e| e.contains("waits for itself")),
        "{cycle:?}"
    );
    let settings = errors(&format!(
        "{HEAD}[process cam]\nmachine = a\nprogram = camsim\nset.steer.speed_mps = 1\n"
    ));
    assert!(settings[0].contains("only the mechweed programs run, record and ros2 take settings"));
    let unknown = errors(&format!("{HEAD}[proces x]\nmachine = a\n"));
    assert!(
        unknown
            .iter()
            .any(|e| e.contains("unknown section [proces x]")),
        "{unknown:?}"
    );
}

#[test]
fn the_plan_wires_every_program_to_the_controller() {
    let graph = Graph::parse("config/cluster-local.ini", LOCAL).unwrap();
    let robot = for_machine(&graph, "robot-pc").unwrap();
    let controller = &robot.processes[0];
    let line = controller.command_line();
    assert!(controller.controller && controller.auto);
    for part in [
        "mechweed run --headless",
        "--set bus.listen=tcp/127.0.0.1:7451",
        "--set bus.robot=mechweed",
        "--set bus.required=yes",
        // A rows flow comes in: the camera link takes the bus's rows.
        "--set camera.port=bus",
        "--set sim.events=4 power_up, 5 mode autonomous",
    ] {
        assert!(line.contains(part), "{part:?} not in {line}");
    }
    assert_eq!(controller.after, ["camera"]);
    let camera = &for_machine(&graph, "camera-pc").unwrap().processes[0];
    assert_eq!(
        camera.command_line(),
        "mechweed camsim --bus --connect tcp/127.0.0.1:7451 --robot mechweed"
    );
    assert!(camera.restart);
    let laptop = for_machine(&graph, "laptop").unwrap();
    assert!(
        !laptop.processes[0].auto,
        "the operator view is started by hand"
    );
    assert!(
        laptop.processes[1]
            .command_line()
            .starts_with("mechweed record --bus --connect tcp/127.0.0.1:7451")
    );
    assert!(for_machine(&graph, "tractor").is_none());
}

#[test]
fn the_picture_has_every_machine_process_and_flow() {
    let graph = Graph::parse("config/cluster.ini", FIELD).unwrap();
    let picture = dot(&graph);
    assert!(picture.starts_with("digraph \"mechweed\" {"));
    for machine in &graph.machines {
        assert!(picture.contains(&format!("label=\"{}  {}\"", machine.name, machine.endpoint)));
    }
    assert!(picture.contains("\"camera\" -> \"controller\" [label=\"rows\"]"));
    assert!(picture.contains("\"controller\" -> \"recorder\" [label=\"status, tick, event\"]"));
    assert!(picture.contains("\"operator-view\" -> \"controller\" [label=\"requests\"]"));
    // Labels keep their line breaks as DOT's \n, never a raw line end inside quotes.
    assert!(
        picture.lines().all(|l| l.matches('"').count() % 2 == 0),
        "{picture}"
    );
}

#[test]
fn a_graph_that_opens_plain_tcp_beyond_loopback_is_refused() {
    let open = "[cluster]\nrobot = r\nmaster = tcp/0.0.0.0:7450\nmaster_lost = run_on\n\
                [machine a]\nendpoint = tcp/192.168.1.10:7451\n";
    let found = errors(open);
    for key in [
        "[cluster] master = tcp/0.0.0.0:7450",
        "[machine a] endpoint = tcp/192.168.1.10:7451",
    ] {
        assert!(
            found
                .iter()
                .any(|f| f.contains(key) && f.contains("without TLS")),
            "{key} in {found:#?}"
        );
    }
    // Said to be trusted: taken, at the user's word.
    let trusted = open.replace(
        "master_lost = run_on",
        "master_lost = run_on\ntrusted_network = yes",
    );
    assert!(errors(&trusted).is_empty(), "{:?}", errors(&trusted));
    // Secured, every endpoint is tls/.
    let secured = trusted
        .replace(
            "trusted_network = yes",
            "tls_ca = k/ca.pem\ntls_cert = k/master.pem\ntls_key = k/master.key",
        )
        .replace("tcp/", "tls/");
    assert!(errors(&secured).is_empty(), "{:?}", errors(&secured));
}

#[test]
fn arguments_split_at_spaces_and_quotes_keep_them() {
    let graph = |args: &str| {
        Graph::parse(
            "g.ini",
            &format!("{HEAD}[process x]\nmachine = a\nprogram = sh\nargs = {args}\n"),
        )
    };
    let args = |text: &str| graph(text).unwrap().processes[0].args.clone();
    assert_eq!(args("-c  \"echo $A  b\" \"\""), ["-c", "echo $A  b", ""]);
    assert_eq!(
        args("--headless --mode autonomous"),
        ["--headless", "--mode", "autonomous"]
    );
    let open = graph("-c \"echo").unwrap_err()[0].to_string();
    assert_eq!(open, "g.ini line 10: [process x] args: a \" is not closed");
}

#[test]
fn a_ros2_bridge_takes_the_robots_flows_and_its_settings() {
    let graph = format!(
        "{HEAD}[process c]\nmachine = a\nprogram = run\n[process ros]\nmachine = a\nprogram = ros2\n\
         set.ros2.connect = tcp/127.0.0.1:7448\n[flow s]\nfrom = c.status\nto = ros.status\n"
    );
    assert!(errors(&graph).is_empty(), "{:?}", errors(&graph));
    let wrong_way = errors(&format!("{graph}[flow r]\nfrom = ros.rows\nto = c.rows\n"));
    assert!(
        wrong_way[0].contains("ros2 sends out nothing, not rows"),
        "{wrong_way:?}"
    );
    let graph = Graph::parse("g.ini", &graph).unwrap();
    let plan = for_machine(&graph, "a").unwrap();
    assert_eq!(
        plan.processes[1].command_line(),
        "mechweed ros2 --robot-connect tcp/127.0.0.1:7451 --robot r --set ros2.connect=tcp/127.0.0.1:7448"
    );
}
