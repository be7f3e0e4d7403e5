#pragma once
#include <Eigen/Core>

#include "rt_core/rotor_params.hpp"

namespace ambdrop {

/// Matrices of one Timoshenko beam element in one bending plane, DOF (w1, s1, w2, s2) with
/// w the lateral displacement and s = dw/dz the section slope. Shear deformation enters through
/// Phi = 12 E I / (kappa G A L^2) (Friswell et al., Dynamics of Rotating Machines, Sec. 5.4;
/// Przemieniecki's element).
struct PlaneElementMatrices {
  Eigen::Matrix4d stiffness;  ///< bending + shear
  Eigen::Matrix4d translational_mass;
  Eigen::Matrix4d rotary_mass;  ///< rotary inertia rho*I
  /// Polar counterpart rho*J of the rotary matrix: the gyroscopic block between the planes.
  Eigen::Matrix4d polar_rotary;
};

/// Shear coefficient of a hollow circular section (Cowper 1966, as used by Friswell Eq. (5.xx)).
double HollowCircleShearCoefficient(double poisson_ratio, double inner_over_outer);

PlaneElementMatrices TimoshenkoPlaneElement(double length_m, double outer_diameter_m,
                                            double inner_diameter_m, double youngs_modulus_Pa,
                                            double shear_modulus_Pa, double density_kg_m3);

/// The element of the chosen beam theory (Friswell Sec. 5.4-5.5): Timoshenko as above; Rayleigh
/// the same with Phi = 0 (no shear deformation); Euler-Bernoulli also without the rotary and
/// polar rotary matrices. The shear modulus is read by the Timoshenko element only.
PlaneElementMatrices ShaftPlaneElement(ShaftElementTheory theory, double length_m,
                                       double outer_diameter_m, double inner_diameter_m,
                                       double youngs_modulus_Pa, double shear_modulus_Pa,
                                       double density_kg_m3);

}  // namespace ambdrop
