//! One supervisor tick on the simulated robot, driving autonomously along the row:
//! the controller alone, and a whole lockstep step (plant, link, steer, supervisor).
//!
//! cargo bench --bench supervisor_tick

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

use mechweed::config::Settings;
use mechweed::lockstep::Lockstep;
use mechweed::modes::Mode;

fn driving() -> Lockstep {
    let mut sim = Lockstep::new(&Settings::shipped(), Mode::Autonomous);
    sim.run_for(5.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    sim
}

fn supervisor_tick(c: &mut Criterion) {
    let mut sim = driving();
    let inputs = sim.robot.inputs();
    let steer = sim.steer_command;
    let link = *sim.link.status();
    let mut now_s = sim.now_s();
    c.bench_function("supervisor tick (controller only)", |b| {
        b.iter(|| {
            now_s += 0.01;
            black_box(sim.supervisor.tick(
                now_s,
                black_box(&inputs),
                &steer,
                &link,
                &Default::default(),
            ))
        })
    });
    let mut sim = driving();
    c.bench_function(
        "lockstep step of 10 ms (plant + link + steer + supervisor)",
        |b| b.iter(|| black_box(sim.tick())),
    );
}

criterion_group!(benches, supervisor_tick);
criterion_main!(benches);
