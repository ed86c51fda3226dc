//! The column names of the CSV files the commands read and write, in one place.

pub use c5_runtime::platform::Freedom;

/// Time (s).
pub const TIME: &str = "t";
/// The pose `[α β γ xc yc zc]`.
pub const POSE: [&str; 6] = ["alpha", "beta", "gamma", "xc", "yc", "zc"];
/// The twist `(ω; v_C)`.
pub const TWIST: [&str; 6] = ["wx", "wy", "wz", "vx", "vy", "vz"];
/// The classical acceleration `(ω̇; a_C)`.
pub const ACCEL: [&str; 6] = ["wdx", "wdy", "wdz", "ax", "ay", "az"];
/// `{name}1` … `{name}n`: one column per actuator.
pub fn per_actuator(name: &str, n: usize) -> Vec<String> {
    (1..=n).map(|i| format!("{name}{i}")).collect()
}

/// `t`, the pose, the twist and the acceleration in a platform's coordinates: a whole
/// trajectory row.
pub fn state(freedom: Freedom) -> Vec<String> {
    std::iter::once(TIME)
        .chain(freedom.pose_names().iter().copied())
        .chain(freedom.twist_names().iter().copied())
        .chain(freedom.acceleration_names().iter().copied())
        .map(String::from)
        .collect()
}
