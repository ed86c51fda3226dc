//! `c5 eval --derivatives` and `c5 forward --derivatives` against central differences of the
//! nalgebra reference of the model (an implementation the generator does not share), on unseen
//! seeded states, to 1e-6 relative to each Jacobian's largest entry (step 1e-5: the finite
//! differences themselves are good to about 1e-9 here).

use crate::support;

use c5_runtime::reference as r;
use c5_runtime::{Acceleration, Model, Pose, Robot, Twist};
use rand::{Rng, SeedableRng};
use serde_json::{json, Value};

const STEP: f64 = 1e-5;

fn lines(args: &[&str], input: &str) -> Vec<Value> {
    let out = support::c5_ok(args, input);
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn matrix(v: &Value) -> [[f64; 6]; 6] {
    std::array::from_fn(|i| std::array::from_fn(|j| v[i][j].as_f64().unwrap()))
}

/// Row-major central differences of `f` in each component of `x`.
fn central(f: impl Fn(&[f64; 6]) -> [f64; 6], x: &[f64; 6]) -> [[f64; 6]; 6] {
    let columns: Vec<[f64; 6]> = (0..6)
        .map(|j| {
            let (mut up, mut down) = (*x, *x);
            up[j] += STEP;
            down[j] -= STEP;
            let (fu, fd) = (f(&up), f(&down));
            std::array::from_fn(|i| (fu[i] - fd[i]) / (2.0 * STEP))
        })
        .collect();
    std::array::from_fn(|i| std::array::from_fn(|j| columns[j][i]))
}

fn assert_close(what: &str, got: &[[f64; 6]; 6], want: &[[f64; 6]; 6]) {
    let scale = want.iter().flatten().fold(1.0_f64, |m, w| m.max(w.abs()));
    let worst = got
        .iter()
        .flatten()
        .zip(want.iter().flatten())
        .fold(0.0_f64, |m, (g, w)| m.max((g - w).abs()));
    assert!(worst <= 1e-6 * scale, "{what}: {worst:e} of {scale:e}");
}

fn state(rng: &mut rand_chacha::ChaCha8Rng) -> [[f64; 6]; 3] {
    let mut u = |b: f64| rng.gen_range(-b..=b);
    [
        [u(0.5), u(0.5), u(0.5), u(0.08), u(0.08), u(0.08)],
        [u(1.0), u(1.0), u(1.0), u(0.5), u(0.5), u(0.5)],
        [u(5.0), u(5.0), u(5.0), u(2.0), u(2.0), u(2.0)],
    ]
}

#[test]
fn eval_derivatives_are_the_references_central_differences() {
    let robot = Robot::default();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
    for model in Model::ALL {
        let states: Vec<[[f64; 6]; 3]> = (0..20).map(|_| state(&mut rng)).collect();
        let input: Vec<String> = states
            .iter()
            .map(|[x, v, a]| {
                json!({"pose": x, "omega": &v[..3], "velocity": &v[3..], "omega_dot": &a[..3],
                       "acceleration": &a[3..]})
                .to_string()
            })
            .collect();
        let out = lines(
            &["eval", "--model", model.name(), "--derivatives"],
            &input.join("\n"),
        );
        for (line, [x, v, a]) in out.iter().zip(&states) {
            let gamma = |x: &[f64; 6], v: &[f64; 6], a: &[f64; 6]| -> [f64; 6] {
                let g = (r::model(model).inverse_dynamics)(
                    &robot,
                    &Pose::from_array(*x),
                    &Twist::from_array(*v),
                    &Acceleration::from_array(*a),
                )
                .unwrap();
                std::array::from_fn(|i| g[i])
            };
            assert_close(
                &format!("{model} d_gamma_d_pose"),
                &matrix(&line["d_gamma_d_pose"]),
                &central(|x| gamma(x, v, a), x),
            );
            assert_close(
                &format!("{model} d_gamma_d_twist"),
                &matrix(&line["d_gamma_d_twist"]),
                &central(|v| gamma(x, v, a), v),
            );
            assert_close(
                &format!("{model} d_gamma_d_acceleration"),
                &matrix(&line["d_gamma_d_acceleration"]),
                &central(|a| gamma(x, v, a), a),
            );
        }
    }
}

#[test]
fn forward_derivatives_are_the_references_central_differences() {
    let robot = Robot::default();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2027);
    for model in Model::ALL {
        let cases: Vec<([f64; 6], [f64; 6], [f64; 6])> = (0..20)
            .map(|_| {
                let [x, v, _] = state(&mut rng);
                let g = std::array::from_fn(|i| {
                    rng.gen_range(-60.0..60.0) + [0.0, 0.0, 0.0, 0.0, 85.0, 85.0][i]
                });
                (x, v, g)
            })
            .collect();
        let input: Vec<String> = cases
            .iter()
            .map(|(x, v, g)| {
                json!({"pose": x, "omega": &v[..3], "velocity": &v[3..], "gamma": g}).to_string()
            })
            .collect();
        let out = lines(
            &["forward", "--model", model.name(), "--derivatives"],
            &input.join("\n"),
        );
        for (line, (x, v, g)) in out.iter().zip(&cases) {
            let accel = |x: &[f64; 6], v: &[f64; 6], g: &[f64; 6]| -> [f64; 6] {
                r::forward_dynamics(
                    &robot,
                    model,
                    &Pose::from_array(*x),
                    &Twist::from_array(*v),
                    g,
                )
                .unwrap()
                .to_array()
            };
            assert_close(
                &format!("{model} d_acceleration_d_pose"),
                &matrix(&line["d_acceleration_d_pose"]),
                &central(|x| accel(x, v, g), x),
            );
            assert_close(
                &format!("{model} d_acceleration_d_twist"),
                &matrix(&line["d_acceleration_d_twist"]),
                &central(|v| accel(x, v, g), v),
            );
            assert_close(
                &format!("{model} d_acceleration_d_gamma"),
                &matrix(&line["d_acceleration_d_gamma"]),
                &central(|g| accel(x, v, g), g),
            );
        }
    }
}
