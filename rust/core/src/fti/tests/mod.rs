//! Tests of the whole initiation on simulated data (module `sim`), and what the stages' unit
//! tests share: the simulator, [`run`] and [`candidates_of`].

mod candidates;
mod missed;
mod own_witnesses;
mod progress;
mod reference;
mod rounds;
pub(super) mod sim;

use super::candidate::Candidate;
use super::candidates::generate;
use super::closeness::{closeness, closeness_and_gradient, Precomputed};
use super::descent::descend;
use super::output::StageCounts;
use super::problem::Problem;
use super::scans::{resolve_pairs, Scans, Slot};
use super::{initiate, DescentOptions, Initiation, InitiationOptions, Spreads};
use crate::data::{Measurements, Sensors};
use crate::error::{CoreError, CoreResult};
use crate::geometry::angles::wrap;
use crate::geometry::model::{predict, Motion, Space, StateLayout, MAX_DIM};
use crate::parallel::with_threads;
use crate::progress::Silent;
use reference::rules_off;
use sim::{Scenario, PAPER_TARGETS};

pub(super) fn run(sc: &Scenario, options: &InitiationOptions) -> Result<Initiation, CoreError> {
    let sensors = sc.sensors();
    let table = sc.measurements(&sensors);
    initiate(&sensors, &table, &sc.spreads(), 0.0, options)
}

/// What [`candidates_of`] returns: the fitted candidates, the stage counts, the scans and
/// the resolved pairs.
pub(super) type CandidateRun = (Vec<Candidate>, StageCounts, Scans, Vec<[usize; 2]>);

/// The candidates of pass 1 only (no search), whole.
pub(super) fn candidates_of(
    sensors: &Sensors<'_>,
    measurements: &Measurements<'_>,
    t0: f64,
    options: &InitiationOptions,
) -> CoreResult<CandidateRun> {
    let problem = Problem {
        sensors: *sensors,
        measurements: *measurements,
        layout: StateLayout::new(sensors.space(), Motion::ConstantVelocity { t0 }),
        t0,
        progress: &Silent,
    };
    let scans = Scans::new(measurements, sensors.len());
    let pairs = resolve_pairs(options.pairs(), &scans)?;
    let slots: Vec<Slot> = pairs
        .iter()
        .flat_map(|&p| scans.scan_slots(p, 1, false))
        .map(Slot::untested)
        .collect();
    let set = generate(&problem, &scans, &slots, None, options, None)?;
    Ok((
        set.candidates.into_whole(&problem),
        set.counts,
        scans,
        pairs,
    ))
}

fn precomputed(sc: &Scenario) -> Precomputed {
    let sensors = sc.sensors();
    Precomputed::new(&sensors, &sc.measurements(&sensors), &sc.spreads(), 0.0).expect("valid")
}

/// R straight from eq. 17–18: predicted angles, wrapped differences, every exp evaluated.
fn naive_closeness(sc: &Scenario, x: &[f64]) -> f64 {
    let layout = StateLayout::new(sc.space, Motion::ConstantVelocity { t0: 0.0 });
    let n = sc.sensor.len();
    let mut sum = 0.0;
    for m in 0..n {
        let j = sc.sensor[m] as usize;
        let p = [
            sc.positions[3 * j],
            sc.positions[3 * j + 1],
            sc.positions[3 * j + 2],
        ];
        let [a, e] = predict(sc.space, &p, &layout.position(x, sc.time[m]));
        let da = wrap(sc.azimuth[m] - a) / sc.spread_az[j];
        sum += match sc.space {
            Space::Planar => (-da * da).exp(),
            Space::Spatial => {
                let de = wrap(sc.elevation[m] - e) / sc.spread_el[j];
                0.5 * (-da * da).exp() + 0.5 * (-de * de).exp()
            }
        };
    }
    sum / n as f64
}

fn perturbed(truth: &[f64], rng: &mut sim::Rng, size: [f64; 2]) -> Vec<f64> {
    let p = truth.len() / 2;
    truth
        .iter()
        .enumerate()
        .map(|(k, v)| v + size[usize::from(k >= p)] * rng.normal())
        .collect()
}

#[test]
fn closeness_matches_the_formula_and_its_gradient_central_differences() {
    let mut rng = sim::Rng::new(7);
    for sc in [sim::paper(1, true, 8, 8), sim::planar(2, true, 4, 6)] {
        let pre = precomputed(&sc);
        let d = pre.dim();
        for target in &sc.targets {
            for _ in 0..4 {
                let x = perturbed(target, &mut rng, [60.0, 1.5]);
                let (r, g) = closeness_and_gradient(&pre, &x);
                assert!((r - naive_closeness(&sc, &x)).abs() <= 1e-14, "{r}");
                assert_eq!(r, closeness(&pre, &x));
                for k in 0..d {
                    let h = if k < d / 2 { 1e-2 } else { 1e-4 };
                    let (mut up, mut down) = (x.clone(), x.clone());
                    up[k] += h;
                    down[k] -= h;
                    let numeric = (closeness(&pre, &up) - closeness(&pre, &down)) / (2.0 * h);
                    let scale = g[..d].iter().map(|v| v.abs()).fold(1e-12, f64::max);
                    assert!(
                        (numeric - g[k]).abs() <= 1e-5 * scale,
                        "component {k}: {numeric} vs {}",
                        g[k]
                    );
                }
            }
        }
    }
}

#[test]
fn descent_climbs_to_the_noiseless_optimum_in_few_steps() {
    let sc = sim::paper(3, false, 0, 8);
    let sensors = sc.sensors();
    let table = sc.measurements(&sensors);
    let (candidates, ..) =
        candidates_of(&sensors, &table, 0.0, &InitiationOptions::default()).expect("runs");
    let pre = precomputed(&sc);
    // Other targets' rows pull R's maximum slightly off the truth: find it by a long, tight
    // descent from the truth, then check the default one reaches it from 2σ away.
    let truth = PAPER_TARGETS[2];
    let own = candidates
        .iter()
        .find(|c| c.rows.iter().all(|&m| sc.truth[m] == 2))
        .expect("its candidate");
    let offset = [1.5, -1.0, 1.0, 0.5, -0.5, 1.0];
    let start: [f64; MAX_DIM] = std::array::from_fn(|k| {
        truth[k] + (0..=k).map(|c| own.factor[k][c] * offset[c]).sum::<f64>()
    });
    let opt = descend(&pre, &start, &own.factor, &DescentOptions::default());
    let tight = DescentOptions::default()
        .with_max_iter(5000)
        .with_step_tol(1e-9)
        .and_then(|o| o.with_r_tol(0.0))
        .expect("valid");
    let best = descend(&pre, &truth, &own.factor, &tight);
    assert!(opt.closeness >= closeness(&pre, &start), "R must not fall");
    assert!(opt.iterations <= 30, "{} iterations", opt.iterations);
    assert!(best.closeness - opt.closeness < 1e-4 * best.closeness);
    for k in 0..6 {
        assert!(
            (opt.x[k] - best.x[k]).abs() < 0.05 * own.scale[k],
            "component {k}: {:?} vs {:?}",
            opt.x,
            best.x
        );
    }
}

/// Every row in exactly one track or in clutter, and labels agree with the track lists.
pub(super) fn assert_partition(result: &Initiation, n: usize) {
    assert_eq!(result.labels.len(), n);
    let mut seen = vec![false; n];
    for (t, track) in result.tracks.iter().enumerate() {
        for &m in &track.measurements {
            assert!(!seen[m], "row {m} in two tracks");
            seen[m] = true;
            assert_eq!(result.labels[m], t as i64);
        }
    }
    for (m, (&s, &label)) in seen.iter().zip(&result.labels).enumerate() {
        assert_eq!(s, label >= 0, "row {m}");
    }
}

/// For each true target, the track holding its rows (all of them, and nothing else).
pub(super) fn assert_exact_tracks(sc: &Scenario, result: &Initiation, tol: f64) {
    assert_eq!(
        result.tracks.len(),
        sc.targets.len(),
        "{:?}",
        result.stage_counts
    );
    for (i, target) in sc.targets.iter().enumerate() {
        let rows: Vec<usize> = (0..sc.truth.len())
            .filter(|&m| sc.truth[m] == i as i64)
            .collect();
        let track = result
            .tracks
            .iter()
            .find(|t| t.measurements == rows)
            .unwrap_or_else(|| panic!("no track holds exactly target {i}'s rows"));
        for (k, v) in target.iter().enumerate() {
            assert!(
                (track.estimate[k] - v).abs() <= tol * v.abs().max(1.0),
                "target {i} component {k}"
            );
        }
    }
}

#[test]
fn noiseless_paper_scenario_gives_exactly_the_four_tracks() {
    let sc = sim::paper(11, false, 0, 8);
    let result = run(&sc, &InitiationOptions::default()).expect("runs");
    assert_partition(&result, sc.sensor.len());
    assert_exact_tracks(&sc, &result, 1e-6);
    for t in &result.tracks {
        assert_eq!(t.measurements.len(), 16);
        assert!(t.chi2 < 1e-12);
    }
    assert_eq!(result.stage_counts.raw, 4usize.pow(4));
}

#[test]
fn cluttered_noisy_paper_run_finds_the_targets_and_partitions_every_row() {
    let sc = sim::paper(2024, true, 8, 8);
    // One candidate pass (the paper's): exactly the product of the four outer scans.
    let paper = InitiationOptions::default()
        .with_candidate_scans(1)
        .expect("valid");
    let result = run(&sc, &paper).expect("runs");
    assert_partition(&result, sc.sensor.len());
    let c = result.stage_counts;
    assert_eq!(c.raw, 12usize.pow(4));
    assert!(
        c.raw >= c.ray_gate && c.ray_gate >= c.behind && c.behind >= c.v_max && c.v_max >= c.fitted
    );
    assert!(
        c.fitted >= c.chi2_gate
            && c.chi2_gate >= c.supported
            && c.supported == c.optima
            && c.optima >= c.merged
            && c.merged >= c.detected
    );
    assert_eq!(result.descent_iterations.len(), c.optima);
    // Every true target is found with most of its 16 rows.
    for i in 0..4 {
        let best = result
            .tracks
            .iter()
            .map(|t| t.measurements.iter().filter(|&&m| sc.truth[m] == i).count())
            .max()
            .unwrap_or(0);
        assert!(
            best >= 14,
            "target {i}: {best} rows in its best track; {c:?}"
        );
    }
}

#[test]
fn planar_bearing_only_scenario_gives_exact_tracks() {
    let sc = sim::planar(5, false, 3, 6);
    let result = run(&sc, &InitiationOptions::default()).expect("runs");
    assert_partition(&result, sc.sensor.len());
    assert_eq!(result.dim, 4);
    assert_exact_tracks(&sc, &result, 1e-6);
    // No χ² information in 2-D: the gate passes everything fitted.
    assert_eq!(result.stage_counts.chi2_gate, result.stage_counts.fitted);
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let sc = sim::paper(77, true, 8, 8);
    let one = with_threads(Some(1), || run(&sc, &InitiationOptions::default()))
        .expect("pool")
        .expect("runs");
    let two = with_threads(Some(2), || run(&sc, &InitiationOptions::default()))
        .expect("pool")
        .expect("runs");
    assert_eq!(one.tracks, two.tracks);
    assert_eq!(one.labels, two.labels);
    assert_eq!(one.stage_counts, two.stage_counts);
    assert_eq!(one.descent_iterations, two.descent_iterations);
}

#[test]
fn bad_input_is_reported_with_the_argument() {
    let sc = sim::paper(1, false, 0, 3);
    let reason = |options: InitiationOptions| match run(&sc, &options) {
        Err(e) => e,
        Ok(_) => panic!("accepted {options:?}"),
    };
    let with_pairs = |p: Vec<[usize; 2]>| InitiationOptions::default().with_pairs(Some(p));
    assert!(matches!(
        reason(with_pairs(vec![[0, 2]])),
        CoreError::OutOfRange { arg: "pairs", .. }
    ));
    assert!(matches!(
        reason(with_pairs(vec![[1, 1]])),
        CoreError::OutOfRange { arg: "pairs", .. }
    ));
    assert!(matches!(
        reason(with_pairs(vec![[0, 1], [1, 0]])),
        CoreError::OutOfRange { arg: "pairs", .. }
    ));
    // Value-only settings are rejected by their setters, before any data is seen.
    let defaults = InitiationOptions::default;
    assert!(matches!(
        defaults().with_gate_sigmas(0.0),
        Err(CoreError::OutOfRange {
            arg: "gate_sigmas",
            ..
        })
    ));
    assert!(matches!(
        defaults().with_n_detect(Some(0)),
        Err(CoreError::OutOfRange {
            arg: "n_detect",
            ..
        })
    ));
    assert!(matches!(
        defaults().with_v_max(Some(-1.0)),
        Err(CoreError::OutOfRange { arg: "v_max", .. })
    ));
    // Past the cap the formation stops with what it found (the default), or refuses:
    let capped = (rules_off().with_max_candidates(5).expect("valid")).with_stop_at_limit(false);
    assert!(matches!(
        reason(capped),
        CoreError::CapExceeded { cap: 5, .. }
    ));

    // A sensor with a single scan cannot give first and last.
    let mut one_scan = sim::paper(1, false, 0, 2);
    for m in 0..one_scan.time.len() {
        if one_scan.sensor[m] == 1 {
            one_scan.time[m] = 5.0;
        }
    }
    match run(&one_scan, &InitiationOptions::default()) {
        Err(CoreError::IllPosed {
            arg: "pairs",
            reason,
        }) => assert_eq!(reason, "sensor 1 has 1 scan; need first and last"),
        other => panic!("{other:?}"),
    }

    let sensors = sc.sensors();
    let bad_spread = [0.01, -0.01];
    let spreads = Spreads::new(Space::Spatial, 2, &bad_spread, &sc.spread_el);
    assert!(matches!(
        spreads,
        Err(CoreError::OutOfRange {
            arg: "spread_azimuth",
            ..
        })
    ));
    let table = sc.measurements(&sensors);
    let t0 = initiate(
        &sensors,
        &table,
        &sc.spreads(),
        f64::NAN,
        &InitiationOptions::default(),
    );
    assert!(matches!(t0, Err(CoreError::OutOfRange { arg: "t0", .. })));
}
