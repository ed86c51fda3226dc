//! Kinematic calibration's benches for any legged mechanism, in its bench's group: a whole fit
//! of its geometry to 60 planned poses measured with a tracker's noise, and the plan of 60
//! poses (docs/calibration.md). Each mechanism's bench includes this file.

use c5_runtime::calibrate::{calibrate, plan, simulate, Noise, Nominal, Options};
use c5_runtime::Description;
use criterion::measurement::WallTime;
use criterion::{black_box, BenchmarkGroup};

/// `robot` as built: every fitted value moved by 1.5e-3 (m or rad), up and down in turn.
// The Gough-Stewart bench keeps the robot its table's figures were measured on.
#[allow(dead_code)]
pub fn as_built(robot: &Description) -> Description {
    let mut built = robot.clone();
    let mut leg = 0;
    while !built.fitted_values(leg).is_empty() {
        let values: Vec<f64> = built
            .fitted_values(leg)
            .iter()
            .enumerate()
            .map(|(k, v)| v + if (k + leg) % 2 == 0 { 1.5e-3 } else { -1.5e-3 })
            .collect();
        built.set_fitted_values(leg, &values);
        leg += 1;
    }
    built
}

/// `calibrate_60_poses` and `plan_60_poses` of `nominal`, the measurements simulated on
/// `truth`, in `group`.
pub fn fit_and_plan(group: &mut BenchmarkGroup<'_, WallTime>, nominal: &Nominal, truth: &Nominal) {
    let options = Options::default();
    let poses = plan(nominal, 60, &options, 1).unwrap();
    let data = simulate(truth, &poses, &Noise::default(), 2).unwrap();
    group.sample_size(20);
    group.bench_function("calibrate_60_poses", |b| {
        b.iter(|| calibrate(nominal, black_box(&data), &options).unwrap())
    });
    group.bench_function("plan_60_poses", |b| {
        b.iter(|| plan(nominal, 60, &options, black_box(1)).unwrap())
    });
}
