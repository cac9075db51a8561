//! One supervisor step on the simulated robot while it really drives along the row
//! (read every input, tick, write every output), and a whole lockstep step of 10 ms
//! (plant, camera link, steer tick and supervisor step). Only the step is timed; a new
//! run is started, untimed, whenever the row ends or the robot stops, so that no figure
//! comes from a robot standing in a fault.
//!
//! cargo bench --bench supervisor_tick

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use mechweed::config::Settings;
use mechweed::state::modes::Mode;
use mechweed::threads::lockstep::Lockstep;

/// A robot driving autonomously, 3 s into its row.
fn driving() -> Lockstep {
    let mut sim = Lockstep::new(&Settings::shipped(), Mode::Autonomous);
    sim.run_for(3.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    sim
}

/// Keep `sim` driving: a fresh run when the row is done or the robot stopped.
fn keep_driving(sim: &mut Lockstep) {
    if sim.robot.truth().row_done || sim.supervisor.mode() != Mode::Autonomous {
        *sim = driving();
    }
}

fn supervisor_tick(c: &mut Criterion) {
    let mut group = c.benchmark_group("simulated robot driving");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(3));
    let mut sim = driving();
    group.bench_function("supervisor step (read, tick, write)", |b| {
        b.iter_custom(|iterations| {
            let mut timed = Duration::ZERO;
            for _ in 0..iterations {
                keep_driving(&mut sim);
                sim.advance();
                let start = Instant::now();
                black_box(sim.supervisor_step());
                timed += start.elapsed();
            }
            timed
        })
    });
    group.bench_function(
        "lockstep step of 10 ms (plant, link, steer, supervisor)",
        |b| {
            b.iter_custom(|iterations| {
                let mut timed = Duration::ZERO;
                for _ in 0..iterations {
                    keep_driving(&mut sim);
                    let start = Instant::now();
                    black_box(sim.tick());
                    timed += start.elapsed();
                }
                timed
            })
        },
    );
    group.finish();
}

criterion_group!(benches, supervisor_tick);
criterion_main!(benches);
