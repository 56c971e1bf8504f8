//! One batched fit of 10 000 six-state problems (4 az/el measurements each: two sensors, two
//! scans), timed once: the target for instruction-count profiling, which does not depend on
//! machine load:
//!
//! ```text
//! cargo bench --bench fit_profile --no-run
//! valgrind --tool=callgrind target/release/deps/fit_profile-<hash> 1
//! ```
//!
//! Run directly with a repeat count (`... fit_profile-<hash> 20`) it prints µs per fit. A
//! second number is the scans of each sensor (`... fit_profile-<hash> 1 8`: 16 measurements
//! over the same 110 s, as `benches/bench_fit.py --scans 8`).
//!
//! For where the time goes (docs/performance.md, *Where the floor is*), the same binary under
//! `perf record` with `60 8` (sixty repeats: the data generation drops out of the profile).

use passive_assoc_core::data::{Measurements, Sensors};
use passive_assoc_core::estimation::fit::batch::{fit_batch, Problems};
use passive_assoc_core::estimation::fit::FitOptions;
use passive_assoc_core::geometry::model::{predict, Motion, Space, StateLayout};
use passive_assoc_core::parallel::with_threads;
fn main() {
    let layout = StateLayout::new(Space::Spatial, Motion::ConstantVelocity { t0: 0.0 });
    let pos = [[0.0, 0.0, 0.0], [20_000.0, 0.0, 0.0]];
    // `cargo bench` passes `--bench`; only numbers are the repeat count and the scans.
    let numbers: Vec<usize> = std::env::args()
        .skip(1)
        .filter_map(|v| v.parse().ok())
        .collect();
    let reps = numbers.first().copied().unwrap_or(1);
    let scans = numbers.get(1).copied().unwrap_or(2).max(2);
    let period = 105.0 / (scans - 1) as f64;
    let sched: Vec<(usize, f64)> = (0..scans)
        .flat_map(|k| (0..2).map(move |j| (j, k as f64 * period + 5.0 * j as f64)))
        .collect();
    let (mut s, mut t, mut a, mut e, mut idx, mut off, mut init) =
        (vec![], vec![], vec![], vec![], vec![], vec![0i64], vec![]);
    let mut seed = 1u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 10_000;
    for _ in 0..n {
        let truth = [
            rnd() * 30e3 - 5e3,
            rnd() * 28e3 + 2e3,
            rnd() * 2500.0 + 500.0,
            rnd() * 500.0 - 250.0,
            rnd() * 500.0 - 250.0,
            0.0,
        ];
        for &(j, tt) in &sched {
            let [aa, ee] = predict(Space::Spatial, &pos[j], &layout.position(&truth, tt));
            idx.push(s.len() as i64);
            s.push(j as i64);
            t.push(tt);
            a.push(aa + 5e-3 * (rnd() - 0.5) * 3.4);
            e.push(ee + 5e-3 * (rnd() - 0.5) * 3.4);
        }
        off.push(idx.len() as i64);
        init.extend(truth.iter().map(|v| v * 1.01 + 20.0));
    }
    let flat: Vec<f64> = pos.iter().flatten().copied().collect();
    let sig = vec![5e-3; 2];
    let sensors = Sensors::new(Space::Spatial, &flat, &sig, &sig).unwrap();
    let table = Measurements::new(&sensors, &s, &t, &a, &e).unwrap();
    let problems = Problems {
        indices: &idx,
        offsets: &off,
        initial: Some(&init),
    };
    let start = std::time::Instant::now();
    let mut iters = 0u64;
    for _ in 0..reps {
        let out = with_threads(Some(1), || {
            fit_batch(&table, &sensors, &layout, &problems, &FitOptions::default())
        })
        .unwrap()
        .unwrap();
        iters += out.iterations.iter().map(|&i| i as u64).sum::<u64>();
    }
    let el = start.elapsed().as_secs_f64();
    println!(
        "{} measurements: {:.3} us/fit, {:.2} iterations/fit",
        sched.len(),
        el / (reps * n) as f64 * 1e6,
        iters as f64 / (reps * n) as f64
    );
}
