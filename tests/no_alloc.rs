//! The generated kernels and the runtime's hot path allocate nothing: a counting global
//! allocator watches this thread while they run.

use c5_runtime::{Acceleration, Model, Pose, Robot, State, Twist, C5};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        System.alloc(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
        System.realloc(ptr, layout, size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

#[test]
fn kernels_and_hot_path_do_not_allocate() {
    let robot = C5::new(Robot::default()).unwrap();
    let paper = C5::with_model(Robot::default(), Model::Paper).unwrap();
    let state = State {
        pose: Pose::from_array([0.1, -0.2, 0.3, 0.01, 0.02, -0.03]),
        twist: Twist {
            omega: [0.1, 0.2, 0.3],
            velocity: [0.1, 0.0, -0.1],
        },
        accel: Acceleration {
            omega_dot: [1.0, -1.0, 0.5],
            linear: [0.5, 0.2, 0.1],
        },
    };
    let (x, v, a) = (
        state.pose.to_array(),
        state.twist.to_array(),
        state.accel.to_array(),
    );
    let mut sink = 0.0;
    let n = allocations_during(|| {
        for k in c5_generated::f64::MODELS {
            sink += k.inverse_dynamics(&x, &v, &a).0[0];
            sink += k.inverse_kinematics(&x).0[0];
            sink += k.jacobian_pose(&x).0[0][0];
            sink += k.joint_accelerations(&x, &v, &a).0[0];
        }
        for c5 in [&robot, &paper] {
            sink += c5.inverse_dynamics(&state).unwrap()[0];
            sink += c5.joint_accelerations(&state).unwrap()[0];
            sink += c5.evaluate(&state).unwrap().gamma[0];
        }
        // An error is refused without allocating too.
        let mut bad = state;
        bad.pose.alpha = f64::NAN;
        sink += robot.inverse_dynamics(&bad).map_or(1.0, |g| g[0]);
    });
    assert!(sink.is_finite());
    assert_eq!(n, 0, "allocations on the hot path");
    // The counter does count: a Vec allocates.
    assert!(allocations_during(|| drop(std::hint::black_box(vec![1u8; 16]))) > 0);
}
