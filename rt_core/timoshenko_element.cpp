#include "rt_core/timoshenko_element.hpp"

#include <cmath>
#include <numbers>

namespace ambdrop {

double HollowCircleShearCoefficient(double nu, double m) {
  const double a = (1.0 + m * m) * (1.0 + m * m);
  return 6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * m * m);
}

PlaneElementMatrices TimoshenkoPlaneElement(double L, double D, double d, double E, double G,
                                            double rho) {
  return ShaftPlaneElement(ShaftElementTheory::kTimoshenko, L, D, d, E, G, rho);
}

PlaneElementMatrices ShaftPlaneElement(ShaftElementTheory theory, double L, double D, double d,
                                       double E, double G, double rho) {
  const double pi = std::numbers::pi;
  const double area = pi / 4.0 * (D * D - d * d);
  const double inertia = pi / 64.0 * (D * D * D * D - d * d * d * d);
  const double polar = 2.0 * inertia;
  // Without shear deformation Phi = 0 exactly, and the matrices below become the Euler-Bernoulli
  // stiffness and consistent mass and the Rayleigh rotary inertia (Friswell Sec. 5.4). Raising G
  // cannot get there: Cowper's kappa with nu = E/2G - 1 keeps kappa G finite as G grows.
  double phi = 0.0;
  if (theory == ShaftElementTheory::kTimoshenko) {
    const double nu = E / (2.0 * G) - 1.0;
    const double kappa = HollowCircleShearCoefficient(nu, d / D);
    phi = 12.0 * E * inertia / (kappa * G * area * L * L);
  }
  const double p1 = 1.0 + phi;

  PlaneElementMatrices out;
  // Stiffness with shear, Friswell Eq. (5.41).
  {
    const double c = E * inertia / (p1 * L * L * L);
    const double a = (4.0 + phi) * L * L;
    const double b = (2.0 - phi) * L * L;
    out.stiffness << 12, 6 * L, -12, 6 * L,  //
        6 * L, a, -6 * L, b,                 //
        -12, -6 * L, 12, -6 * L,             //
        6 * L, b, -6 * L, a;
    out.stiffness *= c;
  }
  // Translational mass, Friswell Eq. (5.43).
  {
    const double m1 = 312 + 588 * phi + 280 * phi * phi;
    const double m2 = (44 + 77 * phi + 35 * phi * phi) * L;
    const double m3 = 108 + 252 * phi + 140 * phi * phi;
    const double m4 = (26 + 63 * phi + 35 * phi * phi) * L;
    const double m5 = (8 + 14 * phi + 7 * phi * phi) * L * L;
    const double m6 = (6 + 14 * phi + 7 * phi * phi) * L * L;
    out.translational_mass << m1, m2, m3, -m4,  //
        m2, m5, m4, -m6,                        //
        m3, m4, m1, -m2,                        //
        -m4, -m6, -m2, m5;
    out.translational_mass *= rho * area * L / (840.0 * p1 * p1);
  }
  // Rotary inertia, Friswell Eq. (5.44); the polar version feeds the gyroscopic matrix.
  {
    const double m7 = (3 - 15 * phi) * L;
    const double m8 = (4 + 5 * phi + 10 * phi * phi) * L * L;
    const double m9 = (1 + 5 * phi - 5 * phi * phi) * L * L;
    Eigen::Matrix4d r;
    r << 36, m7, -36, m7,   //
        m7, m8, -m7, -m9,   //
        -36, -m7, 36, -m7,  //
        m7, -m9, -m7, m8;
    r /= 30.0 * p1 * p1 * L;
    out.rotary_mass = rho * inertia * r;
    out.polar_rotary = rho * polar * r;
  }
  // Euler-Bernoulli: the section's rotary inertia is neglected, and with it the gyroscopic
  // moment of the shaft (Friswell Sec. 5.4; discs keep theirs).
  if (theory == ShaftElementTheory::kEulerBernoulli) {
    out.rotary_mass.setZero();
    out.polar_rotary.setZero();
  }
  return out;
}

}  // namespace ambdrop
