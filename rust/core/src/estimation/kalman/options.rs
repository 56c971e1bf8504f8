//! [`KalmanOptions`]: the filter's settings, built with validated `with_*` setters.

use super::init::Init;
use super::measurement::MeasurementModel;
use super::motion::MotionModel;
use crate::error::{CoreError, CoreResult};

/// Settings of [`kalman_filter`](super::kalman_filter). There is no default process noise (it
/// depends on the targets, and the Python `KalmanFilter` requires it too), so construction
/// starts from [`KalmanOptions::new`], [`KalmanOptions::recommended`] or
/// [`KalmanOptions::paper`], each given it, and there is no `Default`.
///
/// ```
/// use passive_assoc_core::estimation::kalman::{Init, KalmanOptions, MeasurementModel, MotionModel};
/// let o = KalmanOptions::new(MotionModel::ConstantAcceleration, 0.5).unwrap()
///     .with_measurement(MeasurementModel::Polar)
///     .with_init(Init::SinglePoint)
///     .with_init_velocity_std(300.0).unwrap();
/// assert_eq!((o.process_noise(), o.init_velocity_std()), (0.5, 300.0));
/// assert_eq!(o.init_acceleration_std(), 50.0);
/// assert!(KalmanOptions::new(MotionModel::ConstantVelocity, -1.0).is_err());
/// assert!(o.with_init_acceleration_std(f64::NAN).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KalmanOptions {
    motion: MotionModel,
    measurement: MeasurementModel,
    process_noise: f64,
    init: Init,
    init_velocity_std: f64,
    init_acceleration_std: f64,
}

impl KalmanOptions {
    /// `motion` with process-noise spectral density `process_noise` (finite, ≥ 0; m²/s³ for
    /// CV, m²/s⁵ for CA); position measurements, differencing initialisation,
    /// single-point prior standard deviations 500 m/s and 50 m/s².
    pub fn new(motion: MotionModel, process_noise: f64) -> CoreResult<Self> {
        let options = Self {
            motion,
            measurement: MeasurementModel::Position,
            process_noise: 0.0,
            init: Init::Differencing,
            init_velocity_std: 500.0,
            init_acceleration_std: 50.0,
        };
        options.with_process_noise(process_noise)
    }

    /// The project's defaults, those of the Python package (`KalmanFilter`), with process
    /// noise `process_noise`: constant velocity, position measurements, differencing
    /// initialisation, single-point prior standard deviations 500 m/s and 50 m/s² (the same
    /// as [`new`](Self::new) with constant velocity).
    pub fn recommended(process_noise: f64) -> CoreResult<Self> {
        Self::new(MotionModel::ConstantVelocity, process_noise)
    }

    /// The filter of METHODS §5 (paper 003), with process noise `process_noise`: differs from
    /// [`recommended`](Self::recommended) in the constant-acceleration motion (factor u1 needs
    /// an acceleration); Cartesian (position) measurements keep it linear. The paper gives no
    /// initialisation or priors: those are the recommended ones.
    pub fn paper(process_noise: f64) -> CoreResult<Self> {
        Self::new(MotionModel::ConstantAcceleration, process_noise)
    }

    pub fn with_motion(mut self, motion: MotionModel) -> Self {
        self.motion = motion;
        self
    }

    pub fn with_measurement(mut self, measurement: MeasurementModel) -> Self {
        self.measurement = measurement;
        self
    }

    /// Spectral density of the white acceleration (CV) or jerk (CA) on every axis; 0 makes
    /// the motion deterministic.
    pub fn with_process_noise(mut self, process_noise: f64) -> CoreResult<Self> {
        non_negative("process_noise", process_noise)?;
        self.process_noise = process_noise;
        Ok(self)
    }

    pub fn with_init(mut self, init: Init) -> Self {
        self.init = init;
        self
    }

    /// Prior standard deviation of every velocity component for `single_point` (m/s, > 0).
    pub fn with_init_velocity_std(mut self, std: f64) -> CoreResult<Self> {
        positive("init_velocity_std", std)?;
        self.init_velocity_std = std;
        Ok(self)
    }

    /// Prior standard deviation of every acceleration component for `single_point` with CA
    /// (m/s², > 0).
    pub fn with_init_acceleration_std(mut self, std: f64) -> CoreResult<Self> {
        positive("init_acceleration_std", std)?;
        self.init_acceleration_std = std;
        Ok(self)
    }

    pub fn motion(&self) -> MotionModel {
        self.motion
    }

    pub fn measurement(&self) -> MeasurementModel {
        self.measurement
    }

    pub fn process_noise(&self) -> f64 {
        self.process_noise
    }

    pub fn init(&self) -> Init {
        self.init
    }

    pub fn init_velocity_std(&self) -> f64 {
        self.init_velocity_std
    }

    pub fn init_acceleration_std(&self) -> f64 {
        self.init_acceleration_std
    }
}

fn non_negative(arg: &'static str, value: f64) -> CoreResult<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(CoreError::out_of_range(
            arg,
            format!("{value} must be finite and >= 0"),
        ))
    }
}

fn positive(arg: &'static str, value: f64) -> CoreResult<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(CoreError::out_of_range(
            arg,
            format!("{value} must be finite and > 0"),
        ))
    }
}
