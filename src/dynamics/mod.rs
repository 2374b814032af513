//! Rigid-body dynamics of a fixed-base serial chain: recursive Newton–Euler inverse dynamics,
//! gravity torque, joint-space mass matrix, kinetic and potential energy.
//!
//! Pinocchio's model/data split (architecture rule 1): a [`DynModel`] holds the precomputed,
//! immutable per-link parameters; a [`DynData`] is a per-thread workspace (fixed-size arrays,
//! no heap); the algorithms are free functions.
//!
//! Equation of motion (seed 000, eq. 1): `τ = M(q) q̈ + C(q, q̇) q̇ + G(q)`; RNEA computes the
//! right-hand side in one pass (seed 000, eq. 5: `τ = rne(q, q̇, q̈)`). Friction (seed 000, eq. 2)
//! is not part of this module: see [`crate::effects`].
//!
//! Internally every joint frame is re-oriented by a constant rotation `A_i` so that the joint
//! axis is its local +z (`A_i e_z = axis_i`). A revolute transform then reads
//! `R = C_i Rz(q)` with a constant `C_i = A_{i-1}ᵀ R_origin A_i` (snapped onto the signed
//! permutation it is within 1e-14 of, if any: RNEA then applies it by relabelling, see
//! `batch.rs`); link inertias are stored about the joint origin (first moment `m c` and
//! `I_O = I_c + m([c]ᵀ[c])`). Quantities reported to the caller are joint-space only, so the
//! re-orientation is invisible.
//!
//! Limitations: fixed base only; revolute and prismatic joints (no mimic coupling, no
//! spherical/floating joints); at most [`MAX_DOF`] joints.

mod batch;
mod derivatives;
mod rnea;

pub use batch::{rnea_batch, Lanes, StateBatch};
pub(crate) use batch::{rnea_lanes, RneaScratch};

pub use derivatives::{complete_derivatives, fill_derivatives};
pub use rnea::{
    gravity_torque, kinetic_energy, mass_matrix, potential_energy, rnea, rnea_regressor,
    rnea_with_sincos, DynData, DynModel, DynOptions, MAX_DOF,
};
