//! The two models of the legs' mechanism.

use crate::Error;
use alloc::string::ToString;
use core::fmt;
use core::str::FromStr;

/// Which model of the legs' mechanism the kinematics and dynamics follow.
///
/// Both share the inverse kinematics (eq 16) and the platform's dynamics (eqs 52-57); they
/// differ in how a leg ties its actuator to the platform.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum Model {
    /// The mechanism eq 16 describes (a design decision, docs/models.md): the ball centre `B_i` is on
    /// the actuator axis, the crossed plates slide in the platform plane through `C` with normal
    /// `m_i = R e_k`, the plates and ball housing (body 2) keep the platform's orientation. Its
    /// velocities and accelerations are the exact time derivatives of eq 16, and its forces
    /// close the power balance. The default wherever forces are computed.
    #[default]
    Consistent,
    /// The chapter as published: the inverse Jacobian of eq 22 (rows `[(n_i × P_i2)ᵀ n_iᵀ]`),
    /// the projection scheme of eqs 43-48 and Khalil's model (eq 60). It is the derivative of
    /// eq 16 only at zero orientation (slip 4); kept to reproduce the chapter.
    Paper,
}

impl Model {
    /// Every model, the default first.
    pub const ALL: [Model; 2] = [Model::Consistent, Model::Paper];

    /// The model's name as the command line, the manifest and the generated modules spell it.
    pub fn name(self) -> &'static str {
        match self {
            Model::Consistent => "consistent",
            Model::Paper => "paper",
        }
    }
}

impl fmt::Display for Model {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Model {
    type Err = Error;

    /// # Errors
    /// [`Error::UnknownModel`] with the accepted names.
    fn from_str(s: &str) -> Result<Self, Error> {
        Model::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| Error::UnknownModel {
                given: s.to_string(),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::string::ToString;

    #[test]
    fn names_round_trip_and_unknown_names_list_the_choices() {
        for m in Model::ALL {
            assert_eq!(m.name().parse::<Model>().unwrap(), m);
        }
        assert_eq!(Model::default(), Model::Consistent);
        let e = "exact".parse::<Model>().unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown model `exact` (choose one of: consistent, paper)"
        );
    }
}
