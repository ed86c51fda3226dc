//! What the singularity terms the legged mechanisms' kernels return measure: each mechanism's
//! module describes its terms in `SINGULARITY_TERMS` (and, with a closed-form forward
//! kinematics, `FORWARD_KINEMATICS_TERMS`), so a caller checks any mechanism's terms with one
//! function, bounding each by its kind.

/// What a singularity term measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TermKind {
    /// The sine of a U joint's angle: zero where the joint locks.
    UJoint,
    /// `1 - (K/ρ)²` of a crank: zero where crank and rod align, negative beyond reach.
    Reach,
    /// A pivot ratio of the solve with `J⁻ᵀ`, in `(0, 1]`: zero at a parallel singularity.
    Pivot,
    /// The legs' hold as one ratio `det(J⁻¹)² / Π |row_i|²`: zero at a parallel singularity.
    Hold,
    /// A term of a closed-form forward kinematics: zero where its solutions merge.
    ForwardKinematics,
}

impl TermKind {
    /// Whether the term measures the legs' hold on the platform (a parallel singularity).
    pub const fn is_hold(self) -> bool {
        matches!(self, TermKind::Pivot | TermKind::Hold)
    }
}

/// One singularity term of a kernel's last result.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SingularityTerm {
    /// What it measures.
    pub kind: TermKind,
    /// Its name, as errors report it.
    pub name: &'static str,
    /// Its name where it is negative (the point beyond reach); `name` where that reads the same.
    pub negative: &'static str,
}
