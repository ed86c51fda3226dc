//! Errors of the runtime API.

use alloc::string::{String, ToString};
use core::fmt;

/// Why a computation was refused.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// An input held NaN or an infinity.
    NonFinite { input: &'static str, index: usize },
    /// A divisor vanishes: `term` (`r11`, `r22` or `r33` of eq 16, or `y5 - y6`, `z1 - z2`,
    /// `x3 - x4` of eq 39) has magnitude below [`crate::SINGULARITY_TOLERANCE`] (or is NaN).
    Singular { term: &'static str, value: f64 },
    /// The actuator positions belong to no pose of the workspace: the forward singularity
    /// term `1 + abc` (`a = (Q2 - Q1)/2L`, `b = (Q4 - Q3)/2L`, `c = (Q6 - Q5)/2L`) is below
    /// [`crate::SINGULARITY_TOLERANCE`] (or NaN). At zero the platform is at the forward
    /// singularity (e.g. turned by about 120° about (1, 1, 1)); below it, beyond.
    ForwardSingular { value: f64 },
    /// A result overflowed to an infinity or NaN (inputs far outside the robot's workspace).
    NonFiniteResult { output: &'static str },
    /// The robot description breaks a rule: `field` as the description spells it, and the
    /// rule (`must be positive`, `breaks the triangle inequality Ixx ≤ Iyy + Izz ...`).
    Robot { field: String, rule: String },
    /// A setting is out of its range: `what` it is, and the `rule` it breaks.
    Invalid {
        what: &'static str,
        rule: &'static str,
    },
    /// A limit of the robot is broken: which, at which actuator (1..6), the value there and
    /// its margin (negative: how far beyond the limit), in the limit's unit.
    Limit {
        limit: crate::limits::Limit,
        actuator: usize,
        value: f64,
        margin: f64,
    },
    /// A singularity term is below its bound (or NaN): `term` names it (a Gough-Stewart
    /// platform's U joint, or the legs' hold on the platform), `value` is its value and `bound`
    /// the least the results need.
    Singularity {
        term: &'static str,
        value: f64,
        bound: f64,
    },
    /// The pose is too near a singularity for `what` to be served to its accuracy bound:
    /// `term` (the C5's `r11`, `r22` or `r33` of eq 16, a hexapod's legs' hold) is `value`,
    /// below `bound`, where the result's error against exact arithmetic would pass `1e-8`
    /// (docs/embedding.md).
    IllConditioned {
        what: &'static str,
        term: &'static str,
        value: f64,
        bound: f64,
    },
    /// An iteration stopped short of its tolerance: `what` it computes, and the residual it
    /// reached.
    NotConverged { what: &'static str, residual: f64 },
    /// The robot's mechanism has no such computation: `what` was asked of the `mechanism`,
    /// and `why` it has none (and what to do instead).
    Unsupported {
        what: &'static str,
        mechanism: &'static str,
        why: &'static str,
    },
    /// A slice argument has the wrong length.
    WrongLength {
        input: &'static str,
        expected: usize,
        got: usize,
    },
}

impl Error {
    pub(crate) fn from_robot(e: c5_robot::Error) -> Self {
        match e {
            c5_robot::Error::Invalid { field, rule } => Error::Robot { field, rule },
            other => Error::Robot {
                field: String::new(),
                rule: other.to_string(),
            },
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::NonFinite { input, index } => {
                write!(f, "{input}[{index}] is not a finite number")
            }
            Error::Singular { term, value } => write!(
                f,
                "singular pose: {term} = {value:e} (|{term}| must be at least {:e})",
                crate::SINGULARITY_TOLERANCE
            ),
            Error::ForwardSingular { value } => write!(
                f,
                "forward singular: 1 + abc = {value:e} (it must be at least {:e}): no pose of the \
                 workspace has these actuator positions",
                crate::SINGULARITY_TOLERANCE
            ),
            Error::NonFiniteResult { output } => {
                write!(
                    f,
                    "{output} is not finite (the state is far outside the workspace)"
                )
            }
            Error::Robot { field, rule } => write!(f, "invalid robot: `{field}` {rule}"),
            Error::Invalid { what, rule } => write!(f, "{what}: {rule}"),
            Error::Singularity { term, value, bound } => write!(
                f,
                "singular pose: {term} = {value:e} (it must be at least {bound:e})"
            ),
            Error::IllConditioned {
                what,
                term,
                value,
                bound,
            } => write!(
                f,
                "{what} refused: {term} = {value:e} is below {bound:e}, too near its \
                 singularity for an error within 1e-8 of exact arithmetic"
            ),
            Error::NotConverged { what, residual } => write!(
                f,
                "{what} did not converge: the residual stays at {residual:e} (no pose near the \
                 start has these actuator positions)"
            ),
            Error::Unsupported {
                what,
                mechanism,
                why,
            } => write!(f, "no {what} for the {mechanism} mechanism: {why}"),
            Error::WrongLength {
                input,
                expected,
                got,
            } => write!(f, "{input} has {got} values, expected {expected}"),
            Error::Limit {
                limit,
                actuator,
                value,
                margin,
            } => write!(
                f,
                "{limit} limit exceeded at actuator {actuator}: {value:.6} {unit}, {:.6} {unit} \
                 beyond the limit",
                -margin,
                unit = limit.unit()
            ),
        }
    }
}

impl core::error::Error for Error {}
