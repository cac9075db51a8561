//! Decoding throughput of the camera link: clean frames, and frames in garbage.
//!
//! cargo bench --bench decoder

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use mechweed_hw::camproto::{Decoder, RowEstimate, encode_row};
use std::hint::black_box;

fn stream(garbage_every: usize) -> Vec<u8> {
    let mut bytes = Vec::new();
    for k in 0..10_000u32 {
        let est = RowEstimate {
            seq: k as u8,
            angle_rad: 0.01,
            offset_m: -0.02,
            quality: 90,
        };
        bytes.extend_from_slice(&encode_row(&est));
        if garbage_every > 0 && (k as usize).is_multiple_of(garbage_every) {
            // A false sync and some noise, as on a noisy line.
            bytes.extend_from_slice(&[0xA5, 0x13, 0x77, 0x00, 0xA5, 0xFF]);
        }
    }
    bytes
}

fn decode(c: &mut Criterion) {
    let mut group = c.benchmark_group("camera link decoder");
    for (name, garbage_every) in [("clean frames", 0), ("garbage after every 3rd frame", 3)] {
        let bytes = stream(garbage_every);
        group.throughput(Throughput::Bytes(bytes.len() as u64));
        group.bench_function(name, |b| {
            b.iter(|| {
                let mut dec = Decoder::new();
                let mut frames = 0u32;
                for &byte in black_box(&bytes) {
                    frames += dec.push(byte).is_some() as u32;
                }
                frames
            })
        });
    }
    group.finish();
}

criterion_group!(benches, decode);
criterion_main!(benches);
