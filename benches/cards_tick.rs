//! The I/O cards' share of a supervisor tick, on emulated cards: port accesses per
//! tick while driving (counted by a CountingPort around each card), the time of the
//! cards' read and write, and of a whole supervisor tick with them.
//!
//! cargo bench --bench cards_tick
//!
//! The emulated A/D is busy for 3 status reads after each start; a real one takes
//! about 10 us, so on the real bus expect more status reads per conversion.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

use mechweed::config::Settings;
use mechweed::state::modes::Mode;
use mechweed::threads::lockstep::{Io, Lockstep};
use mechweed_hw::Hw;
use mechweed_hw::cards::port::AccessCount;
use mechweed_hw::emulated::CardRig;

/// Driving autonomously through emulated cards whose accesses are counted.
fn driving(count: &AccessCount) -> Lockstep {
    let s = Settings::shipped();
    let rig = CardRig::counting(&s.cards, &s.io, count).expect("emulated cards open");
    let mut sim = Lockstep::with_io(&s, Mode::Autonomous, Io::Cards(Box::new(rig)));
    sim.run_for(5.0);
    assert_eq!(sim.supervisor.mode(), Mode::Autonomous);
    sim
}

fn accesses_per_tick() {
    let count = AccessCount::default();
    let mut sim = driving(&count);
    let ticks = 1000;
    let (reads, writes) = (count.reads(), count.writes());
    for _ in 0..ticks {
        sim.tick();
    }
    println!(
        "port accesses per supervisor tick, driving: {:.1} reads + {:.1} writes = {:.1}",
        (count.reads() - reads) as f64 / ticks as f64,
        (count.writes() - writes) as f64 / ticks as f64,
        (count.total() - reads - writes) as f64 / ticks as f64,
    );
}

fn cards_tick(c: &mut Criterion) {
    accesses_per_tick();
    let s = Settings::shipped();
    let count = AccessCount::default();
    let sim = driving(&count);
    let mut rig = CardRig::new(&s.cards, &s.io).expect("emulated cards open");
    rig.set_wires(&sim.robot.inputs());
    let outputs = sim.robot.outputs();
    c.bench_function("cards read + write of one tick (emulated cards)", |b| {
        b.iter(|| {
            let read = rig.hw.read().expect("emulated cards answer");
            rig.hw
                .write(black_box(&outputs))
                .expect("emulated cards answer");
            black_box(read)
        })
    });
    // As benches/supervisor_tick.rs: only the supervisor step is timed, while the robot
    // really drives; a new run starts, untimed, when the row ends or the robot stops.
    let mut sim = driving(&count);
    c.bench_function(
        "supervisor step through the emulated cards (read, tick, write)",
        |b| {
            b.iter_custom(|iterations| {
                let mut timed = std::time::Duration::ZERO;
                for _ in 0..iterations {
                    if sim.robot.truth().row_done || sim.supervisor.mode() != Mode::Autonomous {
                        sim = driving(&count);
                    }
                    sim.advance();
                    let start = std::time::Instant::now();
                    black_box(sim.supervisor_step());
                    timed += start.elapsed();
                }
                timed
            })
        },
    );
}

criterion_group!(benches, cards_tick);
criterion_main!(benches);
