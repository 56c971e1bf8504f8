//! `option_defaults`: the core's option values as Python names them, so the package's tests
//! can check that each Python default is the core's recommended value.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use passive_assoc_core::assign::branch_bound::BranchBoundOptions;
use passive_assoc_core::assign::lagrangian::{LagrangianOptions, SensorOrder, WarmStart};
use passive_assoc_core::error::CoreResult;
use passive_assoc_core::estimation::fit::FitOptions;
use passive_assoc_core::estimation::kalman::{Init, KalmanOptions, MeasurementModel, MotionModel};
use passive_assoc_core::formation::{ClusterRadius, FormationOptions, Reference as Subset};
use passive_assoc_core::fti::{DescentOptions, DetectionOrder, InitiationOptions, Scaling};
use passive_assoc_core::radar_esm::CoarseOptions;
use passive_assoc_core::static_los::{EnumerateOptions, IntensityOptions};
use passive_assoc_core::topology::{
    Decision, DecisionOptions, Diffusion, Gate, Reference as Sector0, TopologyOptions,
};

use super::errors::BindResult;

/// Every options struct of the core, recommended (or `paper=True`: the published method's),
/// as `{kind: {Python parameter name: value}}`. Values are in the core's units and meaning:
/// `decision`'s `threshold` is absolute (λ·M·N), `time_limit` is in seconds. Values with no
/// Python counterpart are left out, as are the required ones with no default (the Kalman
/// filter's process noise, the coarse gate's χ² threshold).
#[pyfunction]
#[pyo3(signature = (paper=false))]
pub fn option_defaults(py: Python<'_>, paper: bool) -> BindResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    let kind = |name: &str| -> PyResult<Bound<'_, PyDict>> {
        let entries = PyDict::new(py);
        out.set_item(name, &entries)?;
        Ok(entries)
    };

    let o = pick(
        paper,
        InitiationOptions::recommended,
        InitiationOptions::paper,
    );
    let d = kind("initiation")?;
    let pairs: Option<Vec<(usize, usize)>> =
        o.pairs().map(|p| p.iter().map(|&[a, b]| (a, b)).collect());
    d.set_item("candidates", o.candidates().name())?;
    d.set_item("prefit_gates", o.prefit_gates())?;
    d.set_item("sweep", o.sweep())?;
    d.set_item("untangle", o.untangle())?;
    d.set_item("on_limit", if o.stop_at_limit() { "warn" } else { "raise" })?;
    d.set_item("pairs", pairs)?;
    d.set_item("gate_sigmas", o.gate_sigmas())?;
    d.set_item("n_detect", o.n_detect())?;
    d.set_item("ray_gate_sigmas", o.ray_gate_sigmas())?;
    d.set_item("reject_behind", o.reject_behind())?;
    d.set_item("v_max", o.v_max())?;
    d.set_item("chi2_gate", o.chi2_gate())?;
    d.set_item("one_per_scan", o.one_per_scan())?;
    d.set_item("detection_order", detection_order(o.detection_order()))?;
    d.set_item("merge_tol", o.merge_tol())?;
    d.set_item("descent_scaling", scaling(o.descent().scaling()))?;
    d.set_item("descent_max_iter", o.descent().max_iter())?;
    d.set_item("max_candidates", o.max_candidates())?;
    d.set_item("refine_passes", o.refine_passes())?;
    d.set_item("candidate_scans", o.candidate_scans())?;
    d.set_item("support_gate", o.support_gate())?;
    d.set_item("track_test", o.track_test())?;
    d.set_item("gate_pd", o.gate_pd())?;
    d.set_item("search_stage", o.search_stage())?;

    let o = pick(paper, DescentOptions::recommended, DescentOptions::paper);
    let d = kind("descent")?;
    d.set_item("scaling", scaling(o.scaling()))?;
    d.set_item("max_iter", o.max_iter())?;

    let o = pick(
        paper,
        EnumerateOptions::recommended,
        EnumerateOptions::paper,
    );
    let d = kind("enumeration")?;
    d.set_item("gate_sigmas", o.gate_sigmas())?;
    d.set_item("min_intensity", o.min_intensity())?;
    d.set_item("max_candidates", o.max_candidates())?;

    let o = pick(
        paper,
        IntensityOptions::recommended,
        IntensityOptions::paper,
    );
    let d = kind("intensity")?;
    d.set_item("vote_fraction", o.vote_fraction())?;
    d.set_item("valid_airspace", o.valid_airspace())?;
    d.set_item("max_chains", o.max_chains())?;

    let o = pick(
        paper,
        LagrangianOptions::recommended,
        LagrangianOptions::paper,
    );
    let d = kind("lagrangian")?;
    d.set_item("max_iter", o.max_iter())?;
    d.set_item("gap_tol", o.gap_tol())?;
    d.set_item("time_limit", o.time_limit().map(|t| t.as_secs_f64()))?;
    d.set_item("warm_start", warm_start(o.warm_start()))?;
    d.set_item("sensor_order", sensor_order(o.sensor_order()))?;
    d.set_item("polish", o.polish())?;

    let o = pick(
        paper,
        BranchBoundOptions::recommended,
        BranchBoundOptions::paper,
    );
    let d = kind("branch_bound")?;
    d.set_item("max_nodes", o.max_nodes())?;
    d.set_item("time_limit", o.time_limit().map(|t| t.as_secs_f64()))?;

    let o = pick(
        paper,
        FormationOptions::recommended,
        FormationOptions::paper,
    );
    let d = kind("formation")?;
    d.set_item("baseline_sensor", o.baseline_sensor())?;
    match o.reference() {
        Subset::Smallest => d.set_item("reference", "smallest")?,
        Subset::Sensor(k) => d.set_item("reference", k)?,
    }
    d.set_item("cluster_radius", cluster_radius(o.cluster_radius()))?;
    d.set_item("one_to_one", o.one_to_one())?;
    d.set_item("r_max", o.r_max())?;
    d.set_item(
        "region",
        o.region().map(|r| (r.x[0], r.x[1], r.y[0], r.y[1])),
    )?;
    d.set_item("in_front", o.in_front())?;
    d.set_item("max_pairs", o.max_pairs())?;

    let o = pick(paper, TopologyOptions::recommended, TopologyOptions::paper);
    let d = kind("topology")?;
    d.set_item("rings", o.rings())?;
    d.set_item("sectors", o.sectors())?;
    d.set_item("radius", o.radius())?;
    d.set_item("delta", o.delta())?;
    d.set_item("delta_prime", o.delta_prime())?;
    d.set_item("diffusion", diffusion(o.diffusion()))?;
    d.set_item("heading_reference", o.reference() == Sector0::Heading)?;

    let o = pick(paper, DecisionOptions::recommended, DecisionOptions::paper);
    let d = kind("decision")?;
    d.set_item("threshold", o.threshold())?;
    d.set_item("window", o.window())?;
    match o.gate() {
        Gate::Off => d.set_item("gate", None::<f64>)?,
        Gate::Distance(g) => d.set_item("gate", g)?,
        Gate::Auto => d.set_item("gate", "auto")?,
    }
    d.set_item("decision", decision(o.decision()))?;
    d.set_item("max_bias_deg", o.max_bias_deg())?;
    d.set_item("max_range", o.max_range())?;
    d.set_item("gate_probability", o.gate_probability())?;
    d.set_item("topology_weight", o.topology_weight())?;

    let o = pick(paper, FitOptions::recommended, FitOptions::paper);
    let d = kind("fit")?;
    d.set_item("max_iter", o.max_iter())?;
    d.set_item("xtol", o.xtol())?;
    d.set_item("step_sigmas", o.step_sigmas())?;

    let o = kalman(paper)?;
    let d = kind("kalman")?;
    d.set_item("motion", motion(o.motion()))?;
    d.set_item("measurement", measurement(o.measurement()))?;
    d.set_item("init", init(o.init()))?;
    d.set_item("init_velocity_std", o.init_velocity_std())?;
    d.set_item("init_acceleration_std", o.init_acceleration_std())?;

    let o = coarse(paper)?;
    let d = kind("coarse")?;
    d.set_item("whitened", o.whitened())?;
    Ok(out)
}

/// `published()` when `paper`, else `recommended()`.
fn pick<T>(paper: bool, recommended: fn() -> T, published: fn() -> T) -> T {
    if paper {
        published()
    } else {
        recommended()
    }
}

/// The Kalman options with a placeholder process noise (left out of the answer).
fn kalman(paper: bool) -> CoreResult<KalmanOptions> {
    match paper {
        true => KalmanOptions::paper(0.0),
        false => KalmanOptions::recommended(0.0),
    }
}

/// The coarse gate's options with a placeholder threshold (left out of the answer).
fn coarse(paper: bool) -> CoreResult<CoarseOptions> {
    match paper {
        true => CoarseOptions::paper(1.0),
        false => CoarseOptions::recommended(1.0),
    }
}

// The Python spelling of each enum value: the strings its `FromStr` accepts.

fn detection_order(value: DetectionOrder) -> &'static str {
    match value {
        DetectionOrder::Membership => "membership",
        DetectionOrder::Closeness => "closeness",
    }
}

fn scaling(value: Scaling) -> &'static str {
    match value {
        Scaling::Whitened => "whitened",
        Scaling::Diagonal => "diagonal",
    }
}

fn warm_start(value: WarmStart) -> &'static str {
    match value {
        WarmStart::Auto => "auto",
        WarmStart::Always => "always",
        WarmStart::Never => "never",
    }
}

fn sensor_order(value: SensorOrder) -> &'static str {
    match value {
        SensorOrder::Auto => "auto",
        SensorOrder::Given => "given",
    }
}

fn cluster_radius(value: ClusterRadius) -> &'static str {
    match value {
        ClusterRadius::Planar => "2d",
        ClusterRadius::AlongBaseline => "1d",
    }
}

fn diffusion(value: Diffusion) -> &'static str {
    match value {
        Diffusion::Additive => "additive",
        Diffusion::AtLeast => "at_least",
    }
}

fn decision(value: Decision) -> &'static str {
    match value {
        Decision::Fused => "fused",
        Decision::Assignment => "assignment",
        Decision::PerSystemTrack => "per_system_track",
    }
}

fn motion(value: MotionModel) -> &'static str {
    match value {
        MotionModel::ConstantVelocity => "cv",
        MotionModel::ConstantAcceleration => "ca",
    }
}

fn measurement(value: MeasurementModel) -> &'static str {
    match value {
        MeasurementModel::Position => "position",
        MeasurementModel::Polar => "polar",
        MeasurementModel::PolarConverted => "polar_converted",
    }
}

fn init(value: Init) -> &'static str {
    match value {
        Init::Differencing => "differencing",
        Init::SinglePoint => "single_point",
    }
}
