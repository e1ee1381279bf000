// SPDX-License-Identifier: BSD-3-Clause
// Logistic-regression contact normals and separations (contact 2020 §3.1, Eqs. 19–25, and the
// Appendix, Eqs. 53–57).

#include "contact_lr.hpp"

#include "sparsempm/errors.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace smpm {

LogisticFit logistic_regression_normal(const ConstFieldRef& points,
                                       const Eigen::Ref<const Eigen::VectorXd>& classes,
                                       double cell) {
  SMPM_VERIFY(classes.size() == points.rows() && points.cols() >= 1 && points.cols() <= 3,
              "logistic_regression_normal: one class per point, 1 to 3 coordinates");
  return detail::logistic_fit(
      int(points.cols()), points.rows(),
      [&](Index k) {
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for (int a = 0; a < points.cols(); ++a)
          x[a] = points(k, a);
        return x;
      },
      [&](Index k) { return classes[k]; }, cell);
}

double particle_radius_along(int dim, const double* F, const double* r0, const Eigen::Vector3d& n) {
  // n₀ = F⁻¹ n̂ (Eq. 25), by the adjugate: F⁻¹ = adj(F)/det F.
  Eigen::Vector3d n0 = Eigen::Vector3d::Zero();
  if (dim == 1) {
    n0[0] = n[0] / F[0];
  } else if (dim == 2) {
    const double det = F[0] * F[3] - F[1] * F[2];
    n0[0] = (F[3] * n[0] - F[1] * n[1]) / det;
    n0[1] = (-F[2] * n[0] + F[0] * n[1]) / det;
  } else {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> Fm(F);
    n0 = Fm.inverse() * n;
  }
  double s = 0;
  for (int a = 0; a < dim; ++a)
    s += n0[a] * n0[a] / (r0[a] * r0[a]);
  return 1 / std::sqrt(s);
}

} // namespace smpm
