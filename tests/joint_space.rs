//! The kernels from the actuator positions (what the encoders measure) against the pose they
//! came from: the forward kinematics undoes the inverse kinematics, every model.

mod support;

use c5_runtime::reference as r;
use c5_runtime::Model;
use support::*;

const STATES: usize = 10_000;

#[test]
fn forward_kinematics_undoes_the_inverse_kinematics() {
    let mut rng = rng(80);
    for _ in 0..STATES {
        let s = random_state(&mut rng);
        for model in Model::ALL {
            let k = c5_runtime::kernels(model);
            let (q, _, _) = k.inverse_kinematics(&s.pose.to_array());
            let (rot, c, singular) = k.forward_kinematics(&q);
            assert!(singular[0] > 0.0, "a pose of the workspace: 1 + abc > 0");
            let want = r::rotation(&s.pose);
            for i in 0..3 {
                for j in 0..3 {
                    assert!((rot[i][j] - want[(i, j)]).abs() < 1e-13, "{model}");
                }
                assert!((c[i] - s.pose.center[i]).abs() < 1e-13, "{model}");
            }
            assert_eq!(singular[1..], [rot[0][0], rot[1][1], rot[2][2]]);
        }
    }
}
