//! The Lagrangian S-D solver alone, on problems dumped by
//! `python3 benches/bench_lagrangian_scans.py --dump FILE` (the static-association paper's
//! scans, enumerated), with the polish on as `assign_sd` has it by default. The target for
//! instruction counts, which do not depend on machine load:
//!
//! ```text
//! python3 benches/bench_lagrangian_scans.py --scans 100 --dump /tmp/scans.txt
//! cargo bench --bench lagrangian_profile --no-run
//! valgrind --tool=callgrind target/release/deps/lagrangian_profile-<hash> /tmp/scans.txt
//! ```
//!
//! (`<hash>` as `cargo bench --no-run` prints it: the executable, not the `.d` file beside it.)
//!
//! Run directly (`... lagrangian_profile-<hash> FILE [REPEAT]`) it prints ms per solve, best of
//! REPEAT passes, and checksums of the answers (the bits of the summed primal costs and dual
//! bounds, the iterations, a hash of the chosen tuples), which two builds must share.

use passive_assoc_core::assign::lagrangian::{self, LagrangianOptions};
use passive_assoc_core::assign::SdProblem;

/// The dump's problems: per problem a line `S sizes… n_tuples`, a line of the flat tuples and
/// a line of the costs as `f64` bit patterns (so they load exactly).
fn load(text: &str) -> Vec<SdProblem> {
    let numbers = |line: Option<&str>| -> Vec<u64> {
        let line = line.unwrap_or_default().split_whitespace();
        line.map(|x| x.parse().expect("the dump holds integers"))
            .collect()
    };
    let mut lines = text.lines().filter(|line| !line.trim().is_empty());
    let mut problems = Vec::new();
    while let Some(head) = lines.next() {
        let head = numbers(Some(head));
        let s = head[0] as usize;
        let sizes = head[1..=s].iter().map(|&n| n as usize).collect();
        let tuples = numbers(lines.next()).iter().map(|&i| i as usize).collect();
        let costs = numbers(lines.next())
            .into_iter()
            .map(f64::from_bits)
            .collect();
        problems.push(SdProblem::new(tuples, s, costs, sizes).expect("the dump is valid"));
    }
    problems
}

fn main() {
    // `cargo bench` runs every bench with `--bench`: without a file there is nothing to do.
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let Some(path) = args.first() else {
        println!("lagrangian_profile: give a dump of bench_lagrangian_scans.py --dump");
        return;
    };
    let text = std::fs::read_to_string(path).expect("the dump is readable");
    let repeat: usize = match args.get(1) {
        Some(r) => r.parse().expect("REPEAT is a whole number"),
        None => 1,
    };
    let problems = load(&text);
    let options = LagrangianOptions::default().with_polish(true);
    let (mut best, mut sums) = (f64::INFINITY, (0.0, 0.0, 0, 0u64));
    for _ in 0..repeat {
        let start = std::time::Instant::now();
        sums = (0.0, 0.0, 0, 0);
        for p in &problems {
            let s = lagrangian::solve(p, &options);
            sums.0 += s.primal_cost;
            sums.1 += s.dual_bound;
            sums.2 += s.iterations;
            // Each problem's tuples, then a separator, so the hash tells where each ends.
            for k in s.chosen.iter().map(|&k| k as u64).chain([u64::MAX]) {
                sums.3 = sums.3.wrapping_mul(31).wrapping_add(k);
            }
        }
        best = best.min(start.elapsed().as_secs_f64());
    }
    println!(
        "{:.3} ms a solve (best of {repeat}); primal {:016x} dual {:016x} iterations {} chosen {:016x}",
        best / problems.len() as f64 * 1e3,
        sums.0.to_bits(),
        sums.1.to_bits(),
        sums.2,
        sums.3
    );
}
