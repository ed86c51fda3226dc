//! Pose, twist and acceleration of the platform, with the conventions of the whole crate.

/// Platform pose: RPY angles (eq 15, rad) and the centre `C` in the base frame (m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Pose {
    pub alpha: f64,
    pub beta: f64,
    pub gamma: f64,
    pub center: [f64; 3],
}

impl Pose {
    /// From `X = [α β γ xc yc zc]`.
    pub fn from_array(x: [f64; 6]) -> Self {
        Pose {
            alpha: x[0],
            beta: x[1],
            gamma: x[2],
            center: [x[3], x[4], x[5]],
        }
    }
    pub fn to_array(&self) -> [f64; 6] {
        let [x, y, z] = self.center;
        [self.alpha, self.beta, self.gamma, x, y, z]
    }
}

/// Platform twist `V = (ω; v_C)` at `C`, base frame (rad/s, m/s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Twist {
    pub omega: [f64; 3],
    pub velocity: [f64; 3],
}

impl Twist {
    /// From `(ω; v_C)`.
    pub fn from_array(v: [f64; 6]) -> Self {
        Twist {
            omega: [v[0], v[1], v[2]],
            velocity: [v[3], v[4], v[5]],
        }
    }
    pub fn to_array(&self) -> [f64; 6] {
        let ([a, b, c], [d, e, f]) = (self.omega, self.velocity);
        [a, b, c, d, e, f]
    }
    #[cfg(feature = "reference")]
    pub fn to_vector(&self) -> nalgebra::Vector6<f64> {
        nalgebra::Vector6::from(self.to_array())
    }
}

/// Classical platform acceleration `(ω̇; a_C)`, `a_C = d v_C/dt` (rad/s², m/s²).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Acceleration {
    pub omega_dot: [f64; 3],
    pub linear: [f64; 3],
}

impl Acceleration {
    /// From `(ω̇; a_C)`.
    pub fn from_array(a: [f64; 6]) -> Self {
        Acceleration {
            omega_dot: [a[0], a[1], a[2]],
            linear: [a[3], a[4], a[5]],
        }
    }
    pub fn to_array(&self) -> [f64; 6] {
        let ([a, b, c], [d, e, f]) = (self.omega_dot, self.linear);
        [a, b, c, d, e, f]
    }
    #[cfg(feature = "reference")]
    pub fn to_vector(&self) -> nalgebra::Vector6<f64> {
        nalgebra::Vector6::from(self.to_array())
    }
}

/// A platform state: pose, twist and acceleration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct State {
    pub pose: Pose,
    pub twist: Twist,
    pub accel: Acceleration,
}

/// The state of a platform that only translates (the Delta's): the position, velocity and
/// acceleration of `C` (base frame).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Translation {
    /// `C` (m).
    pub position: [f64; 3],
    /// `v_C` (m/s).
    pub velocity: [f64; 3],
    /// `a_C` (m/s²).
    pub acceleration: [f64; 3],
}
