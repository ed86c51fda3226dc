//! The descriptions of the robots the project knows, and the choice of the C5's contact model.
//!
//! [`Description`] is a robot of one of the mechanisms, read from a robot file whose
//! `mechanism` line chooses: a C5 joint parallel robot ([`Robot`], the default) or a
//! Gough-Stewart platform ([`GoughStewart`]).
//!
//! [`Robot`] holds the geometry, gravity and the dynamic parameters of every body; it is
//! generic over its scalar, so the same description holds numbers (`Robot<f64>`, validated by
//! [`Robot::validate`]) and symbols (the generator's `Robot<Expr>`). [`Robot::flatten`] fixes
//! the order of the runtime parameter vector once. [`Model`] names the two models of the legs'
//! mechanism the kernels implement.
//!
//! [`Description::export`] writes any of them for other tools: MJCF (MuJoCo, and Pinocchio
//! with its loop closures) or URDF, from the robot as a tree of rigid bodies
//! ([`Description::body_tree`], [`tree`]) whose loops are cut at the base (docs/export.md).
//!
//! This crate has no dependency by default and is `no_std` (with `alloc`) without its `std`
//! feature, so a controller can hold and check a robot description without the generator.
//!
//! # Example
//!
//! ```
//! use c5_robot::{Model, Robot};
//!
//! let mut robot = Robot::default(); // the chapter's robot
//! robot.platform.mass = 12.0;
//! robot.validate()?;
//! // A body whose principal moments break the triangle inequality is refused.
//! robot.platform.inertia = [[1.0, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.1]];
//! assert!(robot.validate().unwrap_err().to_string().contains("triangle inequality"));
//! assert_eq!("paper".parse::<Model>()?, Model::Paper);
//! # Ok::<(), c5_robot::Error>(())
//! ```

#![cfg_attr(not(feature = "std"), no_std)]

extern crate alloc;

pub mod calibration;
pub mod delta;
pub mod description;
mod error;
pub mod export;
pub mod gough_stewart;
mod inertia;
mod limits;
mod math;
mod model;
mod robot;
pub mod rus;
pub mod rus_hexapod;
mod standard;
pub mod tree;

pub use delta::{Delta, DeltaPlatform};
pub use description::Description;
pub use error::Error;
pub use export::Format;
pub use gough_stewart::{GoughStewart, LegBody, LegLimits, Platform, UpsLeg};
pub use inertia::check_inertia;
pub use limits::Limits;
pub use model::Model;
pub use robot::{
    standard_of, RigidBody, Robot, Rod, Segment, AXIS, GEOMETRY_PARAMETERS, PARAMETERS,
};
pub use rus::{Crank, RusLeg, RusRod};
pub use rus_hexapod::RusHexapod;
pub use standard::{standard_parameter_names, Friction, STANDARD_PARAMETERS};
pub use tree::BodyTree;
